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

// The rules R1 and R2 (src/DelaunayRefinementRules.h, docs/algorithm.md, "Rules") asked of one tetrahedron made by
// hand: four points whose circumsphere is known, inside a box far larger than it (so that the four make a cell of the
// Delaunay triangulation), near the top of a ball of radius 100 (the surface z = 0 there, to 1e-2 over the
// tetrahedron). The whole refinement would hide which rule fired: a rule that splits too early or too late changes
// the mesh, not a guarantee the meshes are checked for.

#include "DelaunayRefinementAnalyticOracles.h"
#include "DelaunayRefinementMeshState.h"
#include "DelaunayRefinementRules.h"
#include "DelaunayRefinementSizing.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <optional>
#include <vector>

namespace dr = delaunay_refinement;
using dr::detail::CellHandle;
using dr::detail::Rule;

namespace
{

constexpr double Delta = 1.0;

/** A tetrahedron with circumcentre (0, 0, `height`) and circumradius `radius`: its lowest corner (0, 0, height -
 * radius), a feature vertex, and an equilateral triangle of free vertices on the horizontal great circle. The surface
 * is the top of a ball of radius 100 centred at (0, 0, -100): the closest surface point to the circumcentre is the
 * origin, and the circumcentre is `height` from the surface. */
class HandMadeTetrahedron
{
public:
  HandMadeTetrahedron(double height, double radius)
    : m_Oracle(dr::Vector3{ { 0.0, 0.0, -100.0 } }, 100.0)
    , m_Parameters(Parameters())
    , m_State(m_Oracle, m_Parameters)
    , m_Sizing(Delta)
  {
    m_State.SetNewCellsHook([](const std::vector<CellHandle> &) {});
    std::array<dr::Vector3, 8> corners{};
    for (int corner = 0; corner < 8; ++corner)
    {
      for (int axis = 0; axis < 3; ++axis)
      {
        corners[corner][axis] = (corner >> axis) & 1 ? BoxHalfSide : -BoxHalfSide;
      }
    }
    m_Box.lower = corners[0];
    m_Box.upper = corners[7];
    m_State.InsertBoxCorners(corners);
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
    const dr::detail::RefinementRules rules(m_Oracle, m_Parameters, m_State, m_Sizing, m_Box);
    return rules.FindApplicableRule(m_Cell);
  }

private:
  static constexpr double BoxHalfSide = 50.0;

  static dr::RefinementParameters
  Parameters()
  {
    dr::RefinementParameters parameters;
    parameters.surfaceSamplingDistance = Delta;
    parameters.radiusEdgeBound = 2.0;
    parameters.minimumDihedralAngle = 0.0;
    return parameters;
  }

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
