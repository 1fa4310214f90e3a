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
#ifndef DelaunayRefinementManifoldRepair_h
#define DelaunayRefinementManifoldRepair_h

// The manifold repair (docs/algorithm.md, "Topology"): where a tissue's boundary comes out non-manifold, halve δ
// locally and let the rules refine there again, as CGAL Mesh_3 keeps its manifold criteria in
// Refine_facets_manifold_base.h apart from the rules. The loop that alternates check and refinement is the
// driver's; this file finds the places, plans the zones of smaller δ, and says which cells they affect.

#include "DelaunayRefinementExtraction.h"
#include "DelaunayRefinementMeshQuality.h"
#include "DelaunayRefinementNonManifoldPlaces.h"
#include "DelaunayRefinementSizing.h"
#include "DelaunayRefinementVertexLinks.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{

/** Finds non-manifold places on the tissues' boundaries and refines δ around them. */
class ManifoldRepair
{
public:
  ManifoldRepair(const MeshState & state, const MeshExtraction & extraction, LocalSampling & sizing,
                 const RefinementParameters & parameters)
    : m_State(state)
    , m_Extraction(extraction)
    , m_Sizing(sizing)
    , m_FinestDelta(std::max(parameters.surfaceSamplingDistance /
                               std::pow(2.0, static_cast<double>(parameters.manifoldRefinementLevels)),
                             parameters.minimumSurfaceSamplingDistance))
  {}

  /** The paper guarantees a manifold only for δ small against the local feature size; a slit or a bridge
   * thinner than δ breaks it. Works on the triangulation's boundary facets directly: a full extraction (every
   * tetrahedron, sorted) costs more than the check itself. */
  NonManifoldPlaces
  FindNonManifoldPlaces() const
  {
    std::vector<VertexHandle>                             boundaryVertices;
    std::map<Label, std::vector<std::array<uint32_t, 3>>> trianglesPerLabel;
    for (auto vertex = m_State.GetTriangulation().finite_vertices_begin();
         vertex != m_State.GetTriangulation().finite_vertices_end();
         ++vertex)
    {
      vertex->info().outputIndex = NoOutputIndex;
    }
    const auto indexOf = [&boundaryVertices](VertexHandle vertex) {
      if (vertex->info().outputIndex == NoOutputIndex)
      {
        vertex->info().outputIndex = static_cast<uint32_t>(boundaryVertices.size());
        boundaryVertices.push_back(vertex);
      }
      return vertex->info().outputIndex;
    };
    m_Extraction.ForEachInterfaceFacet(m_Extraction.ObjectCells(), [&](CellHandle cell, int facet, Label otherLabel) {
      const std::array<uint32_t, 3> triangle{ indexOf(cell->vertex(Triangulation::vertex_triple_index(facet, 0))),
                                              indexOf(cell->vertex(Triangulation::vertex_triple_index(facet, 1))),
                                              indexOf(cell->vertex(Triangulation::vertex_triple_index(facet, 2))) };
      // Each tissue's boundary, and the union's (keyed by the background): facets against the background.
      trianglesPerLabel[cell->cache.label].push_back(triangle);
      trianglesPerLabel[otherLabel].push_back(triangle);
    });
    std::vector<std::pair<VertexHandle, Label>> offending;
    for (const auto & labelTriangles : trianglesPerLabel)
    {
      for (const uint32_t vertex : FindNonManifoldVertices(labelTriangles.second))
      {
        offending.emplace_back(boundaryVertices[vertex], labelTriangles.first);
      }
    }
    // In insertion order, as the extracted mesh numbers its vertices: nothing depends on addresses.
    std::sort(offending.begin(), offending.end(), [](const auto & a, const auto & b) {
      return std::make_pair(a.first->info().id, a.second) < std::make_pair(b.first->info().id, b.second);
    });
    NonManifoldPlaces places;
    for (const auto & [vertex, label] : offending)
    {
      places.Add(vertex, m_State.PointOf(vertex), label);
    }
    return places;
  }

