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
// 60°), and the boundary moves by the cap's thickness only. A flat tetrahedron whose other two facets are not inside
// its tissue takes the label beyond two of its facets all the same (LabelAsFlatCap): it has no inside, so the
// boundary moves by rounding only, and the facets that become boundary are checked. Splitting a cap instead, as a
// sliver, puts free vertices on the boundary and edges below δ (Lemmas 2 and 5), so it is relabelled, after every
// rule and repair, and only where that makes no boundary non-manifold. With σ > 0 the same step peels off the
// background the slivers that R4′ left as caps on it (no split point there passed its acceptance test): their new
// boundary triangles are checked for 30° and for R1's bound (circumradius below the local δ), since they are not
// co-circular: on the randomized images with σ = 10°, 36 of 2,800 meshes had a peeled sliver's triangle up to 5 %
// wider than δ. A sliver whose peel would make a boundary non-manifold stays, and the refinement splits it after all
// (Refiner::PeelFlatCaps in DelaunayRefinementMesher.cxx).

#include "DelaunayRefinementGeometry.h"
#include "DelaunayRefinementMeshState.h"
#include "DelaunayRefinementSizing.h"
#include "DelaunayRefinementVertexLinks.h"

#include <algorithm>
#include <array>
#include <iterator>
#include <map>
#include <optional>
#include <utility>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{

class FlatCaps
{
public:
  FlatCaps(const MeshState & state, const LocalSampling & sizing, double minimumDihedralAngle)
    : m_State(state)
    , m_Sizing(sizing)
    , m_DihedralBound(minimumDihedralAngle)
  {}

  /** The label a tissue's tetrahedron would take as a cap: the one beyond its two boundary facets when exactly two
   * of its facets are on its label's boundary, both against that label, and its other two facets, which would
   * take their place, keep the boundary's bounds: every planar angle above 30°, circumradius below the local δ.
   * None for any other tetrahedron. */
  static std::optional<Label>
  LabelAsCap(const MeshState & state, const LocalSampling & sizing, CellHandle cell)
  {
    const Label label = cell->cache.label;
    if (label == BackgroundLabel)
    {
      return std::nullopt;
    }
    std::vector<int> boundaryFacets;
    std::vector<int> innerFacets;
    for (int facet = 0; facet < 4; ++facet)
    {
      (state.LabelBeyondFacet(cell, facet) == label ? innerFacets : boundaryFacets).push_back(facet);
    }
    if (boundaryFacets.size() != 2 ||
        state.LabelBeyondFacet(cell, boundaryFacets[0]) != state.LabelBeyondFacet(cell, boundaryFacets[1]) ||
        !KeepBoundaryBounds(state, sizing, cell, innerFacets))
    {
      return std::nullopt;
    }
    return state.LabelBeyondFacet(cell, boundaryFacets[0]);
  }

  /** The label a tissue's tetrahedron flat to rounding takes as a cap: the one label other than its own beyond two or
   * more of its facets (the smaller of two such), when its other facets, which become that label's boundary, keep
   * the boundary's bounds. LabelAsCap's caps are the case where those other facets are inside its tissue. A flat
   * tetrahedron has no inside, so the boundary moves by rounding only whichever label it takes, and one between three
   * labels (its tissue, another, the background) is a cap too: the randomized suite's SaltAndPepper 2164606 left one,
   * with two facets on the background, one on its tissue and one on another tissue, that no move and no edge removal
   * took out (docs/algorithm.md, "Flat caps"). */
  static std::optional<Label>
  LabelAsFlatCap(const MeshState & state, const LocalSampling & sizing, CellHandle cell)
  {
    const Label label = cell->cache.label;
    if (label == BackgroundLabel)
    {
      return std::nullopt;
    }
    std::array<Label, 4> beyond{};
    for (int facet = 0; facet < 4; ++facet)
    {
      beyond[facet] = state.LabelBeyondFacet(cell, facet);
    }
    std::optional<Label> cap;
    for (const Label other : beyond)
    {
      if (other != label && std::count(beyond.begin(), beyond.end(), other) >= 2 && (!cap || other < *cap))
      {
        cap = other;
      }
    }
    if (!cap)
    {
      return std::nullopt;
    }
    std::vector<int> facetsBecomingBoundary;
    for (int facet = 0; facet < 4; ++facet)
    {
      if (beyond[facet] != *cap)
      {
        facetsBecomingBoundary.push_back(facet);
      }
    }
    return KeepBoundaryBounds(state, sizing, cell, facetsBecomingBoundary) ? cap : std::nullopt;
  }

  /** Whether R4′ leaves the sliver `cell` to this step: with σ > 0, a sliver that is a cap on the background is
   * peeled off (relabelled to the background) like a flat cap, since no split point can leave its boundary with
   * surface vertices and 30° angles (SliverSplit). */
  static bool
  IsCapOnBackground(const MeshState & state, const LocalSampling & sizing, CellHandle cell)
  {
    return LabelAsCap(state, sizing, cell) == std::optional<Label>(BackgroundLabel);
  }

  /** What Relabel() did: the tetrahedra relabelled, each with its label before, and the slivers it had to leave
   * in their tissue because peeling them made a boundary non-manifold. */
  struct Relabelling
  {
    std::vector<std::pair<CellHandle, Label>> relabelled;
    std::vector<CellHandle>                   sliversKept;

