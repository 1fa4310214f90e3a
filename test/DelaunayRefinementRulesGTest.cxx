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

// The rules R1 and R2 (src/DelaunayRefinementRules.h, docs/algorithm.md, "Rules"), with and without zones of finer
// sampling, and R3's threshold, asked of one tetrahedron made by hand: four points whose circumsphere is known, inside
// a box far larger than it (so that the four make a cell of the Delaunay triangulation), near the top of a ball of
// radius 100 (the surface z = 0 there, to 1e-2 over the tetrahedron). The whole refinement would hide which rule fired:
// a rule that splits too early or too late changes the mesh, not a guarantee the meshes are checked for. R4′'s move of
// a corner of a tetrahedron flat to rounding (src/DelaunayRefinementSliverPerturbation.h) is asked of one made by hand
// on the same surface, for the same reason, and its move of a sliver's corner along the surface of one made by hand on
// the rim of the genus-2 plate; R4′'s choice of a split point (src/DelaunayRefinementSliverSplit.h) of a sliver among
// cells labelled by hand.

#include "DelaunayRefinementAnalyticOracles.h"
#include "DelaunayRefinementBoxProtection.h"
#include "DelaunayRefinementHandMadeCube.h"
#include "DelaunayRefinementMeshState.h"
#include "DelaunayRefinementRules.h"
#include "DelaunayRefinementSizing.h"
#include "DelaunayRefinementSliverPerturbation.h"
#include "DelaunayRefinementSliverSplit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace dr = delaunay_refinement;
using dr::detail::CellHandle;
using dr::detail::Rule;

namespace
{

constexpr double Delta = 1.0;

/** δ, ρ = 2 and σ = 0: the paper's method, whose rules the tests work out by hand. */
dr::RefinementParameters
PaperParameters(double delta)
{
  dr::RefinementParameters parameters;
  parameters.surfaceSamplingDistance = delta;
  parameters.radiusEdgeBound = 2.0;
  parameters.minimumDihedralAngle = 0.0;
  return parameters;
}

/** A tetrahedron with circumcentre (0, 0, `height`) and circumradius `radius`: its lowest corner (0, 0, height -
 * radius), a feature vertex, and an equilateral triangle of free vertices on the horizontal great circle. The surface
 * is the top of a ball of radius 100 centred at (0, 0, -100): the closest surface point to the circumcentre is the
 * origin, and the circumcentre is `height` from the surface. */
class HandMadeTetrahedron
{
public:
  HandMadeTetrahedron(double height, double radius)
    : m_Oracle(dr::Vector3{ { 0.0, 0.0, -100.0 } }, 100.0)
    , m_Parameters(PaperParameters(Delta))
    , m_State(m_Oracle, m_Parameters)
    , m_Sizing(Delta)
  {
    StartWithCubeCorners(m_State, BoxHalfSide);
    m_Box.lower = { { -BoxHalfSide, -BoxHalfSide, -BoxHalfSide } };
    m_Box.upper = { { BoxHalfSide, BoxHalfSide, BoxHalfSide } };
    std::vector<dr::detail::VertexHandle> vertices;
    const auto                            insert = [&](const dr::Vector3 & point, dr::VertexKind kind) {
      const std::optional<dr::detail::VertexHandle> vertex = m_State.InsertVertex(point, kind, CellHandle());
      ASSERT_TRUE(vertex.has_value());
      vertices.push_back(*vertex);
    };
    insert({ { 0.0, 0.0, height - radius } }, dr::VertexKind::Feature);
    for (int k = 0; k < 3; ++k)
    {
      const double angle = 2.0 * 3.14159265358979323846 * k / 3.0;
      insert({ { radius * std::cos(angle), radius * std::sin(angle), height } }, dr::VertexKind::Free);
    }
    for (auto cell = m_State.GetTriangulation().finite_cells_begin();
         cell != m_State.GetTriangulation().finite_cells_end();
         ++cell)
    {
      int found = 0;
      for (const auto & vertex : vertices)
      {
        found += cell->has_vertex(vertex) ? 1 : 0;
      }
      if (found == 4)
      {
        m_Cell = cell;
      }
    }
  }

  /** Which rule applies to the tetrahedron, if any; the test fails when the four points are no cell. */
  std::optional<dr::detail::Action>
  ApplicableRule() const
  {
    EXPECT_NE(m_Cell, CellHandle()) << "the four points make no cell";
    if (m_Cell == CellHandle())
    {
      return std::nullopt;
    }
    const dr::detail::RefinementRules rules(
      m_Oracle, m_Parameters, m_State, m_Sizing, m_Box, dr::detail::RefinementTestHooks{});
    return rules.FindApplicableRule(m_Cell);
  }

  /** R3's threshold for a restricted facet with corners `a`, `b`, `c` whose surface ball is centred at `center`. */
  double
  SurfaceBallThreshold(const dr::Vector3 & center, const dr::Vector3 & a, const dr::Vector3 & b,
                       const dr::Vector3 & c) const
  {
    const dr::detail::RefinementRules rules(
      m_Oracle, m_Parameters, m_State, m_Sizing, m_Box, dr::detail::RefinementTestHooks{});
    return rules.SurfaceBallThreshold(center, a, b, c);
  }

  /** A zone of finer sampling, as the refiner makes around a thin part (LocalSampling::AddZone). */
  void
  AddZone(const dr::Vector3 & center, double delta, double radius, dr::detail::ZoneReach reach)
  {
    m_Sizing.AddZone(center, delta, radius, reach);
  }

private:
  static constexpr double BoxHalfSide = 50.0;

  dr::SphereOracle          m_Oracle;
  dr::RefinementParameters  m_Parameters;
  dr::detail::MeshState     m_State;
  dr::detail::LocalSampling m_Sizing;
  dr::AxisAlignedBox        m_Box;
  CellHandle                m_Cell;
};

} // namespace

/** R2 splits an intersecting tetrahedron whose circumradius reaches 3δ (IntersectingCircumradiusFactor), and no
 * smaller one: circumradii 2 and 2.9 (both circumspheres meet the surface, and a feature vertex lies within δ of the
 * surface point closest to the circumcentre, so R1 does not apply) leave R2 out; 3.2 and 4 call for it, at the
 * circumcentre. Without the square on the bound (r² against 3δ) every one of them would be split. */
