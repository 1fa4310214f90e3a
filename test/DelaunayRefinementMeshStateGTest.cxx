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

// The mesh's own changes (src/DelaunayRefinementMeshState.h, docs/algorithm.md, "Deletion"), asked of vertices placed
// by hand in a box of half side 10: which vertices an insertion of a feature vertex and the emptying of a ball delete,
// what a move counts, and where the vertex cap stops. The whole refinement would hide these: a deletion radius a little
// short, or one vertex more than the cap, changes a mesh no guarantee check looks at.

#include "DelaunayRefinementAnalyticOracles.h"
#include "DelaunayRefinementHandMadeCube.h"
#include "DelaunayRefinementMeshState.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <optional>
#include <vector>

namespace dr = delaunay_refinement;
using dr::detail::CellHandle;
using dr::detail::VertexHandle;

namespace
{

/** A mesh state with the eight corners of a box of half side 10, δ = `delta` and the vertex cap `cap`. */
class HandMadeState
{
public:
  explicit HandMadeState(double delta = 1.0, std::size_t cap = 10000000)
    : m_Oracle(dr::Vector3{ { 0.0, 0.0, 0.0 } }, 5.0)
    , m_Parameters(ParametersOf(delta, cap))
    , m_State(m_Oracle, m_Parameters)
  {
    StartWithCubeCorners(m_State, 10.0);
  }

  dr::detail::MeshState &
  State()
  {
    return m_State;
  }

  VertexHandle
  Insert(const dr::Vector3 & point, dr::VertexKind kind)
  {
    const std::optional<VertexHandle> vertex = m_State.InsertVertex(point, kind, CellHandle());
    EXPECT_TRUE(vertex.has_value());
    return vertex.value_or(VertexHandle());
  }

  /** Whether a vertex is at `point`. */
  bool
  HasVertexAt(const dr::Vector3 & point) const
  {
    const auto & triangulation = m_State.GetTriangulation();
    for (auto vertex = triangulation.finite_vertices_begin(); vertex != triangulation.finite_vertices_end(); ++vertex)
    {
      if (m_State.PointOf(vertex) == point)
      {
        return true;
      }
    }
    return false;
  }

private:
  static dr::RefinementParameters
  ParametersOf(double delta, std::size_t cap)
  {
    dr::RefinementParameters parameters;
    parameters.surfaceSamplingDistance = delta;
    parameters.maximumNumberOfVertices = cap;
    return parameters;
  }

  dr::SphereOracle         m_Oracle;
  dr::RefinementParameters m_Parameters;
  dr::detail::MeshState    m_State;
};

dr::Vector3
At(double x, double y, double z)
{
  return { { x, y, z } };
}

} // namespace

/** "Exceeding it throws" (RefinementParameters::maximumNumberOfVertices): a cap of 10 lets the box's 8 corners and 2
 * more vertices in, and refuses the 11th, leaving the triangulation as it was. */
TEST(MeshState, TheVertexCapAllowsExactlyItsNumberOfVertices)
{
  HandMadeState made(1.0, 10);
  made.Insert(At(1.0, 2.0, 3.0), dr::VertexKind::Free);
  made.Insert(At(-2.0, 1.0, 0.5), dr::VertexKind::Free);
  EXPECT_EQ(made.State().GetTriangulation().number_of_vertices(), 10u);
  EXPECT_THROW(made.State().InsertVertex(At(3.0, -1.0, 2.0), dr::VertexKind::Free, CellHandle()),
               dr::VertexLimitExceeded);
  EXPECT_EQ(made.State().GetTriangulation().number_of_vertices(), 10u);
  EXPECT_FALSE(made.HasVertexAt(At(3.0, -1.0, 2.0)));
}

/** After a feature vertex is inserted, every free vertex closer than twice the local δ to it is deleted (Lemma 2's
 * spacing rests on it), and no other: with local δ 1.5, free vertices 2.9 and 2.99 away go, one 3.01 away stays, and
 * a feature vertex 1 away and the box's corners stay whatever their distance. Each deletion is counted. */
TEST(MeshState, AFeatureVertexDeletesTheFreeVerticesWithinTwiceTheLocalDelta)
{
  HandMadeState     made(1.0);
  const dr::Vector3 near = At(2.9, 0.0, 0.0);
  const dr::Vector3 nearer = At(0.0, -2.99, 0.0);
  const dr::Vector3 beyond = At(0.0, 0.0, 3.01);
  const dr::Vector3 feature = At(-1.0, 0.0, 0.0);
  made.Insert(near, dr::VertexKind::Free);
  made.Insert(nearer, dr::VertexKind::Free);
  made.Insert(beyond, dr::VertexKind::Free);
  made.Insert(feature, dr::VertexKind::Feature);
  ASSERT_EQ(made.State().NumberOfDeletedVertices(), 0u);

  EXPECT_TRUE(made.State().InsertFeatureVertex(At(0.0, 0.0, 0.0), 1.5, CellHandle()));
  EXPECT_FALSE(made.HasVertexAt(near));
  EXPECT_FALSE(made.HasVertexAt(nearer));
  EXPECT_TRUE(made.HasVertexAt(beyond));
  EXPECT_TRUE(made.HasVertexAt(feature));
  EXPECT_EQ(made.State().NumberOfDeletedVertices(), 2u);
  EXPECT_EQ(made.State().GetTriangulation().number_of_vertices(), 8u + 3u);
  EXPECT_TRUE(made.State().AnyFeatureVertexWithin(At(0.0, 0.0, 0.1), 0.2)) << "the new vertex is a feature vertex";

  // A point that is already a vertex is not inserted again, and deletes nothing.
  EXPECT_FALSE(made.State().InsertFeatureVertex(At(0.0, 0.0, 0.0), 5.0, CellHandle()));
  EXPECT_TRUE(made.HasVertexAt(beyond));
}