    /** Gives the relabelled tetrahedra their labels back. */
    void
    Undo() const
    {
      for (const auto & [cell, label] : relabelled)
      {
        cell->cache.label = label;
      }
    }
  };

  /** Gives every flat cap the label beyond its boundary facets where no boundary becomes non-manifold by it. */
  Relabelling
  Relabel() const
  {
    std::vector<std::pair<CellHandle, Label>> caps = FindCaps();
    if (caps.empty())
    {
      return {};
    }
    // Only the caps' corners' stars change, so only their links are tested (VertexLinks, the local form of
    // ManifoldRepair::FindNonManifoldPlaces): two walks over the whole mesh had cost 40-60 ms of the atlas phantom
    // at 2 mm and the k-means tissues at 4 mm with σ = 15°.
    const std::vector<VertexHandle>    corners = CornersOf(caps);
    const std::map<VertexHandle, bool> nonManifoldBefore = NonManifoldAmong(corners);
    for (auto & [cell, label] : caps)
    {
      std::swap(cell->cache.label, label);
    }
    // A cap that made a place non-manifold gets its label back, until none does.
    for (bool reverted = true; reverted;)
    {
      reverted = false;
      const std::map<VertexHandle, bool> nonManifoldAfter = NonManifoldAmong(corners);
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
    Relabelling relabelling;
    for (const auto & [cell, label] : caps)
    {
      if (cell->cache.label != label)
      {
        relabelling.relabelled.emplace_back(cell, label);
      }
      else if (!IsFlatToRounding(m_State.CornersOf(cell)))
      {
        relabelling.sliversKept.push_back(cell);
      }
    }
    return relabelling;
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
      if (cell->cache.label == BackgroundLabel)
      {
        continue;
      }
      const std::array<Vector3, 4> corners = m_State.CornersOf(cell);
      const bool                   isFlat = IsFlatToRounding(corners);
      if (!isFlat && !m_DihedralBound.IsSliver(corners))
      {
        continue;
      }
      const std::optional<Label> label =
        isFlat ? LabelAsFlatCap(m_State, m_Sizing, cell) : LabelAsCap(m_State, m_Sizing, cell);
      // A sliver is peeled off the background only: given another tissue's label it would stay in the mesh.
      if (label && (isFlat || *label == BackgroundLabel))
      {
        caps.emplace_back(cell, *label);
      }
    }
    return caps;
  }

  /** Whether the facets that would become boundary keep every planar angle above 30° and R1's bound (on a nearly
   * co-circular cap they do by the arcs and the common circle; rounding decides). */
  static bool
  KeepBoundaryBounds(const MeshState & state, const LocalSampling & sizing, CellHandle cell,
                     const std::vector<int> & facets)
  {
    for (const int facet : facets)
    {
      const Vector3 a = state.PointOf(cell->vertex(Triangulation::vertex_triple_index(facet, 0)));
      const Vector3 b = state.PointOf(cell->vertex(Triangulation::vertex_triple_index(facet, 1)));
      const Vector3 c = state.PointOf(cell->vertex(Triangulation::vertex_triple_index(facet, 2)));
      if (!HasPlanarAnglesAbove30Degrees(a, b, c) || !sizing.KeepsBoundaryFacetBound(a, b, c))
      {
        return false;
      }
    }
    return true;
  }

  /** The caps' corners, each once. */
  static std::vector<VertexHandle>
  CornersOf(const std::vector<std::pair<CellHandle, Label>> & caps)
  {
    std::vector<VertexHandle> corners;
    for (const auto & cap : caps)
    {
      for (int corner = 0; corner < 4; ++corner)
      {
        corners.push_back(cap.first->vertex(corner));
      }
    }
    std::sort(corners.begin(), corners.end());
    corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
    return corners;
  }

  /** Whether some boundary (a tissue's or the union's) is not a manifold at each of `vertices`, with the labels as
   * they are now. */
  std::map<VertexHandle, bool>
  NonManifoldAmong(const std::vector<VertexHandle> & vertices) const
  {
    const Triangulation &        triangulation = m_State.GetTriangulation();
    std::map<VertexHandle, bool> nonManifold;
    std::vector<CellHandle>      star;
    for (const VertexHandle vertex : vertices)
    {
      star.clear();
      triangulation.incident_cells(vertex, std::back_inserter(star));
      nonManifold.emplace(vertex, m_Links.NonManifoldLabelsAt(triangulation, vertex, star) > 0);
    }
    return nonManifold;
  }

  /** Whether one of the cell's corners is non-manifold now and was not before. */
  static bool
  MakesAnyNew(CellHandle cell, const std::map<VertexHandle, bool> & before, const std::map<VertexHandle, bool> & after)
  {
    for (int corner = 0; corner < 4; ++corner)
    {
      const VertexHandle vertex = cell->vertex(corner);
      if (after.at(vertex) && !before.at(vertex))
      {
        return true;
      }
    }
    return false;
  }

  const MeshState &        m_State;
  const LocalSampling &    m_Sizing;
  const DihedralAngleBound m_DihedralBound;
  VertexLinks              m_Links;
};

} // namespace detail
} // namespace delaunay_refinement

#endif
