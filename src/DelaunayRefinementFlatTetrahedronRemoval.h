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
#ifndef DelaunayRefinementFlatTetrahedronRemoval_h
#define DelaunayRefinementFlatTetrahedronRemoval_h

// The last resort for a tetrahedron flat to rounding inside a tissue (docs/algorithm.md, "Flat tetrahedra inside a
// tissue"): in the extracted mesh, one of its edges is removed, the ring of tetrahedra around it replaced by the
// tetrahedra joining the edge's two ends to a triangulation of the ring's link polygon (an edge removal, as in
// TetGen and Shewchuk's "Two discrete optimization algorithms for the topological improvement of tetrahedral
// meshes", 2002). Only where the ring lies inside one tissue, so no boundary or interface triangle changes, and
// only when every new tetrahedron keeps the guarantees: positive volume that is not flat to rounding, radius-edge
// ratio < ρ, and the tissue's label at its circumcentre (the output's invariant). A ring with tetrahedra that the
// topology relabelling gave their label (which they need not carry at their circumcentres) is replaced only by
// tetrahedra listed as relabelled too, whose circumcentres are not asked. The mesh is then no longer
// Delaunay there, which no guarantee needs. It is for the flat tetrahedra that no move of a corner removes: where
// the surface samples of the voxel lattice are barely more than δ apart, every move breaks Lemma 2's spacing.

#include "DelaunayRefinementGeometry.h"
#include "DelaunayRefinementOracle.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{

class FlatTetrahedronRemoval
{
public:
  /** The largest ring (tetrahedra around the edge) tried: its link polygon has at most 42 triangulations. */
  static constexpr std::size_t LargestRing = 7;

  FlatTetrahedronRemoval(const LabelOracle & oracle, double radiusEdgeBound)
    : m_Oracle(oracle)
    , m_RadiusEdgeBound(radiusEdgeBound)
  {}

  /** Removes the tetrahedra of a tissue flat to rounding where an edge removal can (see the file's comment);
   * returns how many. The mesh's other tetrahedra keep their order; the new ones come at the end. */
  std::size_t
  Remove(TetrahedralMesh & mesh)
  {
    const std::vector<uint32_t> flat = FlatTissueTetrahedra(mesh);
    if (flat.empty())
    {
      return 0;
    }
    BuildIncidence(mesh);
    m_InterfaceTriangles.clear();
    m_Removed.assign(mesh.tetrahedra.size(), 0);
    MarkRelabelled(mesh);
    std::size_t removed = 0;
    for (const uint32_t t : flat)
    {
      if (!m_Removed[t] && RemoveAnEdgeOf(mesh, t))
      {
        ++removed;
      }
    }
    if (removed > 0)
    {
      Compact(mesh);
      WriteFlippedInterfaceTriangles(mesh);
    }
    return removed;
  }

  /** The tissue tetrahedra of the mesh flat to rounding, by index, increasing. */
  static std::vector<uint32_t>
  FlatTissueTetrahedra(const TetrahedralMesh & mesh)
  {
    std::vector<uint32_t> flat;
    for (uint32_t t = 0; t < mesh.tetrahedra.size(); ++t)
    {
      if (mesh.tetrahedronLabels[t] != BackgroundLabel && IsFlatToRounding(CornersOf(mesh, t)))
      {
        flat.push_back(t);
      }
    }
    return flat;
  }

  static std::array<Vector3, 4>
  CornersOf(const TetrahedralMesh & mesh, uint32_t t)
  {
    return CornersOf(mesh, mesh.tetrahedra[t]);
  }

private:
  using Tetrahedron = std::array<uint32_t, 4>;
  using Triangle = std::array<uint32_t, 3>;

  static std::array<Vector3, 4>
  CornersOf(const TetrahedralMesh & mesh, const Tetrahedron & tetrahedron)
  {
    return {
      mesh.points[tetrahedron[0]], mesh.points[tetrahedron[1]], mesh.points[tetrahedron[2]], mesh.points[tetrahedron[3]]
    };
  }

