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
#include <array>
#include <cmath>
#include <limits>
#include <utility>

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

namespace
{

/** The corner of a cube: three right angles at the origin. Its dihedral angles are 90° at the three edges through
 * the origin and arccos(1/√3) = 54.7356...° at the three others (each between a coordinate plane and the slanted face
 * x + y + z = 1); its circumcentre is the cube's centre (½, ½, ½). */
std::array<dr::Vector3, 4>
CubeCorner()
{
  return { dr::Vector3{ { 0.0, 0.0, 0.0 } },
           dr::Vector3{ { 1.0, 0.0, 0.0 } },
           dr::Vector3{ { 0.0, 1.0, 0.0 } },
           dr::Vector3{ { 0.0, 0.0, 1.0 } } };
}

/** Every other corner of a cube of side 1: a regular tetrahedron of edge √2, whose dihedral angles are all
 * arccos(1/3) = 70.5288...°, whose circumradius is that of the cube, √3 / 2, and whose volume is a third of it. */
std::array<dr::Vector3, 4>
RegularTetrahedron()
{
  return { dr::Vector3{ { 0.0, 0.0, 0.0 } },
           dr::Vector3{ { 1.0, 1.0, 0.0 } },
           dr::Vector3{ { 0.0, 1.0, 1.0 } },
           dr::Vector3{ { 1.0, 0.0, 1.0 } } };
}

/** The triangle (0, 0, 0), (1, 0, 0), (cos θ, sin θ, 0): isosceles, θ at its apex, (180° − θ) / 2 at the others. */
std::array<dr::Vector3, 3>
IsoscelesTriangleWithApexAngle(double apexDegrees)
{
  const double apex = dr::DegreesToRadians(apexDegrees);
  return { dr::Vector3{ { 0.0, 0.0, 0.0 } },
           dr::Vector3{ { 1.0, 0.0, 0.0 } },
           dr::Vector3{ { std::cos(apex), std::sin(apex), 0.0 } } };
}

const double cubeCornerSlantedAngle = dr::RadiansToDegrees(std::acos(1.0 / std::sqrt(3.0)));
const double regularDihedralAngle = dr::RadiansToDegrees(std::acos(1.0 / 3.0));

} // namespace

/** Each of the six edges in turn is made the shortest: a version that skipped a pair of corners would miss one. */
TEST(TetrahedronMeasures, ShortestEdgeLengthLooksAtEveryEdge)
{
  for (int i = 0; i < 4; ++i)
  {
    for (int j = i + 1; j < 4; ++j)
    {
      std::array<dr::Vector3, 4> corners = RegularTetrahedron();
      corners[j] = corners[i] + 0.25 * (corners[j] - corners[i]);
      EXPECT_DOUBLE_EQ(dr::ShortestEdgeLength(corners), 0.25 * std::sqrt(2.0)) << "edge " << i << j;
    }
  }
  const dr::Vector3 a{ { 0.0, 0.0, 0.0 } };
  const dr::Vector3 b{ { 3.0, 0.0, 0.0 } };
  const dr::Vector3 c{ { 3.0, 4.0, 0.0 } };
  EXPECT_DOUBLE_EQ(dr::ShortestEdgeLength(a, b, c), 3.0);
  EXPECT_DOUBLE_EQ(dr::ShortestEdgeLength(b, c, a), 3.0);
  EXPECT_DOUBLE_EQ(dr::ShortestEdgeLength(c, a, b), 3.0);
  EXPECT_DOUBLE_EQ(dr::ShortestEdgeLength(a, dr::Vector3{ { 0.0, 5.0, 0.0 } }, dr::Vector3{ { 2.0, 5.0, 0.0 } }), 2.0)
    << "the edge from the second corner to the third";
  EXPECT_DOUBLE_EQ(dr::ShortestEdgeLength(a, dr::Vector3{ { 0.0, 5.0, 0.0 } }, dr::Vector3{ { 1.5, 0.0, 0.0 } }), 1.5)
    << "the edge from the third corner back to the first";
}