TEST(RefinementRules, R2SplitsAnIntersectingTetrahedronFromThreeDeltaOnly)
{
  for (const double radius : { 2.0, 2.9 })
  {
    SCOPED_TRACE(radius);
    // The lowest corner is 0.5 below the closest surface point: within δ of it.
    const HandMadeTetrahedron               tetrahedron(radius - 0.5, radius);
    const std::optional<dr::detail::Action> action = tetrahedron.ApplicableRule();
    EXPECT_TRUE(!action || (action->rule != Rule::R2 && action->rule != Rule::R1))
      << "rule " << static_cast<int>(action->rule);
  }
  for (const double radius : { 3.2, 4.0 })
  {
    SCOPED_TRACE(radius);
    const HandMadeTetrahedron               tetrahedron(radius - 0.5, radius);
    const std::optional<dr::detail::Action> action = tetrahedron.ApplicableRule();
    ASSERT_TRUE(action.has_value());
    EXPECT_EQ(action->rule, Rule::R2);
    EXPECT_NEAR(action->point[2], radius - 0.5, 1e-12);
  }
}

/** R2 reads the δ of a zone of finer sampling: the circumradius 2 of the tetrahedron below (circumcentre 1.5 above the
 * surface, a feature vertex 0.5 below the surface point closest to it, so R1 stays out) is under 3δ but reaches 3 ×
 * 0.5, the δ of a zone around its circumcentre. A zone of reach ZoneReach::Circumballs counts once it meets the
 * circumball, although the circumcentre is outside it (LocalSampling::DeltaForCircumball: a part inside another
 * label's tetrahedron, docs/algorithm.md, "Topology"); a zone that only holds points counts only where it holds the
 * circumcentre. R2 reading δ alone, or the δ at the circumcentre alone, splits none of these or both. */
TEST(RefinementRules, R2ReadsTheDeltaOfAZoneItsCircumballMeets)
{
  constexpr double  ZoneDelta = 0.5;
  constexpr double  ZoneRadius = 1.0;
  const dr::Vector3 circumcenter{ { 0.0, 0.0, 1.5 } };
  const dr::Vector3 zoneAboveTheCircumcenter{ { 0.0, 0.0, 4.0 } }; // 2.5 from it: within 2 + 1, beyond 1
  using dr::detail::ZoneReach;
  {
    SCOPED_TRACE("a zone holding the circumcentre");
    HandMadeTetrahedron tetrahedron(1.5, 2.0);
    tetrahedron.AddZone(circumcenter, ZoneDelta, ZoneRadius, ZoneReach::Points);
    const std::optional<dr::detail::Action> action = tetrahedron.ApplicableRule();
    ASSERT_TRUE(action.has_value());
    EXPECT_EQ(action->rule, Rule::R2);
    EXPECT_NEAR(dr::Distance(action->point, circumcenter), 0.0, 1e-12);
  }
  {
    SCOPED_TRACE("a zone of reach Circumballs meeting the circumball");
    HandMadeTetrahedron tetrahedron(1.5, 2.0);
    tetrahedron.AddZone(zoneAboveTheCircumcenter, ZoneDelta, ZoneRadius, ZoneReach::Circumballs);
    const std::optional<dr::detail::Action> action = tetrahedron.ApplicableRule();
    ASSERT_TRUE(action.has_value());
    EXPECT_EQ(action->rule, Rule::R2);
    EXPECT_NEAR(dr::Distance(action->point, circumcenter), 0.0, 1e-12);
  }
  {
    SCOPED_TRACE("a zone of reach Points meeting the circumball only");
    HandMadeTetrahedron tetrahedron(1.5, 2.0);
    tetrahedron.AddZone(zoneAboveTheCircumcenter, ZoneDelta, ZoneRadius, ZoneReach::Points);
    const std::optional<dr::detail::Action> action = tetrahedron.ApplicableRule();
    EXPECT_TRUE(!action || (action->rule != Rule::R2 && action->rule != Rule::R1))
      << "rule " << static_cast<int>(action->rule);
  }
}

/** R3 splits a restricted facet whose smallest angle is within the margin of the 30° bound's checks
 * (PlanarAngleBoundMarginDegrees), since its threshold (the facet's shortest edge where that is below δ) is shortened
 * by ShortestEdgeFactorForPlanarAngleMargin; a facet clearly above 30° stays. An isosceles triangle of apex angle θ has
 * circumradius R = shortest edge / (2 sin θ), and its surface ball centred at its circumcentre has radius R: at θ =
 * 30° + half the margin R falls short of the shortest edge by 1.5e-11 of it, so a threshold of the shortest edge itself
 * would keep the triangle, which every check of the bound then rejects (the voxel lattice makes such ties: the
 * randomized ManyLabels 5045684 once kept one of 29.99999999999974°). */
TEST(RefinementRules, R3SplitsAFacetWithinTheMarginOfThirtyDegrees)
{
  const HandMadeTetrahedron tetrahedron(1.5, 2.0); // any: the threshold reads the sizing only
  const auto                ballOfTriangleWithApexAngle = [&](double apexDegrees) {
    constexpr double  Pi = 3.14159265358979323846;
    constexpr double  Leg = 0.1; // every edge below δ = 1, so the shortest edge sets the threshold
    const double      half = 0.5 * apexDegrees * Pi / 180.0;
    const dr::Vector3 a{ { 0.0, 0.0, 0.0 } };
    const dr::Vector3 b{ { Leg * std::cos(half), Leg * std::sin(half), 0.0 } };
    const dr::Vector3 c{ { Leg * std::cos(half), -Leg * std::sin(half), 0.0 } };
    // The circumcentre lies on the axis of symmetry, R from a: R = Leg / (2 cos(θ / 2)).
    const double      radius = Leg / (2.0 * std::cos(half));
    const dr::Vector3 center{ { radius, 0.0, 0.0 } };
    EXPECT_NEAR(dr::Distance(center, b), radius, 1e-15);
    return std::make_pair(radius, tetrahedron.SurfaceBallThreshold(center, a, b, c));
  };
  {
    const auto [radius, threshold] = ballOfTriangleWithApexAngle(30.0 + 0.5 * dr::PlanarAngleBoundMarginDegrees);
    EXPECT_GE(radius, threshold) << "R3 keeps a facet of 30° + half the margin";
  }
  {
    const auto [radius, threshold] = ballOfTriangleWithApexAngle(30.0 + 1e-6);
    EXPECT_LT(radius, threshold) << "R3 splits a facet of 30.000001°";
  }
}

