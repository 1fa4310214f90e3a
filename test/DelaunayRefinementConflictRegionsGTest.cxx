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

// The conflict regions that R4′ finds for many points in one search (src/DelaunayRefinementConflictRegions.h,
// docs/algorithm.md, "R4′ picks its point") against CGAL's own locate and find_conflicts, point by point. The
// vertices are integer lattice points and the points half-integer ones, so that many points lie exactly on the
// circumsphere of some cell: there CGAL's symbolic perturbation decides, and the search must decide as it does. The
// one translation unit of the tests that compiles CGAL's triangulation.

#include "DelaunayRefinementConflictRegions.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

namespace dr = delaunay_refinement;
using dr::detail::CellHandle;
using dr::detail::ConflictRegions;
using dr::detail::Triangulation;
using dr::operator-;
using dr::operator+;
using dr::operator*;

namespace
{

/** Integer points of a 7 × 7 × 7 block, about half of them (a fixed draw), with every cell's cache filled as the
 * refinement fills it: circumcentre and squared circumradius. With `centreShift`, each cached circumcentre is moved
 * by that fraction of the circumradius in a direction drawn for the cell, and the squared radius is its squared
 * distance to the cell's first corner (MeshState::ComputeCache): a cache as far off as the refinement's may be. */
Triangulation
LatticeTriangulation(double centreShift = 0.0)
{
  std::mt19937                       random(20261128);
  std::bernoulli_distribution        keep(0.5);
  std::vector<dr::detail::CgalPoint> points;
  for (int x = 0; x < 7; ++x)
  {
    for (int y = 0; y < 7; ++y)
    {
      for (int z = 0; z < 7; ++z)
      {
        if (keep(random))
        {
          points.emplace_back(x, y, z);
        }
      }
    }
  }
  Triangulation                    triangulation(points.begin(), points.end());
  std::normal_distribution<double> component;
  for (auto cell = triangulation.finite_cells_begin(); cell != triangulation.finite_cells_end(); ++cell)
  {
    const dr::Vector3 center = dr::detail::ToVector(triangulation.dual(cell));
    const dr::Vector3 corner = dr::detail::ToVector(cell->vertex(0)->point());
    dr::Vector3       direction{ { component(random), component(random), component(random) } };
    direction = (1.0 / dr::Norm(direction)) * direction;
    cell->cache.circumcenter = center + (centreShift * dr::Norm(center - corner)) * direction;
    cell->cache.squaredRadius = dr::SquaredNorm(cell->cache.circumcenter - corner);
  }
  return triangulation;
}

/** The half-integer points strictly inside 0.9 of the cell's circumball, at most `limit` of them. */
std::vector<dr::Vector3>
HalfIntegerPointsInside(CellHandle cell, std::size_t limit)
{
  const dr::Vector3 &      center = cell->cache.circumcenter;
  const double             radius = std::sqrt(cell->cache.squaredRadius);
  std::vector<dr::Vector3> points;
  for (double x = std::floor(center[0] - radius) - 0.5; x <= center[0] + radius; x += 0.5)
  {
    for (double y = std::floor(center[1] - radius) - 0.5; y <= center[1] + radius; y += 0.5)
    {
      for (double z = std::floor(center[2] - radius) - 0.5; z <= center[2] + radius; z += 0.5)
      {
        const dr::Vector3 point{ { x, y, z } };
        if (points.size() < limit && dr::Norm(point - center) < 0.9 * radius)
        {
          points.push_back(point);
        }
      }
    }
  }
  return points;
}

/** Whether `point` lies exactly on the circumsphere of some cell within the region's reach (its cells and their
 * neighbours), as CGAL's exact predicate sees it: a case that the perturbation decides. */
bool
IsOnSomeSphere(const Triangulation & triangulation, const std::vector<CellHandle> & cells, const dr::Vector3 & point)
{
  const dr::detail::CgalPoint cgalPoint = dr::detail::ToCgal(point);
  for (const CellHandle cell : cells)
  {
    for (int facet = 0; facet < 4; ++facet)
    {
      for (const CellHandle nearby : { cell, cell->neighbor(facet) })
      {
        if (!triangulation.is_infinite(nearby) &&
            triangulation.side_of_sphere(nearby, cgalPoint, false) == CGAL::ON_BOUNDARY)
        {
          return true;
        }
      }
    }
  }
  return false;
}

/** What a comparison with CGAL's regions went through. */
struct Compared
{
  std::size_t points = 0;
  std::size_t pointsOnASphere = 0;
  /** Points that the cached sphere alone, without the margin and the exact predicate, puts on the wrong side of the
   * sphere of some cell within the region's reach. */
  std::size_t pointsTheCacheAloneMisjudges = 0;
};

/** Whether the cached sphere of some finite cell within the region's reach (its cells and their neighbours) puts
 * `point` on the other side than CGAL's exact predicate with its perturbation. */
bool
CacheAloneMisjudges(const Triangulation & triangulation, const std::vector<CellHandle> & cells,
                    const dr::Vector3 & point)
{
  const dr::detail::CgalPoint cgalPoint = dr::detail::ToCgal(point);
  for (const CellHandle cell : cells)
  {
    for (int facet = 0; facet < 4; ++facet)
    {
      for (const CellHandle nearby : { cell, cell->neighbor(facet) })
      {
        if (triangulation.is_infinite(nearby))
        {
          continue;
        }
        const bool byCache = dr::SquaredNorm(point - nearby->cache.circumcenter) < nearby->cache.squaredRadius;
        const bool exactly = triangulation.side_of_sphere(nearby, cgalPoint, true) == CGAL::ON_BOUNDED_SIDE;
        if (byCache != exactly)
        {
          return true;
        }
      }
    }
  }
  return false;
}

/** For every `stride`-th finite cell, the conflict regions of the half-integer points well inside its circumball,
 * found in one search from it, against CGAL's locate and find_conflicts point by point. Clear() between two cells
 * when `clearBetween`; Find() alone otherwise. */
void
CompareWithCgalsRegions(const Triangulation & triangulation, std::size_t stride, bool clearBetween, Compared & compared)
{
  ConflictRegions regions;
  std::size_t     cellIndex = 0;
  for (auto cell = triangulation.finite_cells_begin(); cell != triangulation.finite_cells_end(); ++cell)
  {
    if (cellIndex++ % stride != 0)
    {
      continue;
    }
    const std::vector<dr::Vector3> points = HalfIntegerPointsInside(cell, ConflictRegions::MaximumPoints);
    if (points.empty())
    {
      continue;
    }
    regions.Find(triangulation, cell, points);
    for (std::size_t index = 0; index < points.size(); ++index)
    {
      ASSERT_EQ(regions.IndexOf(points[index]), std::optional<std::size_t>(index));
      std::vector<CellHandle>           cells;
      std::vector<Triangulation::Facet> facets;
      regions.RegionOf(index, cells, facets);

      const dr::detail::CgalPoint cgalPoint = dr::detail::ToCgal(points[index]);
      Triangulation::Locate_type  locateType;
      int                         li = 0;
      int                         lj = 0;
      const CellHandle            start = triangulation.locate(cgalPoint, locateType, li, lj, cell);
      ASSERT_NE(locateType, Triangulation::VERTEX);
      std::vector<CellHandle>           expectedCells;
      std::vector<Triangulation::Facet> expectedFacets;
      triangulation.find_conflicts(
        cgalPoint, start, std::back_inserter(expectedFacets), std::back_inserter(expectedCells));

      std::sort(cells.begin(), cells.end());
      std::sort(expectedCells.begin(), expectedCells.end());
      std::sort(facets.begin(), facets.end());
      std::sort(expectedFacets.begin(), expectedFacets.end());
      ASSERT_EQ(cells, expectedCells) << "point " << points[index][0] << " " << points[index][1] << " "
                                      << points[index][2];
      ASSERT_EQ(facets, expectedFacets);
      ++compared.points;
      compared.pointsOnASphere += IsOnSomeSphere(triangulation, cells, points[index]);
      compared.pointsTheCacheAloneMisjudges += CacheAloneMisjudges(triangulation, cells, points[index]);
    }
    if (clearBetween)
    {
      regions.Clear();
      EXPECT_FALSE(regions.IndexOf(points.front()).has_value());
    }
  }
}

} // namespace

