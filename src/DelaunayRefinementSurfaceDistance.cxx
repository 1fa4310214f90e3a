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
#include <CGAL/AABB_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <boost/iterator/counting_iterator.hpp>
#include <boost/property_map/property_map.hpp>

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

/** A surface's points and its triangles as indices into them: the tree reads a triangle's corners when it needs
 * them, rather than keeping three copies of its points (72 bytes a triangle against 12: 0.7 GB for the 10 M
 * marching-cubes triangles of the k-means tissues on an oblique 0.62 x 0.62 x 1.33 mm grid). */
struct IndexedTriangles
{
  std::vector<CgalPoint>               points;
  std::vector<std::array<uint32_t, 3>> corners;
};

/** The triangle of an index (a property map for CGAL's AABB tree). */
struct TriangleOfIndex
{
  using key_type = std::size_t;
  using value_type = CgalTriangle;
  using reference = CgalTriangle;
  using category = boost::readable_property_map_tag;

  const IndexedTriangles * triangles{ nullptr };

  friend CgalTriangle
  get(const TriangleOfIndex & map, std::size_t index)
  {
    const std::array<uint32_t, 3> & corners = map.triangles->corners[index];
    return { map.triangles->points[corners[0]], map.triangles->points[corners[1]], map.triangles->points[corners[2]] };
  }
};

/** The reference point of a triangle, its first corner (a property map for CGAL's AABB tree). */
struct FirstCornerOfIndex
{
  using key_type = std::size_t;
  using value_type = CgalPoint;
  using reference = const CgalPoint &;
  using category = boost::readable_property_map_tag;

  const IndexedTriangles * triangles{ nullptr };

  friend const CgalPoint &
  get(const FirstCornerOfIndex & map, std::size_t index)
  {
    return map.triangles->points[map.triangles->corners[index][0]];
  }
};

using TrianglePrimitive =
  CGAL::AABB_primitive<std::size_t, TriangleOfIndex, FirstCornerOfIndex, CGAL::Tag_true, CGAL::Tag_false>;
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

void
CheckSampleSpacing(const char * caller, double spacing)
{
  if (!(spacing > 0.0) || !std::isfinite(spacing))
  {
    throw std::invalid_argument(std::string(caller) + ": spacing must be finite and > 0, got " +
                                std::to_string(spacing));
  }
}

/** How many parts AppendTriangleSamples cuts each edge of a triangle into: its longest edge over `spacing`. */
std::size_t
SubdivisionsOf(const Vector3 & a, const Vector3 & b, const Vector3 & c, double spacing)
{
  const double longestEdge = std::max({ Distance(a, b), Distance(b, c), Distance(c, a) });
  return std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(longestEdge / spacing)));
}

/** Barycentric grid with n subdivisions per edge: point (i, j) is a + (i/n)(b - a) + (j/n)(c - a) for
 * i + j <= n, written as a weighted mean so that the corners come out exactly. (n + 1)(n + 2) / 2 points. */