/** R1 and R3 read the δ of a zone of finer sampling where their point lies, as R2 does (the zones sample small parts of
 * the labels finely, docs/algorithm.md, "Local sampling distance"). R1: a feature vertex 0.75 below the surface point
 * closest to the circumcentre keeps R1 out at δ = 1, not inside a zone of δ 0.5 around that surface point. R3: the
 * threshold of a facet whose edges are all longer than δ is the local δ at its surface ball's centre, with
 * LatticeTieMargin, inside a zone and outside it. */
TEST(RefinementRules, ROneAndRThreeReadTheDeltaOfTheZoneTheirPointLiesIn)
{
  constexpr double  ZoneDelta = 0.5;
  const dr::Vector3 surfacePoint{ { 0.0, 0.0, 0.0 } };
  {
    SCOPED_TRACE("R1 without a zone");
    const HandMadeTetrahedron               tetrahedron(1.0, 1.75);
    const std::optional<dr::detail::Action> action = tetrahedron.ApplicableRule();
    EXPECT_TRUE(!action || action->rule != Rule::R1) << "R1 at a surface point 0.75 from a feature vertex";
  }
  {
    SCOPED_TRACE("R1 in a zone of delta 0.5");
    HandMadeTetrahedron tetrahedron(1.0, 1.75);
    tetrahedron.AddZone(surfacePoint, ZoneDelta, 0.5, dr::detail::ZoneReach::Points);
    const std::optional<dr::detail::Action> action = tetrahedron.ApplicableRule();
    ASSERT_TRUE(action.has_value());
    EXPECT_EQ(action->rule, Rule::R1);
    EXPECT_NEAR(dr::Norm(action->point), 0.0, 1e-12) << "the surface point closest to the circumcentre";
    EXPECT_EQ(action->localDelta, ZoneDelta);
  }
  // An equilateral facet of side 3, longer than δ: the δ term of the threshold binds.
  const dr::Vector3   a{ { 0.0, 0.0, 0.0 } };
  const dr::Vector3   b{ { 3.0, 0.0, 0.0 } };
  const dr::Vector3   c{ { 1.5, 1.5 * std::sqrt(3.0), 0.0 } };
  const dr::Vector3   inside{ { 10.0, 10.0, 10.0 } };
  const dr::Vector3   outside{ { 10.0, 10.0, 12.0 } };
  HandMadeTetrahedron tetrahedron(1.5, 2.0);
  tetrahedron.AddZone(inside, ZoneDelta, 1.0, dr::detail::ZoneReach::Points);
  EXPECT_DOUBLE_EQ(tetrahedron.SurfaceBallThreshold(inside, a, b, c), ZoneDelta * (1.0 + dr::LatticeTieMargin));
  EXPECT_DOUBLE_EQ(tetrahedron.SurfaceBallThreshold(outside, a, b, c), Delta * (1.0 + dr::LatticeTieMargin));
}

/** R1 inserts the surface point closest to an intersecting tetrahedron's circumcentre unless a feature vertex lies
 * within δ of it, and a feature vertex δ away counts as within, with a margin of LatticeTieMargin (docs/algorithm.md,
 * "Rules": the lattice puts surface points exactly δ apart, and Lemma 2 keeps feature vertices at least δ apart): a
 * feature vertex δ and δ (1 + 5e-5) from the surface point keeps R1 out, one δ (1 + 2e-4) away does not. */
TEST(RefinementRules, R1CountsAFeatureVertexDeltaAwayAsWithinDelta)
{
  for (const double distance : { Delta, Delta * (1.0 + 5e-5) })
  {
    SCOPED_TRACE(distance);
    // Circumcentre 1 above the surface, lowest corner `distance` below it: circumradius 1 + distance < 3δ.
    const HandMadeTetrahedron               tetrahedron(1.0, 1.0 + distance);
    const std::optional<dr::detail::Action> action = tetrahedron.ApplicableRule();
    EXPECT_TRUE(!action || action->rule != Rule::R1)
      << "R1 at a surface point " << distance << " from a feature vertex";
  }
  const HandMadeTetrahedron               tetrahedron(1.0, 1.0 + Delta * (1.0 + 2e-4));
  const std::optional<dr::detail::Action> action = tetrahedron.ApplicableRule();
  ASSERT_TRUE(action.has_value());
  EXPECT_EQ(action->rule, Rule::R1);
  EXPECT_NEAR(dr::Norm(action->point), 0.0, 1e-12) << "the surface point closest to the circumcentre";
}