TEST(ConflictRegions, AreCgalsRegionsPointByPoint)
{
  const Triangulation triangulation = LatticeTriangulation();
  Compared            compared;
  CompareWithCgalsRegions(triangulation, 1, true, compared);
  ASSERT_FALSE(HasFatalFailure());
  // The lattice is there for the degenerate cases (measured: 19,429 points compared, 7,398 of them on a sphere).
  EXPECT_GT(compared.points, 10000u);
  EXPECT_GT(compared.pointsOnASphere, compared.points / 10);
}

TEST(ConflictRegions, AreCgalsRegionsWhenTheCachedCentresAreAsFarOffAsTheRefinementsMayBe)
{
  // MeshState keeps a cached circumcentre within about 1e-7 of the longest edge, so 2e-7 of the radius, of the
  // true one (ConflictRegions::SphereMargin): a point on or near a sphere is then up to about 8e-7 of the squared
  // radius on the wrong side of the cached one, and the exact predicate must decide it.
  const Triangulation triangulation = LatticeTriangulation(2e-7);
  Compared            compared;
  CompareWithCgalsRegions(triangulation, 1, true, compared);
  ASSERT_FALSE(HasFatalFailure());
  EXPECT_GT(compared.points, 10000u);
  // The shifted caches alone would misjudge many points: the margin, not the cache, kept the regions CGAL's.
  EXPECT_GT(compared.pointsTheCacheAloneMisjudges, compared.points / 20);
}

