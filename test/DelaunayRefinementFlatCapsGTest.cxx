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

// The flat caps (src/DelaunayRefinementFlatCaps.h, docs/algorithm.md, "Flat caps") asked of one tetrahedron made by
// hand: four points on the unit circle of the plane z = 0, the last raised a little, inside a box far larger than
// them (its corners 10 away), so that the four make a cell whose circumsphere, centred on the circle's axis, holds no
// other vertex. Before this file only whole meshes reached the flat caps (the brain mask with σ = 15°, one randomized
// regression), where which label a cap takes, and whether it was allowed to take one, changes a few tetrahedra that
// no guarantee looks at. Here the labels beyond each facet are chosen by hand, and the answers follow from the rules
// in the documentation: the label beyond two or more facets (the smaller of two), the facets that become boundary held
// to 30° and R1's bound, a sliver peeled off the background only.
//
// With the fourth point raised by h, the four points' quadrilateral is split along the diagonal p1 p3 on top (the
// facets without p0 and without p2 face up: on that diagonal the lifted point makes the surface higher) and along
// p0 p2 underneath (the facets without p1 and without p3 face down). Every other cell has a box corner beyond the
// plane on one side: it is labelled by the side its centroid is on.

#include "DelaunayRefinementAnalyticOracles.h"
#include "DelaunayRefinementFlatCaps.h"
#include "DelaunayRefinementHandMadeCube.h"
#include "DelaunayRefinementMeshState.h"
#include "DelaunayRefinementSizing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

namespace dr = delaunay_refinement;
using dr::detail::CellHandle;
using dr::detail::FlatCaps;

namespace
{

/** Four points on the unit circle at `degrees` around it (in order), the last raised by `lift`, in a box of half side
 * 10 (its eight corners), with δ = `delta` (every facet of the four points has circumradius 1). */
class HandMadeCap
{
public:
  HandMadeCap(const std::array<double, 4> & degrees, double lift, double delta = 2.0)
    : m_Oracle(dr::Vector3{ { 0.0, 0.0, -100.0 } }, 100.0)
    , m_Parameters(ParametersOf(delta))
    , m_State(m_Oracle, m_Parameters)
    , m_Sizing(delta)
  {
    StartWithCubeCorners(m_State, 10.0);
    for (int k = 0; k < 4; ++k)
    {
      const double angle = degrees[k] * 3.14159265358979323846 / 180.0;
      m_Points[k] = { { std::cos(angle), std::sin(angle), k == 3 ? lift : 0.0 } };
      EXPECT_TRUE(m_State.InsertVertex(m_Points[k], dr::VertexKind::Feature, CellHandle()).has_value());
    }
    for (auto cell = m_State.GetTriangulation().finite_cells_begin();
         cell != m_State.GetTriangulation().finite_cells_end();
         ++cell)
    {
      const std::array<dr::Vector3, 4> own = m_State.CornersOf(cell);
      if (std::all_of(m_Points.begin(), m_Points.end(), [&own](const dr::Vector3 & point) {
            return std::find(own.begin(), own.end(), point) != own.end();
          }))
      {
        m_Cap = cell;
      }
    }
    EXPECT_NE(m_Cap, CellHandle()) << "the four points make no cell";
  }

  /** Every finite cell but the cap takes `above` or `below` by the side of z = 0 its centroid is on; the cap `own`. */
  void
  Label(dr::Label above, dr::Label below, dr::Label own) const
  {
    for (auto cell = m_State.GetTriangulation().finite_cells_begin();
         cell != m_State.GetTriangulation().finite_cells_end();
         ++cell)
    {
      const std::array<dr::Vector3, 4> corners = m_State.CornersOf(cell);
      const double                     z = corners[0][2] + corners[1][2] + corners[2][2] + corners[3][2];
      cell->cache.label = z > 0.0 ? above : below;
    }
    m_Cap->cache.label = own;
  }

  /** The cell beyond the cap's facet without point `k`. */
  CellHandle
  BeyondFacetWithout(int k) const
  {
    return m_Cap->neighbor(FacetWithout(k));
  }

  /** Whether the centroid of the cell beyond the facet without point `k` is above z = 0. */
  bool
  IsAbove(int k) const
  {
    const std::array<dr::Vector3, 4> corners = m_State.CornersOf(BeyondFacetWithout(k));
    return corners[0][2] + corners[1][2] + corners[2][2] + corners[3][2] > 0.0;
  }

  std::optional<dr::Label>
  LabelAsFlatCap() const
  {
    return FlatCaps::LabelAsFlatCap(m_State, m_Sizing, m_Cap);
  }