namespace
{

using dr::detail::SliverPerturbation;

/** An outcome's name, for readable failures. */
const char *
NameOf(SliverPerturbation::Outcome outcome)
{
  switch (outcome)
  {
    case SliverPerturbation::Outcome::Moved:
      return "Moved";
    case SliverPerturbation::Outcome::Undone:
      return "Undone";
    case SliverPerturbation::Outcome::NotTried:
      return "NotTried";
  }
  return "?";
}

/** The cell whose corners are `corners`, if there is one. */
CellHandle
CellWithCorners(const dr::detail::MeshState & state, const std::array<dr::Vector3, 4> & corners)
{
  for (auto cell = state.GetTriangulation().finite_cells_begin(); cell != state.GetTriangulation().finite_cells_end();
       ++cell)
  {
    const std::array<dr::Vector3, 4> own = state.CornersOf(cell);
    if (std::all_of(corners.begin(), corners.end(), [&own](const dr::Vector3 & corner) {
          return std::find(own.begin(), own.end(), corner) != own.end();
        }))
    {
      return cell;
    }
  }
  return CellHandle();
}

/** The feature vertices at none of `places`: the moved one, after a move. */
std::vector<dr::detail::VertexHandle>
FeatureVerticesAwayFrom(const dr::detail::MeshState & state, const std::vector<dr::Vector3> & places)
{
  std::vector<dr::detail::VertexHandle> away;
  for (auto vertex = state.GetTriangulation().finite_vertices_begin();
       vertex != state.GetTriangulation().finite_vertices_end();
       ++vertex)
  {
    if (vertex->info().kind == dr::VertexKind::Feature &&
        std::find(places.begin(), places.end(), state.PointOf(vertex)) == places.end())
    {
      away.push_back(vertex);
    }
  }
  return away;
}

/** The largest cosine of a smallest dihedral angle among the tissue (label 1) cells at `vertex`. */
double
LargestTissueCosineAround(const dr::detail::MeshState & state, dr::detail::VertexHandle vertex)
{
  std::vector<CellHandle> star;
  state.GetTriangulation().incident_cells(vertex, std::back_inserter(star));
  double largest = -1.0;
  for (const CellHandle cell : star)
  {
    if (!state.GetTriangulation().is_infinite(cell) && cell->cache.label != dr::BackgroundLabel)
    {
      largest = std::max(largest, dr::CosineOfSmallestDihedralAngle(state.CornersOf(cell)));
    }
  }
  return largest;
}

/** Four feature vertices on the top of the ball of radius 100 centred at (0, 0, -100), at (±1, 0) and (0, ±1) on one
 * horizontal circle of the sphere, the last raised by 1e-7: a tetrahedron of volume 3e-8 against its shortest edge
 * √2 cubed, flat to rounding (FlatVolumeFraction 1e-5), with its circumcentre 1e-7 / 2 above the circle's centre,
 * inside the ball (label 1). The unit ball around it holds no other vertex (the box's corners are 25 away), so the
 * four make a cell. The cells the box's corners make with them are large and cross the surface far from the four,
 * where no feature vertex is within δ: R1 applies to them (to every cell of this triangulation), and to the cells a
 * move of a corner creates, so the full acceptance test refuses every move. */
/** The refinement's state, rules and R4′ moves over a Delaunay triangulation of hand-placed vertices in a box
 * around `bounds`, on `TOracle`'s surface: what each hand-made fixture below builds around its own points. */
template <typename TOracle>
class HandMadeTriangulation
{
public:
  HandMadeTriangulation(const TOracle & oracle, const dr::RefinementParameters & parameters,
                        const dr::AxisAlignedBox & bounds, const std::vector<dr::Vector3> & featurePoints,
                        const std::vector<dr::Vector3> & freePoints)
    : m_Oracle(oracle)
    , m_Parameters(parameters)
    , m_State(m_Oracle, m_Parameters)
    , m_Sizing(parameters.surfaceSamplingDistance)
    , m_Box(m_State, parameters.surfaceSamplingDistance, m_Statistics)
  {
    m_State.SetNewCellsHook([](const std::vector<CellHandle> &) {});
    m_Box.CreateBox(bounds);
    for (const dr::Vector3 & point : featurePoints)
    {
      EXPECT_TRUE(m_State.InsertVertex(point, dr::VertexKind::Feature, CellHandle()).has_value());
    }
    for (const dr::Vector3 & point : freePoints)
    {
      EXPECT_TRUE(m_State.InsertVertex(point, dr::VertexKind::Free, CellHandle()).has_value());
    }
    m_Rules.emplace(m_Oracle, m_Parameters, m_State, m_Sizing, m_Box.Box(), dr::detail::RefinementTestHooks{});
    m_Perturbation.emplace(m_Oracle, m_Parameters, m_State, *m_Rules, m_Sizing, m_Box);
  }
  HandMadeTriangulation(const HandMadeTriangulation &) = delete;
  HandMadeTriangulation &
  operator=(const HandMadeTriangulation &) = delete;

  const TOracle &
  Oracle() const
  {
    return m_Oracle;
  }

  const dr::detail::MeshState &
  State() const
  {
    return m_State;
  }

  const dr::detail::RefinementRules &
  Rules() const
  {
    return *m_Rules;
  }

  SliverPerturbation &
  Perturbation()
  {
    return *m_Perturbation;
  }

  dr::detail::BoxProtection &
  BoxRules()
  {
    return m_Box;
  }

  const dr::detail::BoxProtection &
  BoxRules() const
  {
    return m_Box;
  }

  const dr::RefinementStatistics &
  Statistics() const
  {
    return m_Statistics;
  }

private:
  TOracle                                    m_Oracle;
  dr::RefinementParameters                   m_Parameters;
  dr::detail::MeshState                      m_State;
  dr::detail::LocalSampling                  m_Sizing;
  dr::RefinementStatistics                   m_Statistics;
  dr::detail::BoxProtection                  m_Box;
  std::optional<dr::detail::RefinementRules> m_Rules;
  std::optional<SliverPerturbation>          m_Perturbation;
};

class HandMadeFlatTetrahedron
{
public:
  static constexpr double Delta = 0.5;

  HandMadeFlatTetrahedron()
    : m_Made(dr::SphereOracle(dr::Vector3{ { 0.0, 0.0, -100.0 } }, 100.0), PaperParameters(Delta), Bounds(),
             CornerPoints(), {})
  {}

  static std::array<dr::Vector3, 4>
  Corners()
  {
    // The sphere's height at distance 1 from the axis.
    const double z = std::sqrt(100.0 * 100.0 - 1.0) - 100.0;
    return { { { { 1.0, 0.0, z } }, { { 0.0, 1.0, z } }, { { -1.0, 0.0, z } }, { { 0.0, -1.0, z + 1e-7 } } } };
  }

  /** The cell whose corners are Corners(), if it is still there. */
  CellHandle
  FlatCell() const
  {
    return CellWithCorners(m_Made.State(), Corners());
  }

  /** The feature vertices that are not at one of Corners(): the moved one, after a move. */
  std::vector<dr::detail::VertexHandle>
  MovedFeatureVertices() const
  {
    const std::array<dr::Vector3, 4> corners = Corners();
    return FeatureVerticesAwayFrom(m_Made.State(), { corners.begin(), corners.end() });
  }

