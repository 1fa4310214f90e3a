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
#ifndef DelaunayRefinementFlatCaps_h
#define DelaunayRefinementFlatCaps_h

// Flat caps (docs/algorithm.md, "Flat caps"): four surface vertices on the voxel-face lattice can be nearly
// co-planar and co-circular, and the Delaunay triangulation may join them in a tetrahedron flat to rounding whose
// radius-edge ratio is small, so no rule splits it; its circumcentre, and with it its label, is arbitrary. When such
// a tetrahedron has two facets on its label's boundary, both against one other label, it is a cap on that boundary:
// giving it the other label swaps the two facets for its other two, which lie in the same plane on the same circle
// (so their angles keep the 30° bound: each is half an arc of the circle that the old facets' angles bound below by
// 60°), and the boundary moves by the cap's thickness only. Splitting it instead, as a sliver, puts free vertices
// on the boundary and edges below δ (Lemmas 2 and 5), so it is relabelled, after every rule and repair, and only
// where that makes no boundary non-manifold.

#include "DelaunayRefinementGeometry.h"
#include "DelaunayRefinementManifoldRepair.h"
#include "DelaunayRefinementMeshState.h"

#include <algorithm>
#include <array>
#include <set>
#include <utility>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{

class FlatCaps
{
public:
  FlatCaps(const MeshState & state, const ManifoldRepair & repair)
    : m_State(state)
    , m_Repair(repair)
  {}

  /** Gives every flat cap the label beyond its boundary facets where no boundary becomes non-manifold by it;
   * returns how many were relabelled. */
  std::size_t
  Relabel() const
  {
    std::vector<std::pair<CellHandle, Label>> caps = FindCaps();
    if (caps.empty())
    {
      return 0;
    }
    const std::set<Vector3> nonManifoldBefore = NonManifoldPoints();
    for (auto & [cell, label] : caps)
    {
      std::swap(cell->cache.label, label);
    }
    // A cap that made a place non-manifold gets its label back, until none does.
    for (bool reverted = true; reverted;)
    {
      reverted = false;
      const std::set<Vector3> nonManifoldAfter = NonManifoldPoints();
      for (auto & [cell, label] : caps)
      {
        if (label == cell->cache.label || !MakesAnyNew(cell, nonManifoldBefore, nonManifoldAfter))
        {
          continue;
        }
        std::swap(cell->cache.label, label);
        label = cell->cache.label;
        reverted = true;
      }
    }
    return static_cast<std::size_t>(
      std::count_if(caps.begin(), caps.end(), [](const auto & cap) { return cap.first->cache.label != cap.second; }));
  }

private:
  /** The flat caps, each with the label it would take. */
  std::vector<std::pair<CellHandle, Label>>
  FindCaps() const
  {
    std::vector<std::pair<CellHandle, Label>> caps;
    const Triangulation &                     triangulation = m_State.GetTriangulation();
    for (auto cell = triangulation.finite_cells_begin(); cell != triangulation.finite_cells_end(); ++cell)
    {
      const Label label = cell->cache.label;
      if (label == BackgroundLabel || !IsFlatToRounding(m_State.CornersOf(cell)))
      {
        continue;
      }
      std::vector<int> boundaryFacets;
      std::vector<int> innerFacets;
      for (int facet = 0; facet < 4; ++facet)
      {
        (m_State.LabelBeyondFacet(cell, facet) == label ? innerFacets : boundaryFacets).push_back(facet);
      }
      if (boundaryFacets.size() != 2 ||
          m_State.LabelBeyondFacet(cell, boundaryFacets[0]) != m_State.LabelBeyondFacet(cell, boundaryFacets[1]) ||
          !HaveAnglesAbove30Degrees(cell, innerFacets))
      {
        continue;
      }
      caps.emplace_back(cell, m_State.LabelBeyondFacet(cell, boundaryFacets[0]));
    }
    return caps;
  }

  /** Whether the facets that would become boundary keep every planar angle above 30° (on a nearly co-circular
   * cap they do by the arcs; rounding decides). */
  bool
  HaveAnglesAbove30Degrees(CellHandle cell, const std::vector<int> & facets) const
  {
    for (const int facet : facets)
    {
      if (!HasPlanarAnglesAbove30Degrees(m_State.PointOf(cell->vertex(Triangulation::vertex_triple_index(facet, 0))),
                                         m_State.PointOf(cell->vertex(Triangulation::vertex_triple_index(facet, 1))),
                                         m_State.PointOf(cell->vertex(Triangulation::vertex_triple_index(facet, 2)))))
      {
        return false;
      }
    }
    return true;
  }

  std::set<Vector3>
  NonManifoldPoints() const
  {
    const std::vector<Vector3> points = m_Repair.FindNonManifoldPlaces().points;
    return std::set<Vector3>(points.begin(), points.end());
  }

  /** Whether one of the cell's corners is non-manifold now and was not before. */
  bool
  MakesAnyNew(CellHandle cell, const std::set<Vector3> & before, const std::set<Vector3> & after) const
  {
    for (int corner = 0; corner < 4; ++corner)
    {
      const Vector3 point = m_State.PointOf(cell->vertex(corner));
      if (after.count(point) != 0 && before.count(point) == 0)
      {
        return true;
      }
    }
    return false;
  }

  const MeshState &      m_State;
  const ManifoldRepair & m_Repair;
};

} // namespace detail
} // namespace delaunay_refinement

#endif