  void
  BuildIncidence(const TetrahedralMesh & mesh)
  {
    m_Incident.assign(mesh.points.size(), {});
    for (uint32_t t = 0; t < mesh.tetrahedra.size(); ++t)
    {
      for (const uint32_t vertex : mesh.tetrahedra[t])
      {
        m_Incident[vertex].push_back(t);
      }
    }
  }

  /** A relabelled tetrahedron (docs/algorithm.md, "Topology") does not carry the label at its circumcentre, and
   * neither need the tetrahedra that replace a ring holding one (RemoveEdge). */
  void
  MarkRelabelled(const TetrahedralMesh & mesh)
  {
    m_Relabelled.assign(mesh.tetrahedra.size(), 0);
    for (const uint32_t t : mesh.topologyRelabelledTetrahedra)
    {
      m_Relabelled[t] = 1;
    }
  }

  /** Tries the flat tetrahedron's six edges in a fixed order, each with a ring inside its tissue; the first
   * removal that keeps the guarantees is made. Then, for a flat tetrahedron on an interface, its edges whose ring
   * is inside the other tissue (FlipInterfaceDiagonal). */
  bool
  RemoveAnEdgeOf(TetrahedralMesh & mesh, uint32_t flat)
  {
    const Tetrahedron corners = mesh.tetrahedra[flat];
    for (int first = 0; first < 4; ++first)
    {
      for (int second = first + 1; second < 4; ++second)
      {
        if (RemoveEdge(mesh, corners[first], corners[second], mesh.tetrahedronLabels[flat], flat))
        {
          return true;
        }
      }
    }
    for (int first = 0; first < 4; ++first)
    {
      for (int second = first + 1; second < 4; ++second)
      {
        if (FlipInterfaceDiagonal(mesh, flat, first, second))
        {
          return true;
        }
      }
    }
    return false;
  }

  /** A flat tetrahedron (a, b, x, y) of tissue L1 whose two facets at the edge (a, b) are on an interface with
   * tissue L2, every other tetrahedron around (a, b) being of L2, and whose two other facets are inside L1, every
   * tetrahedron around (x, y) being of L1: the interface there is the flat quadrilateral a x b y, split along
   * (a, b). Removing (a, b) as if the flat tetrahedron were of L2 splits it along (x, y) instead: the new
   * tetrahedra are of L2 and the interface triangles (a, b, x), (a, b, y) become (a, x, y), (b, x, y), in the
   * same plane. Such a flip within a surface keeps each boundary a manifold: (a, b) leaves the mesh, and (x, y)
   * was on no boundary. The new triangles must keep angles > 30°. */
  bool
  FlipInterfaceDiagonal(TetrahedralMesh & mesh, uint32_t flat, int first, int second)
  {
    const Tetrahedron       corners = mesh.tetrahedra[flat];
    const uint32_t          a = corners[first];
    const uint32_t          b = corners[second];
    std::array<uint32_t, 2> opposite{};
    int                     count = 0;
    for (int corner = 0; corner < 4; ++corner)
    {
      if (corner != first && corner != second)
      {
        opposite[count++] = corners[corner];
      }
    }
    const auto [x, y] = opposite;
    const Label                own = mesh.tetrahedronLabels[flat];
    const std::optional<Label> other = LabelAroundEdgeBesides(mesh, a, b, flat);
    if (!other || *other == own || LabelAroundEdgeBesides(mesh, x, y, flat) != std::optional<Label>(own) ||
        !HasPlanarAnglesAbove30Degrees(mesh.points[a], mesh.points[x], mesh.points[y]) ||
        !HasPlanarAnglesAbove30Degrees(mesh.points[b], mesh.points[x], mesh.points[y]) ||
        !RemoveEdge(mesh, a, b, *other, flat))
    {
      return false;
    }
    // The interface triangles, each oriented out of the smaller label's tetrahedron as the extraction does.
    if (m_InterfaceTriangles.empty())
    {
      for (std::size_t index = 0; index < mesh.boundaryTriangles.size(); ++index)
      {
        m_InterfaceTriangles.emplace(Sorted(mesh.boundaryTriangles[index]),
                                     std::make_pair(mesh.boundaryTriangles[index], mesh.boundaryTriangleLabels[index]));
      }
    }
    m_InterfaceTriangles.erase(Sorted({ a, b, x }));
    m_InterfaceTriangles.erase(Sorted({ a, b, y }));
    const Label smaller = std::min(own, *other);
    const Label larger = std::max(own, *other);
    for (const uint32_t apex : { a, b })
    {
      const Triangle triangle{ apex, x, y };
      const uint32_t inside = FourthVertexOfTetrahedronWith(mesh, triangle, smaller);
      m_InterfaceTriangles[Sorted(triangle)] = { OrientedAwayFrom(mesh, triangle, inside),
                                                 std::array<Label, 2>{ smaller, larger } };
    }
    return true;
  }