  /** The same places, by the local link test (VertexLinks) at the vertices whose manifold test is due (see
   * VertexData::manifoldCheckDue): those whose star changed since the last search, and those it found. The test
   * depends on the star only, so the others keep the answer it gave, and this is what FindNonManifoldPlaces()
   * finds (a vertex fails the link test for a label exactly when it offends that label's triangles: an edge in
   * other than two of them makes both its ends fail it), at the cost of the changed stars instead of a walk over
   * the whole mesh. Every vertex is due at first, and a search where many are due walks the whole mesh instead. */
  NonManifoldPlaces
  FindNonManifoldPlacesWhereChanged() const
  {
    const Triangulation &     triangulation = m_State.GetTriangulation();
    std::vector<VertexHandle> due;
    for (auto vertex = triangulation.finite_vertices_begin(); vertex != triangulation.finite_vertices_end(); ++vertex)
    {
      if (vertex->info().manifoldCheckDue)
      {
        vertex->info().manifoldCheckDue = false;
        due.push_back(vertex);
      }
    }
    // A vertex's link test costs about three times a vertex's share of the walk over the mesh (measured on the
    // k-means tissues at 4.5 mm: 4 µs against 1.3 µs): with more vertices due than a third, the walk is cheaper.
    if (LocalTestCostFactor * due.size() > triangulation.number_of_vertices())
    {
      NonManifoldPlaces places = FindNonManifoldPlaces();
      for (const VertexHandle vertex : places.vertices)
      {
        vertex->info().manifoldCheckDue = true;
      }
      return places;
    }
    // In insertion order, as FindNonManifoldPlaces() lists them.
    std::sort(due.begin(), due.end(), [](VertexHandle a, VertexHandle b) { return a->info().id < b->info().id; });
    std::vector<CellHandle> star;
    NonManifoldPlaces       places;
    for (const VertexHandle vertex : due)
    {
      star.clear();
      triangulation.incident_cells(vertex, std::back_inserter(star));
      const std::vector<Label> labels = m_Links.ListNonManifoldLabelsAt(triangulation, vertex, star);
      if (labels.empty())
      {
        continue;
      }
      vertex->info().manifoldCheckDue = true;
      const Vector3 point = m_State.PointOf(vertex);
      for (const Label label : labels)
      {
        places.Add(vertex, point, label);
      }
    }
    return places;
  }

  /** How many vertices the tissues' boundaries have. */
  std::size_t
  CountBoundaryVertices() const
  {
    std::vector<VertexHandle> boundaryVertices;
    m_Extraction.ForEachInterfaceFacet(m_Extraction.ObjectCells(), [&](CellHandle cell, int facet, Label) {
      for (int corner = 0; corner < 3; ++corner)
      {
        boundaryVertices.push_back(cell->vertex(Triangulation::vertex_triple_index(facet, corner)));
      }
    });
    std::sort(boundaryVertices.begin(), boundaryVertices.end());
    return static_cast<std::size_t>(std::unique(boundaryVertices.begin(), boundaryVertices.end()) -
                                    boundaryVertices.begin());
  }

  /** Halves δ around every non-manifold place and refines again, up to manifoldRefinementLevels times and
   * never below minimumSurfaceSamplingDistance; all rules and guarantees stay as they are, with the local δ
   * (see LocalSampling). It mends isolated defects (a brain mask's one-voxel slit: 0.1 % of its boundary
   * vertices); where most of the boundary is non-manifold (voxel-scale speckle: over half of a k-means
   * segmentation's) refining only resolves more speckle, so it is not tried. It ends because every round
   * halves δ where it refines and δ never goes below the floor. */
  static bool
  IsRepairable(const NonManifoldPlaces & places, std::size_t numberOfBoundaryVertices)
  {
    return static_cast<double>(places.points.size()) <=
           MaximumRepairableFraction * static_cast<double>(numberOfBoundaryVertices);
  }

  /** Halves δ once around each place, from its δ before this round (a place inside the zone just made for a
   * nearby one is not halved again, which would refine by how the places happen to be ordered), never below
   * the finest δ. Returns the new zones; none when every place is at the finest δ already. */
  std::vector<Ball>
  HalveDeltaAround(const NonManifoldPlaces & places)
  {
    std::vector<std::pair<Vector3, double>> halvings;
    for (const Vector3 & point : places.points)
    {
      const double localDelta = m_Sizing.LocalDelta(point);
      if (localDelta > m_FinestDelta * (1.0 + 1e-12))
      {
        halvings.emplace_back(point, std::max(0.5 * localDelta, m_FinestDelta));
      }
    }
    std::vector<Ball> newZones;
    for (const auto & halving : halvings)
    {
      newZones.push_back({ halving.first, m_Sizing.AddZone(halving.first, halving.second) });
    }
    return newZones;
  }

