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

// The manifold repair's searches and plans (src/DelaunayRefinementManifoldRepair.h, docs/algorithm.md, "Topology"),
// asked of the refinement's state made by hand: the 27 points {-1, 0, 1}³ inside a box of half side 10, labelled by
// an oracle whose labels are whole unit cubes around the origin (as in DelaunayRefinementVertexLinksGTest.cxx: the
// Delaunay cells inside [-1, 1]³ each lie in one cube, and their circumcentres are the cubes' centres). Before this
// file the repair was reached through whole meshes only, where a search that forgets a place, a zone below the finest
// δ or a cell missed by the walk after a change shows, if at all, as a few tetrahedra more or less.

#include "DelaunayRefinementAnalyticOracles.h"
#include "DelaunayRefinementHandMadeCube.h"
#include "DelaunayRefinementManifoldRepair.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <map>
#include <vector>

namespace dr = delaunay_refinement;
using dr::detail::CellHandle;
using dr::detail::ManifoldRepair;
using dr::detail::NonManifoldPlaces;
using dr::detail::VertexHandle;

namespace
{

/** The labels of whole unit cubes around the origin (by the signs of a point's coordinates), background elsewhere. */
class CubesOracle : public dr::LabelOracle
{
public:
  dr::Label
  LabelAt(const dr::Vector3 & point) const override
  {
    std::array<int, 3> signs{};
    for (int axis = 0; axis < 3; ++axis)
    {
      if (!(std::abs(point[axis]) < 1.0) || point[axis] == 0.0)
      {
        return dr::BackgroundLabel;
      }
      signs[axis] = point[axis] > 0.0 ? 1 : -1;
    }
    const auto found = labelOfCube.find(signs);
    return found == labelOfCube.end() ? dr::BackgroundLabel : found->second;
  }
  dr::AxisAlignedBox
  ObjectBounds() const override
  {
    return { { { -1.0, -1.0, -1.0 } }, { { 1.0, 1.0, 1.0 } } };
  }
  dr::SurfacePoint
  ClosestSurfacePoint(const dr::Vector3 & query) const override
  {
    return { query, 0.0 };
  }
  double
  SurfaceTolerance() const override
  {
    return 1e-9;
  }

  std::map<std::array<int, 3>, dr::Label> labelOfCube;
};

/** The state over {-1, 0, 1}³ in the box, labelled by the oracle, with the repair over it. */
class LatticeState
{
public:
  explicit LatticeState(const std::map<std::array<int, 3>, dr::Label> & labelOfCube, double delta = 1.0,
                        unsigned int levels = 0, double finest = 0.0)
    : m_Parameters(ParametersOf(delta, levels, finest))
    , m_State(m_Oracle, m_Parameters)
    , m_Extraction(m_State)
    , m_Sizing(delta)
    , m_Repair(m_State, m_Extraction, m_Sizing, m_Parameters)
  {
    m_Oracle.labelOfCube = labelOfCube;
    StartWithCubeCorners(m_State, 10.0);
    for (int x = -1; x <= 1; ++x)
    {
      for (int y = -1; y <= 1; ++y)
      {
        for (int z = -1; z <= 1; ++z)
        {
          const std::optional<VertexHandle> vertex =
            m_State.InsertVertex({ { static_cast<double>(x), static_cast<double>(y), static_cast<double>(z) } },
                                 dr::VertexKind::Feature,
                                 CellHandle());
          EXPECT_TRUE(vertex.has_value());
          if (x == 0 && y == 0 && z == 0)
          {
            m_Origin = *vertex;
          }
        }
      }
    }
  }

  /** Relabels the cubes and refreshes every cell, as the regularisation's rounds do where the labels changed. */
  void
  Relabel(const std::map<std::array<int, 3>, dr::Label> & labelOfCube)
  {
    m_Oracle.labelOfCube = labelOfCube;
    std::vector<CellHandle> cells;
    for (auto cell = m_State.GetTriangulation().finite_cells_begin();
         cell != m_State.GetTriangulation().finite_cells_end();
         ++cell)
    {
      cells.push_back(cell);
    }
    m_State.RefreshCells(cells);
  }