  /** The boundary and interface triangles after the flips, in the extraction's order; once, after every flip:
   * each flip changes two of them, and there may be hundreds of thousands. */
  void
  WriteFlippedInterfaceTriangles(TetrahedralMesh & mesh) const
  {
    if (m_InterfaceTriangles.empty())
    {
      return;
    }
    std::vector<std::pair<Triangle, std::array<Label, 2>>> triangles;
    for (const auto & [key, triangle] : m_InterfaceTriangles)
    {
      triangles.push_back(triangle);
    }
    std::sort(triangles.begin(), triangles.end());
    mesh.boundaryTriangles.clear();
    mesh.boundaryTriangleLabels.clear();
    for (const auto & [triangle, labels] : triangles)
    {
      mesh.boundaryTriangles.push_back(triangle);
      mesh.boundaryTriangleLabels.push_back(labels);
    }
  }

  /** The tetrahedra of the mesh (not removed) that have (a, b) as an edge. */
  std::vector<uint32_t>
  TetrahedraAroundEdge(const TetrahedralMesh & mesh, uint32_t a, uint32_t b) const
  {
    std::vector<uint32_t> ring;
    for (const uint32_t t : m_Incident[a])
    {
      const Tetrahedron & tetrahedron = mesh.tetrahedra[t];
      if (!m_Removed[t] && std::find(tetrahedron.begin(), tetrahedron.end(), b) != tetrahedron.end())
      {
        ring.push_back(t);
      }
    }
    return ring;
  }

  /** The label of every tetrahedron around the edge (a, b) but `skipped`, if they share one. */
  std::optional<Label>
  LabelAroundEdgeBesides(const TetrahedralMesh & mesh, uint32_t a, uint32_t b, uint32_t skipped) const
  {
    std::optional<Label> label;
    for (const uint32_t t : TetrahedraAroundEdge(mesh, a, b))
    {
      if (t == skipped)
      {
        continue;
      }
      if (label && *label != mesh.tetrahedronLabels[t])
      {
        return std::nullopt;
      }
      label = mesh.tetrahedronLabels[t];
    }
    return label;
  }

  static Triangle
  Sorted(Triangle triangle)
  {
    std::sort(triangle.begin(), triangle.end());
    return triangle;
  }

  /** The vertex opposite `triangle` in the (live) tetrahedron of `label` that has it as a facet. */
  uint32_t
  FourthVertexOfTetrahedronWith(const TetrahedralMesh & mesh, const Triangle & triangle, Label label) const
  {
    for (const uint32_t t : m_Incident[triangle[0]])
    {
      const Tetrahedron & tetrahedron = mesh.tetrahedra[t];
      if (m_Removed[t] || mesh.tetrahedronLabels[t] != label)
      {
        continue;
      }
      std::optional<uint32_t> fourth;
      int                     shared = 0;
      for (const uint32_t vertex : tetrahedron)
      {
        if (std::find(triangle.begin(), triangle.end(), vertex) != triangle.end())
        {
          ++shared;
        }
        else
        {
          fourth = vertex;
        }
      }
      if (shared == 3 && fourth)
      {
        return *fourth;
      }
    }
    throw std::logic_error("FlatTetrahedronRemoval: an interface triangle has no tetrahedron on one side");
  }

