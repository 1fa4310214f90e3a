/*=========================================================================
 *
 *  Copyright NumFOCUS
 *
 *  Licensed under the Apache License, Version 2.0 (the "License");
 *  you may not use this file except in compliance with the License.
 *  You may obtain a copy of the License at
 *
 *         http://www.apache.org/licenses/LICENSE-2.0.txt
 *
 *  Unless required by applicable law or agreed to in writing, software
 *  distributed under the License is distributed on an "AS IS" BASIS,
 *  WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
 *  See the License for the specific language governing permissions and
 *  limitations under the License.
 *
 *=========================================================================*/
#ifndef DelaunayRefinementLargeBuffers_h
#define DelaunayRefinementLargeBuffers_h

// Buffers of one value per voxel (the regularisation's flags and distance transform, the oracle's maps) are tens to
// hundreds of megabytes, written once soon after they are allocated. Fresh memory costs a page fault per 4 KiB page
// on its first write; on a virtual machine a fault costs microseconds, and they were a quarter of the whole filter
// on the k-means tissues resampled to 1 mm at δ = 6 mm (12 M voxels; docs/algorithm.md, "Implementation"). Where
// Linux's transparent huge pages are on request (`madvise`, Debian's default), asking for them on such buffers
// makes one fault per 2 MiB. Elsewhere the request is ignored and the buffers are ordinary memory.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>
#include <vector>

#if defined(__linux__)
#  include <sys/mman.h>
#endif

namespace delaunay_refinement
{

/** The size from which a buffer asks for huge pages: one huge page of x86-64 and AArch64 Linux. Smaller buffers
 * would round up to it and waste most of it. */
constexpr std::size_t LargeBufferBytes = std::size_t{ 2 } << 20;

/** Asks for transparent huge pages on the whole huge pages inside `bytes` bytes at `memory`, which are best not
 * written yet (a page written before keeps its size). Advice only: where the system refuses it, or has no such
 * pages, nothing changes. For buffers that other code allocates, such as an itk::Image's after Allocate(). */
inline void
AdviseHugePages(void * memory, std::size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  const auto           begin = reinterpret_cast<std::uintptr_t>(memory);
  const std::uintptr_t first = (begin + LargeBufferBytes - 1) / LargeBufferBytes * LargeBufferBytes;
  const std::uintptr_t end = (begin + bytes) / LargeBufferBytes * LargeBufferBytes;
  if (end > first)
  {
    madvise(reinterpret_cast<void *>(first), end - first, MADV_HUGEPAGE);
  }
#else
  (void)memory;
  (void)bytes;
#endif
}

/** Memory for `bytes` bytes (at least LargeBufferBytes). On Linux it is aligned to LargeBufferBytes, with transparent
 * huge pages requested on the whole huge pages inside it (AdviseHugePages); the tail beyond the last of them stays in
 * ordinary pages, since rounding the buffer up to a whole huge page would make memory it never uses resident (up to
 * 2 MiB a buffer; the nearest-interface map of a 2.6 MB image took 4 MiB). Elsewhere it is ordinary memory. Release
 * with ReleaseLargeBuffer(). */
inline void *
AllocateLargeBuffer(std::size_t bytes)
{
#if defined(__linux__)
  void * memory = nullptr;
  if (posix_memalign(&memory, LargeBufferBytes, bytes) != 0)
  {
    throw std::bad_alloc();
  }
  AdviseHugePages(memory, bytes);
  return memory;
#else
  return ::operator new(bytes);
#endif
}

inline void
ReleaseLargeBuffer(void * memory)
{
  // clang-format reads the second branch as the continuation of the first.
  // clang-format off
#if defined(__linux__)
  std::free(memory);
#else
  ::operator delete(memory);
#endif
  // clang-format on
}

/** A standard allocator whose allocations of LargeBufferBytes and more are AllocateLargeBuffer()'s: for
 * std::vector of one value per voxel (LargeVector). */
template <typename T>
class LargeBufferAllocator
{
public:
  using value_type = T;

  LargeBufferAllocator() = default;
  template <typename U>
  LargeBufferAllocator(const LargeBufferAllocator<U> &) noexcept
  {}

  T *
  allocate(std::size_t count)
  {
    if (count > std::size_t(-1) / sizeof(T))
    {
      throw std::bad_array_new_length();
    }
    if (count * sizeof(T) < LargeBufferBytes)
    {
      return std::allocator<T>().allocate(count);
    }
    return static_cast<T *>(AllocateLargeBuffer(count * sizeof(T)));
  }

  void
  deallocate(T * memory, std::size_t count) noexcept
  {
    if (count * sizeof(T) < LargeBufferBytes)
    {
      std::allocator<T>().deallocate(memory, count);
      return;
    }
    ReleaseLargeBuffer(memory);
  }

  template <typename U>
  bool
  operator==(const LargeBufferAllocator<U> &) const noexcept
  {
    return true;
  }
  template <typename U>
  bool
  operator!=(const LargeBufferAllocator<U> &) const noexcept
  {
    return false;
  }
};

/** A vector of one value per voxel, or of as many (see the file's comment). */
template <typename T>
using LargeVector = std::vector<T, LargeBufferAllocator<T>>;

/** An array whose values are left unset, for buffers that their first pass writes whole; its memory is
 * LargeBufferAllocator's. */
template <typename T>
class UninitializedLargeArray
{
  static_assert(std::is_trivially_default_constructible_v<T> && std::is_trivially_destructible_v<T>,
                "its values are never constructed nor destroyed");

public:
  explicit UninitializedLargeArray(std::size_t count)
    : m_Count(count)
    , m_Values(LargeBufferAllocator<T>().allocate(count))
  {}

  ~UninitializedLargeArray() { LargeBufferAllocator<T>().deallocate(m_Values, m_Count); }

  UninitializedLargeArray(const UninitializedLargeArray &) = delete;
  UninitializedLargeArray &
  operator=(const UninitializedLargeArray &) = delete;

  T &
  operator[](std::size_t index)
  {
    return m_Values[index];
  }
  const T &
  operator[](std::size_t index) const
  {
    return m_Values[index];
  }
  T *
  get()
  {
    return m_Values;
  }
  const T *
  get() const
  {
    return m_Values;
  }

private:
  const std::size_t m_Count;
  T * const         m_Values;
};

} // namespace delaunay_refinement

#endif
