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

// The topology of triangle surfaces (DelaunayRefinementMeshQuality.h): non-manifold edges and vertices,
// edge-connected components and their genus, and the smallest planar angle. The refinement's manifold check
// runs these too, so they work on sorted vectors rather than hash maps.

#include "DelaunayRefinementMeasureHelpers.h"
#include "DelaunayRefinementMeshQuality.h"

#include <algorithm>
#include <functional>
#include <numeric>
#include <unordered_map>
#include <utility>

namespace delaunay_refinement
{
namespace
{

using detail::AngleBetween;
using detail::CheckVertexIndices;
using detail::Triangle;


/** An undirected edge: its two vertex indices, smaller first. */
using Edge = std::pair<uint32_t, uint32_t>;

Edge
MakeEdge(uint32_t a, uint32_t b)
{
  return a < b ? Edge{ a, b } : Edge{ b, a };
}

struct EdgeHash
{
  std::size_t
  operator()(const Edge & edge) const
  {
    return std::hash<uint64_t>{}((static_cast<uint64_t>(edge.first) << 32) | edge.second);
  }
};

/** Each distinct edge of the triangles with the number of triangles that have it, sorted by edge: sorting a
 * flat vector beats hashing here (the manifold checks run inside the refinement). */
using EdgeTriangleCounts = std::vector<std::pair<Edge, std::size_t>>;

EdgeTriangleCounts
CountTrianglesPerEdge(const std::vector<Triangle> & triangles)
{
  std::vector<Edge> edges;
  edges.reserve(3 * triangles.size());
  for (const Triangle & triangle : triangles)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      edges.push_back(MakeEdge(triangle[corner], triangle[(corner + 1) % 3]));
    }
  }
  std::sort(edges.begin(), edges.end());
  EdgeTriangleCounts counts;
  for (const Edge & edge : edges)
  {
    if (counts.empty() || counts.back().first != edge)
    {
      counts.emplace_back(edge, 0);
    }
    ++counts.back().second;
  }
  return counts;
}

/** Disjoint sets with path halving; enough for component labelling. */
class DisjointSets
{
public:
  explicit DisjointSets(std::size_t size)
    : m_Parent(size)
  {
    std::iota(m_Parent.begin(), m_Parent.end(), std::size_t{ 0 });
  }

  std::size_t
  Find(std::size_t element)
  {
    while (m_Parent[element] != element)
    {
      m_Parent[element] = m_Parent[m_Parent[element]];
      element = m_Parent[element];
    }
    return element;
  }

  void
  Unite(std::size_t a, std::size_t b)
  {
    m_Parent[Find(a)] = Find(b);
  }

private:
  std::vector<std::size_t> m_Parent;
};

/** Labels triangles by edge-connected component, 0..count-1 in order of first appearance. */
std::vector<std::size_t>
LabelEdgeConnectedComponents(const std::vector<Triangle> & triangles, std::size_t & numberOfComponents)
{
  DisjointSets                                    sets(triangles.size());
  std::unordered_map<Edge, std::size_t, EdgeHash> firstTriangleOfEdge;
  for (std::size_t t = 0; t < triangles.size(); ++t)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      const auto inserted =
        firstTriangleOfEdge.emplace(MakeEdge(triangles[t][corner], triangles[t][(corner + 1) % 3]), t);
      if (!inserted.second)
      {
        sets.Unite(t, inserted.first->second);
      }
    }
  }
  std::unordered_map<std::size_t, std::size_t> componentOfRoot;
  std::vector<std::size_t>                     component(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t)
  {
    component[t] = componentOfRoot.emplace(sets.Find(t), componentOfRoot.size()).first->second;
  }
  numberOfComponents = componentOfRoot.size();
  return component;
}

/** Genus (2 - χ) / 2 of one component, from that component's own vertices, edges and faces. */
int
ComponentGenus(const std::vector<Triangle> & componentTriangles)
{
  std::vector<uint32_t> vertices;
  for (const Triangle & triangle : componentTriangles)
  {
    vertices.insert(vertices.end(), triangle.begin(), triangle.end());
  }
  std::sort(vertices.begin(), vertices.end());
  const auto numberOfVertices =
    static_cast<long long>(std::unique(vertices.begin(), vertices.end()) - vertices.begin());
  const auto      numberOfEdges = static_cast<long long>(CountTrianglesPerEdge(componentTriangles).size());
  const auto      numberOfFaces = static_cast<long long>(componentTriangles.size());
  const long long eulerCharacteristic = numberOfVertices - numberOfEdges + numberOfFaces;
  return static_cast<int>((2 - eulerCharacteristic) / 2);
}

