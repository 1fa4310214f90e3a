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

// The sizing field (src/DelaunayRefinementSizing.h): which δ each reading of a zone gives. It has no CGAL type, so
// it is tested on points and balls made by hand.

#include "DelaunayRefinementSizing.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dr = delaunay_refinement;

namespace
{

constexpr double Delta = 1.0;

const dr::Vector3 ZoneCenter{ { 0.0, 0.0, 0.0 } };

/** A point `distance` from the zone's centre along x. */
dr::Vector3
AlongX(double distance)
{
  return dr::Vector3{ { distance, 0.0, 0.0 } };
}

} // namespace

/** A zone gives its δ to the points it holds, strictly inside, and R2's circumball reading is the same for a zone of
 * the default reach: a circumball that meets such a zone without its centre inside keeps δ. */
TEST(LocalSampling, APointZoneHoldsOnlyItsInterior)
{
  dr::detail::LocalSampling sizing(Delta);
  EXPECT_EQ(sizing.AddZone(ZoneCenter, 0.25, 0.75), 0.75);
  EXPECT_EQ(sizing.LocalDelta(AlongX(0.5)), 0.25);
  EXPECT_EQ(sizing.LocalDelta(AlongX(0.75)), Delta) << "the zone's sphere is outside it";
  EXPECT_EQ(sizing.LocalDelta(AlongX(0.8)), Delta);
  EXPECT_EQ(sizing.DeltaForCircumball(AlongX(0.5), 0.1), 0.25);
  EXPECT_EQ(sizing.DeltaForCircumball(AlongX(1.0), 0.9), Delta) << "a zone of the default reach reaches points only";
  EXPECT_EQ(sizing.FinestDelta(), 0.25);
}

/** A zone made for a part the refinement left without a tetrahedron gives its δ to every circumball that meets it
 * (the randomized SaltAndPepper 2060717's part sat in a tetrahedron whose circumcentre was outside its zone), to
 * balls that only touch it not, and to the points outside it not: R1 and R3 read it at their points as before. */
TEST(LocalSampling, ARescueZoneReachesEveryCircumballThatMeetsIt)
{
  dr::detail::LocalSampling sizing(Delta);
  sizing.AddZone(ZoneCenter, 0.125, 0.75, dr::detail::ZoneReach::Circumballs);
  EXPECT_EQ(sizing.DeltaForCircumball(AlongX(1.0), 0.9), 0.125) << "the ball reaches 0.1 into the zone";
  EXPECT_EQ(sizing.DeltaForCircumball(AlongX(1.06), 1.18), 0.125) << "the case's tetrahedron";
  EXPECT_EQ(sizing.DeltaForCircumball(AlongX(2.0), 1.25), Delta) << "a ball that touches the zone does not meet it";
  EXPECT_EQ(sizing.DeltaForCircumball(AlongX(2.0), 1.0), Delta);
  EXPECT_EQ(sizing.LocalDelta(AlongX(1.0)), Delta) << "points outside the zone keep δ";
  EXPECT_EQ(sizing.LocalDelta(AlongX(0.5)), 0.125);
}

/** The finest zone a circumball meets wins, whatever the order the zones were made in; a point zone that holds the
 * circumcentre still counts beside a rescue zone. */
TEST(LocalSampling, TheFinestZoneMetWins)
{
  dr::detail::LocalSampling sizing(Delta);
  sizing.AddZone(AlongX(3.0), 0.5, 1.0);
  sizing.AddZone(ZoneCenter, 0.25, 0.75, dr::detail::ZoneReach::Circumballs);
  sizing.AddZone(AlongX(-3.0), 0.0625, 0.5, dr::detail::ZoneReach::Circumballs);
  EXPECT_EQ(sizing.DeltaForCircumball(AlongX(3.0), 0.1), 0.5) << "the point zone holds the centre";
  EXPECT_EQ(sizing.DeltaForCircumball(AlongX(4.5), 0.6), Delta) << "it meets the point zone without its centre in it";
  EXPECT_EQ(sizing.DeltaForCircumball(AlongX(3.0), 2.5), 0.25) << "the ball also meets the rescue zone at 0";
  EXPECT_EQ(sizing.DeltaForCircumball(ZoneCenter, 2.9), 0.0625)
    << "the finer of the two rescue zones it meets; the point zone does not hold its centre";
}

/** A free vertex that R2 inserted for a circumball meeting a rescue zone lies outside that zone, and its edges are
 * bounded by the zone's δ only: the sampling distance exported for it must say so, or a check of every edge against
 * the exported sizing fails where the refinement kept its own bound (the randomized SaltAndPepper 2077343 has edges of
 * 1.87 between a feature vertex and such a free vertex, whose local δ read at its point was 2.35). A sample at a δ the
 * point already has is not recorded, and other points keep their local δ. */