  ManifoldRepair &
  Repair()
  {
    return m_Repair;
  }

  const dr::detail::MeshState &
  State() const
  {
    return m_State;
  }

  dr::detail::LocalSampling &
  Sizing()
  {
    return m_Sizing;
  }

  VertexHandle
  Origin() const
  {
    return m_Origin;
  }

private:
  static dr::RefinementParameters
  ParametersOf(double delta, unsigned int levels, double finest)
  {
    dr::RefinementParameters parameters;
    parameters.surfaceSamplingDistance = delta;
    parameters.manifoldRefinementLevels = levels;
    parameters.minimumSurfaceSamplingDistance = finest;
    return parameters;
  }

  CubesOracle                m_Oracle;
  dr::RefinementParameters   m_Parameters;
  dr::detail::MeshState      m_State;
  dr::detail::MeshExtraction m_Extraction;
  dr::detail::LocalSampling  m_Sizing;
  ManifoldRepair             m_Repair;
  VertexHandle               m_Origin;
};

/** Labels 1 in two opposite cubes, which share the origin only: label 1's boundary and the union's are two cones
 * touching at their tips there, and manifolds everywhere else. */
const std::map<std::array<int, 3>, dr::Label> OppositeCubes{ { { { 1, 1, 1 } }, 1 }, { { { -1, -1, -1 } }, 1 } };

/** The places as (vertex, labels) pairs, for comparison. */
std::vector<std::pair<VertexHandle, std::vector<dr::Label>>>
ListOf(const NonManifoldPlaces & places)
{
  std::vector<std::pair<VertexHandle, std::vector<dr::Label>>> list;
  for (std::size_t index = 0; index < places.vertices.size(); ++index)
  {
    list.emplace_back(places.vertices[index], places.LabelsOf(index));
  }
  return list;
}

} // namespace

/** The fixture's labels are the oracle's at the cubes' centres: every cell with a box corner is background, and label
 * 1 has the 2 x 6 cells of its two cubes (each cube of 8 co-spherical points is split into 6 tetrahedra or more, all
 * with the cube's circumsphere). */
TEST(ManifoldRepair, TheLatticeCellsCarryTheirCubesLabels)
{
  LatticeState lattice(OppositeCubes);
  std::size_t  labelled = 0;
  for (auto cell = lattice.State().GetTriangulation().finite_cells_begin();
       cell != lattice.State().GetTriangulation().finite_cells_end();
       ++cell)
  {
    bool hasBoxCorner = false;
    for (int corner = 0; corner < 4; ++corner)
    {
      hasBoxCorner = hasBoxCorner || std::abs(lattice.State().PointOf(cell->vertex(corner))[0]) == 10.0;
    }
    if (hasBoxCorner)
    {
      EXPECT_EQ(cell->cache.label, dr::BackgroundLabel);
    }
    labelled += cell->cache.label == 1 ? 1 : 0;
  }
  EXPECT_GE(labelled, 10u);
}

/** The search where stars changed must find what the walk over the whole mesh finds, in every round: a place found
 * stays due (its star need not change for it to stay non-manifold), so a later search, with no star changed, lists
 * it again; a search that cleared its flag would report the mesh manifold after one round. */
