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
#include "DelaunayRefinementMeasureHelpers.h"

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

using detail::AngleBetween;
using detail::CheckVertexIndices;
using detail::DegreesPerRadian;
using detail::Tetrahedron;
using detail::Triangle;

/** Exact arithmetic for the measures that floating point cannot take on nearly flat tetrahedra. */
using ExactPoint = CGAL::Exact_predicates_exact_constructions_kernel::Point_3;

/** Relative disagreement of the squared distances from a floating-point circumcentre to the corners beyond which
 * it is recomputed exactly (rounding alone stays near 1e-16). */
constexpr double EquidistanceTolerance = 1e-10;

constexpr double Infinity = std::numeric_limits<double>::infinity();

/** The six edges of a tetrahedron as pairs of local vertex positions. */
constexpr std::array<std::array<int, 2>, 6> TetrahedronEdges{
  { { { 0, 1 } }, { { 0, 2 } }, { { 0, 3 } }, { { 1, 2 } }, { { 1, 3 } }, { { 2, 3 } } }
};

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