/** The link of a vertex v is the graph of the edges opposite v in its incident triangles. v is a manifold
 * vertex exactly when that graph is one cycle: every link vertex has degree 2, the graph is connected, and it
 * has at least 3 edges. A bow-tie (two cones meeting at v) gives two cycles; a boundary vertex gives a path. */
class VertexLinks
{
public:
  /** The links as contiguous runs per vertex, bucketed by vertex index (a counting sort: vertex indices are
   * dense), each run in the triangles' order. */
  explicit VertexLinks(const std::vector<Triangle> & triangles)
  {
    uint32_t numberOfSlots = 0;
    for (const Triangle & triangle : triangles)
    {
      numberOfSlots = std::max({ numberOfSlots, triangle[0] + 1, triangle[1] + 1, triangle[2] + 1 });
    }
    m_LinkStart.assign(std::size_t{ numberOfSlots } + 1, 0);
    for (const Triangle & triangle : triangles)
    {
      for (const uint32_t vertex : triangle)
      {
        ++m_LinkStart[vertex + 1];
      }
    }
    std::partial_sum(m_LinkStart.begin(), m_LinkStart.end(), m_LinkStart.begin());
    std::vector<std::size_t> next(m_LinkStart.begin(), m_LinkStart.end() - 1);
    m_LinkEdges.resize(3 * triangles.size());
    for (const Triangle & triangle : triangles)
    {
      for (int corner = 0; corner < 3; ++corner)
      {
        m_LinkEdges[next[triangle[corner]]++] = MakeEdge(triangle[(corner + 1) % 3], triangle[(corner + 2) % 3]);
      }
    }
  }

  std::size_t
  NumberOfVertices() const
  {
    std::size_t vertices = 0;
    ForEachLink([&vertices](uint32_t, const Edge *, const Edge *) { ++vertices; });
    return vertices;
  }

  /** In increasing order. */
  std::vector<uint32_t>
  NonManifoldVertices() const
  {
    std::vector<uint32_t> vertices;
    std::vector<Edge>     adjacency;
    ForEachLink([&](uint32_t center, const Edge * first, const Edge * last) {
      if (!IsSingleCycle(center, first, last, adjacency))
      {
        vertices.push_back(center);
      }
    });
    return vertices;
  }

private:
  template <typename TVisit>
  void
  ForEachLink(TVisit && visit) const
  {
    for (std::size_t vertex = 0; vertex + 1 < m_LinkStart.size(); ++vertex)
    {
      if (m_LinkStart[vertex] != m_LinkStart[vertex + 1])
      {
        visit(static_cast<uint32_t>(vertex),
              m_LinkEdges.data() + m_LinkStart[vertex],
              m_LinkEdges.data() + m_LinkStart[vertex + 1]);
      }
    }
  }

  /** `adjacency` is scratch space, reused from vertex to vertex. */
  static bool
  IsSingleCycle(uint32_t center, const Edge * first, const Edge * last, std::vector<Edge> & adjacency)
  {
    if (last - first < 3)
    {
      return false;
    }
    // Each link vertex with its two neighbours, as sorted (vertex, neighbour) pairs.
    adjacency.clear();
    for (const Edge * link = first; link != last; ++link)
    {
      const Edge & edge = *link;
      // A degenerate triangle (a repeated vertex) has no proper link edge.
      if (edge.first == edge.second || edge.first == center || edge.second == center)
      {
        return false;
      }
      adjacency.emplace_back(edge.first, edge.second);
      adjacency.emplace_back(edge.second, edge.first);
    }
    std::sort(adjacency.begin(), adjacency.end());
    for (std::size_t i = 0; i < adjacency.size(); i += 2)
    {
      const bool degreeTwo = adjacency[i].first == adjacency[i + 1].first &&
                             (i + 2 == adjacency.size() || adjacency[i + 2].first != adjacency[i].first);
      if (!degreeTwo)
      {
        return false;
      }
    }
    // All degrees are 2, so the graph is a union of cycles; it is one cycle when a walk covers every vertex.
    const auto neighboursOf = [&adjacency](uint32_t vertex) {
      return std::lower_bound(adjacency.begin(), adjacency.end(), Edge{ vertex, 0 });
    };
    const std::size_t numberOfVertices = adjacency.size() / 2;
    const uint32_t    start = adjacency.front().first;
    uint32_t          previous = start;
    uint32_t          current = adjacency.front().second;
    std::size_t       visited = 1;
    while (current != start && visited <= numberOfVertices)
    {
      const auto     next = neighboursOf(current);
      const uint32_t following = next->second != previous ? next->second : (next + 1)->second;
      previous = current;
      current = following;
      ++visited;
    }
    return visited == numberOfVertices;
  }