TEST(ManifoldRepair, TheSearchWhereStarsChangedListsEveryPlaceInEveryRound)
{
  LatticeState lattice(OppositeCubes);
  const auto   walk = ListOf(lattice.Repair().FindNonManifoldPlaces());
  const std::vector<std::pair<VertexHandle, std::vector<dr::Label>>> expected{
    { lattice.Origin(), { dr::detail::VertexLinks::UnionKey, 1 } }
  };
  ASSERT_EQ(walk, expected);
  // The first search has every vertex due (the walk), the later ones the origin alone (the link test).
  for (int round = 0; round < 3; ++round)
  {
    SCOPED_TRACE(round);
    EXPECT_EQ(ListOf(lattice.Repair().FindNonManifoldPlacesWhereChanged()), expected);
  }
  // Filling the cube (+, +, -) as well changes the stars of its corners only; it shares a face with (+, +, +) and the
  // edge from the origin to (0, 0, -1) with (-, -, -): both ends of that edge offend label 1 and the union, whatever
  // else does, and the search where stars changed lists what the walk lists, round after round.
  std::map<std::array<int, 3>, dr::Label> threeCubes = OppositeCubes;
  threeCubes[{ { 1, 1, -1 } }] = 1;
  lattice.Relabel(threeCubes);
  const auto walkAfter = ListOf(lattice.Repair().FindNonManifoldPlaces());
  ASSERT_GE(walkAfter.size(), 2u);
  bool originListed = false;
  bool edgeEndListed = false;
  for (const auto & [vertex, labels] : walkAfter)
  {
    originListed = originListed || (vertex == lattice.Origin() &&
                                    labels == std::vector<dr::Label>{ dr::detail::VertexLinks::UnionKey, 1 });
    edgeEndListed = edgeEndListed || (lattice.State().PointOf(vertex) == dr::Vector3{ { 0.0, 0.0, -1.0 } } &&
                                      labels == std::vector<dr::Label>{ dr::detail::VertexLinks::UnionKey, 1 });
  }
  EXPECT_TRUE(originListed);
  EXPECT_TRUE(edgeEndListed);
  for (int round = 0; round < 3; ++round)
  {
    SCOPED_TRACE(round);
    EXPECT_EQ(ListOf(lattice.Repair().FindNonManifoldPlacesWhereChanged()), walkAfter);
  }
  // Emptying the cube (-, -, -) leaves two cubes across a face: no place.
  lattice.Relabel({ { { { 1, 1, 1 } }, 1 }, { { { 1, 1, -1 } }, 1 } });
  EXPECT_TRUE(lattice.Repair().FindNonManifoldPlacesWhereChanged().places.empty());
  EXPECT_TRUE(lattice.Repair().FindNonManifoldPlaces().places.empty());
}

/** Above 5 % of the boundary's vertices the defects are pervasive and the opt-in halving is not tried
 * (MaximumRepairableFraction); the share counts vertices, not (vertex, label) places: 1 vertex of 20 (5 %, not above
 * it) is repairable even when it offends three boundaries, 2 of 20 are not. */
TEST(ManifoldRepair, TheRepairableShareCountsVerticesUpToFivePercent)
{
  const LatticeState        lattice(OppositeCubes);
  std::vector<VertexHandle> vertices;
  for (auto vertex = lattice.State().GetTriangulation().finite_vertices_begin();
       vertex != lattice.State().GetTriangulation().finite_vertices_end();
       ++vertex)
  {
    vertices.push_back(vertex);
  }
  NonManifoldPlaces one;
  for (const dr::Label label : { 0, 1, 2 })
  {
    one.Add(vertices[0], lattice.State().PointOf(vertices[0]), label);
  }
  EXPECT_TRUE(ManifoldRepair::IsRepairable(one, 20));
  EXPECT_FALSE(ManifoldRepair::IsRepairable(one, 19));
  NonManifoldPlaces two = one;
  two.Add(vertices[1], lattice.State().PointOf(vertices[1]), 1);
  EXPECT_FALSE(ManifoldRepair::IsRepairable(two, 20));
  EXPECT_TRUE(ManifoldRepair::IsRepairable(two, 40));
}

/** The opt-in halving: each round halves δ once around each place, from its δ before the round (a place inside the
 * zone just made for a nearby one is not halved twice in one round), never below the finest δ: δ / 2^levels or the
 * minimum sampling distance, the larger. With δ = 1, 10 levels and a minimum of 0.3: 1 -> 0.5 -> 0.3 (not 0.25), and
 * then no zone. With 1 level and no minimum: 1 -> 0.5, and then no zone. */