/** The box rules empty a ball strictly: of free vertices, and of box-face vertices when asked; a vertex exactly on the
 * sphere stays, and so do feature vertices and the box's corners. */
TEST(MeshState, EmptyBallRemovesTheFreeAndBoxFaceVerticesStrictlyInside)
{
  HandMadeState     made(1.0);
  const dr::Vector3 centre = At(0.0, 0.0, 10.0);
  const dr::Vector3 faceInside = At(1.0, 0.0, 10.0);
  const dr::Vector3 faceOnTheSphere = At(0.0, 2.0, 10.0);
  const dr::Vector3 freeInside = At(0.0, 0.0, 8.5);
  const dr::Vector3 freeOnTheSphere = At(0.0, 0.0, 8.0);
  const dr::Vector3 feature = At(0.5, 0.5, 9.0);
  made.Insert(faceInside, dr::VertexKind::BoxFace);
  made.Insert(faceOnTheSphere, dr::VertexKind::BoxFace);
  made.Insert(freeInside, dr::VertexKind::Free);
  made.Insert(freeOnTheSphere, dr::VertexKind::Free);
  made.Insert(feature, dr::VertexKind::Feature);

  made.State().EmptyBall(centre, 2.0, false);
  EXPECT_TRUE(made.HasVertexAt(faceInside)) << "box-face vertices stay unless asked";
  EXPECT_FALSE(made.HasVertexAt(freeInside));
  EXPECT_TRUE(made.HasVertexAt(freeOnTheSphere));

  made.State().EmptyBall(centre, 2.0, true);
  EXPECT_FALSE(made.HasVertexAt(faceInside));
  EXPECT_TRUE(made.HasVertexAt(faceOnTheSphere));
  EXPECT_TRUE(made.HasVertexAt(freeOnTheSphere));
  EXPECT_TRUE(made.HasVertexAt(feature));
  EXPECT_EQ(made.State().NumberOfDeletedVertices(), 2u);
  EXPECT_EQ(made.State().GetTriangulation().number_of_vertices(), 8u + 3u);
}

/** Where the labels changed, the surface samples are removed: feature and free vertices strictly inside the ball, and
 * nothing else. */
TEST(MeshState, RemoveSurfaceSamplesInsideRemovesFeatureAndFreeVertices)
{
  HandMadeState     made(1.0);
  const dr::Vector3 feature = At(1.0, 0.0, 0.0);
  const dr::Vector3 free = At(0.0, -1.5, 0.0);
  const dr::Vector3 featureOutside = At(0.0, 0.0, 2.5);
  made.Insert(feature, dr::VertexKind::Feature);
  made.Insert(free, dr::VertexKind::Free);
  made.Insert(featureOutside, dr::VertexKind::Feature);
  made.State().RemoveSurfaceSamplesInside(At(0.0, 0.0, 0.0), 2.0);
  EXPECT_FALSE(made.HasVertexAt(feature));
  EXPECT_FALSE(made.HasVertexAt(free));
  EXPECT_TRUE(made.HasVertexAt(featureOutside));
  EXPECT_FALSE(made.State().AnyFeatureVertexWithin(feature, 0.5)) << "the feature vertex left the spatial index too";
  EXPECT_EQ(made.State().NumberOfDeletedVertices(), 2u);
}

/** A move of a vertex (R4′) is a removal and an insertion, not a deletion: the deletion count stays, the vertex keeps
 * its kind, and the cells it reports as new are alive and are, among others, every cell at the moved vertex. */
TEST(MeshState, AMoveIsNoDeletionAndReportsTheCellsAtTheMovedVertex)
{
  HandMadeState made(1.0);
  made.Insert(At(2.0, 0.0, 0.0), dr::VertexKind::Free);
  made.Insert(At(-2.0, 1.0, 0.0), dr::VertexKind::Feature);
  const VertexHandle vertex = made.Insert(At(0.0, 0.0, 1.0), dr::VertexKind::Feature);

  std::vector<CellHandle> newCells;
  const VertexHandle      moved = made.State().MoveVertex(vertex, At(0.0, 0.5, 1.5), newCells);
  EXPECT_EQ(made.State().NumberOfDeletedVertices(), 0u);
  EXPECT_EQ(moved->info().kind, dr::VertexKind::Feature);
  EXPECT_TRUE(made.State().AnyFeatureVertexWithin(At(0.0, 0.5, 1.5), 0.1));
  EXPECT_FALSE(made.State().AnyFeatureVertexWithin(At(0.0, 0.0, 1.0), 0.1));
  EXPECT_FALSE(made.HasVertexAt(At(0.0, 0.0, 1.0)));

  const auto &            triangulation = made.State().GetTriangulation();
  std::vector<CellHandle> star;
  triangulation.incident_cells(moved, std::back_inserter(star));
  for (const CellHandle cell : star)
  {
    if (!triangulation.is_infinite(cell))
    {
      EXPECT_NE(std::find(newCells.begin(), newCells.end(), cell), newCells.end()) << "a cell at the moved vertex";
    }
  }
  for (const CellHandle cell : newCells)
  {
    EXPECT_TRUE(made.State().IsCurrent(cell, cell->cache.stamp));
    EXPECT_FALSE(triangulation.is_infinite(cell));
  }
  std::vector<CellHandle> sorted = newCells;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::unique(sorted.begin(), sorted.end()), sorted.end()) << "each new cell once";
}
