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
#ifndef DelaunayRefinementQueue_h
#define DelaunayRefinementQueue_h

// The refinement's work list (docs/algorithm.md, "Order of work"): the tetrahedra some rule may apply to, in three
// levels (surface work, then radius-edge work, then slivers), largest circumsphere first, ties broken by vertex ids
// so that the order never depends on memory addresses.

#include "DelaunayRefinementTriangulation.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{

/** Queue levels: surface work first (its feature insertions delete nearby free vertices, so quality work
 * done before it would be wasted), then R4's radius-edge work, then R4′'s slivers, whose split points are chosen
 * by the tetrahedra they make (SliverSplit): chosen among settled neighbours, they are not undone by later work. */
enum class QueueLevel : int
{
  Surface = 0,
  Quality = 1,
  Sliver = 2
};

/** 40 bytes: popping sifts entries through a heap of hundreds of thousands of them. */
struct QueueEntry
{
  double     squaredRadius;
  CellHandle cell;
  uint64_t   stamp;
  /** The cell's vertex ids, sorted: a tie-break that depends on the geometry and the (canonical) insertion
   * order only, never on memory addresses, which CGAL's vertex removal lets leak into container orders. */
  std::array<VertexId, 4> vertexIds;
};

/** Largest tetrahedra first; equal sizes (co-spherical cells) by vertex ids, for determinism. */
struct QueueEntryOrder
{
  bool
  operator()(const QueueEntry & a, const QueueEntry & b) const
  {
    if (a.squaredRadius != b.squaredRadius)
    {
      return a.squaredRadius < b.squaredRadius;
    }
    return a.vertexIds > b.vertexIds;
  }
};

/** A max-heap with four children per node: half the depth of a binary heap, and a node's children share a cache
 * line or two, so popping from hundreds of thousands of entries misses the cache about half as often. */
class FourAryHeap
{
public:
  bool
  Empty() const
  {
    return m_Entries.empty();
  }

  std::size_t
  Size() const
  {
    return m_Entries.size();
  }

  void
  Push(const QueueEntry & entry)
  {
    std::size_t position = m_Entries.size();
    m_Entries.push_back(entry);
    while (position > 0)
    {
      const std::size_t parent = (position - 1) / Arity;
      if (!m_Before(m_Entries[parent], entry))
      {
        break;
      }
      m_Entries[position] = m_Entries[parent];
      position = parent;
    }
    m_Entries[position] = entry;
  }

  /** Removes and returns the greatest entry; the heap must not be empty. */
  QueueEntry
  Pop()
  {
    const QueueEntry top = m_Entries.front();
    const QueueEntry last = m_Entries.back();
    m_Entries.pop_back();
    if (!m_Entries.empty())
    {
      SiftDown(last);
    }
    return top;
  }

  /** Removes the entries `isAlive` rejects and restores the heap over the others (Floyd's bottom-up build).
   * Returns how many were removed. */
  template <typename TIsAlive>
  std::size_t
  RemoveDead(TIsAlive && isAlive)
  {
    const auto firstDead = std::partition(
      m_Entries.begin(), m_Entries.end(), [&isAlive](const QueueEntry & entry) { return isAlive(entry); });
    const auto removed = static_cast<std::size_t>(m_Entries.end() - firstDead);
    m_Entries.erase(firstDead, m_Entries.end());
    // From the last entry with a child up to the root; the copy, since the sift overwrites its own position.
    for (std::size_t position = m_Entries.size() > 1 ? (m_Entries.size() - 2) / Arity + 1 : 0; position-- > 0;)
    {
      SiftDownFrom(position, QueueEntry(m_Entries[position]));
    }
    return removed;
  }

  /** Gives the storage back if the heap is empty: emptied, it keeps the memory of the most entries it held. */
  void
  ReleaseIfEmpty()
  {
    if (m_Entries.empty())
    {
      std::vector<QueueEntry>().swap(m_Entries);
    }
  }

private:
  static constexpr std::size_t Arity = 4;

