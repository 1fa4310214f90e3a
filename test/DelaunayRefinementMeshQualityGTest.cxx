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

// The mesh measures are what the core tests trust, so they are checked here on hand-made meshes whose
// answers are derived by hand in the comments.

#include "DelaunayRefinementMeshQuality.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

namespace delaunay_refinement
{
namespace
{

using Triangles = std::vector<std::array<uint32_t, 3>>;

constexpr double Tolerance = 1e-12;
constexpr double DegreesPerRadian = 180.0 / 3.14159265358979323846;
const double     Infinity = std::numeric_limits<double>::infinity();

/** Alternate corners of the cube [-1, 1]^3: a regular tetrahedron with edge 2√2, centred at the origin. Its
 * circumradius is the distance to a corner, √3. In the order 0, 1, 3, 2 it is positively oriented:
 * (p1 - p0) = (0, -2, -2), (p3 - p0) = (-2, -2, 0), (p2 - p0) = (-2, 0, -2),
 * (p3 - p0) x (p2 - p0) = (4, -4, -4), dot with (p1 - p0) = 16, volume 16/6 = 8/3 = (2√2)^3 / (6√2). */
std::vector<Vector3>
RegularTetrahedronPoints()
{
  return { { { 1.0, 1.0, 1.0 } }, { { 1.0, -1.0, -1.0 } }, { { -1.0, 1.0, -1.0 } }, { { -1.0, -1.0, 1.0 } } };
}

const std::array<uint32_t, 4> PositiveRegularTetrahedron{ { 0, 1, 3, 2 } };
const std::array<uint32_t, 4> InvertedRegularTetrahedron{ { 0, 1, 2, 3 } };

TetrahedralMesh
MeshOf(std::vector<Vector3> points, std::vector<std::array<uint32_t, 4>> tetrahedra)
{
  TetrahedralMesh mesh;
  mesh.points = std::move(points);
  mesh.pointKinds.assign(mesh.points.size(), VertexKind::Free);
  mesh.tetrahedra = std::move(tetrahedra);
  mesh.tetrahedronLabels.assign(mesh.tetrahedra.size(), 1);
  return mesh;
}

/** The four faces of tetrahedron (a, b, c, d), each oriented outwards when (a, b, c, d) is positive. */
Triangles
TetrahedronSurface(uint32_t a, uint32_t b, uint32_t c, uint32_t d)
{
  return { { { a, c, b } }, { { a, b, d } }, { { a, d, c } }, { { b, c, d } } };
}

void
Append(Triangles & to, const Triangles & from)
{
  to.insert(to.end(), from.begin(), from.end());
}

TEST(TetrahedronQuality, RegularTetrahedron)
{
  const TetrahedronQuality quality =
    ComputeTetrahedronQuality(MeshOf(RegularTetrahedronPoints(), { PositiveRegularTetrahedron }));
  EXPECT_EQ(quality.numberOfTetrahedra, 1u);
  // Circumradius √3 over edge 2√2 = √6 / 4.
  EXPECT_NEAR(quality.maximumRadiusEdgeRatio, std::sqrt(6.0) / 4.0, Tolerance);
  // All six dihedral angles of a regular tetrahedron are acos(1/3) = 70.5288°.
  const double regularDihedral = std::acos(1.0 / 3.0) * DegreesPerRadian;
  EXPECT_NEAR(quality.minimumDihedralAngle, regularDihedral, 1e-10);
  EXPECT_NEAR(quality.maximumDihedralAngle, regularDihedral, 1e-10);
  ASSERT_EQ(quality.minimumDihedralAngles.size(), 1u);
  EXPECT_NEAR(quality.minimumDihedralAngles[0], regularDihedral, 1e-10);
  EXPECT_NEAR(quality.minimumVolume, 8.0 / 3.0, Tolerance);
  EXPECT_NEAR(quality.totalVolume, 8.0 / 3.0, Tolerance);
  EXPECT_EQ(quality.invertedTetrahedra, 0u);
  EXPECT_EQ(quality.duplicateTetrahedra, 0u);
  EXPECT_EQ(quality.unusedPoints, 0u);
  EXPECT_EQ(quality.malformedTetrahedra, 0u);
}

TEST(TetrahedronQuality, CornerTetrahedron)
{
  // The corner (0,0,0), (1,0,0), (0,1,0), (0,0,1): circumcentre (½,½,½), circumradius √3/2, shortest edge 1.
  // Dihedral angles: 90° at the three axis edges; at the others, between a coordinate plane (normal e_z, say)
  // and the plane x + y + z = 1 (normal (1,1,1)/√3): acos(1/√3) = 54.7356°. Volume 1/6.
  const TetrahedronQuality quality = ComputeTetrahedronQuality(
    MeshOf({ { { 0.0, 0.0, 0.0 } }, { { 1.0, 0.0, 0.0 } }, { { 0.0, 1.0, 0.0 } }, { { 0.0, 0.0, 1.0 } } },
           { { { 0, 1, 2, 3 } } }));
  EXPECT_NEAR(quality.maximumRadiusEdgeRatio, std::sqrt(3.0) / 2.0, Tolerance);
  EXPECT_NEAR(quality.minimumDihedralAngle, std::acos(1.0 / std::sqrt(3.0)) * DegreesPerRadian, 1e-10);
  EXPECT_NEAR(quality.maximumDihedralAngle, 90.0, 1e-10);
  EXPECT_NEAR(quality.minimumVolume, 1.0 / 6.0, Tolerance);
  EXPECT_EQ(quality.invertedTetrahedra, 0u);
}

TEST(TetrahedronQuality, InvertedTetrahedronIsDetected)
{
  // Swapping two vertices of the positive order negates the volume: -8/3.
  const TetrahedronQuality quality = ComputeTetrahedronQuality(
    MeshOf(RegularTetrahedronPoints(), { PositiveRegularTetrahedron, InvertedRegularTetrahedron }));
  EXPECT_EQ(quality.invertedTetrahedra, 1u);
  EXPECT_NEAR(quality.minimumVolume, -8.0 / 3.0, Tolerance);
  EXPECT_NEAR(quality.totalVolume, 0.0, Tolerance);
  // Shape measures do not depend on orientation.
  EXPECT_NEAR(quality.maximumRadiusEdgeRatio, std::sqrt(6.0) / 4.0, Tolerance);
}

TEST(TetrahedronQuality, FlatTetrahedronIsInvertedWithInfiniteRadiusEdgeRatio)
{
  // Four points of the plane z = 0: volume 0 (counted as inverted), no circumsphere.
  const TetrahedronQuality quality = ComputeTetrahedronQuality(
    MeshOf({ { { 0.0, 0.0, 0.0 } }, { { 1.0, 0.0, 0.0 } }, { { 0.0, 1.0, 0.0 } }, { { 1.0, 1.0, 0.0 } } },
           { { { 0, 1, 2, 3 } } }));
  EXPECT_EQ(quality.invertedTetrahedra, 1u);
  EXPECT_EQ(quality.minimumVolume, 0.0);
  EXPECT_EQ(quality.maximumRadiusEdgeRatio, Infinity);
}

TEST(TetrahedronQuality, DuplicatedTetrahedronIsDetected)
{
  // The same vertex set in another order: both copies share their vertex set with another tetrahedron.
  const TetrahedronQuality quality =
    ComputeTetrahedronQuality(MeshOf(RegularTetrahedronPoints(), { PositiveRegularTetrahedron, { { 2, 0, 1, 3 } } }));
  EXPECT_EQ(quality.duplicateTetrahedra, 2u);
  EXPECT_EQ(quality.malformedTetrahedra, 0u);
}

TEST(TetrahedronQuality, UnusedPointIsDetected)
{
  std::vector<Vector3> points = RegularTetrahedronPoints();
  points.push_back({ { 5.0, 5.0, 5.0 } });
  const TetrahedronQuality quality = ComputeTetrahedronQuality(MeshOf(points, { PositiveRegularTetrahedron }));
  EXPECT_EQ(quality.unusedPoints, 1u);
}

TEST(TetrahedronQuality, MalformedTetrahedraAreDetected)
{
  // Index 4 is out of range for 4 points; the second repeats vertex 1.
  const TetrahedronQuality quality = ComputeTetrahedronQuality(
    MeshOf(RegularTetrahedronPoints(), { PositiveRegularTetrahedron, { { 0, 1, 2, 4 } }, { { 0, 1, 1, 3 } } }));
  EXPECT_EQ(quality.numberOfTetrahedra, 3u);
  EXPECT_EQ(quality.malformedTetrahedra, 2u);
  EXPECT_EQ(quality.duplicateTetrahedra, 0u);
  EXPECT_NEAR(quality.minimumVolume, 8.0 / 3.0, Tolerance);
}

TEST(TetrahedronQuality, EmptyMesh)
{
  const TetrahedronQuality quality = ComputeTetrahedronQuality(TetrahedralMesh{});
  EXPECT_EQ(quality.numberOfTetrahedra, 0u);
  EXPECT_EQ(quality.minimumVolume, 0.0);
  EXPECT_EQ(quality.maximumRadiusEdgeRatio, 0.0);
}

TEST(SurfaceTopology, TetrahedronSurfaceIsAClosedSphere)
{
  // V = 4, E = 6, F = 4: χ = 2, genus 0. Every face is equilateral: 60°.
  const SurfaceTopology topology = ComputeSurfaceTopology(RegularTetrahedronPoints(), TetrahedronSurface(0, 1, 3, 2));
  EXPECT_EQ(topology.numberOfTriangles, 4u);
  EXPECT_EQ(topology.numberOfVertices, 4u);
  EXPECT_EQ(topology.numberOfEdges, 6u);
  EXPECT_EQ(topology.nonManifoldEdges, 0u);
  EXPECT_EQ(topology.nonManifoldVertices, 0u);
  EXPECT_TRUE(topology.IsClosedManifold());
  EXPECT_EQ(topology.numberOfComponents, 1);
  EXPECT_EQ(topology.totalGenus, 0);
  EXPECT_EQ(topology.componentGenera, std::vector<int>{ 0 });
  EXPECT_NEAR(topology.minimumPlanarAngle, 60.0, 1e-10);
}

TEST(SurfaceTopology, TwoDisjointTetrahedronSurfacesAreTwoComponents)
{
  std::vector<Vector3> points = RegularTetrahedronPoints();
  for (const Vector3 & p : RegularTetrahedronPoints())
  {
    points.push_back(p + Vector3{ { 10.0, 0.0, 0.0 } });
  }
  Triangles triangles = TetrahedronSurface(0, 1, 3, 2);
  Append(triangles, TetrahedronSurface(4, 5, 7, 6));
  const SurfaceTopology topology = ComputeSurfaceTopology(points, triangles);
  EXPECT_TRUE(topology.IsClosedManifold());
  EXPECT_EQ(topology.numberOfComponents, 2);
  EXPECT_EQ(topology.totalGenus, 0);
  EXPECT_EQ(topology.componentGenera, (std::vector<int>{ 0, 0 }));
}

/** A torus surface from an n x m grid of the (u, v) square with both sides glued: V = nm, E = 3nm (two grid
 * edges and one diagonal per cell), F = 2nm, so χ = 0 and the genus is 1. n, m >= 3 keeps it simplicial. */
void
MakeTorusSurface(uint32_t n, uint32_t m, std::vector<Vector3> & points, Triangles & triangles)
{
  const double majorRadius = 3.0;
  const double minorRadius = 1.0;
  const double twoPi = 2.0 * 3.14159265358979323846;
  const auto   index = [n, m](uint32_t i, uint32_t j) { return (i % n) * m + (j % m); };
  for (uint32_t i = 0; i < n; ++i)
  {
    const double u = twoPi * i / n;
    for (uint32_t j = 0; j < m; ++j)
    {
      const double v = twoPi * j / m;
      const double ringRadius = majorRadius + minorRadius * std::cos(v);
      points.push_back({ { ringRadius * std::cos(u), ringRadius * std::sin(u), minorRadius * std::sin(v) } });
    }
  }
  for (uint32_t i = 0; i < n; ++i)
  {
    for (uint32_t j = 0; j < m; ++j)
    {
      triangles.push_back({ { index(i, j), index(i + 1, j), index(i + 1, j + 1) } });
      triangles.push_back({ { index(i, j), index(i + 1, j + 1), index(i, j + 1) } });
    }
  }
}

TEST(SurfaceTopology, GridTorusHasGenusOne)
{
  std::vector<Vector3> points;
  Triangles            triangles;
  MakeTorusSurface(8, 5, points, triangles);
  const SurfaceTopology topology = ComputeSurfaceTopology(points, triangles);
  EXPECT_EQ(topology.numberOfVertices, 40u);
  EXPECT_EQ(topology.numberOfEdges, 120u);
  EXPECT_EQ(topology.numberOfTriangles, 80u);
  EXPECT_TRUE(topology.IsClosedManifold());
  EXPECT_EQ(topology.numberOfComponents, 1);
  EXPECT_EQ(topology.totalGenus, 1);
  EXPECT_EQ(topology.componentGenera, std::vector<int>{ 1 });
}

TEST(SurfaceTopology, TorusAndTetrahedronGeneraAddUp)
{
  std::vector<Vector3> points;
  Triangles            triangles;
  MakeTorusSurface(6, 4, points, triangles);
  const auto offset = static_cast<uint32_t>(points.size());
  for (const Vector3 & p : RegularTetrahedronPoints())
  {
    points.push_back(p + Vector3{ { 20.0, 0.0, 0.0 } });
  }
  Append(triangles, TetrahedronSurface(offset, offset + 1, offset + 3, offset + 2));
  const SurfaceTopology topology = ComputeSurfaceTopology(points, triangles);
  EXPECT_TRUE(topology.IsClosedManifold());
  EXPECT_EQ(topology.numberOfComponents, 2);
  EXPECT_EQ(topology.totalGenus, 1);
}

TEST(SurfaceTopology, TetrahedronSurfacesSharingAVertexArePinched)
{
  // Two closed surfaces meeting only at vertex 0 (a bow-tie): every edge is still in exactly two triangles,
  // but the triangles around vertex 0 form two cycles. The components are edge-connected, so there are two.
  std::vector<Vector3> points = RegularTetrahedronPoints();
  for (const Vector3 & p : { points[1], points[2], points[3] })
  {
    points.push_back(2.0 * points[0] - p);
  }
  Triangles triangles = TetrahedronSurface(0, 1, 3, 2);
  Append(triangles, TetrahedronSurface(0, 4, 5, 6));
  const SurfaceTopology topology = ComputeSurfaceTopology(points, triangles);
  EXPECT_EQ(topology.nonManifoldEdges, 0u);
  EXPECT_EQ(topology.nonManifoldVertices, 1u);
  EXPECT_FALSE(topology.IsClosedManifold());
  EXPECT_EQ(topology.numberOfComponents, 2);
}

TEST(SurfaceTopology, OpenSurfaceHasBoundaryEdges)
{
  // A tetrahedron surface without its face (1, 3, 2): that face's three edges are in one triangle each, and
  // the triangles around its three vertices form paths, not cycles. Vertex 0 keeps its full cycle.
  Triangles triangles = TetrahedronSurface(0, 1, 3, 2);
  triangles.pop_back();
  const SurfaceTopology topology = ComputeSurfaceTopology(RegularTetrahedronPoints(), triangles);
  EXPECT_EQ(topology.nonManifoldEdges, 3u);
  EXPECT_EQ(topology.nonManifoldVertices, 3u);
  EXPECT_FALSE(topology.IsClosedManifold());
  EXPECT_EQ(topology.numberOfComponents, 1);
}

TEST(SurfaceTopology, EdgeInThreeTrianglesIsNonManifold)
{
  // Three triangles on edge (0, 1): that edge is in three triangles, the other six edges in one.
  const std::vector<Vector3> points{
    { { 0.0, 0.0, 0.0 } }, { { 1.0, 0.0, 0.0 } }, { { 0.5, 1.0, 0.0 } }, { { 0.5, -1.0, 0.0 } }, { { 0.5, 0.0, 1.0 } }
  };
  const SurfaceTopology topology =
    ComputeSurfaceTopology(points, { { { 0, 1, 2 } }, { { 0, 1, 3 } }, { { 0, 1, 4 } } });
  EXPECT_EQ(topology.numberOfEdges, 7u);
  EXPECT_EQ(topology.nonManifoldEdges, 7u);
  EXPECT_EQ(topology.nonManifoldVertices, 5u);
}

/** The refinement's manifold check: the vertices whose link is not one cycle, which includes both endpoints of
 * every edge in a number of triangles other than two; vertex indices need not be contiguous. */
TEST(SurfaceTopology, FindNonManifoldVertices)
{
  EXPECT_TRUE(FindNonManifoldVertices(TetrahedronSurface(10, 11, 13, 12)).empty());

  Triangles twoTetrahedraOnAnEdge = TetrahedronSurface(0, 1, 3, 2);
  Append(twoTetrahedraOnAnEdge, TetrahedronSurface(0, 1, 5, 4));
  EXPECT_EQ(FindNonManifoldVertices(twoTetrahedraOnAnEdge), (std::vector<uint32_t>{ 0, 1 }));

  Triangles bowTie = TetrahedronSurface(0, 1, 3, 2);
  Append(bowTie, TetrahedronSurface(0, 4, 5, 6));
  EXPECT_EQ(FindNonManifoldVertices(bowTie), (std::vector<uint32_t>{ 0 }));

  Triangles open = TetrahedronSurface(20, 21, 23, 22);
  open.pop_back();
  EXPECT_EQ(FindNonManifoldVertices(open), (std::vector<uint32_t>{ 21, 22, 23 }));

  EXPECT_EQ(FindNonManifoldVertices({ { { 0, 1, 2 } }, { { 0, 1, 3 } }, { { 0, 1, 4 } } }),
            (std::vector<uint32_t>{ 0, 1, 2, 3, 4 }));
}

TEST(SurfaceTopology, MinimumPlanarAngle)
{
  // A right triangle with legs 1 and √3: angles 30°, 60°, 90°.
  const std::vector<Vector3> points{ { { 0.0, 0.0, 0.0 } }, { { std::sqrt(3.0), 0.0, 0.0 } }, { { 0.0, 1.0, 0.0 } } };
  // The 30° angle at each of the triangle's three corners in turn: every corner counts.
  for (const std::array<uint32_t, 3> & triangle : { std::array<uint32_t, 3>{ { 0, 1, 2 } },
                                                    std::array<uint32_t, 3>{ { 1, 2, 0 } },
                                                    std::array<uint32_t, 3>{ { 2, 0, 1 } } })
  {
    EXPECT_NEAR(ComputeSurfaceTopology(points, { triangle }).minimumPlanarAngle, 30.0, 1e-10)
      << triangle[0] << ' ' << triangle[1] << ' ' << triangle[2];
  }
}

/** The metric the tests hold R3's bound (boundary circumradius < δ) against, checked against circumradii known in
 * closed form: a test of the guarantee is only as strong as this. */
TEST(BoundaryCircumradius, LargestOfTrianglesKnownInClosedForm)
{
  TetrahedralMesh mesh;
  // A 3-4-5 right triangle (circumradius half the hypotenuse, 2.5), in a plane oblique to every axis, and an
  // equilateral triangle of side 2√3 (circumradius side / √3 = 2).
  const Vector3 origin{ { 1.0, -2.0, 0.5 } };
  const Vector3 u{ { 2.0 / 3.0, 2.0 / 3.0, 1.0 / 3.0 } };
  const Vector3 v{ { -2.0 / 3.0, 1.0 / 3.0, 2.0 / 3.0 } };
  const double  side = 2.0 * std::sqrt(3.0);
  mesh.points = { origin,
                  origin + 3.0 * u,
                  origin + 4.0 * v,
                  { { 0.0, 0.0, 0.0 } },
                  { { side, 0.0, 0.0 } },
                  { { 0.5 * side, 0.5 * std::sqrt(3.0) * side, 0.0 } } };
  mesh.boundaryTriangles = { { { 3, 4, 5 } } };
  EXPECT_NEAR(LargestBoundaryCircumradius(mesh), 2.0, 1e-12);
  mesh.boundaryTriangles.push_back({ { 0, 1, 2 } });
  EXPECT_NEAR(LargestBoundaryCircumradius(mesh), 2.5, 1e-12);
  std::swap(mesh.boundaryTriangles[0], mesh.boundaryTriangles[1]);
  EXPECT_NEAR(LargestBoundaryCircumradius(mesh), 2.5, 1e-12);

  // Collinear corners have no circumcircle; coincident ones neither.
  mesh.points.push_back(origin + 1.5 * u);
  mesh.boundaryTriangles.push_back({ { 0, 1, 6 } });
  EXPECT_EQ(LargestBoundaryCircumradius(mesh), Infinity);
  mesh.boundaryTriangles.back() = { { 0, 0, 1 } };
  EXPECT_EQ(LargestBoundaryCircumradius(mesh), Infinity);

  mesh.boundaryTriangles.back() = { { 0, 1, 7 } };
  EXPECT_THROW(LargestBoundaryCircumradius(mesh), std::invalid_argument);
  mesh.boundaryTriangles.clear();
  EXPECT_EQ(LargestBoundaryCircumradius(mesh), 0.0);
}

TEST(SurfaceTopology, OutOfRangeIndexThrows)
{
  EXPECT_THROW(ComputeSurfaceTopology(RegularTetrahedronPoints(), { { { 0, 1, 7 } } }), std::invalid_argument);
}

TEST(SurfaceTopology, BoundaryAndLabelBoundary)
{
  // Two tetrahedron surfaces: the first separates label 1 from the background, the second label 1 from
  // label 2. Label 1 sees both, label 2 only the second, the background only the first.
  TetrahedralMesh mesh;
  mesh.points = RegularTetrahedronPoints();
  for (const Vector3 & p : RegularTetrahedronPoints())
  {
    mesh.points.push_back(p + Vector3{ { 10.0, 0.0, 0.0 } });
  }
  mesh.boundaryTriangles = TetrahedronSurface(0, 1, 3, 2);
  mesh.boundaryTriangleLabels.assign(4, { { 1, BackgroundLabel } });
  Append(mesh.boundaryTriangles, TetrahedronSurface(4, 5, 7, 6));
  mesh.boundaryTriangleLabels.resize(8, { { 1, 2 } });

  EXPECT_EQ(ComputeBoundaryTopology(mesh).numberOfComponents, 2);
  EXPECT_EQ(ComputeLabelBoundaryTopology(mesh, 1).numberOfComponents, 2);
  const SurfaceTopology second = ComputeLabelBoundaryTopology(mesh, 2);
  EXPECT_EQ(second.numberOfComponents, 1);
  EXPECT_EQ(second.numberOfTriangles, 4u);
  EXPECT_TRUE(second.IsClosedManifold());
  EXPECT_EQ(ComputeLabelBoundaryTopology(mesh, BackgroundLabel).numberOfTriangles, 4u);
  EXPECT_EQ(ComputeLabelBoundaryTopology(mesh, 3).numberOfTriangles, 0u);

  // Every label's triangles in one pass, as the quality report takes them: the same as one label at a time, in the
  // same order, and no entry for a label on no triangle.
  const auto byLabel = BoundaryTrianglesByLabel(mesh);
  ASSERT_EQ(byLabel.size(), 3u);
  for (const Label label : { BackgroundLabel, 1, 2 })
  {
    ASSERT_EQ(byLabel.count(label), 1u) << "label " << label;
    EXPECT_EQ(byLabel.at(label), LabelBoundaryTriangles(mesh, label)) << "label " << label;
  }
  EXPECT_EQ(byLabel.at(1).size(), 8u);
}

/** Two triangles on one vertex set (a "pillow"): every edge is in exactly two triangles, but each vertex's link is
 * one edge taken twice. A link is a surface's only when it is one cycle of at least three edges (a disc around the
 * vertex), so all three vertices are non-manifold and the surface is no closed manifold. Nothing else here says
 * so: the edge counts are those of a closed surface. */
TEST(SurfaceTopology, TwoTrianglesOnOneVertexSetAreNoManifold)
{
  const std::vector<Vector3> points{ { { 0.0, 0.0, 0.0 } }, { { 1.0, 0.0, 0.0 } }, { { 0.0, 1.0, 0.0 } } };
  const Triangles            pillow{ { { 0, 1, 2 } }, { { 0, 2, 1 } } };
  const SurfaceTopology      topology = ComputeSurfaceTopology(points, pillow);
  EXPECT_EQ(topology.numberOfEdges, 3u);
  EXPECT_EQ(topology.nonManifoldEdges, 0u);
  EXPECT_EQ(topology.nonManifoldVertices, 3u);
  EXPECT_FALSE(topology.IsClosedManifold());
  EXPECT_EQ(FindNonManifoldVertices(pillow), (std::vector<uint32_t>{ 0, 1, 2 }));
}

/** A boundary triangle must point away from its tetrahedron (BoundaryConsistency::wrongOrientation); a tetrahedron
 * flat to zero volume has each facet's apex in the facet's plane, so none of its facets points away from it, either
 * way round. The check must call them all wrong, as it calls a reversed one wrong, and the right way round right. */
TEST(BoundaryConsistency, TheFacetsOfAFlatTetrahedronPointNowhere)
{
  TetrahedralMesh regular = MeshOf(RegularTetrahedronPoints(), { PositiveRegularTetrahedron });
  regular.boundaryTriangles = TetrahedronSurface(0, 1, 3, 2);
  regular.boundaryTriangleLabels.assign(4, { { 1, BackgroundLabel } });
  EXPECT_TRUE(CheckBoundaryAgainstTetrahedra(regular).IsConsistent());
  TetrahedralMesh reversed = regular;
  for (auto & triangle : reversed.boundaryTriangles)
  {
    std::swap(triangle[1], triangle[2]);
  }
  EXPECT_EQ(CheckBoundaryAgainstTetrahedra(reversed).wrongOrientation, 4u);

  // Four points of the plane z = 0, so each facet's apex lies in its plane: orientation 0 for all four.
  TetrahedralMesh flat =
    MeshOf({ { { 0.0, 0.0, 0.0 } }, { { 1.0, 0.0, 0.0 } }, { { 0.0, 1.0, 0.0 } }, { { 1.0, 1.0, 0.0 } } },
           { { { 0, 1, 2, 3 } } });
  flat.boundaryTriangles = TetrahedronSurface(0, 1, 2, 3);
  flat.boundaryTriangleLabels.assign(4, { { 1, BackgroundLabel } });
  const BoundaryConsistency consistency = CheckBoundaryAgainstTetrahedra(flat);
  EXPECT_EQ(consistency.missingTriangles, 0u);
  EXPECT_EQ(consistency.extraTriangles, 0u);
  EXPECT_EQ(consistency.wrongLabels, 0u);
  EXPECT_EQ(consistency.wrongOrientation, 4u);
  EXPECT_FALSE(consistency.IsConsistent());
}

TEST(ShortestEdgesByKind, EachEndpointCountsForItsKind)
{
  // Edges: 0-1 = 3, 0-2 = 2, 0-3 = 4, 1-2 = √13, 1-3 = 5, 2-3 = √20.
  // Feature (vertex 0): min(3, 2, 4) = 2. Free (vertex 1): min(3, √13, 5) = 3.
  // Box edge (vertices 2, 3): min(2, √13, √20, 4, 5) = 2. No box-face vertex: +infinity.
  TetrahedralMesh mesh =
    MeshOf({ { { 0.0, 0.0, 0.0 } }, { { 3.0, 0.0, 0.0 } }, { { 0.0, 2.0, 0.0 } }, { { 0.0, 0.0, 4.0 } } },
           { { { 0, 1, 2, 3 } } });
  mesh.pointKinds = { VertexKind::Feature, VertexKind::Free, VertexKind::BoxEdge, VertexKind::BoxEdge };
  const ShortestEdgesByKind shortest = ComputeShortestEdgesByKind(mesh);
  EXPECT_DOUBLE_EQ(shortest.shortestEdge.at(VertexKind::Feature), 2.0);
  EXPECT_DOUBLE_EQ(shortest.shortestEdge.at(VertexKind::Free), 3.0);
  EXPECT_DOUBLE_EQ(shortest.shortestEdge.at(VertexKind::BoxEdge), 2.0);
  EXPECT_EQ(shortest.shortestEdge.at(VertexKind::BoxFace), Infinity);
}

TEST(TriangleSurfaceDistance, PointToTriangle)
{
  // The triangle (0,0,0), (2,0,0), (0,2,0) in the plane z = 0.
  const TriangleSurfaceDistance triangle({ { { 0.0, 0.0, 0.0 } }, { { 2.0, 0.0, 0.0 } }, { { 0.0, 2.0, 0.0 } } },
                                         { { { 0, 1, 2 } } });
  // Above an interior point: the height.
  EXPECT_NEAR(triangle.Distance({ { 0.5, 0.5, 3.0 } }), 3.0, Tolerance);
  // In the plane, beyond the hypotenuse x + y = 2: |2 + 2 - 2| / √2 = √2.
  EXPECT_NEAR(triangle.Distance({ { 2.0, 2.0, 0.0 } }), std::sqrt(2.0), Tolerance);
  // Beyond the edge y = 0, 1 above the plane: √(2² + 1²).
  EXPECT_NEAR(triangle.Distance({ { 1.0, -2.0, 1.0 } }), std::sqrt(5.0), Tolerance);
  // Beyond the corner (2, 0, 0): √(1 + 1 + 1).
  EXPECT_NEAR(triangle.Distance({ { 3.0, -1.0, 1.0 } }), std::sqrt(3.0), Tolerance);
  // On the triangle.
  EXPECT_NEAR(triangle.Distance({ { 0.5, 0.5, 0.0 } }), 0.0, Tolerance);
}

TEST(TriangleSurfaceDistance, EmptySurfaceIsInfinitelyFar)
{
  const TriangleSurfaceDistance empty({}, {});
  EXPECT_EQ(empty.Distance({ { 0.0, 0.0, 0.0 } }), Infinity);
}

TEST(SampleTriangles, BarycentricGridIncludesVerticesAndEdgePoints)
{
  // Longest edge √2, spacing 0.8: n = ceil(1.77) = 2 subdivisions, (n + 1)(n + 2) / 2 = 6 points: the three
  // vertices and the three edge midpoints.
  const std::vector<Vector3> points{ { { 0.0, 0.0, 0.0 } }, { { 1.0, 0.0, 0.0 } }, { { 0.0, 1.0, 0.0 } } };
  const std::vector<Vector3> samples = SampleTriangles(points, { { { 0, 1, 2 } } }, 0.8);
  ASSERT_EQ(samples.size(), 6u);
  for (const Vector3 & expected : { points[0],
                                    points[1],
                                    points[2],
                                    Vector3{ { 0.5, 0.0, 0.0 } },
                                    Vector3{ { 0.5, 0.5, 0.0 } },
                                    Vector3{ { 0.0, 0.5, 0.0 } } })
  {
    bool found = false;
    for (const Vector3 & sample : samples)
    {
      found = found || Distance(sample, expected) < Tolerance;
    }
    EXPECT_TRUE(found) << expected[0] << ", " << expected[1] << ", " << expected[2];
  }
  // A spacing larger than the triangle still gives its vertices.
  EXPECT_EQ(SampleTriangles(points, { { { 0, 1, 2 } } }, 10.0).size(), 3u);
  // n = ceil(√2 / 0.1) = 15: 16 * 17 / 2 = 136 points.
  EXPECT_EQ(SampleTriangles(points, { { { 0, 1, 2 } } }, 0.1).size(), 136u);
}

TEST(SampleTriangles, InvalidSpacingThrows)
{
  const std::vector<Vector3> points{ { { 0.0, 0.0, 0.0 } }, { { 1.0, 0.0, 0.0 } }, { { 0.0, 1.0, 0.0 } } };
  EXPECT_THROW(SampleTriangles(points, { { { 0, 1, 2 } } }, 0.0), std::invalid_argument);
  EXPECT_THROW(SampleTriangles(points, { { { 0, 1, 2 } } }, std::nan("")), std::invalid_argument);
}

TEST(SummarizeDistances, MeanPercentileMaximum)
{
  // 1..20: mean 10.5; the 95th percentile is sorted position ceil(0.95 * 20) - 1 = 18, i.e. the value 19.
  std::vector<double> distances;
  for (int value = 20; value >= 1; --value)
  {
    distances.push_back(value);
  }
  const DistanceStatistics statistics = SummarizeDistances(distances);
  EXPECT_EQ(statistics.count, 20u);
  EXPECT_DOUBLE_EQ(statistics.mean, 10.5);
  EXPECT_EQ(statistics.percentile95, 19.0);
  EXPECT_EQ(statistics.maximum, 20.0);
  // 1 value: position ceil(0.95) - 1 = 0.
  EXPECT_EQ(SummarizeDistances({ 7.0 }).percentile95, 7.0);
  const DistanceStatistics none = SummarizeDistances({});
  EXPECT_EQ(none.count, 0u);
  EXPECT_EQ(none.mean, 0.0);
  EXPECT_EQ(none.percentile95, 0.0);
  EXPECT_EQ(none.maximum, 0.0);
}

TEST(TwoSidedDistance, ShiftedUnitSquare)
{
  // The unit square z = 0 (two triangles) against the same square at z = 0.25: every sample of either lies
  // right above or below the other, at distance 0.25. Spacing 0.1: 136 samples per triangle (see above).
  const std::vector<Vector3> square{
    { { 0.0, 0.0, 0.0 } }, { { 1.0, 0.0, 0.0 } }, { { 1.0, 1.0, 0.0 } }, { { 0.0, 1.0, 0.0 } }
  };
  std::vector<Vector3> shifted;
  for (const Vector3 & p : square)
  {
    shifted.push_back(p + Vector3{ { 0.0, 0.0, 0.25 } });
  }
  const Triangles        triangles{ { { 0, 1, 2 } }, { { 0, 2, 3 } } };
  const TwoSidedDistance distance = ComputeTwoSidedDistance(square, triangles, shifted, triangles, 0.1);
  EXPECT_EQ(distance.fromFirst.count, 272u);
  EXPECT_EQ(distance.fromSecond.count, 272u);
  EXPECT_EQ(distance.combined.count, 544u);
  for (const DistanceStatistics & statistics : { distance.fromFirst, distance.fromSecond, distance.combined })
  {
    EXPECT_NEAR(statistics.mean, 0.25, Tolerance);
    EXPECT_NEAR(statistics.percentile95, 0.25, Tolerance);
    EXPECT_NEAR(statistics.maximum, 0.25, Tolerance);
  }
}

TEST(TwoSidedDistance, IsNotSymmetricPerSide)
{
  // The unit square against its left half: the half is within the square (distance 0 from the first side),
  // but the square's right edge is 0.5 from the half.
  const std::vector<Vector3> square{
    { { 0.0, 0.0, 0.0 } }, { { 1.0, 0.0, 0.0 } }, { { 1.0, 1.0, 0.0 } }, { { 0.0, 1.0, 0.0 } }
  };
  const std::vector<Vector3> half{
    { { 0.0, 0.0, 0.0 } }, { { 0.5, 0.0, 0.0 } }, { { 0.5, 1.0, 0.0 } }, { { 0.0, 1.0, 0.0 } }
  };
  const Triangles        triangles{ { { 0, 1, 2 } }, { { 0, 2, 3 } } };
  const TwoSidedDistance distance = ComputeTwoSidedDistance(square, triangles, half, triangles, 0.05);
  EXPECT_NEAR(distance.fromFirst.maximum, 0.5, Tolerance);
  EXPECT_NEAR(distance.fromSecond.maximum, 0.0, Tolerance);
  EXPECT_NEAR(distance.combined.maximum, 0.5, Tolerance);
}

/** A height field z = height(x, y) over [0, 1]², triangulated on a grid whose columns widen along x (the triangles'
 * sample counts differ, so each one's samples start at a different place). */
template <typename THeight>
void
MakeHeightField(std::size_t columns, std::size_t rows, THeight && height, std::vector<Vector3> & points,
                Triangles & triangles)
{
  for (std::size_t j = 0; j <= rows; ++j)
  {
    for (std::size_t i = 0; i <= columns; ++i)
    {
      const double u = static_cast<double>(i) / static_cast<double>(columns);
      const double x = u * u;
      const double y = static_cast<double>(j) / static_cast<double>(rows);
      points.push_back({ { x, y, height(x, y) } });
    }
  }
  const auto at = [columns](std::size_t i, std::size_t j) { return static_cast<uint32_t>(i + (columns + 1) * j); };
  for (std::size_t j = 0; j < rows; ++j)
  {
    for (std::size_t i = 0; i < columns; ++i)
    {
      triangles.push_back({ { at(i, j), at(i + 1, j), at(i + 1, j + 1) } });
      triangles.push_back({ { at(i, j), at(i + 1, j + 1), at(i, j + 1) } });
    }
  }
}

/** Two height fields over [0, 1]² with 100,000+ samples at spacing 0.01 between them: enough for several threads. */
struct TwoHeightFields
{
  std::vector<Vector3> firstPoints;
  Triangles            firstTriangles;
  std::vector<Vector3> secondPoints;
  Triangles            secondTriangles;