  /** The link edges of vertex v are m_LinkEdges[m_LinkStart[v], m_LinkStart[v + 1]). */
  std::vector<std::size_t> m_LinkStart;
  std::vector<Edge>        m_LinkEdges;
};

double
MinimumPlanarAngle(const std::vector<Vector3> & points, const std::vector<Triangle> & triangles)
{
  double smallest = 180.0;
  for (const Triangle & triangle : triangles)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      const Vector3 & apex = points[triangle[corner]];
      const Vector3   toNext = points[triangle[(corner + 1) % 3]] - apex;
      const Vector3   toPrevious = points[triangle[(corner + 2) % 3]] - apex;
      smallest = std::min(smallest, AngleBetween(toNext, toPrevious));
    }
  }
  return smallest;
}

} // namespace

SurfaceTopology
ComputeSurfaceTopology(const std::vector<Vector3> & points, const std::vector<std::array<uint32_t, 3>> & triangles)
{
  CheckVertexIndices("ComputeSurfaceTopology", "triangle", points, triangles);
  SurfaceTopology topology;
  topology.numberOfTriangles = triangles.size();

  const EdgeTriangleCounts trianglesPerEdge = CountTrianglesPerEdge(triangles);
  topology.numberOfEdges = trianglesPerEdge.size();
  for (const auto & entry : trianglesPerEdge)
  {
    if (entry.second != 2)
    {
      ++topology.nonManifoldEdges;
    }
  }

  const VertexLinks links(triangles);
  topology.numberOfVertices = links.NumberOfVertices();
  topology.nonManifoldVertices = links.NonManifoldVertices().size();

  std::size_t                        numberOfComponents = 0;
  const std::vector<std::size_t>     componentOfTriangle = LabelEdgeConnectedComponents(triangles, numberOfComponents);
  std::vector<std::vector<Triangle>> trianglesOfComponent(numberOfComponents);
  for (std::size_t t = 0; t < triangles.size(); ++t)
  {
    trianglesOfComponent[componentOfTriangle[t]].push_back(triangles[t]);
  }
  topology.numberOfComponents = static_cast<int>(numberOfComponents);
  for (const auto & componentTriangles : trianglesOfComponent)
  {
    topology.componentGenera.push_back(ComponentGenus(componentTriangles));
    topology.totalGenus += topology.componentGenera.back();
  }

  topology.minimumPlanarAngle = MinimumPlanarAngle(points, triangles);
  return topology;
}

std::vector<uint32_t>
FindNonManifoldVertices(const std::vector<std::array<uint32_t, 3>> & triangles)
{
  // An edge va in k != 2 triangles gives a degree k in v's link (and v degree k in a's), so both of its endpoints
  // fail the single-cycle test: the edges need no count of their own.
  return VertexLinks(triangles).NonManifoldVertices();
}

SurfaceTopology
ComputeBoundaryTopology(const TetrahedralMesh & mesh)
{
  return ComputeSurfaceTopology(mesh.points, mesh.boundaryTriangles);
}

std::vector<std::array<uint32_t, 3>>
LabelBoundaryTriangles(const TetrahedralMesh & mesh, Label label)
{
  std::vector<Triangle> triangles;
  for (std::size_t i = 0; i < mesh.boundaryTriangles.size() && i < mesh.boundaryTriangleLabels.size(); ++i)
  {
    if (mesh.boundaryTriangleLabels[i][0] == label || mesh.boundaryTriangleLabels[i][1] == label)
    {
      triangles.push_back(mesh.boundaryTriangles[i]);
    }
  }
  return triangles;
}

std::map<Label, std::vector<std::array<uint32_t, 3>>>
BoundaryTrianglesByLabel(const TetrahedralMesh & mesh)
{
  std::map<Label, std::vector<Triangle>> triangles;
  for (std::size_t i = 0; i < mesh.boundaryTriangles.size() && i < mesh.boundaryTriangleLabels.size(); ++i)
  {
    const std::array<Label, 2> & sides = mesh.boundaryTriangleLabels[i];
    triangles[sides[0]].push_back(mesh.boundaryTriangles[i]);
    if (sides[1] != sides[0])
    {
      triangles[sides[1]].push_back(mesh.boundaryTriangles[i]);
    }
  }
  return triangles;
}

SurfaceTopology
ComputeLabelBoundaryTopology(const TetrahedralMesh & mesh, Label label)
{
  return ComputeSurfaceTopology(mesh.points, LabelBoundaryTriangles(mesh, label));
}

} // namespace delaunay_refinement
