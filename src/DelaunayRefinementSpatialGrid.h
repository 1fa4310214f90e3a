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
#include <unordered_map>
#include <vector>

namespace delaunay_refinement
{

/** A hash grid of payloads at points, for "which items lie within r of p" when r is about the cell size.
 * Larger radii fall back to scanning the occupied cells, so every query is exact whatever its radius. */
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
    m_Cells[KeyOf(point)].push_back({ point, payload });
    ++m_Size;
  }

  /** Removes the entry with this payload stored at this point, if any. */
  void
  Remove(const Vector3 & point, const TPayload & payload)
  {
    const auto cell = m_Cells.find(KeyOf(point));
    if (cell == m_Cells.end())
    {
      return;
    }
    std::vector<Entry> & entries = cell->second;
    const auto           found =
      std::find_if(entries.begin(), entries.end(), [&](const Entry & entry) { return entry.payload == payload; });
    if (found != entries.end())
    {
      *found = entries.back();
      entries.pop_back();
      --m_Size;
      if (entries.empty())
      {
        m_Cells.erase(cell);
      }
    }
  }

  /** Calls visit(payload) for every entry strictly closer than `radius` to `center`. */
  template <typename TVisitor>
  void
  ForEachWithin(const Vector3 & center, double radius, TVisitor && visit) const
  {
    const double squaredRadius = radius * radius;
    const auto   visitCell = [&](const std::vector<Entry> & entries) {
      for (const Entry & entry : entries)
      {
        if (SquaredNorm(entry.point - center) < squaredRadius)
        {
          visit(entry.payload);
        }
      }
    };
    // In floating point until the scan is known to be small: the reach of a huge radius does not fit a long.
    const double reachInCells = std::ceil(radius / m_CellSize);
    const double cellsToVisit = std::pow(2.0 * reachInCells + 1.0, 3);
    if (!(cellsToVisit <= static_cast<double>(m_Cells.size())))
    {
      for (const auto & cell : m_Cells)
      {
        visitCell(cell.second);
      }
      return;
    }
    const long reach = static_cast<long>(reachInCells);
    const Key  middle = KeyOf(center);
    for (long i = -reach; i <= reach; ++i)
    {
      for (long j = -reach; j <= reach; ++j)
      {
        for (long k = -reach; k <= reach; ++k)
        {
          const auto cell = m_Cells.find(Key{ middle.i + i, middle.j + j, middle.k + k });
          if (cell != m_Cells.end())
          {
            visitCell(cell->second);
          }
        }
      }
    }
  }

  bool
  AnyWithin(const Vector3 & center, double radius) const
  {
    bool found = false;
    ForEachWithin(center, radius, [&](const TPayload &) { found = true; });
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

  struct KeyHash
  {
    std::size_t
    operator()(const Key & key) const
    {
      // Unsigned: signed overflow would be undefined behaviour for the large keys of a small cell size.
      return static_cast<std::size_t>(key.i) * 73856093u ^ static_cast<std::size_t>(key.j) * 19349663u ^
             static_cast<std::size_t>(key.k) * 83492791u;
    }
  };

  struct Entry
  {
    Vector3  point;
    TPayload payload;
  };

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

  double                                               m_CellSize;
  std::unordered_map<Key, std::vector<Entry>, KeyHash> m_Cells;
  std::size_t                                          m_Size{ 0 };
};

} // namespace delaunay_refinement

#endif