  /** Places `entry` from the root down, moving greater children up. */
  void
  SiftDown(const QueueEntry & entry)
  {
    SiftDownFrom(0, entry);
  }

  /** Places `entry` at `position` or below it, moving greater children up. */
  void
  SiftDownFrom(std::size_t position, const QueueEntry & entry)
  {
    const std::size_t size = m_Entries.size();
    for (;;)
    {
      const std::size_t firstChild = Arity * position + 1;
      if (firstChild >= size)
      {
        break;
      }
      std::size_t greatest = firstChild;
      for (std::size_t child = firstChild + 1; child < std::min(firstChild + Arity, size); ++child)
      {
        if (m_Before(m_Entries[greatest], m_Entries[child]))
        {
          greatest = child;
        }
      }
      if (!m_Before(entry, m_Entries[greatest]))
      {
        break;
      }
      m_Entries[position] = m_Entries[greatest];
      position = greatest;
    }
    m_Entries[position] = entry;
  }

  std::vector<QueueEntry> m_Entries;
  QueueEntryOrder         m_Before;
};

/** One heap per level, each emptied before the next is looked at: the level is then never compared. */
class RefinementQueue
{
public:
  void
  Push(QueueLevel level, const QueueEntry & entry)
  {
    m_Levels[static_cast<std::size_t>(level)].Push(entry);
    ++m_PushesSinceRemoval;
  }

  bool
  Empty() const
  {
    return std::all_of(m_Levels.begin(), m_Levels.end(), [](const FourAryHeap & heap) { return heap.Empty(); });
  }

  std::size_t
  Size() const
  {
    std::size_t size = 0;
    for (const FourAryHeap & heap : m_Levels)
    {
      size += heap.Size();
    }
    return size;
  }

  /** Removes the entries of dead tetrahedra (`isAlive` rejects them) once as many entries have been pushed since the
   * last time as the queue held after it, and at least MinimumPushesBetweenRemovals: then the removal's pass over
   * the queue costs a constant per push. Returns how many were removed.
   *
   * Most entries die in the queue: a tetrahedron waits there while insertions near it destroy it (two thirds of
   * the entries of the 1 mm brain mask at δ = 2 mm were dead when popped). Popping a dead entry sifts through the
   * whole heap, a cache miss a level; removing it here costs one look at its tetrahedron. The order in which the
   * live entries come out is the same: the order is total on entries of distinct tetrahedra. */
  template <typename TIsAlive>
  std::size_t
  RemoveDeadWhenDue(TIsAlive && isAlive)
  {
    if (m_PushesSinceRemoval < std::max(m_SizeAfterRemoval, MinimumPushesBetweenRemovals))
    {
      return 0;
    }
    std::size_t removed = 0;
    for (FourAryHeap & heap : m_Levels)
    {
      removed += heap.RemoveDead(isAlive);
    }
    m_PushesSinceRemoval = 0;
    m_SizeAfterRemoval = Size();
    return removed;
  }

  /** The next entry to process and its level; the queue must not be empty. */
  QueueEntry
  Pop(QueueLevel & level)
  {
    std::size_t index = 0;
    while (m_Levels[index].Empty())
    {
      ++index;
    }
    level = static_cast<QueueLevel>(index);
    return m_Levels[index].Pop();
  }

  /** Gives back the storage of the empty levels (FourAryHeap::ReleaseIfEmpty), before the mesh is extracted while
   * the triangulation is still there: the 1 mm brain mask at δ = 2 mm kept 5 MB for 131,072 entries. */
  void
  ReleaseEmptyLevels()
  {
    for (FourAryHeap & heap : m_Levels)
    {
      heap.ReleaseIfEmpty();
    }
  }

private:
  /** Below this, a removal's fixed cost is not worth it: small meshes keep their dead entries. */
  static constexpr std::size_t MinimumPushesBetweenRemovals = 4096;

  std::array<FourAryHeap, 3> m_Levels;
  std::size_t                m_PushesSinceRemoval{ 0 };
  std::size_t                m_SizeAfterRemoval{ 0 };
};

} // namespace detail
} // namespace delaunay_refinement

#endif