  /** The largest cosine of a smallest dihedral angle among the tissue (label 1) cells at `vertex`. */
  double
  LargestCosineAround(dr::detail::VertexHandle vertex) const
  {
    return LargestTissueCosineAround(m_Made.State(), vertex);
  }

  /** The name of what R4′'s moves did to the flat tetrahedron, allowed acceptance levels up to `lastResort`. */
  std::string
  Perturb(SliverPerturbation::Acceptance lastResort)
  {
    return NameOf(m_Made.Perturbation().Perturb(FlatCell(), lastResort));
  }

  const dr::SphereOracle &
  Oracle() const
  {
    return m_Made.Oracle();
  }

private:
  static std::vector<dr::Vector3>
  CornerPoints()
  {
    const std::array<dr::Vector3, 4> corners = Corners();
    return { corners.begin(), corners.end() };
  }

  static dr::AxisAlignedBox
  Bounds()
  {
    dr::AxisAlignedBox bounds;
    bounds.lower = { { -10.0, -10.0, -10.0 } };
    bounds.upper = { { 10.0, 10.0, 10.0 } };
    return bounds;
  }

  HandMadeTriangulation<dr::SphereOracle> m_Made;
};

} // namespace

/** A tetrahedron flat to rounding left after the refinement gets its moves under an acceptance that relaxes in levels,
 * up to the level the caller allows, each tried with every candidate before the next (docs/algorithm.md, "R4′ picks
 * its point": first the full test, then one where R1-R4 may apply to the new tetrahedra). Here the full test refuses
 * every move (see HandMadeFlatTetrahedron), so allowed the full test only, the tetrahedron stays, the moves undone;
 * allowed the next level too (where a move may still make no vertex non-manifold, and may leave one as it was), a
 * surface corner moves along the surface, away from the others' centre by a small step (at most FlatStepFractions'
 * last, 1e-2 of the shortest edge), the flat tetrahedron is gone, and the tissue tetrahedra at the moved corner are all
 * better shaped than it was. */
TEST(SliverPerturbation, AFlatTetrahedronMovesAtTheLevelItIsAllowedOnly)
{
  const double shortestEdge = std::sqrt(2.0);
  {
    HandMadeFlatTetrahedron flat;
    ASSERT_NE(flat.FlatCell(), CellHandle()) << "the four points make no cell";
    ASSERT_EQ(flat.FlatCell()->cache.label, 1) << "the flat tetrahedron is not in the ball";
    ASSERT_TRUE(dr::IsFlatToRounding(HandMadeFlatTetrahedron::Corners()));
    EXPECT_EQ(flat.Perturb(SliverPerturbation::Acceptance::EveryRule), "Undone");
    EXPECT_NE(flat.FlatCell(), CellHandle()) << "a move the full test refuses was kept";
    EXPECT_TRUE(flat.MovedFeatureVertices().empty());
  }
  HandMadeFlatTetrahedron flat;
  const double            cosineBefore = dr::CosineOfSmallestDihedralAngle(HandMadeFlatTetrahedron::Corners());
  EXPECT_EQ(flat.Perturb(SliverPerturbation::Acceptance::RefinementMayFollow), "Moved");
  EXPECT_EQ(flat.FlatCell(), CellHandle()) << "the flat tetrahedron is still there";
  const std::vector<dr::detail::VertexHandle> moved = flat.MovedFeatureVertices();
  ASSERT_EQ(moved.size(), 1u);
  const dr::Vector3 point = dr::detail::ToVector(moved.front()->point());
  // On the surface, to the oracle's bisection tolerance.
  EXPECT_NEAR(dr::Distance(point, dr::Vector3{ { 0.0, 0.0, -100.0 } }), 100.0, flat.Oracle().SurfaceTolerance());
  // The corner it came from: the nearest one.
  const std::array<dr::Vector3, 4> corners = HandMadeFlatTetrahedron::Corners();
  const dr::Vector3                from =
    *std::min_element(corners.begin(), corners.end(), [&point](const dr::Vector3 & a, const dr::Vector3 & b) {
      return dr::Distance(point, a) < dr::Distance(point, b);
    });
  EXPECT_GT(dr::Distance(point, from), 0.0);
  EXPECT_LE(dr::Distance(point, from), 0.02 * shortestEdge) << "the corner moved more than a small step";
  // A flat tetrahedron's corner moves in its plane away from the others' centre (docs/algorithm.md, "R4′ picks its
  // point": that breaks the co-circularity), here along the sphere: off the circle, outwards.
  const double centroidX = 0.25 * (corners[0][0] + corners[1][0] + corners[2][0] + corners[3][0]);
  const double centroidY = 0.25 * (corners[0][1] + corners[1][1] + corners[2][1] + corners[3][1]);
  EXPECT_GT(std::hypot(point[0] - centroidX, point[1] - centroidY),
            std::hypot(from[0] - centroidX, from[1] - centroidY))
    << "the corner moved towards the others' centre";
  EXPECT_LT(flat.LargestCosineAround(moved.front()), cosineBefore) << "the move made a tissue cell no better";
}

namespace
{

/** A sliver of four surface vertices, which no move but one along the surface can remove, on the rim of the genus-2
 * plate (plate radius 200, thickness 25; its holes, at x = ±200, are far away): along the plate's straight side the
 * rim is the cylinder of radius 25 about the line y = 200, z = 0, whose points (x, 200 + u, z) with u² + z² = 25² are
 * integer for integer x. Surface vertices sit in rows along x at (u, z) = (25, 0), (24, ±7), (20, ±15) and (15, ±20),
 * the rows at x = 0, ±10, ±20 and at x = ±5, ±15 in turn; the top row's two at ±5 are pulled out to ±7, so that they
 * and the two at x = 0 of the rows (24, ±7) make a square, 1 deep across the surface: a sliver (smallest dihedral
 * angle 11.5°, below σ = 15°) whose circumsphere, of radius 7, holds no other vertex. Free vertices in the rows'
 * directions at radii 16 (inside the rim: tissue) and 34 (outside: background), rounded to integers, in the other
 * rows' places along x, close the stars of the sliver's corners with tetrahedra to which no rule but R4′ applies (δ =
 * 10, the rows' spacing; with σ > 0 a move need not keep Lemma 2's spacing). Every coordinate is an integer, so that
 * every face normal is exact: a surface normal that summed the boundary facets around a corner without turning them
 * from the smaller label towards the larger (each is seen from both of its cells) would be exactly zero, not a
 * rounding residue that may point anywhere. */
class HandMadeRimSliver
{
public:
  HandMadeRimSliver()
    : HandMadeRimSliver(Points())
  {}

