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

// The hash grid behind the refinement's "which vertices lie within r of p" (src/DelaunayRefinementSpatialGrid.h),
// asked about random points against a brute-force scan of the same points. The refinement's own meshes would hide a
// query that misses an entry: R1 and R2 then insert a vertex more, which changes the mesh, not a guarantee the meshes
// are checked for.

#include "DelaunayRefinementSpatialGrid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <random>
#include <vector>

namespace dr = delaunay_refinement;
using dr::operator-;

namespace
{

/** The indices of `points` strictly closer than `radius` to `center`, by a scan of them all. */
std::vector<std::size_t>
BruteForceWithin(const std::vector<dr::Vector3> & points, const dr::Vector3 & center, double radius)
{
  std::vector<std::size_t> within;
  for (std::size_t index = 0; index < points.size(); ++index)
  {
    if (dr::SquaredNorm(points[index] - center) < radius * radius)
    {
      within.push_back(index);
    }
  }
  return within;
}

std::vector<std::size_t>
GridWithin(const dr::SpatialGrid<std::size_t> & grid, const dr::Vector3 & center, double radius)
{
  std::vector<std::size_t> within;
  grid.ForEachWithin(center, radius, [&](std::size_t index) { within.push_back(index); });
  std::sort(within.begin(), within.end());
  return within;
}

} // namespace

/** Points on both sides of zero in every axis (where the cells' keys change sign), queried with radii from a tenth of
 * a cell to several cells: every query finds exactly the points the scan finds, in whichever cell they are. */
TEST(SpatialGrid, FindsExactlyThePointsWithinTheRadiusInEveryCell)
{
  std::mt19937                           random(20261203);
  std::uniform_real_distribution<double> coordinate(-4.0, 4.0);
  std::uniform_real_distribution<double> radiusDraw(0.1, 3.0);
  const double                           cellSize = 1.0;
  dr::SpatialGrid<std::size_t>           grid(cellSize);
  std::vector<dr::Vector3>               points;
  for (std::size_t index = 0; index < 3000; ++index)
  {
    points.push_back({ { coordinate(random), coordinate(random), coordinate(random) } });
    grid.Insert(points.back(), index);
  }
  EXPECT_EQ(grid.Size(), points.size());
  std::size_t pointsFound = 0;
  for (int query = 0; query < 2000; ++query)
  {
    const dr::Vector3              center{ { coordinate(random), coordinate(random), coordinate(random) } };
    const double                   radius = radiusDraw(random);
    const std::vector<std::size_t> expected = BruteForceWithin(points, center, radius);
    ASSERT_EQ(GridWithin(grid, center, radius), expected)
      << "centre " << center[0] << " " << center[1] << " " << center[2] << ", radius " << radius;
    ASSERT_EQ(grid.AnyWithin(center, radius), !expected.empty())
      << "centre " << center[0] << " " << center[1] << " " << center[2] << ", radius " << radius;
    pointsFound += expected.size();
  }
  // Most queries find something, and many find points in several cells (measured: about 120 points a query).
  EXPECT_GT(pointsFound, 2000u * 10);
}

/** The balls are open: an entry exactly `radius` away is not within it, whether it lies in the query's own cell (which
 * AnyWithin() looks at first) or in another. The distances are exact in binary. */
TEST(SpatialGrid, AnEntryExactlyTheRadiusAwayIsNotWithin)
{
  dr::SpatialGrid<int> grid(1.0);
  const dr::Vector3    center{ { 0.25, 0.25, 0.25 } };
  grid.Insert({ { 0.75, 0.25, 0.25 } }, 1);  // 0.5 away, in the centre's cell
  grid.Insert({ { 0.25, -0.75, 0.25 } }, 2); // 1 away, in the cell below
  EXPECT_FALSE(grid.AnyWithin(center, 0.5));
  EXPECT_TRUE(grid.AnyWithin(center, 0.5 + 1e-12));
  std::vector<int> found;
  grid.ForEachWithin(center, 1.0, [&](int payload) { found.push_back(payload); });
  EXPECT_EQ(found, std::vector<int>{ 1 });
  grid.Remove({ { 0.75, 0.25, 0.25 } }, 1);
  EXPECT_FALSE(grid.AnyWithin(center, 1.0));
  EXPECT_TRUE(grid.AnyWithin(center, 1.0 + 1e-12));
}

/** Removing an entry removes that one only, wherever it stands among the entries of its cell; removing one that is not
 * there (at a point of an empty cell, or removed already) changes nothing. */
TEST(SpatialGrid, RemovesTheNamedEntryAndNoOther)
{
  dr::SpatialGrid<int>     grid(1.0);
  std::vector<dr::Vector3> points;
  for (int index = 0; index < 6; ++index)
  {
    // Six points of one cell.
    points.push_back({ { 0.1 + 0.1 * index, 0.5, 0.5 } });
    grid.Insert(points.back(), index);
  }
  const dr::Vector3 center{ { 0.5, 0.5, 0.5 } };
  const auto        found = [&] {
    std::vector<int> payloads;
    grid.ForEachWithin(center, 0.9, [&](int payload) { payloads.push_back(payload); });
    std::sort(payloads.begin(), payloads.end());
    return payloads;
  };
  grid.Remove(points[1], 1); // one in the middle of the cell's list
  EXPECT_EQ(found(), (std::vector<int>{ 0, 2, 3, 4, 5 }));
  grid.Remove(points[0], 0); // the first
  EXPECT_EQ(found(), (std::vector<int>{ 2, 3, 4, 5 }));
  grid.Remove(points[5], 5); // the last
  EXPECT_EQ(found(), (std::vector<int>{ 2, 3, 4 }));
  grid.Remove({ { 7.5, 7.5, 7.5 } }, 2); // a point of a cell that holds nothing
  grid.Remove(points[1], 1);             // removed already
  EXPECT_EQ(found(), (std::vector<int>{ 2, 3, 4 }));
  EXPECT_EQ(grid.Size(), 3u);
}