  /** After the refinement ran out of work, only rules evaluated with a local δ or labels that changed can apply
   * again: R1 at the surface point closest to a circumcentre (inside the circumball), R2 at the circumcentre, R3
   * at a surface-ball centre on the Voronoi edge between two circumcentres (inside the union of the two
   * circumballs). So the cells whose circumball meets a changed ball, and their neighbours, are all that need
   * another look; the rest of the mesh is not walked again.
   *
   * Those cells (finite, each once, sorted) are, for one ball, connected through facets: a cell meeting it has a point
   * x of the ball in its circumball, so it is in x's conflict region, which is connected and holds the cell containing
   * x, and the cells along the segment from the ball's centre to x all contain a point of the ball. So a walk from the
   * cell containing the centre through the neighbours that meet the ball finds them all, at the cost of what it finds.
   */
  std::vector<CellHandle>
  CellsMeeting(const std::vector<Ball> & balls) const
  {
    const Triangulation &   triangulation = m_State.GetTriangulation();
    std::vector<CellHandle> meeting;
    std::vector<CellHandle> front;
    std::set<CellHandle>    seen;
    for (const Ball & ball : balls)
    {
      const auto meets = [&ball](CellHandle cell) {
        return Distance(cell->cache.circumcenter, ball.center) < std::sqrt(cell->cache.squaredRadius) + ball.radius;
      };
      const CellHandle start = triangulation.locate(ToCgal(ball.center));
      if (triangulation.is_infinite(start))
      {
        // Outside the box the refinement meshes (not where the repair puts its balls): every cell is looked at.
        for (auto cell = triangulation.finite_cells_begin(); cell != triangulation.finite_cells_end(); ++cell)
        {
          if (meets(cell))
          {
            meeting.push_back(cell);
          }
        }
        continue;
      }
      seen.clear();
      front.assign(1, start);
      seen.insert(start);
      while (!front.empty())
      {
        const CellHandle cell = front.back();
        front.pop_back();
        if (triangulation.is_infinite(cell) || !meets(cell))
        {
          continue;
        }
        meeting.push_back(cell);
        for (int facet = 0; facet < 4; ++facet)
        {
          if (seen.insert(cell->neighbor(facet)).second)
          {
            front.push_back(cell->neighbor(facet));
          }
        }
      }
    }
    std::sort(meeting.begin(), meeting.end());
    meeting.erase(std::unique(meeting.begin(), meeting.end()), meeting.end());
    return meeting;
  }

  /** The cells and their finite neighbours, each once. */
  std::vector<CellHandle>
  WithNeighbors(const std::vector<CellHandle> & cells) const
  {
    std::vector<CellHandle> affected;
    for (const CellHandle cell : cells)
    {
      affected.push_back(cell);
      for (int facet = 0; facet < 4; ++facet)
      {
        if (!m_State.GetTriangulation().is_infinite(cell->neighbor(facet)))
        {
          affected.push_back(cell->neighbor(facet));
        }
      }
    }
    std::sort(affected.begin(), affected.end());
    affected.erase(std::unique(affected.begin(), affected.end()), affected.end());
    return affected;
  }

private:
  /** Above this fraction of non-manifold boundary vertices the defects are pervasive, not local: see
   * IsRepairable(). Measured: brain mask 0.1 %, k-means segmentation 57-69 %. */
  static constexpr double MaximumRepairableFraction = 0.05;
  /** How much more a vertex's link test costs than a vertex's share of FindNonManifoldPlaces()'s walk. */
  static constexpr std::size_t LocalTestCostFactor = 3;

  const MeshState &      m_State;
  const MeshExtraction & m_Extraction;
  LocalSampling &        m_Sizing;
  const double           m_FinestDelta;
  VertexLinks            m_Links;
};

} // namespace detail
} // namespace delaunay_refinement

#endif