  TwoHeightFields()
  {
    const auto wavy = [](double x, double y) { return 0.3 * std::sin(3.0 * x) * std::cos(2.0 * y); };
    const auto tilted = [](double x, double y) { return 0.25 + 0.2 * std::cos(2.0 * x + y); };
    MakeHeightField(60, 45, wavy, firstPoints, firstTriangles);
    MakeHeightField(47, 52, tilted, secondPoints, secondTriangles);
  }
};

/** ComputeTwoSidedDistance measures the samples where it makes them, on several threads, and summarises ranges of
 * one list: it must give exactly what its parts give one by one (SampleTriangles, TriangleSurfaceDistance,
 * SummarizeDistances on each direction's list and on the two lists pooled, first then second). */
TEST(TwoSidedDistance, EqualsItsPartsComputedOneByOne)
{
  const TwoHeightFields fields;
  const auto & [firstPoints, firstTriangles, secondPoints, secondTriangles] = fields;
  const double spacing = 0.01;

  const TriangleSurfaceDistance first(firstPoints, firstTriangles);
  const TriangleSurfaceDistance second(secondPoints, secondTriangles);
  std::vector<double>           fromFirst;
  for (const Vector3 & sample : SampleTriangles(firstPoints, firstTriangles, spacing))
  {
    fromFirst.push_back(second.Distance(sample));
  }
  std::vector<double> fromSecond;
  for (const Vector3 & sample : SampleTriangles(secondPoints, secondTriangles, spacing))
  {
    fromSecond.push_back(first.Distance(sample));
  }
  std::vector<double> pooled(fromFirst);
  pooled.insert(pooled.end(), fromSecond.begin(), fromSecond.end());
  // Enough samples for the measurement to run on more than one thread where there are several.
  ASSERT_GT(pooled.size(), 100000u);

  const TwoSidedDistance distance =
    ComputeTwoSidedDistance(firstPoints, firstTriangles, secondPoints, secondTriangles, spacing);
  const std::array<std::pair<DistanceStatistics, DistanceStatistics>, 3> pairs{
    { { distance.fromFirst, SummarizeDistances(fromFirst) },
      { distance.fromSecond, SummarizeDistances(fromSecond) },
      { distance.combined, SummarizeDistances(pooled) } }
  };
  for (const auto & [computed, expected] : pairs)
  {
    EXPECT_EQ(computed.count, expected.count);
    EXPECT_EQ(computed.mean, expected.mean);
    EXPECT_EQ(computed.percentile95, expected.percentile95);
    EXPECT_EQ(computed.maximum, expected.maximum);
  }
  EXPECT_GT(distance.combined.maximum, distance.combined.percentile95);
  EXPECT_GT(distance.combined.percentile95, distance.combined.mean);
}

/** The progress goes from 0 to 1 without going back, is told several times on a surface of 100,000+ samples, and
 * does not change what is measured. */
TEST(TwoSidedDistance, TellsItsProgress)
{
  const TwoHeightFields fields;
  const auto & [firstPoints, firstTriangles, secondPoints, secondTriangles] = fields;
  const double           spacing = 0.01;
  std::vector<double>    told;
  const TwoSidedDistance withProgress = ComputeTwoSidedDistance(
    firstPoints, firstTriangles, secondPoints, secondTriangles, spacing, [&told](double fraction) {
      told.push_back(fraction);
    });
  ASSERT_GE(told.size(), 3u);
  EXPECT_EQ(told.front(), 0.0);
  EXPECT_EQ(told.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(told.begin(), told.end()));
  EXPECT_TRUE(std::any_of(told.begin(), told.end(), [](double fraction) { return fraction > 0.0 && fraction < 1.0; }));
  const TwoSidedDistance without =
    ComputeTwoSidedDistance(firstPoints, firstTriangles, secondPoints, secondTriangles, spacing);
  EXPECT_EQ(withProgress.combined.mean, without.combined.mean);
  EXPECT_EQ(withProgress.combined.percentile95, without.combined.percentile95);
  EXPECT_EQ(withProgress.combined.maximum, without.combined.maximum);
}

TEST(TwoSidedDistance, InvalidSpacingThrows)
{
  const std::vector<Vector3> points{ { { 0.0, 0.0, 0.0 } }, { { 1.0, 0.0, 0.0 } }, { { 0.0, 1.0, 0.0 } } };
  const Triangles            triangles{ { { 0, 1, 2 } } };
  EXPECT_THROW(ComputeTwoSidedDistance(points, triangles, points, triangles, 0.0), std::invalid_argument);
  EXPECT_THROW(ComputeTwoSidedDistance(points, triangles, points, triangles, -1.0), std::invalid_argument);
}

} // namespace
} // namespace delaunay_refinement
