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
#ifndef DelaunayRefinementExtraction_h
#define DelaunayRefinementExtraction_h

// The output (docs/algorithm.md, "Output"): the tetrahedra whose circumcentre is inside the object, each with the
// label there, and the facets between different labels, numbered and ordered canonically so that the same input
// gives the same mesh whatever the memory addresses were. The walk over interface facets is also what the
// manifold check looks at.

#include "DelaunayRefinementMeshState.h"
#include "DelaunayRefinementSizing.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>
#include <tuple>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{

/** Reads the output mesh off the refined triangulation. */
class MeshExtraction
{
public:
  explicit MeshExtraction(const MeshState & state)
    : m_State(state)
  {}

  /** The tetrahedra whose circumcentre is inside the object, in a canonical order, with the sampling distance of
   * `sizing` at each point. */
  TetrahedralMesh
  ExtractMesh(const LocalSampling & sizing) const
  {
    const std::vector<CellHandle> objectCells = ObjectCells();
    TetrahedralMesh               mesh;
    NumberOutputVertices(objectCells, mesh);
    for (const Vector3 & point : mesh.points)
    {
      mesh.pointSamplingDistances.push_back(sizing.SamplingDistanceOf(point));
    }
    AddTetrahedra(objectCells, mesh);
    AddBoundaryTriangles(objectCells, mesh);
    return mesh;
  }

  /** The cells that the output keeps: those whose circumcentre is inside the object. */
  std::vector<CellHandle>
  ObjectCells() const
  {
    std::vector<CellHandle> objectCells;
    for (auto cell = m_State.GetTriangulation().finite_cells_begin();
         cell != m_State.GetTriangulation().finite_cells_end();
         ++cell)
    {
      if (cell->cache.label != BackgroundLabel)
      {
        objectCells.push_back(cell);
      }
    }
    return objectCells;
  }

  /** Calls visit(cell, facet, otherLabel) for each interface facet once: from the tissue side when the other
   * side is background, else from the smaller label. */
  template <typename TVisit>
  void
  ForEachInterfaceFacet(const std::vector<CellHandle> & objectCells, TVisit && visit) const
  {
    for (CellHandle cell : objectCells)
    {
      const Label label = cell->cache.label;
      for (int facet = 0; facet < 4; ++facet)
      {
        const Label otherLabel = m_State.LabelBeyondFacet(cell, facet);
        if (otherLabel != label && (otherLabel == BackgroundLabel || label < otherLabel))
        {
          visit(cell, facet, otherLabel);
        }
      }
    }
  }

private:
  /** The output's vertices: those of the object's tetrahedra, numbered in insertion order, which (unlike
   * the triangulation's container order) does not depend on memory addresses. */
  void
  NumberOutputVertices(const std::vector<CellHandle> & objectCells, TetrahedralMesh & mesh) const
  {
    // Ids are insertion counters: a table indexed by id orders the vertices without a sort.
    std::vector<VertexHandle> verticesById(m_State.NumberOfVertexIds(), VertexHandle());
    for (CellHandle cell : objectCells)
    {
      for (int corner = 0; corner < 4; ++corner)
      {
        verticesById[cell->vertex(corner)->info().id] = cell->vertex(corner);
      }
    }
    for (const VertexHandle & vertex : verticesById)
    {
      if (vertex != VertexHandle())
      {
        vertex->info().outputIndex = static_cast<uint32_t>(mesh.points.size());
        mesh.points.push_back(m_State.PointOf(vertex));
        mesh.pointKinds.push_back(vertex->info().kind);
      }
    }
  }

  /** Sorted indices, with the last two swapped when sorting was an odd permutation: a canonical form that
   * keeps the orientation. */
  static std::array<uint32_t, 4>
  CanonicalTetrahedron(std::array<uint32_t, 4> indices)
  {
    bool odd = false;
    for (int i = 0; i < 4; ++i)
    {
      for (int j = 0; j + 1 < 4 - i; ++j)
      {
        if (indices[j] > indices[j + 1])
        {
          std::swap(indices[j], indices[j + 1]);
          odd = !odd;
        }
      }
    }
    if (odd)
    {
      std::swap(indices[2], indices[3]);
    }
    return indices;
  }

  /** The facet's vertices ordered so that its normal points away from the cell, smallest index first. CGAL's
   * cells are positively oriented (decided exactly) and vertex_triple_index() lists a facet with its normal
   * pointing into the cell, so the reverse order points out. A floating-point side test would be a coin toss on
   * the tetrahedra flat to rounding that voxel data produce. */
  std::array<uint32_t, 3>
  OutwardFacet(CellHandle cell, int facet) const
  {
    std::array<uint32_t, 3> triangle{ cell->vertex(Triangulation::vertex_triple_index(facet, 0))->info().outputIndex,
                                      cell->vertex(Triangulation::vertex_triple_index(facet, 2))->info().outputIndex,
                                      cell->vertex(Triangulation::vertex_triple_index(facet, 1))->info().outputIndex };
    std::rotate(triangle.begin(), std::min_element(triangle.begin(), triangle.end()), triangle.end());
    return triangle;
  }

  void
  AddTetrahedra(const std::vector<CellHandle> & objectCells, TetrahedralMesh & mesh) const
  {
    std::vector<std::tuple<std::array<uint32_t, 4>, Label, bool>> tetrahedra;
    for (CellHandle cell : objectCells)
    {
      tetrahedra.emplace_back(CanonicalTetrahedron({ cell->vertex(0)->info().outputIndex,
                                                     cell->vertex(1)->info().outputIndex,
                                                     cell->vertex(2)->info().outputIndex,
                                                     cell->vertex(3)->info().outputIndex }),
                              cell->cache.label,
                              cell->cache.relabelledForTopology);
    }
    std::sort(tetrahedra.begin(), tetrahedra.end());
    for (const auto & [indices, label, relabelled] : tetrahedra)
    {
      if (relabelled)
      {
        mesh.topologyRelabelledTetrahedra.push_back(static_cast<uint32_t>(mesh.tetrahedra.size()));
      }
      mesh.tetrahedra.push_back(indices);
      mesh.tetrahedronLabels.push_back(label);
    }
  }

  void
  AddBoundaryTriangles(const std::vector<CellHandle> & objectCells, TetrahedralMesh & mesh) const
  {
    std::vector<std::pair<std::array<uint32_t, 3>, std::array<Label, 2>>> triangles;
    ForEachInterfaceFacet(objectCells, [&](CellHandle cell, int facet, Label otherLabel) {
      triangles.emplace_back(OutwardFacet(cell, facet), std::array<Label, 2>{ cell->cache.label, otherLabel });
    });
    std::sort(triangles.begin(), triangles.end());
    for (const auto & [indices, labels] : triangles)
    {
      mesh.boundaryTriangles.push_back(indices);
      mesh.boundaryTriangleLabels.push_back(labels);
    }
  }

  const MeshState & m_State;
};

} // namespace detail
} // namespace delaunay_refinement

#endif