  static std::array<dr::Vector3, 4>
  SliverCorners()
  {
    return { { { { -7.0, PlateRadius + 25.0, 0.0 } },
               { { 7.0, PlateRadius + 25.0, 0.0 } },
               { { 0.0, PlateRadius + 24.0, 7.0 } },
               { { 0.0, PlateRadius + 24.0, -7.0 } } } };
  }

  /** The distance from `point` to the rim's axis. */
  static double
  DistanceToTheAxis(const dr::Vector3 & point)
  {
    return std::hypot(point[1] - PlateRadius, point[2]);
  }

  CellHandle
  SliverCell() const
  {
    return CellWithCorners(m_Made.State(), SliverCorners());
  }

  std::optional<dr::detail::Action>
  ApplicableRule(CellHandle cell) const
  {
    return m_Made.Rules().FindApplicableRule(cell);
  }

  std::string
  Perturb()
  {
    return NameOf(m_Made.Perturbation().Perturb(SliverCell()));
  }

  std::vector<dr::detail::VertexHandle>
  MovedSurfaceVertices() const
  {
    return FeatureVerticesAwayFrom(m_Made.State(), m_SurfacePoints);
  }

  double
  LargestCosineAround(dr::detail::VertexHandle vertex) const
  {
    return LargestTissueCosineAround(m_Made.State(), vertex);
  }

  const dr::Genus2Oracle &
  Oracle() const
  {
    return m_Made.Oracle();
  }

  static constexpr double PlateRadius = 200.0;
  static constexpr double RimRadius = 25.0;

private:
  /** The surface points, in staggered rows along x on the rim, and the free points inside and outside it. */
  static std::pair<std::vector<dr::Vector3>, std::vector<dr::Vector3>>
  Points()
  {
    struct Row
    {
      double u;
      double z;
      bool   atTens;
    };
    std::pair<std::vector<dr::Vector3>, std::vector<dr::Vector3>> points;
    const std::array<Row, 7>                                      rows{ { { 25.0, 0.0, false },
                                                                          { 24.0, 7.0, true },
                                                                          { 24.0, -7.0, true },
                                                                          { 20.0, 15.0, false },
                                                                          { 20.0, -15.0, false },
                                                                          { 15.0, 20.0, true },
                                                                          { 15.0, -20.0, true } } };
    const std::vector<double>                                     tens{ -20.0, -10.0, 0.0, 10.0, 20.0 };
    const std::vector<double>                                     fives{ -15.0, -5.0, 5.0, 15.0 };
    for (const Row & row : rows)
    {
      for (const double x : row.atTens ? tens : fives)
      {
        const double pulled = row.u == RimRadius && std::abs(x) == 5.0 ? std::copysign(7.0, x) : x;
        points.first.push_back({ { pulled, PlateRadius + row.u, row.z } });
      }
      for (const double radius : { 16.0, 34.0 })
      {
        for (const double x : row.atTens ? fives : tens)
        {
          points.second.push_back(
            { { x, PlateRadius + std::round(row.u * radius / RimRadius), std::round(row.z * radius / RimRadius) } });
        }
      }
    }
    return points;
  }

  explicit HandMadeRimSliver(const std::pair<std::vector<dr::Vector3>, std::vector<dr::Vector3>> & points)
    : m_Made(RimOracle(), Parameters(), RimOracle().ObjectBounds(), points.first, points.second)
    , m_SurfacePoints(points.first)
  {}

  static dr::Genus2Oracle
  RimOracle()
  {
    return dr::Genus2Oracle(dr::Vector3{ { 0.0, 0.0, 0.0 } }, 200.0, PlateRadius, 50.0, RimRadius);
  }

  static dr::RefinementParameters
  Parameters()
  {
    dr::RefinementParameters parameters;
    parameters.surfaceSamplingDistance = 10.0;
    parameters.radiusEdgeBound = 2.0;
    parameters.minimumDihedralAngle = 15.0;
    return parameters;
  }

  HandMadeTriangulation<dr::Genus2Oracle> m_Made;
  std::vector<dr::Vector3>                m_SurfacePoints;
};

} // namespace

/** R4′ removes a sliver of surface vertices by moving one of its corners along the surface (docs/algorithm.md, "R4′
 * moves a vertex"): along the part of the sliver's height at that corner tangent to the surface, whose normal there
 * is estimated from the boundary facets around the corner, then back onto the surface along that normal. Here the
 * sliver's corners are all on the rim (see HandMadeRimSliver), so every move is one along it: the sliver is gone, one
 * corner moved by less than half the sliver's shortest edge (the steps are 0.2 and 0.4 of it) and lies on the rim
 * to the oracle's bisection tolerance, and the tissue tetrahedra at it are all better shaped than the sliver was. */
