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
#ifndef DelaunayRefinementConflictRegions_h
#define DelaunayRefinementConflictRegions_h

// The conflict regions of several points at once (docs/algorithm.md, "R4′ picks its point"): R4′ scores up to 15
// free points around a sliver's circumcentre, each by the tetrahedra its insertion would make, and so needs each
// point's conflict region (the cells whose circumball holds it). Every one of those points lies well inside the
// sliver's circumball, so every region holds the sliver, and one search from the sliver over the cells in conflict
// with any of them finds them all: a Delaunay conflict region is connected. A search per point (CGAL's locate and
// find_conflicts) had cost 0.14 s of the atlas phantom at 2 mm and 0.28 s of the k-means tissues at 4 mm with
// σ = 15°, most of it walking the same cells again.

#include "DelaunayRefinementTriangulation.h"

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{

class ConflictRegions
{
public:
  /** At most this many points, one bit each. */
  static constexpr std::size_t MaximumPoints = 32;

  /** Finds the conflict region of each of `points` (at most MaximumPoints), all of which lie strictly inside the
   * circumball of `start`, a finite cell. A cell is in conflict with a point exactly when CGAL's insertion would
   * replace it (`side_of_sphere` with its symbolic perturbation): the cached circumsphere decides where the point
   * is clearly inside or outside it, the exact predicate where it is within a relative margin of the sphere
   * (SphereMargin). */
  void
  Find(const Triangulation & triangulation, CellHandle start, const std::vector<Vector3> & points)
  {
    if (points.size() > MaximumPoints)
    {
      throw std::logic_error("ConflictRegions: more points than bits");
    }
    Clear();
    m_Points = points;
    for (const Vector3 & point : points)
    {
      m_CgalPoints.push_back(ToCgal(point));
    }
    Visit(triangulation, start);
    for (std::size_t member = 0; member < m_Members.size(); ++member)
    {
      const CellHandle cell = m_Members[member].cell;
      for (int facet = 0; facet < 4; ++facet)
      {
        // Visit() may add members, so the member is looked up again after it.
        const uint32_t neighborMask = Visit(triangulation, cell->neighbor(facet));
        m_Members[member].neighborMasks[facet] = neighborMask;
      }
    }
  }

  /** Forgets the regions: they hold only while the triangulation does not change. */
  void
  Clear()
  {
    m_Points.clear();
    m_CgalPoints.clear();
    m_Members.clear();
    m_Masks.clear();
  }

  /** Which of the points Find() was given `point` is, if any. */
  std::optional<std::size_t>
  IndexOf(const Vector3 & point) const
  {
    for (std::size_t index = 0; index < m_Points.size(); ++index)
    {
      if (m_Points[index] == point)
      {
        return index;
      }
    }
    return std::nullopt;
  }

  /** The conflict region of point `index`: its cells and its boundary facets (a cell of the region and the facet
   * opposite the neighbour outside it), as CGAL's find_conflicts gives them up to their order. */
  void
  RegionOf(std::size_t index, std::vector<CellHandle> & cells, std::vector<Triangulation::Facet> & boundaryFacets) const
  {
    const uint32_t bit = uint32_t{ 1 } << index;
    cells.clear();
    boundaryFacets.clear();
    for (const Member & member : m_Members)
    {
      if ((member.mask & bit) == 0)
      {
        continue;
      }
      cells.push_back(member.cell);
      for (int facet = 0; facet < 4; ++facet)
      {
        if ((member.neighborMasks[facet] & bit) == 0)
        {
          boundaryFacets.emplace_back(member.cell, facet);
        }
      }
    }
  }

private:
  /** A cell in conflict with at least one point: the points' bits, and its neighbours'. */
  struct Member
  {
    CellHandle              cell;
    uint32_t                mask;
    std::array<uint32_t, 4> neighborMasks;
  };

  /** The mask of `cell`, computed the first time it is seen; a cell in conflict with some point joins the members,
   * and the search goes on from it (Find() visits the members' neighbours in turn). */
  uint32_t
  Visit(const Triangulation & triangulation, CellHandle cell)
  {
    const auto [found, isNew] = m_Masks.emplace(&*cell, 0U);
    if (!isNew)
    {
      return found->second;
    }
    uint32_t mask = 0;
    for (std::size_t index = 0; index < m_Points.size(); ++index)
    {
      mask |= static_cast<uint32_t>(IsInConflict(triangulation, cell, index)) << index;
    }
    found->second = mask;
    if (mask != 0)
    {
      m_Members.push_back({ cell, mask, {} });
    }
    return mask;
  }

  bool
  IsInConflict(const Triangulation & triangulation, CellHandle cell, std::size_t index) const
  {
    if (!triangulation.is_infinite(cell))
    {
      const double squaredDistance = SquaredNorm(m_Points[index] - cell->cache.circumcenter);
      const double squaredRadius = cell->cache.squaredRadius;
      if (squaredDistance < (1.0 - SphereMargin) * squaredRadius)
      {
        return true;
      }
      if (squaredDistance > (1.0 + SphereMargin) * squaredRadius)
      {
        return false;
      }
    }
    return triangulation.side_of_sphere(cell, m_CgalPoints[index], true) == CGAL::ON_BOUNDED_SIDE;
  }

  /** Within this fraction of the squared circumradius of the cached sphere, the exact predicate decides. The cached
   * circumcentre is within about 1e-7 of the longest edge, so 2e-7 of the radius, of the true one
   * (MeshState::FlatnessTolerance), which moves a point's squared distance minus the squared radius by at most about
   * 8e-7 of the squared radius near the sphere: the margin is over a hundred times that, so the cache never decides
   * a case the predicate would decide otherwise. */
  static constexpr double SphereMargin = 1e-4;

  std::vector<Vector3>                       m_Points;
  std::vector<CgalPoint>                     m_CgalPoints;
  std::vector<Member>                        m_Members;
  std::unordered_map<const void *, uint32_t> m_Masks;
};

} // namespace detail
} // namespace delaunay_refinement

#endif
