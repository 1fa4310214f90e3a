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
#include "DelaunayBenchChildProcess.h"

#include <malloc.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace delaunay_bench
{
namespace
{

/** A /proc/self/status field in kB (e.g. "VmHWM:"), as bytes. */
std::size_t
StatusBytes(const std::string & field)
{
  std::ifstream status("/proc/self/status");
  std::string   line;
  while (std::getline(status, line))
  {
    if (line.compare(0, field.size(), field) == 0)
    {
      return 1024 * std::stoull(line.substr(field.size()));
    }
  }
  throw std::runtime_error("/proc/self/status has no " + field + " line: peak memory cannot be measured");
}

/** Reads one byte of every page the program maps from its files (the executable's and the libraries' code and
 * constants), so that those pages are resident before a mesher's peak is measured. A forked child does not inherit
 * the parent's page table entries of file mappings: it maps them again as it runs, and its peak then counted the
 * code the mesher ran, about 3.7 MB of ours and 1.5 MB of CGAL's on the 64-voxel sphere at δ = 4 mm, more than
 * either allocated. That code does not grow with the image, and a process that meshes twice reads it once. */
void
ReadInTheProgramsFiles()
{
  constexpr std::uintptr_t PageBytes = 4096;
  std::ifstream            maps("/proc/self/maps");
  std::string              line;
  unsigned char            sum = 0;
  while (std::getline(maps, line))
  {
    // address range, permissions, offset, device, inode, path
    std::istringstream fields(line);
    std::string        range;
    std::string        permissions;
    std::string        offset;
    std::string        device;
    unsigned long      inode = 0;
    std::string        path;
    fields >> range >> permissions >> offset >> device >> inode >> path;
    // Files only: not the heap, the stacks nor the kernel's pages ([vvar] may not be read).
    if (permissions.empty() || permissions[0] != 'r' || inode == 0 || path.empty() || path[0] == '[')
    {
      continue;
    }
    const std::size_t    dash = range.find('-');
    const std::uintptr_t begin = std::stoull(range.substr(0, dash), nullptr, 16);
    const std::uintptr_t end = std::stoull(range.substr(dash + 1), nullptr, 16);
    for (std::uintptr_t page = begin; page < end; page += PageBytes)
    {
      sum += *reinterpret_cast<const volatile unsigned char *>(page);
    }
  }
  // Used, so that the reads are not optimised away.
  static volatile unsigned char sink;
  sink = sum;
}

void
ResetPeakResidentBytes()
{
  std::ofstream clearReferences("/proc/self/clear_refs");
  clearReferences << "5";
  clearReferences.close();
  if (!clearReferences)
  {
    throw std::runtime_error("cannot reset the peak resident memory through /proc/self/clear_refs");
  }
}

// ---- The pipe's byte stream ---------------------------------------------------------------------------------

enum class ChildStatus : uint8_t
{
  Succeeded = 0,
  Failed = 1
};

class PipeWriter
{
public:
  explicit PipeWriter(int descriptor)
    : m_Descriptor(descriptor)
  {}

  void
  Bytes(const void * data, std::size_t size)
  {
    const auto * next = static_cast<const char *>(data);
    while (size > 0)
    {
      const ssize_t written = ::write(m_Descriptor, next, size);
      if (written < 0 && errno == EINTR)
      {
        continue;
      }
      if (written <= 0)
      {
        // The parent is gone: nobody is left to report to.
        ::_exit(3);
      }
      next += written;
      size -= static_cast<std::size_t>(written);
    }
  }

  template <typename T>
  void
  Value(const T & value)
  {
    Bytes(&value, sizeof(T));
  }

  template <typename T>
  void
  Vector(const std::vector<T> & values)
  {
    Value<uint64_t>(values.size());
    Bytes(values.data(), values.size() * sizeof(T));
  }

private:
  int m_Descriptor;
};

class ByteReader
{
public:
  explicit ByteReader(const std::string & bytes)
    : m_Bytes(bytes)
  {}

  void
  Bytes(void * data, std::size_t size)
  {
    if (m_Position + size > m_Bytes.size())
    {
      throw std::runtime_error("the child process sent a truncated result");
    }
    std::memcpy(data, m_Bytes.data() + m_Position, size);
    m_Position += size;
  }

  template <typename T>
  T
  Value()
  {
    T value;
    Bytes(&value, sizeof(T));
    return value;
  }

  template <typename T>
  void
  Vector(std::vector<T> & values)
  {
    values.resize(Value<uint64_t>());
    Bytes(values.data(), values.size() * sizeof(T));
  }

  std::string
  Rest() const
  {
    return m_Bytes.substr(m_Position);
  }

private:
  const std::string & m_Bytes;
  std::size_t         m_Position{ 0 };
};

void
WriteRun(PipeWriter & pipe, const MeasuredRun & run)
{
  pipe.Value(ChildStatus::Succeeded);
  pipe.Value(run.output.totalSeconds);
  pipe.Value(run.output.totalCpuSeconds);
  pipe.Value(run.output.refinementSeconds);
  pipe.Value(run.output.refinementCpuSeconds);
  pipe.Value<uint64_t>(run.output.peakResidentBytes);
  pipe.Value<uint64_t>(run.meshingMemoryBytes);
  const delaunay_refinement::TetrahedralMesh & mesh = run.output.mesh;
  pipe.Vector(mesh.points);
  pipe.Vector(mesh.pointKinds);
  pipe.Vector(mesh.tetrahedra);
  pipe.Vector(mesh.tetrahedronLabels);
  pipe.Vector(mesh.boundaryTriangles);
  pipe.Vector(mesh.boundaryTriangleLabels);
}

MeasuredRun
ReadRun(const std::string & bytes)
{
  ByteReader reader(bytes);
  if (reader.Value<ChildStatus>() != ChildStatus::Succeeded)
  {
    throw std::runtime_error("the mesher failed in its child process: " + reader.Rest());
  }
  MeasuredRun run;
  run.output.totalSeconds = reader.Value<double>();
  run.output.totalCpuSeconds = reader.Value<double>();
  run.output.refinementSeconds = reader.Value<double>();
  run.output.refinementCpuSeconds = reader.Value<double>();
  run.output.peakResidentBytes = reader.Value<uint64_t>();
  run.meshingMemoryBytes = reader.Value<uint64_t>();
  delaunay_refinement::TetrahedralMesh & mesh = run.output.mesh;
  reader.Vector(mesh.points);
  reader.Vector(mesh.pointKinds);
  reader.Vector(mesh.tetrahedra);
  reader.Vector(mesh.tetrahedronLabels);
  reader.Vector(mesh.boundaryTriangles);
  reader.Vector(mesh.boundaryTriangleLabels);
  return run;
}

// ---- The two sides of the fork ------------------------------------------------------------------------------

/** What a child that ran out of memory under RLIMIT_AS reports (std::bad_alloc's what()). */
constexpr const char * OutOfMemoryMessage = "std::bad_alloc";

void
SetLimit(int resource, rlim_t soft, rlim_t hard)
{
  const rlimit limit{ soft, hard };
  if (::setrlimit(resource, &limit) != 0)
  {
    throw std::runtime_error(std::string("setrlimit() failed: ") + std::strerror(errno));
  }
}

[[noreturn]] void
RunChild(const std::function<MesherOutput()> & mesher, int descriptor, const std::optional<ResourceCap> & cap)
{
  PipeWriter pipe(descriptor);
  try
  {
    if (cap)
    {
      // The soft CPU limit sends SIGXCPU, which ends the child; the hard one a second later is SIGKILL.
      const auto seconds = static_cast<rlim_t>(std::ceil(cap->cpuSeconds));
      SetLimit(RLIMIT_CPU, seconds, seconds + 1);
      SetLimit(RLIMIT_AS, cap->addressSpaceBytes, cap->addressSpaceBytes);
    }
    // Free heap pages inherited from the parent would otherwise be reused without counting.
    ::malloc_trim(0);
    ReadInTheProgramsFiles();
    ResetPeakResidentBytes();
    const std::size_t startBytes = StatusBytes("VmRSS:");
    MeasuredRun       run;
    run.output = mesher();
    run.meshingMemoryBytes = run.output.peakResidentBytes - std::min(startBytes, run.output.peakResidentBytes);
    WriteRun(pipe, run);
  }
  catch (const std::exception & error)
  {
    pipe.Value(ChildStatus::Failed);
    pipe.Bytes(error.what(), std::strlen(error.what()));
  }
  ::close(descriptor);
  // _exit: the parent's stdio buffers and static destructors are the parent's business.
  ::_exit(0);
}

std::string
ReadAll(int descriptor)
{
  std::string bytes;
  char        buffer[1 << 16];
  for (;;)
  {
    const ssize_t count = ::read(descriptor, buffer, sizeof(buffer));
    if (count < 0 && errno == EINTR)
    {
      continue;
    }
    if (count <= 0)
    {
      return bytes;
    }
    bytes.append(buffer, static_cast<std::size_t>(count));
  }
}

} // namespace

std::size_t
PeakResidentBytes()
{
  return StatusBytes("VmHWM:");
}

namespace
{

/** The child's result bytes and wait status. */
std::pair<std::string, int>
ForkAndRun(const std::function<MesherOutput()> & mesher, const std::optional<ResourceCap> & cap)
{
  int descriptors[2];
  if (::pipe(descriptors) != 0)
  {
    throw std::runtime_error(std::string("pipe() failed: ") + std::strerror(errno));
  }
  std::fflush(nullptr);
  const pid_t child = ::fork();
  if (child < 0)
  {
    throw std::runtime_error(std::string("fork() failed: ") + std::strerror(errno));
  }
  if (child == 0)
  {
    ::close(descriptors[0]);
    RunChild(mesher, descriptors[1], cap);
  }
  ::close(descriptors[1]);
  std::string bytes = ReadAll(descriptors[0]);
  ::close(descriptors[0]);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR)
  {}
  return { std::move(bytes), status };
}

void
RequireNormalExit(int status)
{
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
  {
    throw std::runtime_error("the mesher's child process died (wait status " + std::to_string(status) + ")");
  }
}

} // namespace

MeasuredRun
RunInChildProcess(const std::function<MesherOutput()> & mesher)
{
  const auto [bytes, status] = ForkAndRun(mesher, std::nullopt);
  RequireNormalExit(status);
  return ReadRun(bytes);
}

std::optional<MeasuredRun>
RunInChildProcessWithin(const std::function<MesherOutput()> & mesher, const ResourceCap & cap, std::string & overCap)
{
  const auto [bytes, status] = ForkAndRun(mesher, cap);
  if (WIFSIGNALED(status) && (WTERMSIG(status) == SIGXCPU || WTERMSIG(status) == SIGKILL))
  {
    overCap = "over the " + std::to_string(static_cast<long>(cap.cpuSeconds)) + " s cap";
    return std::nullopt;
  }
  RequireNormalExit(status);
  if (!bytes.empty() && static_cast<ChildStatus>(bytes[0]) == ChildStatus::Failed &&
      bytes.find(OutOfMemoryMessage) != std::string::npos)
  {
    overCap = "over the " + std::to_string(cap.addressSpaceBytes >> 30) + " GB cap";
    return std::nullopt;
  }
  return ReadRun(bytes);
}

} // namespace delaunay_bench