TEST(ManifoldRepair, HalvingStopsAtTheFinestDeltaAndHalvesEachPlaceOncePerRound)
{
  const dr::Vector3 p{ { 0.0, 0.0, 0.0 } };
  const dr::Vector3 q{ { 0.1, 0.0, 0.0 } };
  {
    LatticeState      lattice(OppositeCubes, 1.0, 10, 0.3);
    NonManifoldPlaces places;
    places.Add(lattice.Origin(), p, 1);
    // Another vertex handle for the second place: only its point is read.
    const VertexHandle other = lattice.State().GetTriangulation().finite_vertices_begin();
    ASSERT_NE(other, lattice.Origin());
    places.Add(other, q, 1);

    EXPECT_EQ(lattice.Repair().HalveDeltaAround(places).size(), 2u);
    EXPECT_DOUBLE_EQ(lattice.Sizing().LocalDelta(p), 0.5);
    EXPECT_DOUBLE_EQ(lattice.Sizing().LocalDelta(q), 0.5) << "halved twice in one round";
    EXPECT_EQ(lattice.Repair().HalveDeltaAround(places).size(), 2u);
    EXPECT_DOUBLE_EQ(lattice.Sizing().LocalDelta(p), 0.3);
    EXPECT_DOUBLE_EQ(lattice.Sizing().LocalDelta(q), 0.3);
    EXPECT_TRUE(lattice.Repair().HalveDeltaAround(places).empty()) << "at the finest delta already";
    EXPECT_DOUBLE_EQ(lattice.Sizing().LocalDelta(p), 0.3);
  }
  {
    LatticeState      lattice(OppositeCubes, 1.0, 1, 0.0);
    NonManifoldPlaces places;
    places.Add(lattice.Origin(), p, 1);
    EXPECT_EQ(lattice.Repair().HalveDeltaAround(places).size(), 1u);
    EXPECT_DOUBLE_EQ(lattice.Sizing().LocalDelta(p), 0.5);
    EXPECT_TRUE(lattice.Repair().HalveDeltaAround(places).empty());
    EXPECT_DOUBLE_EQ(lattice.Sizing().LocalDelta(p), 0.5);
  }
}

/** After labels or δ changed in balls, the cells looked at again are exactly those whose circumball meets a ball
 * (checked against every cell), and with their finite neighbours each once. Two overlapping balls: the walk for the
 * second must not skip the cells the first walk saw without keeping them. */
TEST(ManifoldRepair, CellsMeetingAreThoseOfEveryCellWhoseCircumballMeetsABall)
{
  LatticeState                             lattice(OppositeCubes);
  const auto &                             triangulation = lattice.State().GetTriangulation();
  const std::vector<std::vector<dr::Ball>> cases{
    { { { { 0.3, 0.2, 0.1 } }, 0.05 } },
    { { { { 0.3, 0.2, 0.1 } }, 0.05 }, { { { 0.4, 0.3, 0.2 } }, 0.9 } },
    { { { { -0.6, 0.7, 0.2 } }, 0.3 }, { { { 5.0, -5.0, 5.0 } }, 0.5 }, { { { 0.9, -0.9, -0.9 } }, 0.01 } },
  };
  for (const std::vector<dr::Ball> & balls : cases)
  {
    SCOPED_TRACE(balls.size());
    std::vector<CellHandle> expected;
    for (auto cell = triangulation.finite_cells_begin(); cell != triangulation.finite_cells_end(); ++cell)
    {
      for (const dr::Ball & ball : balls)
      {
        if (dr::Distance(cell->cache.circumcenter, ball.center) < std::sqrt(cell->cache.squaredRadius) + ball.radius)
        {
          expected.push_back(cell);
          break;
        }
      }
    }
    std::sort(expected.begin(), expected.end());
    const std::vector<CellHandle> meeting = lattice.Repair().CellsMeeting(balls);
    EXPECT_EQ(meeting, expected);

    std::vector<CellHandle> withNeighbors = expected;
    for (const CellHandle cell : expected)
    {
      for (int facet = 0; facet < 4; ++facet)
      {
        if (!triangulation.is_infinite(cell->neighbor(facet)))
        {
          withNeighbors.push_back(cell->neighbor(facet));
        }
      }
    }
    std::sort(withNeighbors.begin(), withNeighbors.end());
    withNeighbors.erase(std::unique(withNeighbors.begin(), withNeighbors.end()), withNeighbors.end());
    EXPECT_EQ(lattice.Repair().WithNeighbors(meeting), withNeighbors);
  }
}