  std::optional<dr::Label>
  LabelAsCap() const
  {
    return FlatCaps::LabelAsCap(m_State, m_Sizing, m_Cap);
  }

  FlatCaps::Relabelling
  Relabel(double sigma) const
  {
    return FlatCaps(m_State, m_Sizing, sigma).Relabel();
  }

  CellHandle
  Cap() const
  {
    return m_Cap;
  }

  const std::array<dr::Vector3, 4> &
  Points() const
  {
    return m_Points;
  }

private:
  static dr::RefinementParameters
  ParametersOf(double delta)
  {
    dr::RefinementParameters parameters;
    parameters.surfaceSamplingDistance = delta;
    return parameters;
  }

  int
  FacetWithout(int k) const
  {
    for (int corner = 0; corner < 4; ++corner)
    {
      if (m_State.PointOf(m_Cap->vertex(corner)) == m_Points[k])
      {
        return corner;
      }
    }
    ADD_FAILURE() << "point " << k << " is no corner of the cap";
    return 0;
  }

  dr::SphereOracle           m_Oracle;
  dr::RefinementParameters   m_Parameters;
  dr::detail::MeshState      m_State;
  dr::detail::LocalSampling  m_Sizing;
  std::array<dr::Vector3, 4> m_Points{};
  CellHandle                 m_Cap;
};

/** A square, its last corner raised by 1e-7: volume 3e-8 against a shortest edge √2, flat to rounding; each of its
 * facets is a right isosceles triangle of circumradius 1. */
constexpr std::array<double, 4> Square{ { 0.0, 90.0, 180.0, 270.0 } };
constexpr double                FlatLift = 1e-7;

} // namespace

/** The fixture's claim about which facets face up, which every test below reads. */
TEST(FlatCaps, TheRaisedCornerPutsTheDiagonalThroughItOnTop)
{
  const HandMadeCap cap(Square, FlatLift);
  EXPECT_TRUE(cap.IsAbove(0));
  EXPECT_TRUE(cap.IsAbove(2));
  EXPECT_FALSE(cap.IsAbove(1));
  EXPECT_FALSE(cap.IsAbove(3));
}

/** A flat tetrahedron of tissue 3 between tissues 1 and 2, each beyond two of its facets: it takes the smaller label,
 * 1, whichever side it is on (the documented tie rule; taking the larger, or the first met, changes the interface
 * without breaking any bound a mesh is checked for). It is no cap in LabelAsCap's sense: all four facets are on its
 * label's boundary. */
TEST(FlatCaps, AFlatTetrahedronBetweenTwoLabelsTakesTheSmaller)
{
  const HandMadeCap cap(Square, FlatLift);
  ASSERT_TRUE(dr::IsFlatToRounding(cap.Points()));
  cap.Label(1, 2, 3);
  EXPECT_EQ(cap.LabelAsFlatCap(), std::optional<dr::Label>(1));
  cap.Label(2, 1, 3);
  EXPECT_EQ(cap.LabelAsFlatCap(), std::optional<dr::Label>(1));
  EXPECT_EQ(cap.LabelAsCap(), std::nullopt) << "four boundary facets, not two";
  // The background beyond two facets is a label like any other: the smallest.
  cap.Label(2, dr::BackgroundLabel, 3);
  EXPECT_EQ(cap.LabelAsFlatCap(), std::optional<dr::Label>(dr::BackgroundLabel));
  // A background tetrahedron is never a cap.
  cap.Label(1, 1, dr::BackgroundLabel);
  EXPECT_EQ(cap.LabelAsFlatCap(), std::nullopt);
}

/** The facets that become the new label's boundary are all those not against it: the cap's own label's and a third
 * label's alike, and each must keep 30° and R1's bound. On the circle at 0°, 90°, 180° and 200° the lower facet
 * (p0, p2, p3) has an angle of 10° at p0 (half the 20° arc between p2 and p3): the tetrahedron, of tissue 1 with
 * tissue 2 above it and below it tissue 1 and that facet against tissue 3, would put it on tissue 2's boundary, and
 * keeps its label. A check of the facets inside its own tissue only would let it through. On the square every
 * facet is a right isosceles triangle, and the same labels make it a cap of tissue 2; at δ = 0.9 the facets'
 * circumradius 1 breaks R1's bound, and it is no cap. */
