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

// Mesh measures computed from the mesh alone, so that tests can check the refinement's guarantees without
// trusting anything the refinement reports about itself. Floating point where it is trustworthy; CGAL's exact
// predicates where it is not (orientations, and the circumradii of nearly flat tetrahedra).

#include "DelaunayRefinementMeshQuality.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

namespace delaunay_refinement
{
namespace
{

/** Exact arithmetic for the measures that floating point cannot take on nearly flat tetrahedra. */
using ExactPoint = CGAL::Exact_predicates_exact_constructions_kernel::Point_3;

/** Relative disagreement of the squared distances from a floating-point circumcentre to the corners beyond which
 * it is recomputed exactly (rounding alone stays near 1e-16). */
constexpr double EquidistanceTolerance = 1e-10;

constexpr double Infinity = std::numeric_limits<double>::infinity();
constexpr double DegreesPerRadian = 180.0 / 3.14159265358979323846;

/** The six edges of a tetrahedron as pairs of local vertex positions. */
constexpr std::array<std::array<int, 2>, 6> TetrahedronEdges{
  { { { 0, 1 } }, { { 0, 2 } }, { { 0, 3 } }, { { 1, 2 } }, { { 1, 3 } }, { { 2, 3 } } }
};

/** Angle between two vectors in degrees. atan2 stays accurate near 0° and 180°, where acos of a normalised dot
 * product loses half its digits. A zero vector gives 0°. */
double
AngleBetween(const Vector3 & u, const Vector3 & v)
{
  return std::atan2(Norm(Cross(u, v)), Dot(u, v)) * DegreesPerRadian;
}

using Tetrahedron = std::array<uint32_t, 4>;
using Triangle = std::array<uint32_t, 3>;
using TetrahedronCorners = std::array<Vector3, 4>;

bool
IsMalformed(const Tetrahedron & tetrahedron, std::size_t numberOfPoints)
{
  for (std::size_t i = 0; i < 4; ++i)
  {
    if (tetrahedron[i] >= numberOfPoints)
    {
      return true;
    }
    for (std::size_t j = i + 1; j < 4; ++j)
    {
      if (tetrahedron[i] == tetrahedron[j])
      {
        return true;
      }
    }
  }
  return false;
}

TetrahedronCorners
CornersOf(const std::vector<Vector3> & points, const Tetrahedron & tetrahedron)
{
  return { { points[tetrahedron[0]], points[tetrahedron[1]], points[tetrahedron[2]], points[tetrahedron[3]] } };
}

double
SignedVolume(const TetrahedronCorners & p)
{
  return Dot(p[1] - p[0], Cross(p[2] - p[0], p[3] - p[0])) / 6.0;
}

double
ShortestEdge(const TetrahedronCorners & p)
{
  double shortest = Infinity;
  for (const auto & edge : TetrahedronEdges)
  {
    shortest = std::min(shortest, Distance(p[edge[0]], p[edge[1]]));
  }
  return shortest;
}

ExactPoint
ToExact(const Vector3 & point)
{
  return { point[0], point[1], point[2] };
}

/** The sign of the orientation of the tetrahedron, exactly: the mesher's (CGAL's) own notion of orientation.
 * The floating-point volume of a tetrahedron flat to rounding can be 0 or negative when it is not. */
CGAL::Orientation
ExactOrientation(const TetrahedronCorners & p)
{
  return CGAL::orientation(ToExact(p[0]), ToExact(p[1]), ToExact(p[2]), ToExact(p[3]));
}

/** Circumradius from the closed form of the circumcentre relative to p0, or exactly when that closed form loses
 * its digits (its centre is not equidistant from the corners): for the nearly flat tetrahedra that
 * voxel-derived, co-spherical points produce, the floating-point radius is noise. +infinity for four exactly
 * coplanar points, whose circumsphere does not exist (or is not unique). */
double
Circumradius(const TetrahedronCorners & p)
{
  const Vector3 a = p[1] - p[0];
  const Vector3 b = p[2] - p[0];
  const Vector3 c = p[3] - p[0];
  const double  denominator = 2.0 * Dot(a, Cross(b, c));
  if (denominator != 0.0)
  {
    const Vector3 offset = (1.0 / denominator) *
                           (SquaredNorm(a) * Cross(b, c) + SquaredNorm(b) * Cross(c, a) + SquaredNorm(c) * Cross(a, b));
    const double squaredRadius = SquaredNorm(offset);
    bool         equidistant = true;
    for (int corner = 1; corner < 4; ++corner)
    {
      equidistant = equidistant && std::abs(SquaredNorm(p[0] + offset - p[corner]) - squaredRadius) <=
                                     EquidistanceTolerance * squaredRadius;
    }
    if (equidistant)
    {
      return std::sqrt(squaredRadius);
    }
  }
  if (ExactOrientation(p) == CGAL::COPLANAR)
  {
    return Infinity;
  }
  return std::sqrt(CGAL::to_double(CGAL::squared_radius(ToExact(p[0]), ToExact(p[1]), ToExact(p[2]), ToExact(p[3]))));
}

/** Interior dihedral angle at edge (i, j): the angle between the two other vertices seen along the edge, i.e.
 * after projecting them onto the plane orthogonal to it. Independent of the orientation of the tetrahedron. */
double
DihedralAngleAtEdge(const TetrahedronCorners & p, int i, int j)
{
  int others[2];
  int count = 0;
  for (int k = 0; k < 4; ++k)
  {
    if (k != i && k != j)
    {
      others[count++] = k;
    }
  }
  const Vector3 edge = p[j] - p[i];
  const double  edgeSquaredLength = SquaredNorm(edge);
  const auto    projectOffEdge = [&](const Vector3 & v) {
    return edgeSquaredLength > 0.0 ? v - (Dot(v, edge) / edgeSquaredLength) * edge : v;
  };
  return AngleBetween(projectOffEdge(p[others[0]] - p[i]), projectOffEdge(p[others[1]] - p[i]));
}

std::pair<double, double>
DihedralAngleRange(const TetrahedronCorners & p)
{
  double smallest = 180.0;
  double largest = 0.0;
  for (const auto & edge : TetrahedronEdges)
  {
    const double angle = DihedralAngleAtEdge(p, edge[0], edge[1]);
    smallest = std::min(smallest, angle);
    largest = std::max(largest, angle);
  }
  return { smallest, largest };
}

struct ArrayHash
{
  template <std::size_t N>
  std::size_t
  operator()(const std::array<uint32_t, N> & values) const
  {
    std::size_t hash = 0;
    for (const uint32_t value : values)
    {
      hash = hash * 1000003u ^ std::hash<uint32_t>{}(value);
    }
    return hash;
  }
};

/** Counts every tetrahedron whose vertex set also belongs to another tetrahedron (both members of a duplicated
 * pair count). Malformed tetrahedra are left out: they are counted separately. */
std::size_t
CountDuplicateTetrahedra(const std::vector<Tetrahedron> & tetrahedra, std::size_t numberOfPoints)
{
  std::unordered_map<Tetrahedron, std::size_t, ArrayHash> occurrences;
  for (const Tetrahedron & tetrahedron : tetrahedra)
  {
    if (!IsMalformed(tetrahedron, numberOfPoints))
    {
      Tetrahedron sorted = tetrahedron;
      std::sort(sorted.begin(), sorted.end());
      ++occurrences[sorted];
    }
  }
  std::size_t duplicates = 0;
  for (const auto & entry : occurrences)
  {
    if (entry.second > 1)
    {
      duplicates += entry.second;
    }
  }
  return duplicates;
}

/** Points referenced by no tetrahedron; an in-range index of a malformed tetrahedron still counts as a use. */
std::size_t
CountUnusedPoints(const TetrahedralMesh & mesh)
{
  std::vector<bool> used(mesh.points.size(), false);
  for (const Tetrahedron & tetrahedron : mesh.tetrahedra)
  {
    for (const uint32_t index : tetrahedron)
    {
      if (index < used.size())
      {
        used[index] = true;
      }
    }
  }
  return static_cast<std::size_t>(std::count(used.begin(), used.end(), false));
}

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

/** Throws std::invalid_argument, naming `caller` and the kind of cell, for a vertex index out of range: the
 * measures index the points without checking. */
template <std::size_t NumberOfCorners>
void
CheckVertexIndices(const char * caller, const char * cellName, const std::vector<Vector3> & points,
                   const std::vector<std::array<uint32_t, NumberOfCorners>> & cells)
{
  for (const auto & cell : cells)
  {
    for (const uint32_t index : cell)
    {
      if (index >= points.size())
      {
        throw std::invalid_argument(std::string(caller) + ": " + cellName + " vertex index " + std::to_string(index) +
                                    " is out of range (number of points: " + std::to_string(points.size()) + ")");
      }
    }
  }
}

/** Throws std::invalid_argument, naming `caller`, when `labels` does not label every cell exactly once. */
void
CheckLabelCount(const char * caller, const char * labelsName, std::size_t numberOfLabels, std::size_t numberOfCells)
{
  if (numberOfLabels != numberOfCells)
  {
    throw std::invalid_argument(std::string(caller) + ": " + labelsName + " has " + std::to_string(numberOfLabels) +
                                " entries for " + std::to_string(numberOfCells) + " cells");
  }
}

Triangle
SortedVertices(Triangle triangle)
{
  std::sort(triangle.begin(), triangle.end());
  return triangle;
}

/** A tetrahedron seen from one of its facets: the facet's sorted vertices, the tetrahedron, and its vertex off
 * the facet. */
struct FacetSide
{
  Triangle    facet;
  std::size_t tetrahedron;
  uint32_t    apex;
};

/** Every facet of every tetrahedron, sorted by facet so that the sides of a facet are adjacent: one sorted array
 * instead of a node per facet, for the millions of facets of a large mesh. */
std::vector<FacetSide>
SortedFacetSides(const std::vector<Tetrahedron> & tetrahedra)
{
  std::vector<FacetSide> sides;
  sides.reserve(4 * tetrahedra.size());
  for (std::size_t t = 0; t < tetrahedra.size(); ++t)
  {
    const Tetrahedron & v = tetrahedra[t];
    for (int apex = 0; apex < 4; ++apex)
    {
      sides.push_back({ SortedVertices({ { v[(apex + 1) % 4], v[(apex + 2) % 4], v[(apex + 3) % 4] } }), t, v[apex] });
    }
  }
  std::sort(sides.begin(), sides.end(), [](const FacetSide & a, const FacetSide & b) { return a.facet < b.facet; });
  return sides;
}

/** A facet between different labels: what its boundary triangle must carry. */
struct ExpectedBoundaryTriangle
{
  Triangle             facet;
  std::array<Label, 2> labels;
  /** The side whose tetrahedron carries labels[0]: the triangle's normal must point away from it. */
  const FacetSide * firstLabelSide;
  bool              seen;
};

/** The boundary triangle a facet with sides labelled `one` and `other` (the background for a facet on the hull)
 * must carry, as TetrahedralMesh promises: the tissue first against the background, else the smaller label
 * first. Both the tissue/background and the tissue/tissue order are decided by the labels alone, not by which
 * side is met first. */
std::array<Label, 2>
BoundaryLabelsBetween(Label one, Label other)
{
  if (other == BackgroundLabel || one == BackgroundLabel)
  {
    return { { one == BackgroundLabel ? other : one, BackgroundLabel } };
  }
  return { { std::min(one, other), std::max(one, other) } };
}

/** "boundary triangle i ( (x, y, z) ... ) faces into tetrahedron t (label l): kind (x, y, z) ...": enough to
 * reproduce a wrongly oriented triangle by hand. */
std::string
DescribeTriangleFacingInto(const TetrahedralMesh & mesh, std::size_t triangleIndex, std::size_t tetrahedron)
{
  std::ostringstream text;
  text.precision(17);
  const auto writePoint = [&text, &mesh](uint32_t index) {
    const Vector3 & point = mesh.points[index];
    text << " (" << point[0] << ", " << point[1] << ", " << point[2] << ")";
  };
  text << "boundary triangle " << triangleIndex << " (";
  for (const uint32_t corner : mesh.boundaryTriangles[triangleIndex])
  {
    writePoint(corner);
  }
  text << " ) faces into tetrahedron " << tetrahedron << " (label " << mesh.tetrahedronLabels[tetrahedron] << "):";
  for (const uint32_t corner : mesh.tetrahedra[tetrahedron])
  {
    // A mesh assembled by hand may come without point kinds.
    if (corner < mesh.pointKinds.size())
    {
      text << ' ' << VertexKindName(mesh.pointKinds[corner]);
    }
    writePoint(corner);
  }
  return text.str();
}

} // namespace

TetrahedronQuality
ComputeTetrahedronQuality(const TetrahedralMesh & mesh)
{
  TetrahedronQuality quality;
  quality.numberOfTetrahedra = mesh.tetrahedra.size();
  quality.minimumVolume = mesh.tetrahedra.empty() ? 0.0 : Infinity;
  quality.minimumDihedralAngles.reserve(mesh.tetrahedra.size());
  for (const Tetrahedron & tetrahedron : mesh.tetrahedra)
  {
    if (IsMalformed(tetrahedron, mesh.points.size()))
    {
      ++quality.malformedTetrahedra;
      continue;
    }
    const TetrahedronCorners corners = CornersOf(mesh.points, tetrahedron);
    const double             volume = SignedVolume(corners);
    quality.minimumVolume = std::min(quality.minimumVolume, volume);
    quality.totalVolume += volume;
    if (ExactOrientation(corners) != CGAL::POSITIVE)
    {
      ++quality.invertedTetrahedra;
    }
    quality.maximumRadiusEdgeRatio =
      std::max(quality.maximumRadiusEdgeRatio, Circumradius(corners) / ShortestEdge(corners));
    const auto dihedralRange = DihedralAngleRange(corners);
    quality.minimumDihedralAngle = std::min(quality.minimumDihedralAngle, dihedralRange.first);
    quality.maximumDihedralAngle = std::max(quality.maximumDihedralAngle, dihedralRange.second);
    quality.minimumDihedralAngles.push_back(dihedralRange.first);
  }
  if (quality.malformedTetrahedra == quality.numberOfTetrahedra)
  {
    quality.minimumVolume = 0.0;
  }
  quality.duplicateTetrahedra = CountDuplicateTetrahedra(mesh.tetrahedra, mesh.points.size());
  quality.unusedPoints = CountUnusedPoints(mesh);
  return quality;
}

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

SurfaceTopology
ComputeLabelBoundaryTopology(const TetrahedralMesh & mesh, Label label)
{
  return ComputeSurfaceTopology(mesh.points, LabelBoundaryTriangles(mesh, label));
}

double
LargestBoundaryCircumradius(const TetrahedralMesh & mesh)
{
  CheckVertexIndices("LargestBoundaryCircumradius", "boundary triangle", mesh.points, mesh.boundaryTriangles);
  double largest = 0.0;
  for (const Triangle & triangle : mesh.boundaryTriangles)
  {
    const Vector3 & a = mesh.points[triangle[0]];
    const Vector3 & b = mesh.points[triangle[1]];
    const Vector3 & c = mesh.points[triangle[2]];
    const double    twiceArea = Norm(Cross(b - a, c - a));
    // R = |ab| |bc| |ca| / (4 area). Coincident corners give 0 / 0: a NaN would drop out of the maximum and hide
    // the degenerate triangle, which has no more a circumcircle than a collinear one (x / 0 = infinity).
    const double circumradius = Distance(a, b) * Distance(b, c) * Distance(c, a) / (2.0 * twiceArea);
    largest = std::isnan(circumradius) ? Infinity : std::max(largest, circumradius);
  }
  return largest;
}

BoundaryConsistency
CheckBoundaryAgainstTetrahedra(const TetrahedralMesh & mesh)
{
  constexpr const char * caller = "CheckBoundaryAgainstTetrahedra";
  CheckVertexIndices(caller, "tetrahedron", mesh.points, mesh.tetrahedra);
  CheckVertexIndices(caller, "boundary triangle", mesh.points, mesh.boundaryTriangles);
  CheckLabelCount(caller, "tetrahedronLabels", mesh.tetrahedronLabels.size(), mesh.tetrahedra.size());
  CheckLabelCount(caller, "boundaryTriangleLabels", mesh.boundaryTriangleLabels.size(), mesh.boundaryTriangles.size());

  const std::vector<FacetSide> sides = SortedFacetSides(mesh.tetrahedra);
  BoundaryConsistency          consistency;
  // In facet order, as the sides are: found by binary search.
  std::vector<ExpectedBoundaryTriangle> expected;
  for (std::size_t first = 0; first < sides.size();)
  {
    std::size_t end = first + 1;
    while (end < sides.size() && sides[end].facet == sides[first].facet)
    {
      ++end;
    }
    if (end - first > 2)
    {
      ++consistency.overSharedFacets;
    }
    else
    {
      const FacetSide & one = sides[first];
      const Label       oneLabel = mesh.tetrahedronLabels[one.tetrahedron];
      const Label       otherLabel =
        end - first == 2 ? mesh.tetrahedronLabels[sides[first + 1].tetrahedron] : BackgroundLabel;
      if (oneLabel != otherLabel)
      {
        const std::array<Label, 2> labels = BoundaryLabelsBetween(oneLabel, otherLabel);
        expected.push_back({ one.facet, labels, oneLabel == labels[0] ? &one : &sides[first + 1], false });
      }
    }
    first = end;
  }

  std::size_t seen = 0;
  for (std::size_t i = 0; i < mesh.boundaryTriangles.size(); ++i)
  {
    const Triangle & triangle = mesh.boundaryTriangles[i];
    const Triangle   facet = SortedVertices(triangle);
    const auto       found = std::lower_bound(
      expected.begin(), expected.end(), facet, [](const ExpectedBoundaryTriangle & entry, const Triangle & key) {
        return entry.facet < key;
      });
    if (found == expected.end() || found->facet != facet || found->seen)
    {
      ++consistency.extraTriangles;
      continue;
    }
    found->seen = true;
    ++seen;
    if (mesh.boundaryTriangleLabels[i] != found->labels)
    {
      ++consistency.wrongLabels;
      continue;
    }
    // The normal points away from the tetrahedron with the first label exactly when its apex is behind the
    // triangle: (p0, p1, p2, apex) is negatively oriented. Flat counts as wrong: it points nowhere.
    const FacetSide & inner = *found->firstLabelSide;
    if (ExactOrientation({ { mesh.points[triangle[0]],
                             mesh.points[triangle[1]],
                             mesh.points[triangle[2]],
                             mesh.points[inner.apex] } }) != CGAL::NEGATIVE &&
        consistency.wrongOrientation++ == 0)
    {
      consistency.firstWronglyOriented = DescribeTriangleFacingInto(mesh, i, inner.tetrahedron);
    }
  }
  consistency.missingTriangles = expected.size() - seen;
  return consistency;
}

const char *
VertexKindName(VertexKind kind)
{
  switch (kind)
  {
    case VertexKind::BoxFace:
      return "box-face";
    case VertexKind::BoxEdge:
      return "box-edge";
    case VertexKind::Feature:
      return "feature";
    case VertexKind::Free:
      return "free";
  }
  return "?";
}

ShortestEdgesByKind
ComputeShortestEdgesByKind(const TetrahedralMesh & mesh)
{
  ShortestEdgesByKind result;
  for (const VertexKind kind : { VertexKind::BoxFace, VertexKind::BoxEdge, VertexKind::Feature, VertexKind::Free })
  {
    result.shortestEdge[kind] = Infinity;
  }
  const auto updateKindOf = [&](uint32_t vertex, double length) {
    if (vertex < mesh.pointKinds.size())
    {
      double & shortest = result.shortestEdge[mesh.pointKinds[vertex]];
      shortest = std::min(shortest, length);
    }
  };
  for (const Tetrahedron & tetrahedron : mesh.tetrahedra)
  {
    if (IsMalformed(tetrahedron, mesh.points.size()))
    {
      continue;
    }
    for (const auto & edge : TetrahedronEdges)
    {
      const uint32_t a = tetrahedron[edge[0]];
      const uint32_t b = tetrahedron[edge[1]];
      const double   length = Distance(mesh.points[a], mesh.points[b]);
      updateKindOf(a, length);
      updateKindOf(b, length);
    }
  }
  return result;
}

} // namespace delaunay_refinement