TEST(TetrahedronMeasures, SignedVolumeAndOrientation)
{
  std::array<dr::Vector3, 4> corners = CubeCorner();
  EXPECT_DOUBLE_EQ(dr::SignedVolume(corners), 1.0 / 6.0) << "(x, y, z) is right-handed";
  std::swap(corners[1], corners[2]);
  EXPECT_DOUBLE_EQ(dr::SignedVolume(corners), -1.0 / 6.0);
  EXPECT_DOUBLE_EQ(dr::SignedVolume(RegularTetrahedron()), 1.0 / 3.0);
}

/** The face opposite each corner of the cube corner: its normal points away from that corner. */
TEST(TetrahedronMeasures, OutwardFaceNormalsPointAwayFromTheOppositeCorner)
{
  const std::array<dr::Vector3, 4> corners = CubeCorner();
  const auto                       direction = [&corners](int face) {
    const dr::Vector3 normal = dr::OutwardFaceNormal(corners, face);
    return (1.0 / dr::Norm(normal)) * normal;
  };
  const double      third = 1.0 / std::sqrt(3.0);
  const dr::Vector3 expected[] = {
    { { third, third, third } }, { { -1.0, 0.0, 0.0 } }, { { 0.0, -1.0, 0.0 } }, { { 0.0, 0.0, -1.0 } }
  };
  for (int face = 0; face < 4; ++face)
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      EXPECT_NEAR(direction(face)[axis], expected[face][axis], 1e-15) << "face " << face << ", axis " << axis;
    }
  }
}

TEST(TetrahedronMeasures, DihedralAnglesOfTheCubeCornerAndTheRegularTetrahedron)
{
  std::array<double, 6> corner = dr::DihedralAngles(CubeCorner());
  std::sort(corner.begin(), corner.end());
  for (int k = 0; k < 3; ++k)
  {
    EXPECT_NEAR(corner[k], cubeCornerSlantedAngle, 1e-12);
    EXPECT_NEAR(corner[k + 3], 90.0, 1e-12);
  }
  EXPECT_NEAR(dr::MinimumDihedralAngle(CubeCorner()), cubeCornerSlantedAngle, 1e-12);
  EXPECT_NEAR(dr::CosineOfSmallestDihedralAngle(CubeCorner()), 1.0 / std::sqrt(3.0), 1e-15);
  for (const double angle : dr::DihedralAngles(RegularTetrahedron()))
  {
    EXPECT_NEAR(angle, regularDihedralAngle, 1e-12);
  }
  EXPECT_NEAR(dr::CosineOfSmallestDihedralAngle(RegularTetrahedron()), 1.0 / 3.0, 1e-15);

  // A sliver: the corners of a unit square, one diagonal lifted by 0.01 and the other lowered. The faces at a side
  // of the square, say from (0, 0, 0.01) to (1, 0, -0.01), have normals (0.02, -0.02, 1) and (0.02, 0.02, 1) (cross
  // products of the side with the edges to the two other corners): the dihedral angle there is the angle between them,
  // arccos(1 / 1.0008) = 2.29°, the same at the four sides; at the two diagonals it is 180° less twice that.
  const std::array<dr::Vector3, 4> sliver{ dr::Vector3{ { 0.0, 0.0, 0.01 } },
                                           dr::Vector3{ { 1.0, 1.0, 0.01 } },
                                           dr::Vector3{ { 1.0, 0.0, -0.01 } },
                                           dr::Vector3{ { 0.0, 1.0, -0.01 } } };
  const double                     expectedSmallest = dr::RadiansToDegrees(std::acos(1.0 / 1.0008));
  EXPECT_NEAR(dr::MinimumDihedralAngle(sliver), expectedSmallest, 1e-10);
  EXPECT_NEAR(dr::CosineOfSmallestDihedralAngle(sliver), std::cos(dr::DegreesToRadians(expectedSmallest)), 1e-13);
}

/** σ = 0 turns the bound off whatever the tetrahedron; otherwise a tetrahedron is a sliver exactly when its smallest
 * dihedral angle is below σ. */
