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

// Distances between triangle surfaces, for measuring how faithfully a mesh boundary follows a surface. The
// only part of the quality measures that needs CGAL (its AABB tree), kept in its own translation unit so the
// slow CGAL compilation is paid once.

#include "DelaunayRefinementMeshQuality.h"
#include "DelaunayRefinementParallel.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>

namespace delaunay_refinement
{
namespace
{

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalPoint = Kernel::Point_3;
using CgalTriangle = Kernel::Triangle_3;
using TriangleIterator = std::vector<CgalTriangle>::const_iterator;
using TrianglePrimitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, TrianglePrimitive>>;

CgalPoint
ToCgal(const Vector3 & point)
{
  return { point[0], point[1], point[2] };
}

void
CheckTriangleIndices(const char * caller, const std::vector<Vector3> & points,
                     const std::vector<std::array<uint32_t, 3>> & triangles)
{
  for (const auto & triangle : triangles)
  {
    for (const uint32_t index : triangle)
    {
      if (index >= points.size())
      {
        throw std::invalid_argument(std::string(caller) + ": triangle vertex index " + std::to_string(index) +
                                    " is out of range (number of points: " + std::to_string(points.size()) + ")");
      }
    }
  }
}

/** Barycentric grid with n subdivisions per edge: point (i, j) is a + (i/n)(b - a) + (j/n)(c - a) for
 * i + j <= n, written as a weighted mean so that the corners come out exactly. */
void
AppendTriangleSamples(const Vector3 & a, const Vector3 & b, const Vector3 & c, double spacing,
                      std::vector<Vector3> & samples)
{
  const double longestEdge = std::max({ Distance(a, b), Distance(b, c), Distance(c, a) });
  const auto   subdivisions = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(longestEdge / spacing)));
  const double n = static_cast<double>(subdivisions);
  for (std::size_t i = 0; i <= subdivisions; ++i)
  {
    for (std::size_t j = 0; i + j <= subdivisions; ++j)
    {
      const double weightB = static_cast<double>(i) / n;
      const double weightC = static_cast<double>(j) / n;
      const double weightA = static_cast<double>(subdivisions - i - j) / n;
      samples.push_back(weightA * a + weightB * b + weightC * c);
    }
  }
}

/** Below this many queries per thread, starting a thread costs more than it saves. */
constexpr std::size_t MinimumQueriesPerThread = 20000;

/** The distance of every query to the surface, on every hardware thread: the queries are independent, the tree is
 * only read once built (TriangleSurfaceDistance builds its search tree up front), and each thread fills its own
 * range of the result, so the result does not depend on the number of threads. The report's distances are most
 * of its cost: millions of samples on a speckled segmentation's marching-cubes surface. */
std::vector<double>
DistancesTo(const TriangleSurfaceDistance & surface, const std::vector<Vector3> & queries)
{
  std::vector<double> distances(queries.size());
  const auto          fill = [&surface, &queries, &distances](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      distances[i] = surface.Distance(queries[i]);
    }
  };
  detail::ForEachRangeInParallel(queries.size(), std::thread::hardware_concurrency(), MinimumQueriesPerThread, fill);
  return distances;
}

} // namespace

/** The triangles must outlive the tree, which keeps iterators into them: both live here, triangles first. */
struct TriangleSurfaceDistance::Tree
{
  std::vector<CgalTriangle> triangles;
  AabbTree                  tree;
};

TriangleSurfaceDistance::TriangleSurfaceDistance(const std::vector<Vector3> &                 points,
                                                 const std::vector<std::array<uint32_t, 3>> & triangles)
  : m_Tree(std::make_unique<Tree>())
{
  CheckTriangleIndices("TriangleSurfaceDistance", points, triangles);
  m_Tree->triangles.reserve(triangles.size());
  for (const auto & triangle : triangles)
  {
    m_Tree->triangles.emplace_back(
      ToCgal(points[triangle[0]]), ToCgal(points[triangle[1]]), ToCgal(points[triangle[2]]));
  }
  if (!m_Tree->triangles.empty())
  {
    m_Tree->tree.insert(m_Tree->triangles.cbegin(), m_Tree->triangles.cend());
    m_Tree->tree.build();
    // Builds the internal search tree now rather than on the first query, and makes every query start near
    // its answer instead of at an arbitrary primitive.
    m_Tree->tree.accelerate_distance_queries();
  }
}

TriangleSurfaceDistance::~TriangleSurfaceDistance() = default;

double
TriangleSurfaceDistance::Distance(const Vector3 & query) const
{
  if (m_Tree->triangles.empty())
  {
    return std::numeric_limits<double>::infinity();
  }
  return std::sqrt(CGAL::to_double(m_Tree->tree.squared_distance(ToCgal(query))));
}

std::vector<Vector3>
SampleTriangles(const std::vector<Vector3> & points, const std::vector<std::array<uint32_t, 3>> & triangles,
                double spacing)
{
  if (!(spacing > 0.0) || !std::isfinite(spacing))
  {
    throw std::invalid_argument("SampleTriangles: spacing must be finite and > 0, got " + std::to_string(spacing));
  }
  CheckTriangleIndices("SampleTriangles", points, triangles);
  std::vector<Vector3> samples;
  for (const auto & triangle : triangles)
  {
    AppendTriangleSamples(points[triangle[0]], points[triangle[1]], points[triangle[2]], spacing, samples);
  }
  return samples;
}

DistanceStatistics
SummarizeDistances(std::vector<double> distances)
{
  DistanceStatistics statistics;
  statistics.count = distances.size();
  if (distances.empty())
  {
    return statistics;
  }
  const double sum = std::accumulate(distances.begin(), distances.end(), 0.0);
  statistics.mean = sum / static_cast<double>(distances.size());
  statistics.maximum = *std::max_element(distances.begin(), distances.end());
  // Position ceil(0.95 n) - 1 of the sorted distances, in integers so that 0.95 n cannot round the wrong way.
  const std::size_t percentilePosition = (95 * distances.size() + 99) / 100 - 1;
  std::nth_element(distances.begin(), distances.begin() + percentilePosition, distances.end());
  statistics.percentile95 = distances[percentilePosition];
  return statistics;
}

TwoSidedDistance
ComputeTwoSidedDistance(const std::vector<Vector3> &                 firstPoints,
                        const std::vector<std::array<uint32_t, 3>> & firstTriangles,
                        const std::vector<Vector3> &                 secondPoints,
                        const std::vector<std::array<uint32_t, 3>> & secondTriangles, double spacing)
{
  const TriangleSurfaceDistance first(firstPoints, firstTriangles);
  const TriangleSurfaceDistance second(secondPoints, secondTriangles);
  const std::vector<double>     fromFirst = DistancesTo(second, SampleTriangles(firstPoints, firstTriangles, spacing));
  const std::vector<double> fromSecond = DistancesTo(first, SampleTriangles(secondPoints, secondTriangles, spacing));

  std::vector<double> pooled(fromFirst);
  pooled.insert(pooled.end(), fromSecond.begin(), fromSecond.end());

  TwoSidedDistance result;
  result.fromFirst = SummarizeDistances(fromFirst);
  result.fromSecond = SummarizeDistances(fromSecond);
  result.combined = SummarizeDistances(std::move(pooled));
  return result;
}

} // namespace delaunay_refinement