TEST(FlatCaps, AFlatCapKeepsItsLabelWhenAFacetItWouldPutOnABoundaryIsNarrowOrWide)
{
  {
    const HandMadeCap cap({ { 0.0, 90.0, 180.0, 200.0 } }, FlatLift);
    ASSERT_FALSE(cap.IsAbove(1));
    cap.Label(2, 1, 1);
    cap.BeyondFacetWithout(1)->cache.label = 3;
    EXPECT_EQ(cap.LabelAsFlatCap(), std::nullopt) << "a 10-degree facet put on tissue 2's boundary";
    // The same facet against tissue 1 instead: it is then an inner facet of tissue 1, and still becomes boundary.
    cap.Label(2, 1, 1);
    EXPECT_EQ(cap.LabelAsFlatCap(), std::nullopt);
  }
  {
    const HandMadeCap cap(Square, FlatLift);
    cap.Label(2, 1, 1);
    cap.BeyondFacetWithout(1)->cache.label = 3;
    EXPECT_EQ(cap.LabelAsFlatCap(), std::optional<dr::Label>(2));
  }
  {
    const HandMadeCap cap(Square, FlatLift, 0.9);
    cap.Label(2, 1, 1);
    cap.BeyondFacetWithout(1)->cache.label = 3;
    EXPECT_EQ(cap.LabelAsFlatCap(), std::nullopt) << "facets of circumradius 1 put on a boundary at delta 0.9";
  }
}

/** LabelAsCap (slivers and flat tetrahedra whose other facets are inside their tissue): exactly two facets on the
 * label's boundary, both against one other label. A sliver of the square raised by 0.05 (not flat: volume 1/60), of
 * tissue 1 with tissue 1 below: tissue 2 above it makes it a cap of tissue 2; tissues 2 and 3 above it, one beyond each
 * upper facet, make it none (no one label would swap the facets); tissue 2 also beyond a lower facet (three boundary
 * facets) makes it none either. */
TEST(FlatCaps, ACapHasExactlyTwoBoundaryFacetsAgainstOneLabel)
{
  const HandMadeCap cap(Square, 0.05);
  ASSERT_FALSE(dr::IsFlatToRounding(cap.Points()));
  cap.Label(2, 1, 1);
  EXPECT_EQ(cap.LabelAsCap(), std::optional<dr::Label>(2));
  cap.BeyondFacetWithout(0)->cache.label = 3;
  EXPECT_EQ(cap.LabelAsCap(), std::nullopt) << "its two boundary facets against tissues 3 and 2";
  cap.Label(2, 1, 1);
  cap.BeyondFacetWithout(1)->cache.label = 2;
  EXPECT_EQ(cap.LabelAsCap(), std::nullopt) << "three boundary facets";
  cap.Label(2, 1, dr::BackgroundLabel);
  EXPECT_EQ(cap.LabelAsCap(), std::nullopt) << "a background tetrahedron";
}

/** With σ > 0 the step peels a sliver that is a cap on the background off it, and leaves a sliver that is a cap on
 * another tissue in its own (given another tissue's label it would stay in the mesh, as a sliver). The sliver of the
 * square raised by 0.05 has dihedral angles of about 2° (atan(0.05 / √2) at the square's sides), below σ = 10°. */
TEST(FlatCaps, ASliverIsPeeledOffTheBackgroundOnly)
{
  const HandMadeCap cap(Square, 0.05);
  ASSERT_TRUE(dr::DihedralAngleBound(10.0).IsSliver(cap.Points()));

  cap.Label(dr::BackgroundLabel, 1, 1);
  const FlatCaps::Relabelling peeled = cap.Relabel(10.0);
  EXPECT_EQ(cap.Cap()->cache.label, dr::BackgroundLabel) << "a sliver capping tissue 1 against the background";
  ASSERT_EQ(peeled.relabelled.size(), 1u);
  EXPECT_EQ(peeled.relabelled[0].first, cap.Cap());
  EXPECT_EQ(peeled.relabelled[0].second, 1) << "the label it had";
  EXPECT_TRUE(peeled.sliversKept.empty());
  peeled.Undo();
  EXPECT_EQ(cap.Cap()->cache.label, 1);

  cap.Label(2, 1, 1);
  const FlatCaps::Relabelling kept = cap.Relabel(10.0);
  EXPECT_EQ(cap.Cap()->cache.label, 1) << "a sliver capping tissue 1 against tissue 2";
  EXPECT_TRUE(kept.relabelled.empty());

  // With σ = 0 no tetrahedron is a sliver, and a cap that is not flat stays.
  cap.Label(dr::BackgroundLabel, 1, 1);
  EXPECT_TRUE(cap.Relabel(0.0).relabelled.empty());
  EXPECT_EQ(cap.Cap()->cache.label, 1);
}