  /** The triangle with its normal (right hand) pointing away from `inside`, its smallest index first, as the
   * extraction writes them. */
  static Triangle
  OrientedAwayFrom(const TetrahedralMesh & mesh, Triangle triangle, uint32_t inside)
  {
    if (SignedVolume(
          { mesh.points[triangle[0]], mesh.points[triangle[1]], mesh.points[triangle[2]], mesh.points[inside] }) > 0.0)
    {
      std::swap(triangle[1], triangle[2]);
    }
    std::rotate(triangle.begin(), std::min_element(triangle.begin(), triangle.end()), triangle.end());
    return triangle;
  }

  /** Removes the edge (a, b) when its ring is inside `label` (the flat tetrahedron `flat` aside) and a
   * triangulation of its link polygon gives tetrahedra of `label` that keep the guarantees; among those, the one
   * whose smallest dihedral angle is largest. Where the topology relabelling gave a tetrahedron of the ring its label,
   * the ring's label is not the oracle's there: the new tetrahedra are listed as relabelled, and their circumcentres'
   * labels are not asked (the randomized SaltAndPepper 2125029 kept a flat tetrahedron whose every ring of one label
   * held relabelled tetrahedra). No boundary or interface triangle changes either way. */
  bool
  RemoveEdge(TetrahedralMesh & mesh, uint32_t a, uint32_t b, Label label, uint32_t flat)
  {
    const std::vector<uint32_t> ring = TetrahedraAroundEdge(mesh, a, b);
    bool                        ringRelabelled = false;
    for (const uint32_t t : ring)
    {
      if (t != flat && mesh.tetrahedronLabels[t] != label)
      {
        return false;
      }
      ringRelabelled = ringRelabelled || m_Relabelled[t];
    }
    if (ring.size() < 3 || ring.size() > LargestRing)
    {
      return false;
    }
    const std::optional<std::vector<uint32_t>> polygon = LinkPolygon(mesh, ring, a, b);
    if (!polygon)
    {
      return false;
    }
    std::vector<Tetrahedron> best;
    double                   bestCosine = 2.0;
    ForEachTriangulation(*polygon, [&](const std::vector<Triangle> & triangles) {
      if (!FillsTheRing(mesh, a, b, triangles))
      {
        return;
      }
      std::vector<Tetrahedron> created;
      double                   largestCosine = -1.0;
      for (const Triangle & triangle : triangles)
      {
        for (const uint32_t apex : { a, b })
        {
          std::optional<Tetrahedron> tetrahedron = Oriented(mesh, apex, triangle);
          if (!tetrahedron ||
              !KeepsTheGuarantees(mesh, *tetrahedron, ringRelabelled ? std::nullopt : std::optional(label)))
          {
            return;
          }
          largestCosine = std::max(largestCosine, CosineOfSmallestDihedralAngle(CornersOf(mesh, *tetrahedron)));
          created.push_back(*tetrahedron);
        }
      }
      if (largestCosine < bestCosine)
      {
        bestCosine = largestCosine;
        best = std::move(created);
      }
    });
    if (best.empty())
    {
      return false;
    }
    for (const uint32_t t : ring)
    {
      m_Removed[t] = 1;
    }
    for (const Tetrahedron & tetrahedron : best)
    {
      const auto t = static_cast<uint32_t>(mesh.tetrahedra.size());
      mesh.tetrahedra.push_back(tetrahedron);
      mesh.tetrahedronLabels.push_back(label);
      m_Removed.push_back(0);
      m_Relabelled.push_back(ringRelabelled ? 1 : 0);
      if (ringRelabelled)
      {
        mesh.topologyRelabelledTetrahedra.push_back(t);
      }
      for (const uint32_t vertex : tetrahedron)
      {
        m_Incident[vertex].push_back(t);
      }
    }
    return true;
  }

