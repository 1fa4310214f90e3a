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

// The edge removal that takes tetrahedra flat to rounding out of a tissue
// (src/DelaunayRefinementFlatTetrahedronRemoval.h, docs/algorithm.md, "Flat tetrahedra inside a tissue"), on the
// smallest mesh that has one: an octahedron whose square is split by one diagonal above and by the other below, the
// flat tetrahedron of the square's four corners between them. Volumes, orientation and conformity are computed here
// from the coordinates.

#include "DelaunayRefinementFlatTetrahedronRemoval.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

namespace dr = delaunay_refinement;

namespace
{

/** Label 1 everywhere near the octahedron. */
class TissueEverywhere : public dr::LabelOracle
{
public:
  dr::Label
  LabelAt(const dr::Vector3 &) const override
  {
    return 1;
  }
  dr::AxisAlignedBox
  ObjectBounds() const override
  {
    return { { { -2.0, -2.0, -2.0 } }, { { 2.0, 2.0, 2.0 } } };
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
};

enum Corner : uint32_t
{
  A,
  B,
  C,
  D,
  Above,
  Below
};

/** The square A B C D on the unit circle of z = 0, split by A C above (apex at z = 1) and by B D below (z = -1),
 * and the flat tetrahedron A B C D, each tetrahedron with positive volume. */
dr::TetrahedralMesh
OctahedronWithAFlatTetrahedron()
{
  dr::TetrahedralMesh mesh;
  mesh.points = { { { 1.0, 0.0, 0.0 } },  { { 0.0, 1.0, 0.0 } }, { { -1.0, 0.0, 0.0 } },
                  { { 0.0, -1.0, 0.0 } }, { { 0.0, 0.0, 1.0 } }, { { 0.0, 0.0, -1.0 } } };
  mesh.pointKinds.assign(mesh.points.size(), dr::VertexKind::Free);
  mesh.tetrahedra = { { A, B, C, D }, { A, B, C, Above }, { A, C, D, Above }, { A, B, D, Below }, { B, C, D, Below } };
  for (auto & tetrahedron : mesh.tetrahedra)
  {
    const std::array<dr::Vector3, 4> corners{
      mesh.points[tetrahedron[0]], mesh.points[tetrahedron[1]], mesh.points[tetrahedron[2]], mesh.points[tetrahedron[3]]
    };
    if (dr::SignedVolume(corners) < 0.0)
    {
      std::swap(tetrahedron[2], tetrahedron[3]);
    }
  }
  mesh.tetrahedronLabels.assign(mesh.tetrahedra.size(), 1);
  return mesh;
}

double
SignedVolumeOf(const dr::TetrahedralMesh & mesh, const std::array<uint32_t, 4> & t)
{
  const auto from = [&](int corner) {
    const dr::Vector3 & p = mesh.points[t[corner]];
    const dr::Vector3 & o = mesh.points[t[0]];
    return std::array<double, 3>{ { p[0] - o[0], p[1] - o[1], p[2] - o[2] } };
  };
  const std::array<double, 3> b = from(1);
  const std::array<double, 3> c = from(2);
  const std::array<double, 3> d = from(3);
  return (b[0] * (c[1] * d[2] - c[2] * d[1]) - b[1] * (c[0] * d[2] - c[2] * d[0]) +
          b[2] * (c[0] * d[1] - c[1] * d[0])) /
         6.0;
}

/** How many tetrahedra each triangle is a face of. */
std::map<std::array<uint32_t, 3>, int>
FaceUses(const dr::TetrahedralMesh & mesh)
{
  std::map<std::array<uint32_t, 3>, int> uses;
  for (const auto & t : mesh.tetrahedra)
  {
    for (int skipped = 0; skipped < 4; ++skipped)
    {
      std::array<uint32_t, 3> face{};
      int                     count = 0;
      for (int corner = 0; corner < 4; ++corner)
      {
        if (corner != skipped)
        {
          face[count++] = t[corner];
        }
      }
      std::sort(face.begin(), face.end());
      ++uses[face];
    }
  }
  return uses;
}

/** The mesh fills a region of volume `volume` once: every tetrahedron has at least `smallest` volume, positive, the
 * volumes add up, every face inside is shared by two tetrahedra, and `outerFaces` faces by one. */
void
ExpectFilledOnce(const dr::TetrahedralMesh & mesh, double smallest, double volume, int outerFaces)
{
  double total = 0.0;
  for (const auto & t : mesh.tetrahedra)
  {
    const double tetrahedronVolume = SignedVolumeOf(mesh, t);
    EXPECT_GT(tetrahedronVolume, smallest) << "no tetrahedron is flat or inverted";
    total += tetrahedronVolume;
  }
  EXPECT_NEAR(total, volume, 1e-12) << "the region is filled once";
  int outer = 0;
  for (const auto & [face, uses] : FaceUses(mesh))
  {
    EXPECT_LE(uses, 2);
    outer += uses == 1;
  }
  EXPECT_EQ(outer, outerFaces);
}

TEST(FlatTetrahedronRemoval, TakesTheFlatTetrahedronOutOfAnOctahedron)
{
  const TissueEverywhere oracle;
  dr::TetrahedralMesh    mesh = OctahedronWithAFlatTetrahedron();
  ASSERT_NEAR(SignedVolumeOf(mesh, mesh.tetrahedra[0]), 0.0, 1e-15) << "the square's tetrahedron is flat";

  EXPECT_EQ(dr::detail::FlatTetrahedronRemoval(oracle, 2.0).Remove(mesh), 1u);

  ASSERT_EQ(mesh.tetrahedra.size(), 4u);
  ASSERT_EQ(mesh.tetrahedronLabels.size(), 4u);
  // The octahedron's volume, and its 8 faces.
  ExpectFilledOnce(mesh, 0.1, 4.0 / 3.0, 8);
}

/** The ring around the z axis's edge from (0, 0, 1) to (0, 0, -1) over the pentagon (1, 0), (2, 0), (0, 1), (-1, 0),
 * (0, -1) of z = 0, whose first two corners are on one ray from the axis: their tetrahedron with the edge is flat. The
 * pentagon is not convex at (1, 0), and the triangulations with the diagonal from (0, -1) to (2, 0) put a triangle
 * outside it: joined to the edge's ends, it makes tetrahedra outside the ring, which must not be made (a and b must
 * see every triangle from its two sides, the same two for all). */
TEST(FlatTetrahedronRemoval, FillsOnlyTheRingWhereItIsNotConvex)
{
  const TissueEverywhere oracle;
  dr::TetrahedralMesh    mesh;
  mesh.points = { { { 0.0, 0.0, 1.0 } }, { { 0.0, 0.0, -1.0 } }, { { 1.0, 0.0, 0.0 } }, { { 2.0, 0.0, 0.0 } },
                  { { 0.0, 1.0, 0.0 } }, { { -1.0, 0.0, 0.0 } }, { { 0.0, -1.0, 0.0 } } };
  mesh.pointKinds.assign(mesh.points.size(), dr::VertexKind::Free);
  mesh.tetrahedra = { { 0, 1, 2, 3 }, { 0, 1, 3, 4 }, { 0, 1, 4, 5 }, { 0, 1, 5, 6 }, { 0, 1, 6, 2 } };
  for (auto & tetrahedron : mesh.tetrahedra)
  {
    if (SignedVolumeOf(mesh, tetrahedron) < 0.0)
    {
      std::swap(tetrahedron[2], tetrahedron[3]);
    }
  }
  mesh.tetrahedronLabels.assign(mesh.tetrahedra.size(), 1);
  ASSERT_NEAR(SignedVolumeOf(mesh, mesh.tetrahedra[0]), 0.0, 1e-15) << "the first tetrahedron is flat";

  // ρ large: the shapes of the new tetrahedra do not decide here, only whether they fill the ring.
  EXPECT_EQ(dr::detail::FlatTetrahedronRemoval(oracle, 100.0).Remove(mesh), 1u);

  // Two pyramids of height 1 over the pentagon, of area 2.5, and their 10 faces: the ring, and nothing beyond it.
  ExpectFilledOnce(mesh, 0.01, 5.0 / 3.0, 10);
}

TEST(FlatTetrahedronRemoval, LeavesTetrahedraOfAnotherTissueAsTheyAre)
{
  const TissueEverywhere oracle;
  dr::TetrahedralMesh    mesh = OctahedronWithAFlatTetrahedron();
  // The ring around A C holds a tetrahedron of tissue 2: only B D's ring, all of tissue 1, may be removed.
  mesh.tetrahedronLabels[1] = 2;
  const std::array<uint32_t, 4> otherTissue = mesh.tetrahedra[1];

  EXPECT_EQ(dr::detail::FlatTetrahedronRemoval(oracle, 2.0).Remove(mesh), 1u);

  ASSERT_EQ(mesh.tetrahedra.size(), 4u);
  EXPECT_EQ(mesh.tetrahedra[0], otherTissue) << "the other tissue's tetrahedron keeps its place";
  EXPECT_EQ(mesh.tetrahedronLabels[0], 2);
  for (const auto & t : mesh.tetrahedra)
  {
    EXPECT_GT(SignedVolumeOf(mesh, t), 0.1);
  }
  for (const auto & [face, uses] : FaceUses(mesh))
  {
    EXPECT_LE(uses, 2);
  }
}

TEST(FlatTetrahedronRemoval, KeepsTheMeshWhenEveryRingMixesTissues)
{
  const TissueEverywhere oracle;
  dr::TetrahedralMesh    mesh = OctahedronWithAFlatTetrahedron();
  mesh.tetrahedronLabels[1] = 2;
  mesh.tetrahedronLabels[3] = 2;
  const dr::TetrahedralMesh before = mesh;

  EXPECT_EQ(dr::detail::FlatTetrahedronRemoval(oracle, 2.0).Remove(mesh), 0u);

  EXPECT_EQ(mesh.tetrahedra, before.tetrahedra);
  EXPECT_EQ(mesh.tetrahedronLabels, before.tetrahedronLabels);
}

TEST(FlatTetrahedronRemoval, KeepsTheMeshWhenTheNewTetrahedraWouldReachRho)
{
  const TissueEverywhere    oracle;
  dr::TetrahedralMesh       mesh = OctahedronWithAFlatTetrahedron();
  const dr::TetrahedralMesh before = mesh;
  // The new tetrahedra have radius-edge ratio 1/sqrt(2): a bound below that refuses them.
  EXPECT_EQ(dr::detail::FlatTetrahedronRemoval(oracle, 0.7).Remove(mesh), 0u);
  EXPECT_EQ(mesh.tetrahedra, before.tetrahedra);
}

/** Tissue 2 above z = 0 (the origin included), tissue 1 below. */
class TwoTissues : public TissueEverywhere
{
public:
  dr::Label
  LabelAt(const dr::Vector3 & point) const override
  {
    return point[2] >= 0.0 ? 2 : 1;
  }
};

TEST(FlatTetrahedronRemoval, FlipsTheDiagonalOfAnInterface)
{
  // The flat tetrahedron is of tissue 1, below the interface; the tetrahedra above are of tissue 2. Removing B D
  // inside tissue 1 would make tetrahedra whose circumcentre (the origin) is in tissue 2: refused. Removing A C as
  // if the flat tetrahedron were of tissue 2 flips the interface from A B C, A C D to A B D, B C D.
  const TwoTissues    oracle;
  dr::TetrahedralMesh mesh = OctahedronWithAFlatTetrahedron();
  mesh.tetrahedronLabels = { 1, 2, 2, 1, 1 };
  mesh.boundaryTriangles = { { A, B, C }, { A, C, D } };
  mesh.boundaryTriangleLabels = { { 1, 2 }, { 1, 2 } };

  EXPECT_EQ(dr::detail::FlatTetrahedronRemoval(oracle, 2.0).Remove(mesh), 1u);

  ASSERT_EQ(mesh.tetrahedra.size(), 4u);
  for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
  {
    EXPECT_GT(SignedVolumeOf(mesh, mesh.tetrahedra[t]), 0.1);
    const bool above =
      std::find(mesh.tetrahedra[t].begin(), mesh.tetrahedra[t].end(), Above) != mesh.tetrahedra[t].end();
    EXPECT_EQ(mesh.tetrahedronLabels[t], above ? 2 : 1) << "tissue 2 above, tissue 1 below";
  }
  ASSERT_EQ(mesh.boundaryTriangles.size(), 2u);
  std::vector<std::array<uint32_t, 3>> sorted;
  for (std::size_t index = 0; index < 2; ++index)
  {
    const auto & triangle = mesh.boundaryTriangles[index];
    EXPECT_EQ(mesh.boundaryTriangleLabels[index], (std::array<dr::Label, 2>{ 1, 2 }));
    // Oriented out of tissue 1 (the smaller label), below: the normal points up.
    const dr::Vector3 & p = mesh.points[triangle[0]];
    const dr::Vector3 & q = mesh.points[triangle[1]];
    const dr::Vector3 & r = mesh.points[triangle[2]];
    const double        normalZ = (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
    EXPECT_GT(normalZ, 0.0);
    std::array<uint32_t, 3> copy = triangle;
    std::sort(copy.begin(), copy.end());
    sorted.push_back(copy);
  }
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(sorted, (std::vector<std::array<uint32_t, 3>>{ { A, B, D }, { B, C, D } }));
}

} // namespace