TEST(SliverPerturbation, ASliverOfSurfaceVerticesLosesACornerMovedAlongTheSurface)
{
  HandMadeRimSliver rim;
  ASSERT_NE(rim.SliverCell(), CellHandle()) << "the four points make no cell";
  ASSERT_EQ(rim.SliverCell()->cache.label, 1) << "the sliver is not in the rim";
  const std::optional<dr::detail::Action> action = rim.ApplicableRule(rim.SliverCell());
  ASSERT_TRUE(action.has_value());
  ASSERT_EQ(action->rule, Rule::R4Dihedral) << "the sliver is not R4′'s";
  const std::array<dr::Vector3, 4> corners = HandMadeRimSliver::SliverCorners();
  const double                     cosineBefore = dr::CosineOfSmallestDihedralAngle(corners);
  EXPECT_EQ(rim.Perturb(), "Moved");
  EXPECT_EQ(rim.SliverCell(), CellHandle()) << "the sliver is still there";
  const std::vector<dr::detail::VertexHandle> moved = rim.MovedSurfaceVertices();
  ASSERT_EQ(moved.size(), 1u);
  const dr::Vector3 point = dr::detail::ToVector(moved.front()->point());
  EXPECT_NEAR(
    HandMadeRimSliver::DistanceToTheAxis(point), HandMadeRimSliver::RimRadius, rim.Oracle().SurfaceTolerance());
  const double nearestCorner = dr::Distance(
    point, *std::min_element(corners.begin(), corners.end(), [&point](const dr::Vector3 & a, const dr::Vector3 & b) {
      return dr::Distance(point, a) < dr::Distance(point, b);
    }));
  EXPECT_GT(nearestCorner, 0.0);
  EXPECT_LT(nearestCorner, 0.5 * dr::ShortestEdgeLength(corners)) << "no corner of the sliver moved";
  EXPECT_LT(rim.LargestCosineAround(moved.front()), cosineBefore) << "the move made a tissue cell no better";
}

namespace
{

/** The box rules E1-E3 (src/DelaunayRefinementBoxProtection.h, docs/algorithm.md, "Box rules E1-E3") on the bare box
 * of the set-up, its eight corners the only vertices: the object's bounds [0, 4] x [0, 1] x [0, 1] at δ = 0.5 grow by
 * 3δ into the box [-1.5, 5.5] x [-1.5, 2.5] x [-1.5, 2.5], 7 x 4 x 4. Its faces are split into two right triangles
 * each, whose circumcentre is the face's centre. The meshes would hide a rule that protects the wrong edge or face:
 * the box is background, and only the number of vertices around it changes. */
class BareBox
{
public:
  static constexpr double Delta = 0.5;

  BareBox()
    : m_Made(dr::SphereOracle(dr::Vector3{ { 2.0, 0.5, 0.5 } }, 0.5), PaperParameters(Delta), Bounds(), {}, {})
  {}

  const dr::AxisAlignedBox &
  Box() const
  {
    return m_Made.BoxRules().Box();
  }

  /** Asks the box rules about a circumcentre `point` of the cell holding `inside`. */
  bool
  Protect(const dr::Vector3 & point, const dr::Vector3 & inside)
  {
    const CellHandle cell = m_Made.State().GetTriangulation().locate(dr::detail::ToCgal(inside));
    EXPECT_FALSE(m_Made.State().GetTriangulation().is_infinite(cell));
    return m_Made.BoxRules().ProtectBox(point, cell);
  }

  /** The vertices of `kind`, by position. */
  std::vector<dr::Vector3>
  VerticesOfKind(dr::VertexKind kind) const
  {
    std::vector<dr::Vector3>      points;
    const dr::detail::MeshState & state = m_Made.State();
    for (auto vertex = state.GetTriangulation().finite_vertices_begin();
         vertex != state.GetTriangulation().finite_vertices_end();
         ++vertex)
    {
      if (vertex->info().kind == kind)
      {
        points.push_back(state.PointOf(vertex));
      }
    }
    return points;
  }

  bool
  HasVertexAt(dr::VertexKind kind, const dr::Vector3 & point) const
  {
    const std::vector<dr::Vector3> points = VerticesOfKind(kind);
    return std::find(points.begin(), points.end(), point) != points.end();
  }

  const dr::RefinementStatistics &
  Statistics() const
  {
    return m_Made.Statistics();
  }

private:
  static dr::AxisAlignedBox
  Bounds()
  {
    dr::AxisAlignedBox bounds;
    bounds.lower = { { 0.0, 0.0, 0.0 } };
    bounds.upper = { { 4.0, 1.0, 1.0 } };
    return bounds;
  }

  HandMadeTriangulation<dr::SphereOracle> m_Made;
};

} // namespace

/** The box is the object's bounds grown by 3δ (docs/algorithm.md, "Set-up"), and E1 protects each of its 12 edges: a
 * circumcentre just outside the box beside an edge's midpoint (0.1 off both faces, deep inside that edge's diametral
 * ball and in no other edge's) makes E1 insert the midpoint as a box-edge vertex; then one beside the point a quarter
 * along the edge, inside the ball of the half subsegment only, makes it insert that quarter point: the first split was
 * recorded on the edge. */
TEST(BoxRules, E1SplitsEachOfTheTwelveEdgesAtItsSubsegmentsMidpoint)
{
  BareBox                  box;
  const dr::AxisAlignedBox expectedBox{ { { -1.5, -1.5, -1.5 } }, { { 5.5, 2.5, 2.5 } } };
  EXPECT_EQ(box.Box().lower, expectedBox.lower);
  EXPECT_EQ(box.Box().upper, expectedBox.upper);
  std::size_t edges = 0;
  for (int axis = 0; axis < 3; ++axis)
  {
    for (const double firstOther : { 0.0, 1.0 })
    {
      for (const double secondOther : { 0.0, 1.0 })
      {
        // The edge along `axis` at the lower or upper side in each other axis, and the direction out of the box there.
        dr::Vector3  start{};
        dr::Vector3  outward{};
        const int    others[2] = { (axis + 1) % 3, (axis + 2) % 3 };
        const double sides[2] = { firstOther, secondOther };
        for (int other = 0; other < 2; ++other)
        {
          const int along = others[other];
          start[along] = sides[other] == 0.0 ? expectedBox.lower[along] : expectedBox.upper[along];
          outward[along] = sides[other] == 0.0 ? -0.1 : 0.1;
        }
        const double length = expectedBox.upper[axis] - expectedBox.lower[axis];
        start[axis] = expectedBox.lower[axis];
        for (const double fraction : { 0.5, 0.25 })
        {
          dr::Vector3 split = start;
          split[axis] += fraction * length;
          SCOPED_TRACE(::testing::Message() << "edge along axis " << axis << ", sides " << firstOther << " "
                                            << secondOther << ", split at " << fraction);
          EXPECT_FALSE(box.HasVertexAt(dr::VertexKind::BoxEdge, split));
          EXPECT_TRUE(box.Protect(dr::operator+(split, outward), { { 2.0, 0.5, 0.5 } }));
          EXPECT_TRUE(box.HasVertexAt(dr::VertexKind::BoxEdge, split));
        }
        ++edges;
      }
    }
  }
  EXPECT_EQ(edges, 12u);
  EXPECT_EQ(box.Statistics().insertionsE1, 24u);
  EXPECT_EQ(box.VerticesOfKind(dr::VertexKind::BoxEdge).size(), 8u + 24u);
  EXPECT_EQ(box.Statistics().insertionsE2 + box.Statistics().insertionsE3, 0u);
}