  /** Whether the tetrahedra joining a and b to the triangles (the link polygon's, in its cyclic order) fill the ring
   * and nothing else: a on one side of every triangle, the same for all, and b on the other (Shewchuk's condition
   * for an edge removal). Where the ring is not convex around the edge, other triangulations give tetrahedra that
   * overlap the ring's neighbours (found at δ = h/√2 on the atlas phantom: tetrahedra twice in the mesh). */
  static bool
  FillsTheRing(const TetrahedralMesh & mesh, uint32_t a, uint32_t b, const std::vector<Triangle> & triangles)
  {
    int sideOfA = 0;
    for (const Triangle & triangle : triangles)
    {
      const Vector3 & p = mesh.points[triangle[0]];
      const Vector3 & q = mesh.points[triangle[1]];
      const Vector3 & r = mesh.points[triangle[2]];
      const double    volumeWithA = SignedVolume({ mesh.points[a], p, q, r });
      const double    volumeWithB = SignedVolume({ mesh.points[b], p, q, r });
      const int       side = volumeWithA > 0.0 ? 1 : -1;
      if (!(volumeWithA * volumeWithB < 0.0) || (sideOfA != 0 && side != sideOfA))
      {
        return false;
      }
      sideOfA = side;
    }
    return true;
  }

  /** The ring's link around the edge (a, b), as a cycle of vertices: each tetrahedron of the ring gives one of its
   * edges. None when they do not make one cycle. */
  static std::optional<std::vector<uint32_t>>
  LinkPolygon(const TetrahedralMesh & mesh, const std::vector<uint32_t> & ring, uint32_t a, uint32_t b)
  {
    std::vector<std::array<uint32_t, 2>> edges;
    for (const uint32_t t : ring)
    {
      std::array<uint32_t, 2> edge{};
      int                     count = 0;
      for (const uint32_t vertex : mesh.tetrahedra[t])
      {
        if (vertex != a && vertex != b)
        {
          edge[count++] = vertex;
        }
      }
      edges.push_back(edge);
    }
    std::vector<uint32_t> polygon{ edges[0][0], edges[0][1] };
    std::vector<char>     used(edges.size(), 0);
    used[0] = 1;
    while (polygon.size() < edges.size())
    {
      bool extended = false;
      for (std::size_t index = 0; index < edges.size() && !extended; ++index)
      {
        if (used[index] || (edges[index][0] != polygon.back() && edges[index][1] != polygon.back()))
        {
          continue;
        }
        const uint32_t next = edges[index][0] == polygon.back() ? edges[index][1] : edges[index][0];
        if (std::find(polygon.begin(), polygon.end(), next) != polygon.end())
        {
          return std::nullopt;
        }
        polygon.push_back(next);
        used[index] = 1;
        extended = true;
      }
      if (!extended)
      {
        return std::nullopt;
      }
    }
    // The last edge closes the cycle.
    const auto   closing = std::find(used.begin(), used.end(), 0);
    const auto & last = edges[static_cast<std::size_t>(closing - used.begin())];
    const bool   closes = (last[0] == polygon.back() && last[1] == polygon.front()) ||
                        (last[1] == polygon.back() && last[0] == polygon.front());
    return closes ? std::optional<std::vector<uint32_t>>(polygon) : std::nullopt;
  }

