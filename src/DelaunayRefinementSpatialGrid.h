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
#ifndef DelaunayRefinementSpatialGrid_h
#define DelaunayRefinementSpatialGrid_h

#include "DelaunayRefinementTypes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace delaunay_refinement
{

/** A hash grid of payloads at points, for "which items lie within r of p" when r is about half the cell size
 * (then a query looks at 2 x 2 x 2 cells). Larger radii visit more cells, and beyond the number of occupied
 * cells fall back to scanning those, so every query is exact whatever its radius.
 *
 * The cells are found through an open-addressing table with a power-of-two capacity: the refinement asks
 * this grid a few times per created cell, and std::unordered_map's prime modulo (an integer division per
 * lookup) and chained buckets were its largest single cost. */
template <typename TPayload>
class SpatialGrid
{
public:
  explicit SpatialGrid(double cellSize)
    : m_CellSize(cellSize)
  {}

  void
  Insert(const Vector3 & point, const TPayload & payload)
  {
    m_Cells[FindOrAddCell(KeyOf(point))].push_back({ point, payload });
    ++m_Size;
  }

  /** Removes the entry with this payload stored at this point, if any. */
  void
  Remove(const Vector3 & point, const TPayload & payload)
  {
    const uint32_t cell = FindCell(KeyOf(point));
    if (cell == NoCell)
    {
      return;
    }
    std::vector<Entry> & entries = m_Cells[cell];
    const auto           found =
      std::find_if(entries.begin(), entries.end(), [&](const Entry & entry) { return entry.payload == payload; });
    if (found != entries.end())
    {
      *found = entries.back();
      entries.pop_back();
      --m_Size;
    }
  }

  /** Calls visit(payload) for every entry strictly closer than `radius` to `center`; stops early when visit
   * returns false (a visitor returning void visits everything). */
  template <typename TVisitor>
  void
  ForEachWithin(const Vector3 & center, double radius, TVisitor && visit) const
  {
    const double squaredRadius = radius * radius;
    const auto   visitCell = [&](const std::vector<Entry> & entries) {
      for (const Entry & entry : entries)
      {
        if (SquaredNorm(entry.point - center) < squaredRadius && !Continue(visit, entry.payload))
        {
          return false;
        }
      }
      return true;
    };
    // The cells the ball's bounding box overlaps, in floating point until the scan is known to be small: the
    // reach of a huge radius does not fit a long.
    double cellsToVisit = 1.0;
    for (int axis = 0; axis < 3; ++axis)
    {
      cellsToVisit *=
        std::floor((center[axis] + radius) / m_CellSize) - std::floor((center[axis] - radius) / m_CellSize) + 1.0;
    }
    if (!(cellsToVisit <= static_cast<double>(m_Cells.size())))
    {
      for (const std::vector<Entry> & entries : m_Cells)
      {
        if (!visitCell(entries))
        {
          return;
        }
      }
      return;
    }
    const Key lower = KeyOf(center - Vector3{ { radius, radius, radius } });
    const Key upper = KeyOf(center + Vector3{ { radius, radius, radius } });
    for (long i = lower.i; i <= upper.i; ++i)
    {
      for (long j = lower.j; j <= upper.j; ++j)
      {
        for (long k = lower.k; k <= upper.k; ++k)
        {
          const uint32_t cell = FindCell(Key{ i, j, k });
          if (cell != NoCell && !visitCell(m_Cells[cell]))
          {
            return;
          }
        }
      }
    }
  }

  bool
  AnyWithin(const Vector3 & center, double radius) const
  {
    // The cell holding the centre first: when an entry is near, it is most often there, and the answer comes
    // without the other 26 lookups.
    const uint32_t centerCell = FindCell(KeyOf(center));
    if (centerCell != NoCell)
    {
      const double squaredRadius = radius * radius;
      for (const Entry & entry : m_Cells[centerCell])
      {
        if (SquaredNorm(entry.point - center) < squaredRadius)
        {
          return true;
        }
      }
    }
    bool found = false;
    ForEachWithin(center, radius, [&](const TPayload &) {
      found = true;
      return false;
    });
    return found;
  }

  std::size_t
  Size() const
  {
    return m_Size;
  }

private:
  struct Key
  {
    long i;
    long j;
    long k;
    bool
    operator==(const Key & other) const
    {
      return i == other.i && j == other.j && k == other.k;
    }
  };

  struct Entry
  {
    Vector3  point;
    TPayload payload;
  };

  /** A slot of the open-addressing table: a cell's key and its index in m_Cells, or NoCell when free. */
  struct Slot
  {
    Key      key{ 0, 0, 0 };
    uint32_t cell{ NoCell };
  };

  static constexpr uint32_t NoCell = 0xffffffffu;

  template <typename TVisitor>
  static bool
  Continue(TVisitor & visit, const TPayload & payload)
  {
    if constexpr (std::is_same_v<decltype(visit(payload)), bool>)
    {
      return visit(payload);
    }
    else
    {
      visit(payload);
      return true;
    }
  }

  /** Unsigned arithmetic: signed overflow would be undefined behaviour for the large keys of a small cell size.
   * The final shift mixes the high bits, which the multiplications fill, into the low bits the mask keeps. */
  static std::size_t
  Hash(const Key & key)
  {
    uint64_t hash = static_cast<uint64_t>(key.i) * 0x9E3779B97F4A7C15ull ^
                    static_cast<uint64_t>(key.j) * 0xC2B2AE3D27D4EB4Full ^
                    static_cast<uint64_t>(key.k) * 0x165667B19E3779F9ull;
    hash ^= hash >> 32;
    return static_cast<std::size_t>(hash);
  }

  uint32_t
  FindCell(const Key & key) const
  {
    if (m_Slots.empty())
    {
      return NoCell;
    }
    const std::size_t mask = m_Slots.size() - 1;
    for (std::size_t slot = Hash(key) & mask;; slot = (slot + 1) & mask)
    {
      if (m_Slots[slot].cell == NoCell || m_Slots[slot].key == key)
      {
        return m_Slots[slot].cell;
      }
    }
  }

  /** Cells are never removed (an emptied cell keeps its slot), so probing needs no tombstones. */
  uint32_t
  FindOrAddCell(const Key & key)
  {
    if (2 * (m_Cells.size() + 1) > m_Slots.size())
    {
      Grow();
    }
    const std::size_t mask = m_Slots.size() - 1;
    std::size_t       slot = Hash(key) & mask;
    while (m_Slots[slot].cell != NoCell && !(m_Slots[slot].key == key))
    {
      slot = (slot + 1) & mask;
    }
    if (m_Slots[slot].cell == NoCell)
    {
      m_Slots[slot] = { key, static_cast<uint32_t>(m_Cells.size()) };
      m_Cells.emplace_back();
    }
    return m_Slots[slot].cell;
  }

  void
  Grow()
  {
    std::vector<Slot> slots(std::max<std::size_t>(64, 2 * m_Slots.size()));
    const std::size_t mask = slots.size() - 1;
    for (const Slot & old : m_Slots)
    {
      if (old.cell == NoCell)
      {
        continue;
      }
      std::size_t slot = Hash(old.key) & mask;
      while (slots[slot].cell != NoCell)
      {
        slot = (slot + 1) & mask;
      }
      slots[slot] = old;
    }
    m_Slots.swap(slots);
  }

  /** Cell coordinates saturate far beyond any real use: a tiny cell size (δ) against the coordinates would
   * otherwise overflow the conversion to an integer, which is undefined behaviour. Saturating keeps every query
   * exact (it only merges far-away cells), since it never moves two keys further apart. */
  static long
  CellCoordinate(double coordinate)
  {
    constexpr double limit = 4.0e18; // below 2^63, with room for the query's reach
    return static_cast<long>(std::clamp(std::floor(coordinate), -limit, limit));
  }

  Key
  KeyOf(const Vector3 & point) const
  {
    return { CellCoordinate(point[0] / m_CellSize),
             CellCoordinate(point[1] / m_CellSize),
             CellCoordinate(point[2] / m_CellSize) };
  }

  double                          m_CellSize;
  std::vector<Slot>               m_Slots;
  std::vector<std::vector<Entry>> m_Cells;
  std::size_t                     m_Size{ 0 };
};

} // namespace delaunay_refinement

#endif