TEST(TetrahedronMeasures, DihedralAngleBoundSplitsAtSigma)
{
  const std::array<dr::Vector3, 4> flat{ dr::Vector3{ { 0.0, 0.0, 0.0 } },
                                         dr::Vector3{ { 1.0, 1.0, 0.0 } },
                                         dr::Vector3{ { 1.0, 0.0, 0.0 } },
                                         dr::Vector3{ { 0.0, 1.0, 0.0 } } };
  const dr::DihedralAngleBound     off(0.0);
  EXPECT_FALSE(off.IsOn());
  EXPECT_FALSE(off.IsSliver(flat));
  EXPECT_FALSE(off.IsSliver(CubeCorner()));

  const dr::DihedralAngleBound fifteen(15.0);
  EXPECT_TRUE(fifteen.IsOn());
  EXPECT_TRUE(fifteen.IsSliver(flat));
  EXPECT_FALSE(fifteen.IsSliver(CubeCorner()));
  EXPECT_FALSE(fifteen.IsSliver(RegularTetrahedron()));
  EXPECT_TRUE(fifteen.IsReachedBy(std::cos(dr::DegreesToRadians(15.0))));
  EXPECT_TRUE(fifteen.IsReachedBy(std::cos(dr::DegreesToRadians(15.001))));
  EXPECT_FALSE(fifteen.IsReachedBy(std::cos(dr::DegreesToRadians(14.999))));

  // Just above and just below the cube corner's smallest angle: it is a sliver for the first bound only.
  EXPECT_TRUE(dr::DihedralAngleBound(cubeCornerSlantedAngle + 1e-6).IsSliver(CubeCorner()));
  EXPECT_FALSE(dr::DihedralAngleBound(cubeCornerSlantedAngle - 1e-6).IsSliver(CubeCorner()));
  EXPECT_TRUE(dr::DihedralAngleBound(regularDihedralAngle + 1e-6).IsSliver(RegularTetrahedron()));
  EXPECT_FALSE(dr::DihedralAngleBound(regularDihedralAngle - 1e-6).IsSliver(RegularTetrahedron()));
}

/** R4's test against the regular tetrahedron's radius-edge ratio √3/2 / √2 = √6 / 4 = 0.6124: a bound at the ratio
 * is reached, to rounding (1e-12); one a millionth above it is not, nor one 1e-11 above it (beyond the margin). */
TEST(TetrahedronMeasures, RadiusEdgeBoundIsReachedAtTheRatioWithinRounding)
{
  const std::array<dr::Vector3, 4> corners = RegularTetrahedron();
  const double                     squaredCircumradius = 0.75;
  const double                     ratio = std::sqrt(6.0) / 4.0;
  EXPECT_NEAR(dr::RadiusEdgeRatio(corners), ratio, 1e-15);
  EXPECT_TRUE(dr::ReachesRadiusEdgeBound(squaredCircumradius, corners, ratio));
  EXPECT_TRUE(dr::ReachesRadiusEdgeBound(squaredCircumradius, corners, ratio * (1.0 + 1e-13)))
    << "within rounding of the bound counts as reaching it";
  EXPECT_FALSE(dr::ReachesRadiusEdgeBound(squaredCircumradius, corners, ratio * (1.0 + 1e-11)));
  EXPECT_FALSE(dr::ReachesRadiusEdgeBound(squaredCircumradius, corners, ratio * (1.0 + 1e-6)));
  EXPECT_TRUE(dr::ReachesRadiusEdgeBound(squaredCircumradius, corners, 0.5));
  EXPECT_FALSE(dr::ReachesRadiusEdgeBound(squaredCircumradius, corners, 2.0));

  // The cube corner: circumradius √3 / 2 over its shortest edge 1.
  EXPECT_NEAR(dr::RadiusEdgeRatio(CubeCorner()), std::sqrt(3.0) / 2.0, 1e-15);
  const dr::Vector3 center = dr::TetrahedronCircumcenter(CubeCorner());
  for (int axis = 0; axis < 3; ++axis)
  {
    EXPECT_NEAR(center[axis], 0.5, 1e-15);
  }
}

/** Flat to rounding below 1e-5 × the shortest edge cubed: the regular tetrahedron is 1 / (6 √2) = 0.1179; the
 * cube corner with its apex moved to (1, 1, h) has volume h / 6 and shortest edge 1 (every edge to the apex is
 * longer than 1). */
