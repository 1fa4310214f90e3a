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

// The link test at a vertex (src/DelaunayRefinementVertexLinks.h) and the list of non-manifold places the repairs
// read (src/DelaunayRefinementNonManifoldPlaces.h), on the Delaunay triangulation of the 27 points {-1, 0, 1}³: each
// of its cells lies in one of the eight unit cubes around the origin, so labelling the cells by cube gives labels made
// of whole cubes, whose boundaries at the origin are known without the library: two cubes that share only the
// origin make a boundary of two cones touching at their tips there, and two cubes that share a face make one boundary
// cycle around it.

#include "DelaunayRefinementNonManifoldPlaces.h"
#include "DelaunayRefinementVertexLinks.h"

#include <gtest/gtest.h>

#include <array>
#include <iterator>
#include <map>
#include <vector>

namespace dr = delaunay_refinement;
using dr::detail::CellHandle;
using dr::detail::Triangulation;
using dr::detail::VertexHandle;

namespace
{

/** The unit cube around the origin a cell lies in, as the signs of its centroid (each -1 or +1). */
std::array<int, 3>
CubeOf(CellHandle cell)
{
  std::array<int, 3> signs{};
  for (int axis = 0; axis < 3; ++axis)
  {
    double sum = 0.0;
    for (int corner = 0; corner < 4; ++corner)
    {
      sum += cell->vertex(corner)->point()[axis];
    }
    signs[axis] = sum > 0.0 ? 1 : -1;
  }
  return signs;
}

/** The triangulation of {-1, 0, 1}³ with each finite cell labelled by `labelOfCube` (indexed by the cube's signs),
 * and its vertex at the origin. */
struct LabelledCubes
{
  explicit LabelledCubes(const std::map<std::array<int, 3>, dr::Label> & labelOfCube)
  {
    std::vector<dr::detail::CgalPoint> points;
    for (int x = -1; x <= 1; ++x)
    {
      for (int y = -1; y <= 1; ++y)
      {
        for (int z = -1; z <= 1; ++z)
        {
          points.emplace_back(x, y, z);
        }
      }
    }
    triangulation.insert(points.begin(), points.end());
    dr::detail::VertexId id = 0;
    for (auto vertex = triangulation.finite_vertices_begin(); vertex != triangulation.finite_vertices_end(); ++vertex)
    {
      vertex->info().id = id++;
      if (vertex->point() == dr::detail::CgalPoint(0, 0, 0))
      {
        origin = vertex;
      }
    }
    for (auto cell = triangulation.finite_cells_begin(); cell != triangulation.finite_cells_end(); ++cell)
    {
      const auto found = labelOfCube.find(CubeOf(cell));
      cell->cache.label = found == labelOfCube.end() ? dr::BackgroundLabel : found->second;
    }
  }

  std::vector<dr::Label>
  NonManifoldLabelsAtTheOrigin() const
  {
    std::vector<CellHandle> star;
    triangulation.incident_cells(origin, std::back_inserter(star));
    return dr::detail::VertexLinks().ListNonManifoldLabelsAt(triangulation, origin, star);
  }

  Triangulation triangulation;
  VertexHandle  origin;
};

TEST(VertexLinks, EveryCellLiesInOneCubeAroundTheOrigin)
{
  const LabelledCubes cubes({});
  ASSERT_NE(cubes.origin, VertexHandle());
  std::vector<CellHandle> star;
  cubes.triangulation.incident_cells(cubes.origin, std::back_inserter(star));
  for (const CellHandle cell : star)
  {
    const std::array<int, 3> cube = CubeOf(cell);
    for (int corner = 0; corner < 4; ++corner)
    {
      for (int axis = 0; axis < 3; ++axis)
      {
        EXPECT_GE(cell->vertex(corner)->point()[axis] * cube[axis], 0.0)
          << "a corner outside the cube the centroid names: labels by cube would not be whole cubes";
      }
    }
  }
}

TEST(VertexLinks, OneCubeAndTwoCubesAcrossAFaceAreManifold)
{
  EXPECT_TRUE(LabelledCubes({ { { 1, 1, 1 }, 1 } }).NonManifoldLabelsAtTheOrigin().empty());
  EXPECT_TRUE(LabelledCubes({ { { 1, 1, 1 }, 1 }, { { 1, 1, -1 }, 1 } }).NonManifoldLabelsAtTheOrigin().empty());
  // Two tissues side by side: each is one cube, and their union two cubes across a face.
  EXPECT_TRUE(LabelledCubes({ { { 1, 1, 1 }, 1 }, { { 1, 1, -1 }, 2 } }).NonManifoldLabelsAtTheOrigin().empty());
}

TEST(VertexLinks, CubesTouchingAtTheOriginOnlyAreNotManifoldThere)
{
  // Label 1: two opposite cubes, which share the origin only.
  EXPECT_EQ(LabelledCubes({ { { 1, 1, 1 }, 1 }, { { -1, -1, -1 }, 1 } }).NonManifoldLabelsAtTheOrigin(),
            (std::vector<dr::Label>{ dr::detail::VertexLinks::UnionKey, 1 }));
  // Two cubes across an edge through the origin: label 1's boundary and the union's pinch along it.
  EXPECT_EQ(LabelledCubes({ { { 1, 1, 1 }, 1 }, { { -1, -1, 1 }, 1 } }).NonManifoldLabelsAtTheOrigin(),
            (std::vector<dr::Label>{ dr::detail::VertexLinks::UnionKey, 1 }));
}

/** Labels 3 and 7 each hold two opposite cubes, (+, +, +) with (-, -, -) and (+, +, -) with (-, -, +): each touches
 * itself at the origin only. Their union is the two columns x, y > 0 and x, y < 0, which touch along the z axis. So
 * the origin offends three boundaries: the union's (keyed by the background), 3's and 7's; and a repair that reads
 * only the first of them would see the union alone. */
TEST(NonManifoldPlaces, AVertexOffendingThreeBoundariesListsEachOfThem)
{
  const LabelledCubes cubes({ { { 1, 1, 1 }, 3 }, { { -1, -1, -1 }, 3 }, { { 1, 1, -1 }, 7 }, { { -1, -1, 1 }, 7 } });
  const std::vector<dr::Label> expected{ dr::detail::VertexLinks::UnionKey, 3, 7 };
  const std::vector<dr::Label> labels = cubes.NonManifoldLabelsAtTheOrigin();
  ASSERT_EQ(labels, expected);

  // The places as the searches add them: by vertex, then by label; a second vertex with one label after it.
  VertexHandle second;
  for (auto vertex = cubes.triangulation.finite_vertices_begin(); vertex != cubes.triangulation.finite_vertices_end();
       ++vertex)
  {
    if (vertex->point() == dr::detail::CgalPoint(1, 1, 1))
    {
      second = vertex;
    }
  }
  ASSERT_NE(second, VertexHandle());
  dr::detail::NonManifoldPlaces places;
  for (const dr::Label label : labels)
  {
    places.Add(cubes.origin, { { 0.0, 0.0, 0.0 } }, label);
  }
  places.Add(second, { { 1.0, 1.0, 1.0 } }, 3);

  ASSERT_EQ(places.vertices.size(), 2u);
  EXPECT_EQ(places.vertices[0], cubes.origin);
  EXPECT_EQ(places.places.size(), 4u);
  EXPECT_EQ(places.LabelsOf(0), expected) << "every boundary the vertex offends, not only the first";
  EXPECT_EQ(places.LabelsOf(1), (std::vector<dr::Label>{ 3 }));
  EXPECT_EQ(places.places[3].point[0], 1.0);
}

} // namespace
