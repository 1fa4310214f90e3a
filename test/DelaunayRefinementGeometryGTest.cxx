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

// Geometric constructions of the core (include/DelaunayRefinementGeometry.h) that the rules rely on, tested on
// points made by hand.

#include "DelaunayRefinementGeometry.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace dr = delaunay_refinement;
// Vector3 is a std::array: its arithmetic is found by name, not by argument-dependent lookup.
using dr::operator+;
using dr::operator-;
using dr::operator*;

namespace
{

/** How far apart, relative to the largest, the distances from `point` to the three corners are. */
double
RelativeSpreadOfCornerDistances(const dr::Vector3 & point, const dr::Vector3 & a, const dr::Vector3 & b,
                                const dr::Vector3 & c)
{
  const double distances[] = { dr::Distance(point, a), dr::Distance(point, b), dr::Distance(point, c) };
  const auto [smallest, largest] = std::minmax_element(std::begin(distances), std::end(distances));
  return (*largest - *smallest) / *largest;
}

} // namespace

/** A right triangle in the plane z = 1 has its circumcentre at the hypotenuse's midpoint and its axis along z: the
 * answer is known exactly, independently of the formula. */
TEST(CircumcenterAxis, ProjectsOntoTheKnownAxisOfARightTriangle)
{
  const dr::Vector3 a{ { 0.0, 0.0, 1.0 } };
  const dr::Vector3 b{ { 2.0, 0.0, 1.0 } };
  const dr::Vector3 c{ { 0.0, 2.0, 1.0 } };
  const dr::Vector3 projected = dr::NearestPointOnCircumcenterAxis(a, b, c, dr::Vector3{ { 5.0, -3.0, 7.0 } });
  EXPECT_EQ(projected, (dr::Vector3{ { 1.0, 1.0, 7.0 } }));
  EXPECT_EQ(dr::NearestPointOnCircumcenterAxis(a, b, c, dr::Vector3{ { 1.0, 1.0, -4.0 } }),
            (dr::Vector3{ { 1.0, 1.0, -4.0 } }))
    << "a point on the axis stays";
}

/** The use R3 makes of it (RefinementRules::SurfaceBallOf): a point between two circumcentres that are off the
 * facet's exact Voronoi line by 1e-8, as those of flat tetrahedra are, is 1e-8 nearer to one corner than to
 * another; put back on the line, it is as far from each as rounding allows, and it moved by no more than the
 * ends' error. */
TEST(CircumcenterAxis, PutsAPointBetweenInexactCircumcentresBackOnTheVoronoiLine)
{
  const dr::Vector3 a{ { 0.3, 0.1, 0.2 } };
  const dr::Vector3 b{ { 2.1, 0.4, -0.3 } };
  const dr::Vector3 c{ { 0.7, 1.9, 0.5 } };
  const dr::Vector3 onAxis = dr::NearestPointOnCircumcenterAxis(a, b, c, dr::Vector3{ { 0.0, 0.0, 0.0 } });
  ASSERT_LT(RelativeSpreadOfCornerDistances(onAxis, a, b, c), 1e-14);
  const dr::Vector3 normal = dr::Cross(b - a, c - a);
  const dr::Vector3 unitNormal = (1.0 / dr::Norm(normal)) * normal;
  const dr::Vector3 inPlaneError = (1e-8 / dr::Norm(b - a)) * (b - a);
  const dr::Vector3 oneEnd = onAxis + 0.7 * unitNormal + inPlaneError;
  const dr::Vector3 otherEnd = onAxis - 0.4 * unitNormal - inPlaneError;
  const dr::Vector3 crossing = 0.5 * (oneEnd + otherEnd) + 0.5 * inPlaneError;
  EXPECT_GT(RelativeSpreadOfCornerDistances(crossing, a, b, c), 1e-9) << "the case the projection is for";
  const dr::Vector3 projected = dr::NearestPointOnCircumcenterAxis(a, b, c, crossing);
  EXPECT_LT(RelativeSpreadOfCornerDistances(projected, a, b, c), 1e-14);
  EXPECT_LT(dr::Distance(projected, crossing), 1e-8);
  EXPECT_NEAR(dr::Dot(projected - onAxis, unitNormal), 0.15, 1e-14) << "the height along the axis is kept";
}

/** Collinear or coincident corners have no circumcentre: the point comes back unchanged, not as NaN. */
TEST(CircumcenterAxis, ADegenerateTriangleLeavesThePoint)
{
  const dr::Vector3 point{ { 0.5, -2.0, 3.0 } };
  const dr::Vector3 a{ { 0.0, 0.0, 0.0 } };
  EXPECT_EQ(
    dr::NearestPointOnCircumcenterAxis(a, dr::Vector3{ { 1.0, 1.0, 1.0 } }, dr::Vector3{ { 2.0, 2.0, 2.0 } }, point),
    point);
  EXPECT_EQ(dr::NearestPointOnCircumcenterAxis(a, a, dr::Vector3{ { 1.0, 0.0, 0.0 } }, point), point);
}