/** A circumcentre 1 beyond the middle of the box's face x = 5.5 (4 x 4), in no edge's diametral ball, of a cell
 * beside that face: the segment from the cell's centroid to it leaves the box through that face, whose triangles'
 * circumcentre, the face's centre (5.5, 0.5, 0.5), lies on the balls of its four edges (2 from their midpoints, their
 * radius) but in none: E2 inserts the centre as a box-face vertex. Nothing is inserted on the opposite face. */
TEST(BoxRules, E2SplitsTheFaceTheCircumcentreLiesBeyond)
{
  BareBox box;
  EXPECT_TRUE(box.Protect({ { 6.5, 0.6, 0.57 } }, { { 5.0, 0.6, 0.57 } }));
  EXPECT_EQ(box.Statistics().insertionsE2, 1u);
  EXPECT_EQ(box.Statistics().insertionsE1 + box.Statistics().insertionsE3, 0u);
  const std::vector<dr::Vector3> faceVertices = box.VerticesOfKind(dr::VertexKind::BoxFace);
  ASSERT_EQ(faceVertices.size(), 1u);
  // On the face exactly; at its centre to the rounding of a triangle's circumcentre.
  EXPECT_EQ(faceVertices[0][0], 5.5);
  EXPECT_NEAR(faceVertices[0][1], 0.5, 1e-12);
  EXPECT_NEAR(faceVertices[0][2], 0.5, 1e-12);
}

/** A circumcentre 3 beyond the middle of the box's face y = 2.5 (7 x 4), in no edge's diametral ball, of a cell beside
 * that face: the face's centre (2, 2.5, 0.5) lies 2 from the midpoints of the face's two edges of length 7 (radius
 * 3.5), inside their balls, so E3 splits one of those edges at its midpoint instead of inserting the centre. */
TEST(BoxRules, E3SplitsTheEdgeAFacesCentreEncroaches)
{
  BareBox box;
  EXPECT_TRUE(box.Protect({ { 2.1, 5.5, 0.57 } }, { { 2.1, 2.0, 0.57 } }));
  EXPECT_EQ(box.Statistics().insertionsE3, 1u);
  EXPECT_EQ(box.Statistics().insertionsE1 + box.Statistics().insertionsE2, 0u);
  EXPECT_TRUE(box.VerticesOfKind(dr::VertexKind::BoxFace).empty());
  EXPECT_NE(box.HasVertexAt(dr::VertexKind::BoxEdge, { { 2.0, 2.5, -1.5 } }),
            box.HasVertexAt(dr::VertexKind::BoxEdge, { { 2.0, 2.5, 2.5 } }))
    << "one of the two midpoints";
}

/** R4′'s acceptance test counts a boundary as changed when the split point's conflict region swallows a tetrahedron of
 * another label, even where every new tetrahedron takes the sliver's label (SliverSplit::ChangesBoundary): the facets
 * between the swallowed region and that label's cells beyond it become boundary triangles, which must then pass the
 * test for free vertices and 30°. Here a sliver of label 1 (four free vertices on the unit circle, one raised by 0.05)
 * lies among cells all given label 2 by hand, while the oracle says 1 everywhere near it (a ball of radius 1000): each
 * candidate point's conflict region holds a cell of label 2 (the one it lies in, or beyond the facet it lies on), whose
 * facets with label 2 beyond then become boundary triangles, so no candidate leaves the boundary as it was. Found by
 * a deliberate bug that looked at the new tetrahedra's labels only: all 533 tests passed. */
TEST(SliverSplit, APointWhoseRegionSwallowsAnotherLabelChangesTheBoundary)
{
  const std::array<dr::Vector3, 4> sliver{
    { { { 1.0, 0.0, 0.0 } }, { { 0.0, 1.0, 0.0 } }, { { -1.0, 0.0, 0.0 } }, { { 0.0, -1.0, 0.05 } } }
  };
  std::vector<dr::Vector3> freePoints(sliver.begin(), sliver.end());
  freePoints.push_back({ { 0.0, 0.0, 1.5 } });
  freePoints.push_back({ { 0.0, 0.0, -1.5 } });
  const HandMadeTriangulation<dr::SphereOracle> made(dr::SphereOracle(dr::Vector3{ { 0.0, 0.0, 0.0 } }, 1000.0),
                                                     PaperParameters(0.5),
                                                     { { { -2.0, -2.0, -2.0 } }, { { 2.0, 2.0, 2.0 } } },
                                                     {},
                                                     freePoints);
  const CellHandle                              cell = CellWithCorners(made.State(), sliver);
  ASSERT_NE(cell, CellHandle()) << "the four points make no cell";
  const dr::detail::Triangulation & triangulation = made.State().GetTriangulation();
  for (auto other = triangulation.finite_cells_begin(); other != triangulation.finite_cells_end(); ++other)
  {
    other->cache.label = 2;
  }
  cell->cache.label = 1;
  const dr::detail::SliverSplit        split(made.Oracle(), made.State(), made.BoxRules(), made.Rules(), 2.0, 15.0);
  const dr::detail::SliverSplit::Split chosen = split.Choose(cell, cell->cache.circumcenter, cell->cache.squaredRadius);
  EXPECT_TRUE(chosen.changesBoundary) << "accepted " << chosen.accepted << " at " << chosen.point[0] << ", "
                                      << chosen.point[1] << ", " << chosen.point[2];
}