void
AppendTriangleSamples(const Vector3 & a, const Vector3 & b, const Vector3 & c, double spacing,
                      std::vector<Vector3> & samples)
{
  const std::size_t subdivisions = SubdivisionsOf(a, b, c, spacing);
  const double      n = static_cast<double>(subdivisions);
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

/** The most reference points the distance search tree of a TriangleSurfaceDistance holds (see its constructor). */
constexpr std::size_t LargestSearchTreePoints = std::size_t{ 1 } << 20;

/** Below this many queries per thread, starting a thread costs more than it saves. */
constexpr std::size_t MinimumQueriesPerThread = 20000;

/** Where each triangle's samples (AppendTriangleSamples) start in a list that holds `before` values already; the
 * last entry is where they end. */
std::vector<std::size_t>
SampleStarts(const std::vector<Vector3> & points, const std::vector<std::array<uint32_t, 3>> & triangles,
             double spacing, std::size_t before)
{
  std::vector<std::size_t> starts(triangles.size() + 1, before);
  for (std::size_t index = 0; index < triangles.size(); ++index)
  {
    const std::array<uint32_t, 3> & corners = triangles[index];
    const std::size_t n = SubdivisionsOf(points[corners[0]], points[corners[1]], points[corners[2]], spacing);
    starts[index + 1] = starts[index] + (n + 1) * (n + 2) / 2;
  }
  return starts;
}

/** How often (in triangles) the calling thread tells its progress. */
constexpr std::size_t TrianglesPerProgressReport = 4096;

/** Writes to `distances`, at `starts` (SampleStarts), the distance to `surface` of every sample of the triangles
 * (SampleTriangles' samples, in its order), on every hardware thread. The samples are made triangle by triangle
 * where they are measured and never kept: on a speckled segmentation's marching-cubes surface they are tens of
 * millions, and the list of them (24 bytes each) and the copies of the distances were 2 GB of the report's 5.8 GB
 * for 73 million samples (the k-means tissues on an oblique 0.62 x 0.62 x 1.33 mm grid at 8 mm). Each triangle's
 * distances go to a fixed place, so the result does not depend on the number of threads. `progress`, when given, is
 * told the fraction of its own triangles the calling thread has measured (the threads share them evenly). */
void
MeasureSamples(const std::vector<Vector3> & points, const std::vector<std::array<uint32_t, 3>> & triangles,
               double spacing, const std::vector<std::size_t> & starts, const TriangleSurfaceDistance & surface,
               std::vector<double> & distances, const DistanceProgress & progress)
{
  const std::size_t     averageSamples = triangles.empty() ? 1 : (starts.back() - starts.front()) / triangles.size();
  const std::thread::id callingThread = std::this_thread::get_id();
  detail::ForEachRangeInParallel(triangles.size(),
                                 std::thread::hardware_concurrency(),
                                 MinimumQueriesPerThread / std::max<std::size_t>(averageSamples, 1),
                                 [&](std::size_t begin, std::size_t end) {
                                   const bool           tells = progress && std::this_thread::get_id() == callingThread;
                                   std::vector<Vector3> samples;
                                   for (std::size_t index = begin; index < end; ++index)
                                   {
                                     if (tells && (index - begin) % TrianglesPerProgressReport == 0)
                                     {
                                       progress(static_cast<double>(index - begin) / static_cast<double>(end - begin));
                                     }
                                     const std::array<uint32_t, 3> & corners = triangles[index];
                                     samples.clear();
                                     AppendTriangleSamples(
                                       points[corners[0]], points[corners[1]], points[corners[2]], spacing, samples);
                                     for (std::size_t sample = 0; sample < samples.size(); ++sample)
                                     {
                                       distances[starts[index] + sample] = surface.Distance(samples[sample]);
                                     }
                                   }
                                 });
}

/** SummarizeDistances in two steps, so that several ranges of one list can be summarised without copies: the mean
 * (summed in the list's order) and the maximum, then the 95th percentile, which reorders the range. */
void
SummarizeMeanAndMaximum(const double * begin, const double * end, DistanceStatistics & statistics)
{
  statistics.count = static_cast<std::size_t>(end - begin);
  if (begin == end)
  {
    return;
  }
  const double sum = std::accumulate(begin, end, 0.0);
  statistics.mean = sum / static_cast<double>(statistics.count);
  statistics.maximum = *std::max_element(begin, end);
}

void
SummarizePercentile95(double * begin, double * end, DistanceStatistics & statistics)
{
  const std::size_t count = static_cast<std::size_t>(end - begin);
  if (count == 0)
  {
    return;
  }
  // Position ceil(0.95 n) - 1 of the sorted distances, in integers so that 0.95 n cannot round the wrong way.
  const std::size_t percentilePosition = (95 * count + 99) / 100 - 1;
  std::nth_element(begin, begin + percentilePosition, end);
  statistics.percentile95 = begin[percentilePosition];
}

} // namespace

/** The triangles must outlive the tree, whose property maps point to them: both live here, triangles first. */
struct TriangleSurfaceDistance::Tree
{
  IndexedTriangles triangles;
  AabbTree         tree;
};