TEST(TetrahedronMeasures, FlatToRoundingBelowTheVolumeFraction)
{
  EXPECT_NEAR(dr::VolumeOverShortestEdgeCubed(RegularTetrahedron()), 1.0 / (6.0 * std::sqrt(2.0)), 1e-15);
  const auto apexAtHeight = [](double height) {
    std::array<dr::Vector3, 4> corners = CubeCorner();
    corners[3] = dr::Vector3{ { 1.0, 1.0, height } };
    return corners;
  };
  EXPECT_NEAR(dr::VolumeOverShortestEdgeCubed(apexAtHeight(0.3)), 0.3 / 6.0, 1e-15);
  EXPECT_FALSE(dr::IsFlatToRounding(apexAtHeight(6.0 * dr::FlatVolumeFraction * 1.01)));
  EXPECT_TRUE(dr::IsFlatToRounding(apexAtHeight(6.0 * dr::FlatVolumeFraction * 0.99)));
  EXPECT_TRUE(dr::IsFlatToRounding(apexAtHeight(0.0)));
  EXPECT_FALSE(dr::IsFlatToRounding(RegularTetrahedron()));
}

/** Theorem 2's planar-angle bound: an isosceles triangle whose apex angle is its smallest is above 30° exactly when
 * the apex is, by the 1e-9° margin: 30° + 1e-8° passes, 30° itself and 30° + 1e-10° do not. Each corner in turn is
 * the apex, so a check of two corners only would pass one of them. */
TEST(TriangleMeasures, PlanarAnglesAbove30DegreesByTheMargin)
{
  const auto passes = [](double apexDegrees, int rotation) {
    std::array<dr::Vector3, 3> corners = IsoscelesTriangleWithApexAngle(apexDegrees);
    std::rotate(corners.begin(), corners.begin() + rotation, corners.end());
    return dr::HasPlanarAnglesAbove30Degrees(corners[0], corners[1], corners[2]);
  };
  for (int rotation = 0; rotation < 3; ++rotation)
  {
    EXPECT_TRUE(passes(60.0, rotation)) << rotation;
    EXPECT_TRUE(passes(30.0 + 1e-8, rotation)) << rotation;
    EXPECT_FALSE(passes(30.0 + 1e-10, rotation)) << rotation;
    EXPECT_FALSE(passes(30.0, rotation)) << rotation;
    EXPECT_FALSE(passes(29.0, rotation)) << rotation;
    EXPECT_FALSE(passes(125.0, rotation)) << "base angles of 27.5°, rotation " << rotation;
  }
  const std::array<dr::Vector3, 3> triangle = IsoscelesTriangleWithApexAngle(40.0);
  const std::array<double, 3>      angles = dr::PlanarAngles(triangle[0], triangle[1], triangle[2]);
  EXPECT_NEAR(angles[0], 40.0, 1e-12);
  EXPECT_NEAR(angles[1], 70.0, 1e-12);
  EXPECT_NEAR(angles[2], 70.0, 1e-12);
}

/** |ab| |bc| |ca| / (4 area): 2.5 for the 3-4-5 right triangle (half its hypotenuse); infinite for collinear or
 * coincident corners, never NaN, which a maximum would drop. */
TEST(TriangleMeasures, CircumradiusOfARightTriangleAndOfDegenerateOnes)
{
  const dr::Vector3 a{ { 0.0, 0.0, 0.0 } };
  const dr::Vector3 b{ { 3.0, 0.0, 0.0 } };
  const dr::Vector3 c{ { 3.0, 0.0, 4.0 } };
  EXPECT_DOUBLE_EQ(dr::TriangleCircumradius(a, b, c), 2.5);
  EXPECT_EQ(dr::TriangleCircumradius(a, b, dr::Vector3{ { 6.0, 0.0, 0.0 } }), std::numeric_limits<double>::infinity());
  EXPECT_EQ(dr::TriangleCircumradius(a, a, b), std::numeric_limits<double>::infinity());
  EXPECT_EQ(dr::TriangleCircumradius(a, a, a), std::numeric_limits<double>::infinity());
}