TEST(ConflictRegions, FindForgetsTheRegionsOfTheSearchBefore)
{
  // Find() after Find(), without Clear(): each search gives the regions of its own points only, as CGAL does. Every
  // third cell, so that two searches in a row start from cells far apart as well as near.
  const Triangulation triangulation = LatticeTriangulation();
  Compared            compared;
  CompareWithCgalsRegions(triangulation, 3, false, compared);
  ASSERT_FALSE(HasFatalFailure());
  EXPECT_GT(compared.points, 3000u);
}

TEST(ConflictRegions, RefusesMorePointsThanBits)
{
  const Triangulation triangulation = LatticeTriangulation();
  // The cell with the largest circumball holds more than 33 half-integer points well inside it.
  CellHandle largest = triangulation.finite_cells_begin();
  for (auto cell = triangulation.finite_cells_begin(); cell != triangulation.finite_cells_end(); ++cell)
  {
    if (cell->cache.squaredRadius > largest->cache.squaredRadius)
    {
      largest = cell;
    }
  }
  std::vector<dr::Vector3> points = HalfIntegerPointsInside(largest, ConflictRegions::MaximumPoints + 1);
  ASSERT_EQ(points.size(), ConflictRegions::MaximumPoints + 1);
  ConflictRegions regions;
  EXPECT_THROW(regions.Find(triangulation, largest, points), std::logic_error);
  // One point fewer, one bit each: the last point has the last bit, and its region holds the start cell.
  points.pop_back();
  regions.Find(triangulation, largest, points);
  std::vector<CellHandle>           cells;
  std::vector<Triangulation::Facet> facets;
  regions.RegionOf(ConflictRegions::MaximumPoints - 1, cells, facets);
  EXPECT_NE(std::find(cells.begin(), cells.end(), largest), cells.end());
}