  /** Calls visit(triangles) for each triangulation of the polygon (vertices in cyclic order), by the usual
   * recursion: the triangle on the edge from the first to the last vertex, with each apex in turn. */
  template <typename TVisit>
  static void
  ForEachTriangulation(const std::vector<uint32_t> & polygon, TVisit && visit)
  {
    std::vector<Triangle>                                                       triangles;
    const std::function<void(std::vector<std::pair<std::size_t, std::size_t>>)> recurse =
      [&](std::vector<std::pair<std::size_t, std::size_t>> pending) {
        if (pending.empty())
        {
          visit(triangles);
          return;
        }
        const auto [first, last] = pending.back();
        pending.pop_back();
        if (last - first < 2)
        {
          recurse(pending);
          return;
        }
        for (std::size_t apex = first + 1; apex < last; ++apex)
        {
          triangles.push_back({ polygon[first], polygon[apex], polygon[last] });
          std::vector<std::pair<std::size_t, std::size_t>> next = pending;
          next.emplace_back(first, apex);
          next.emplace_back(apex, last);
          recurse(next);
          triangles.pop_back();
        }
      };
    recurse({ { 0, polygon.size() - 1 } });
  }

  /** The tetrahedron (apex, triangle) in the extraction's form: indices increasing, the last two swapped when
   * that is needed for a positive volume. None when it is flat to rounding. */
  static std::optional<Tetrahedron>
  Oriented(const TetrahedralMesh & mesh, uint32_t apex, const Triangle & triangle)
  {
    Tetrahedron tetrahedron{ apex, triangle[0], triangle[1], triangle[2] };
    std::sort(tetrahedron.begin(), tetrahedron.end());
    const std::array<Vector3, 4> corners = CornersOf(mesh, tetrahedron);
    if (IsFlatToRounding(corners))
    {
      return std::nullopt;
    }
    if (SignedVolume(corners) < 0.0)
    {
      std::swap(tetrahedron[2], tetrahedron[3]);
    }
    return tetrahedron;
  }

  /** Radius-edge ratio < ρ and, when `labelAtCircumcenter` is given, that label at the circumcentre. */
  bool
  KeepsTheGuarantees(const TetrahedralMesh & mesh, const Tetrahedron & tetrahedron,
                     std::optional<Label> labelAtCircumcenter) const
  {
    const std::array<Vector3, 4> corners = CornersOf(mesh, tetrahedron);
    return RadiusEdgeRatio(corners) < m_RadiusEdgeBound &&
           (!labelAtCircumcenter || m_Oracle.LabelAt(TetrahedronCircumcenter(corners)) == *labelAtCircumcenter);
  }

  /** Drops the removed tetrahedra, keeping the others' order, and renumbers the relabelling list (without the
   * removed ones). */
  void
  Compact(TetrahedralMesh & mesh) const
  {
    std::vector<uint32_t> newIndex(mesh.tetrahedra.size(), 0);
    uint32_t              kept = 0;
    for (uint32_t t = 0; t < mesh.tetrahedra.size(); ++t)
    {
      newIndex[t] = kept;
      if (!m_Removed[t])
      {
        mesh.tetrahedra[kept] = mesh.tetrahedra[t];
        mesh.tetrahedronLabels[kept] = mesh.tetrahedronLabels[t];
        ++kept;
      }
    }
    mesh.tetrahedra.resize(kept);
    mesh.tetrahedronLabels.resize(kept);
    std::vector<uint32_t> relabelled;
    for (const uint32_t t : mesh.topologyRelabelledTetrahedra)
    {
      if (!m_Removed[t])
      {
        relabelled.push_back(newIndex[t]);
      }
    }
    mesh.topologyRelabelledTetrahedra = std::move(relabelled);
  }

  const LabelOracle &                m_Oracle;
  double                             m_RadiusEdgeBound;
  std::vector<std::vector<uint32_t>> m_Incident;
  std::vector<char>                  m_Removed;
  std::vector<char>                  m_Relabelled;
  /** The boundary and interface triangles by their sorted indices, each as written and with its labels; filled at
   * the first flip of an interface (FlipInterfaceDiagonal), empty when there is none. */
  std::map<Triangle, std::pair<Triangle, std::array<Label, 2>>> m_InterfaceTriangles;
};

} // namespace detail
} // namespace delaunay_refinement

#endif
