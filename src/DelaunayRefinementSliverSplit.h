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
#ifndef DelaunayRefinementSliverSplit_h
#define DelaunayRefinementSliverSplit_h

// Where R4' splits a sliver (docs/algorithm.md, "Slivers"): not necessarily at its circumcentre, but at the best
// point of a small ball around it, the picking region of Chew (Guaranteed-quality Delaunay meshing in 3D, 1997)
// and Li and Teng (Generating well-shaped Delaunay meshes in 3D, 2001). A point there is still at least
// (1 - PickingRadius) × the circumradius from every vertex, since the sliver's circumball is empty, so the
// refinement keeps its spacing argument; but its new tetrahedra differ from candidate to candidate, and one whose
// new tetrahedra are all well shaped leaves no sliver behind where the circumcentre would make another.

#include "DelaunayRefinementBoxProtection.h"
#include "DelaunayRefinementGeometry.h"
#include "DelaunayRefinementMeshState.h"

#include <array>
#include <cmath>
#include <iterator>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{

class SliverSplit
{
public:
  /** The picking region's radius, as a fraction of the sliver's circumradius. */
  static constexpr double PickingRadius = 0.3;

  SliverSplit(const MeshState & state, const BoxProtection & box, double radiusEdgeBound, double minimumDihedralAngle)
    : m_State(state)
    , m_Box(box)
    , m_RadiusEdgeBound(radiusEdgeBound)
    , m_CosineOfSigma(std::cos(DegreesToRadians(minimumDihedralAngle)))
  {}

  /** The point to insert for the sliver `cell` (circumcentre `center`, squared circumradius `squaredRadius`):
   * among the circumcentre and candidates on two spheres around it (radius 1/2 and 1 × the picking radius, 14
   * directions each), the one whose new tetrahedra (its conflict region's boundary facets joined to it) have the
   * largest smallest dihedral angle, counting only candidates whose new tetrahedra all have radius-edge ratio < ρ.
   * The first candidate whose new tetrahedra all reach σ ends the search; the circumcentre when no candidate
   * qualifies. Deterministic: fixed candidates in a fixed order, the first best wins. */
  Vector3
  Choose(CellHandle cell, const Vector3 & center, double squaredRadius) const
  {
    const double radius = std::sqrt(squaredRadius);
    Vector3      best = center;
    double       bestCosine = Unusable;
    const auto   consider = [&](const Vector3 & candidate) {
      const double cosine = CosineOfSmallestNewDihedralAngle(candidate, cell, bestCosine);
      if (cosine < bestCosine)
      {
        bestCosine = cosine;
        best = candidate;
      }
      return bestCosine <= m_CosineOfSigma;
    };
    if (consider(center))
    {
      return best;
    }
    for (const double fraction : { 0.5 * PickingRadius, PickingRadius })
    {
      for (const Vector3 & direction : Directions())
      {
        if (consider(center + (fraction * radius) * direction))
        {
          return best;
        }
      }
    }
    return best;
  }

private:
  /** The six axis directions and the eight diagonals, unit length. */
  static const std::array<Vector3, 14> &
  Directions()
  {
    static const std::array<Vector3, 14> directions = [] {
      std::array<Vector3, 14> result{};
      std::size_t             next = 0;
      for (int axis = 0; axis < 3; ++axis)
      {
        for (const double sign : { -1.0, 1.0 })
        {
          Vector3 direction{ { 0.0, 0.0, 0.0 } };
          direction[axis] = sign;
          result[next++] = direction;
        }
      }
      const double diagonal = 1.0 / std::sqrt(3.0);
      for (const double x : { -diagonal, diagonal })
      {
        for (const double y : { -diagonal, diagonal })
        {
          for (const double z : { -diagonal, diagonal })
          {
            result[next++] = Vector3{ { x, y, z } };
          }
        }
      }
      return result;
    }();
    return directions;
  }

  /** Worse than the cosine of any angle. */
  static constexpr double Unusable = 2.0;

  /** The cosine of the smallest dihedral angle of the tetrahedra that inserting `point` would create (angles are
   * compared by their cosines, which fall as they grow), or Unusable when the point cannot be inserted there
   * (outside the box, on a vertex, a new tetrahedron on the hull or one whose radius-edge ratio reaches ρ); once
   * the cosine is known to be at least `toBeat`, any value at least that. */
  double
  CosineOfSmallestNewDihedralAngle(const Vector3 & point, CellHandle hint, double toBeat) const
  {
    if (!m_Box.IsStrictlyInsideBox(point))
    {
      return Unusable;
    }
    const Triangulation &      triangulation = m_State.GetTriangulation();
    const CgalPoint            cgalPoint = ToCgal(point);
    Triangulation::Locate_type locateType;
    int                        li = 0;
    int                        lj = 0;
    const CellHandle           start = triangulation.locate(cgalPoint, locateType, li, lj, hint);
    if (locateType == Triangulation::VERTEX || triangulation.is_infinite(start))
    {
      return Unusable;
    }
    m_BoundaryFacets.clear();
    triangulation.find_conflicts(cgalPoint, start, std::back_inserter(m_BoundaryFacets), CGAL::Emptyset_iterator());
    double largestCosine = -1.0;
    for (const auto & [cell, opposite] : m_BoundaryFacets)
    {
      std::array<Vector3, 4> corners{};
      int                    next = 0;
      for (int vertex = 0; vertex < 4; ++vertex)
      {
        if (vertex == opposite)
        {
          continue;
        }
        if (triangulation.is_infinite(cell->vertex(vertex)))
        {
          return Unusable;
        }
        corners[next++] = m_State.PointOf(cell->vertex(vertex));
      }
      corners[3] = point;
      if (RadiusEdgeRatio(corners) >= m_RadiusEdgeBound)
      {
        return Unusable;
      }
      largestCosine = std::max(largestCosine, CosineOfSmallestDihedralAngle(corners));
      if (largestCosine >= toBeat)
      {
        return largestCosine;
      }
    }
    return largestCosine;
  }

  const MeshState &                         m_State;
  const BoxProtection &                     m_Box;
  double                                    m_RadiusEdgeBound;
  double                                    m_CosineOfSigma;
  mutable std::vector<Triangulation::Facet> m_BoundaryFacets;
};

} // namespace detail
} // namespace delaunay_refinement

#endif