TriangleSurfaceDistance::TriangleSurfaceDistance(const std::vector<Vector3> &                 points,
                                                 const std::vector<std::array<uint32_t, 3>> & triangles)
  : m_Tree(std::make_unique<Tree>())
{
  CheckTriangleIndices("TriangleSurfaceDistance", points, triangles);
  if (triangles.empty())
  {
    return;
  }
  IndexedTriangles & indexed = m_Tree->triangles;
  indexed.points.reserve(points.size());
  for (const Vector3 & point : points)
  {
    indexed.points.push_back(ToCgal(point));
  }
  indexed.corners = triangles;
  m_Tree->tree.insert(boost::counting_iterator<std::size_t>(0),
                      boost::counting_iterator<std::size_t>(triangles.size()),
                      TriangleOfIndex{ &indexed },
                      FirstCornerOfIndex{ &indexed });
  m_Tree->tree.build();
  // Builds the internal search tree now rather than on the first query, and makes every query start near its
  // answer instead of at an arbitrary primitive. The search tree holds a reference point of every primitive by
  // default: for the 10 M triangles of a speckled segmentation's marching-cubes surface it took 1.6 GB while
  // being built and kept 0.56 GB. Every few primitives' points give a start nearly as near; the distance is the
  // same, since the tree's traversal from any start is exact.
  const std::size_t stride = std::max<std::size_t>(1, triangles.size() / LargestSearchTreePoints);
  std::vector<AabbTree::Point_and_primitive_id> referencePoints;
  referencePoints.reserve(triangles.size() / stride + 1);
  for (std::size_t index = 0; index < triangles.size(); index += stride)
  {
    referencePoints.emplace_back(get(FirstCornerOfIndex{ &indexed }, index), index);
  }
  m_Tree->tree.accelerate_distance_queries(referencePoints.cbegin(), referencePoints.cend());
}

TriangleSurfaceDistance::~TriangleSurfaceDistance() = default;

double
TriangleSurfaceDistance::Distance(const Vector3 & query) const
{
  if (m_Tree->triangles.corners.empty())
  {
    return std::numeric_limits<double>::infinity();
  }
  return std::sqrt(CGAL::to_double(m_Tree->tree.squared_distance(ToCgal(query))));
}

std::vector<Vector3>
SampleTriangles(const std::vector<Vector3> & points, const std::vector<std::array<uint32_t, 3>> & triangles,
                double spacing)
{
  CheckSampleSpacing("SampleTriangles", spacing);
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
  SummarizeMeanAndMaximum(distances.data(), distances.data() + distances.size(), statistics);
  SummarizePercentile95(distances.data(), distances.data() + distances.size(), statistics);
  return statistics;
}

TwoSidedDistance
ComputeTwoSidedDistance(const std::vector<Vector3> &                 firstPoints,
                        const std::vector<std::array<uint32_t, 3>> & firstTriangles,
                        const std::vector<Vector3> &                 secondPoints,
                        const std::vector<std::array<uint32_t, 3>> & secondTriangles, double spacing,
                        const DistanceProgress & progress)
{
  CheckSampleSpacing("ComputeTwoSidedDistance", spacing);
  const TriangleSurfaceDistance first(firstPoints, firstTriangles);
  const TriangleSurfaceDistance second(secondPoints, secondTriangles);
  // One list: the first's distances, then the second's, which is the pooled list the combined statistics read.
  const std::vector<std::size_t> firstStarts = SampleStarts(firstPoints, firstTriangles, spacing, 0);
  const std::vector<std::size_t> secondStarts =
    SampleStarts(secondPoints, secondTriangles, spacing, firstStarts.back());
  std::vector<double> pooled(secondStarts.back());
  const std::size_t   fromFirst = firstStarts.back();
  // Each direction's part of the progress is its share of the samples.
  const double total = static_cast<double>(std::max<std::size_t>(pooled.size(), 1));
  const auto   partOfTheProgress = [&progress, total](std::size_t before, std::size_t samples) -> DistanceProgress {
    if (!progress)
    {
      return {};
    }
    return [&progress, total, before, samples](double fraction) {
      progress((static_cast<double>(before) + fraction * static_cast<double>(samples)) / total);
    };
  };
  MeasureSamples(firstPoints, firstTriangles, spacing, firstStarts, second, pooled, partOfTheProgress(0, fromFirst));
  MeasureSamples(secondPoints,
                 secondTriangles,
                 spacing,
                 secondStarts,
                 first,
                 pooled,
                 partOfTheProgress(fromFirst, pooled.size() - fromFirst));
  if (progress)
  {
    progress(1.0);
  }
  double * const begin = pooled.data();
  double * const middle = begin + fromFirst;
  double * const end = begin + pooled.size();

  // The means are summed before any percentile reorders the list, in the list's order.
  TwoSidedDistance result;
  SummarizeMeanAndMaximum(begin, middle, result.fromFirst);
  SummarizeMeanAndMaximum(middle, end, result.fromSecond);
  SummarizeMeanAndMaximum(begin, end, result.combined);
  SummarizePercentile95(begin, middle, result.fromFirst);
  SummarizePercentile95(middle, end, result.fromSecond);
  SummarizePercentile95(begin, end, result.combined);
  return result;
}

} // namespace delaunay_refinement