TEST(LocalSampling, AFreeVertexOutsideTheZoneItWasInsertedForKeepsTheZonesDelta)
{
  dr::detail::LocalSampling sizing(Delta);
  sizing.AddZone(ZoneCenter, 0.125, 0.75, dr::detail::ZoneReach::Circumballs);
  const dr::Vector3 circumcenter = AlongX(1.0);
  const double      deltaUsed = sizing.DeltaForCircumball(circumcenter, 0.9);
  ASSERT_EQ(deltaUsed, 0.125);
  EXPECT_EQ(sizing.SamplingDistanceOf(circumcenter), Delta) << "nothing recorded yet";
  sizing.NoteFinerSample(circumcenter, deltaUsed);
  EXPECT_EQ(sizing.SamplingDistanceOf(circumcenter), 0.125);
  EXPECT_EQ(sizing.LocalDelta(circumcenter), Delta) << "the rules' reading at the point does not change";
  EXPECT_EQ(sizing.SamplingDistanceOf(AlongX(1.0 + 1e-12)), Delta) << "only the vertex itself";
  sizing.NoteFinerSample(circumcenter, 0.5);
  EXPECT_EQ(sizing.SamplingDistanceOf(circumcenter), 0.125) << "a coarser note does not undo a finer one";
  sizing.NoteFinerSample(AlongX(0.5), 0.125);
  sizing.NoteFinerSample(AlongX(0.5), 0.0625);
  EXPECT_EQ(sizing.SamplingDistanceOf(AlongX(0.5)), 0.0625) << "finer than the zone that holds it";
}

/** R3's feature vertex beside a zone of reach ZoneReach::Points, inserted at a facet's shortest edge: the note is kept
 * whatever zones exist (it was kept near zones of reach ZoneReach::Circumballs only). */
TEST(LocalSampling, AFinerSampleIsRecordedBesideAnyZone)
{
  dr::detail::LocalSampling sizing(Delta);
  sizing.AddZone(ZoneCenter, 0.25, 0.75);
  const dr::Vector3 beside = AlongX(1.0);
  ASSERT_EQ(sizing.LocalDelta(beside), Delta);
  sizing.NoteFinerSample(beside, 0.6);
  EXPECT_EQ(sizing.SamplingDistanceOf(beside), 0.6);
  EXPECT_EQ(sizing.LocalDelta(beside), Delta) << "the rules' reading at the point does not change";
}

/** A triangle keeps R1's bound as a boundary facet only when its circumradius is below the local δ at each of its
 * corners (LocalSampling::KeepsBoundaryFacetBound): a corner inside a finer zone brings the zone's δ, whichever
 * corner it is. An equilateral triangle of circumradius 0.5 centred 1 from the zone's centre, with one corner 0.5
 * from it (inside the zone of δ 0.25 and radius 0.75) and two 1.32 from it (outside), is wider than that corner's δ:
 * it must not be kept, whichever of the three corners is the one in the zone. Moved away from the zone, the same
 * triangle is below δ and kept; one wider than δ is not. */
TEST(LocalSampling, ABoundaryFacetKeepsItsBoundOnlyBelowTheDeltaAtEveryCorner)
{
  using dr::                operator+;
  using dr::                operator-;
  using dr::                operator*;
  dr::detail::LocalSampling sizing(Delta);
  sizing.AddZone(ZoneCenter, 0.25, 0.75);
  const double      halfSide = 0.5 * std::sqrt(3.0) / 2.0;
  const dr::Vector3 inZone = AlongX(0.5);
  const dr::Vector3 outside1{ { 1.25, halfSide, 0.0 } };
  const dr::Vector3 outside2{ { 1.25, -halfSide, 0.0 } };
  ASSERT_EQ(sizing.LocalDelta(inZone), 0.25);
  ASSERT_EQ(sizing.LocalDelta(outside1), Delta);
  ASSERT_EQ(sizing.LocalDelta(outside2), Delta);
  EXPECT_FALSE(sizing.KeepsBoundaryFacetBound(inZone, outside1, outside2));
  EXPECT_FALSE(sizing.KeepsBoundaryFacetBound(outside1, inZone, outside2));
  EXPECT_FALSE(sizing.KeepsBoundaryFacetBound(outside1, outside2, inZone));

  const dr::Vector3 away{ { 10.0, 0.0, 0.0 } };
  EXPECT_TRUE(sizing.KeepsBoundaryFacetBound(inZone + away, outside1 + away, outside2 + away));
  // Circumradius 1.1 > δ: the triangle above scaled by 2.2 about its centre, away from the zone.
  EXPECT_FALSE(sizing.KeepsBoundaryFacetBound(
    away + 2.2 * (inZone - AlongX(1.0)), away + 2.2 * (outside1 - AlongX(1.0)), away + 2.2 * (outside2 - AlongX(1.0))));
}
