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
#include "DelaunayRefinementIndependentAngles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
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
 * and the flat tetrahedron A B C D, each tetrahedron with positive volume; with `cornerCX` above -1, C moves along
 * the x axis towards the centre and the square becomes a kite. */
dr::TetrahedralMesh
OctahedronWithAFlatTetrahedron(double cornerCX = -1.0)
{
  dr::TetrahedralMesh mesh;
  mesh.points = { { { 1.0, 0.0, 0.0 } },  { { 0.0, 1.0, 0.0 } }, { { cornerCX, 0.0, 0.0 } },
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

/** Tissue 2 down to z = -0.5, tissue 1 below: the circumcentres of the tetrahedra below the square are in tissue 2. */
class TissueTwoDownToBelowTheSquare : public TissueEverywhere
{
public:
  dr::Label
  LabelAt(const dr::Vector3 & point) const override
  {
    return point[2] >= -0.5 ? 2 : 1;
  }
};

TEST(FlatTetrahedronRemoval, FlipsNoDiagonalThatWouldMakeANarrowInterfaceTriangle)
{
  // The same interface on a kite: C at (-0.2, 0, 0). Removing B D inside tissue 1 is refused (the new tetrahedra's
  // circumcentres are in tissue 2). The flip would make the interface triangles A B D (angles 45°, 45°, 90°) and
  // B C D, whose angles at B and D are atan(0.2) = 11.3°: below R3's 30°, so the flat tetrahedron stays (later steps
  // deal with it) and no interface triangle gets an angle of 30° or less.
  const TissueTwoDownToBelowTheSquare oracle;
  dr::TetrahedralMesh                 mesh = OctahedronWithAFlatTetrahedron(-0.2);
  mesh.tetrahedronLabels = { 1, 2, 2, 1, 1 };
  mesh.boundaryTriangles = { { A, B, C }, { A, C, D } };
  mesh.boundaryTriangleLabels = { { 1, 2 }, { 1, 2 } };
  const dr::TetrahedralMesh before = mesh;

  // ρ large: only the interface triangles' angles can refuse the flip.
  EXPECT_EQ(dr::detail::FlatTetrahedronRemoval(oracle, 100.0).Remove(mesh), 0u);

  EXPECT_EQ(mesh.tetrahedra, before.tetrahedra);
  for (const auto & triangle : mesh.boundaryTriangles)
  {
    EXPECT_GT(dr::SmallestPlanarAngle(mesh.points[triangle[0]], mesh.points[triangle[1]], mesh.points[triangle[2]]),
              30.0);
  }
}

/** The ring of tetrahedra around the z axis's edge from (0, 0, 1) (vertex 0) to (0, 0, -1) (vertex 1) over `link`,
 * a polygon of z = 0 around the axis in counter-clockwise order (vertices 2, 3, ...): one tetrahedron of tissue 1 per
 * side of the polygon, each with positive volume. */
dr::TetrahedralMesh
RingAroundTheZAxis(const std::vector<dr::Vector3> & link)
{
  dr::TetrahedralMesh mesh;
  mesh.points = { { { 0.0, 0.0, 1.0 } }, { { 0.0, 0.0, -1.0 } } };
  mesh.points.insert(mesh.points.end(), link.begin(), link.end());
  mesh.pointKinds.assign(mesh.points.size(), dr::VertexKind::Free);
  const auto corners = static_cast<uint32_t>(link.size());
  for (uint32_t side = 0; side < corners; ++side)
  {
    std::array<uint32_t, 4> tetrahedron{ 0, 1, 2 + side, 2 + (side + 1) % corners };
    if (SignedVolumeOf(mesh, tetrahedron) < 0.0)
    {
      std::swap(tetrahedron[2], tetrahedron[3]);
    }
    mesh.tetrahedra.push_back(tetrahedron);
  }
  mesh.tetrahedronLabels.assign(mesh.tetrahedra.size(), 1);
  return mesh;
}

/** Twice the signed area of the triangle (p, q, r) of z = 0: positive when counter-clockwise. */
double
TwiceSignedArea(const dr::Vector3 & p, const dr::Vector3 & q, const dr::Vector3 & r)
{
  return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
}

/** The largest smallest dihedral angle, in degrees, over the ways to fill the ring of RingAroundTheZAxis(link)
 * without the edge: every triangulation of the link polygon by diagonals whose triangles are all counter-clockwise
 * (inside the polygon), each joined to both ends of the edge. Found by trying them all, with this file's own
 * enumeration and the tests' own angles. */
double
BestSmallestAngleWithoutTheEdge(const std::vector<dr::Vector3> & link)
{
  double                                                                      best = -1.0;
  std::vector<std::array<std::size_t, 3>>                                     triangles;
  const std::function<void(std::vector<std::pair<std::size_t, std::size_t>>)> fill =
    [&](std::vector<std::pair<std::size_t, std::size_t>> chains) {
      while (!chains.empty() && chains.back().second - chains.back().first < 2)
      {
        chains.pop_back();
      }
      if (chains.empty())
      {
        dr::TetrahedralMesh filled;
        filled.points = { { { 0.0, 0.0, 1.0 } }, { { 0.0, 0.0, -1.0 } } };
        filled.points.insert(filled.points.end(), link.begin(), link.end());
        for (const auto & triangle : triangles)
        {
          for (const uint32_t apex : { 0U, 1U })
          {
            filled.tetrahedra.push_back({ apex,
                                          2 + static_cast<uint32_t>(triangle[0]),
                                          2 + static_cast<uint32_t>(triangle[1]),
                                          2 + static_cast<uint32_t>(triangle[2]) });
          }
        }
        best = std::max(best, dr::SmallestDihedralAngleFromNormals(filled));
        return;
      }
      const auto [first, last] = chains.back();
      chains.pop_back();
      for (std::size_t apex = first + 1; apex < last; ++apex)
      {
        if (!(TwiceSignedArea(link[first], link[apex], link[last]) > 1e-9))
        {
          continue;
        }
        triangles.push_back({ first, apex, last });
        std::vector<std::pair<std::size_t, std::size_t>> next = chains;
        next.emplace_back(first, apex);
        next.emplace_back(apex, last);
        fill(next);
        triangles.pop_back();
      }
    };
  fill({ { 0, link.size() - 1 } });
  return best;
}

/** Rings of 6 and 7 (the largest the removal tries) whose link's first two corners are on one ray from the axis:
 * their tetrahedron with the edge is flat. The removal must take it out, and of the polygon's triangulations take the
 * one whose smallest dihedral angle is largest (on these links the first triangulation that fits is not it). */
TEST(FlatTetrahedronRemoval, TakesTheRingsTriangulationWithTheLargestSmallestAngle)
{
  const std::vector<std::vector<dr::Vector3>> links = {
    { { { 1.0, 0.0, 0.0 } },
      { { 1.71937, 0.0, 0.0 } },
      { { 0.771202, 0.955329, 0.0 } },
      { { -0.968254, 0.353713, 0.0 } },
      { { -1.17337, -0.71553, 0.0 } },
      { { 0.598918, -1.25882, 0.0 } } },
    { { { 1.0, 0.0, 0.0 } },
      { { 1.7, 0.0, 0.0 } },
      { { 0.6, 1.04, 0.0 } },
      { { -0.4, 0.69, 0.0 } },
      { { -1.4, 0.0, 0.0 } },
      { { -0.45, -0.78, 0.0 } },
      { { 0.65, -1.13, 0.0 } } },
  };
  const TissueEverywhere oracle;
  for (const auto & link : links)
  {
    dr::TetrahedralMesh mesh = RingAroundTheZAxis(link);
    ASSERT_NEAR(SignedVolumeOf(mesh, mesh.tetrahedra[0]), 0.0, 1e-15) << "the first tetrahedron is flat";
    const double best = BestSmallestAngleWithoutTheEdge(link);
    ASSERT_GT(best, 0.0) << "some triangulation fills the ring";
    double twiceArea = 0.0;
    for (std::size_t corner = 0; corner < link.size(); ++corner)
    {
      twiceArea += TwiceSignedArea({ { 0.0, 0.0, 0.0 } }, link[corner], link[(corner + 1) % link.size()]);
    }

    // ρ large: every triangulation that fills the ring keeps the radius-edge bound.
    EXPECT_EQ(dr::detail::FlatTetrahedronRemoval(oracle, 100.0).Remove(mesh), 1u) << link.size() << " corners";

    // Two pyramids of height 1 over the polygon, and their 2 × corners faces.
    ExpectFilledOnce(mesh, 1e-3, 2.0 * (twiceArea / 2.0) / 3.0, 2 * static_cast<int>(link.size()));
    EXPECT_NEAR(dr::SmallestDihedralAngleFromNormals(mesh), best, 1e-9) << link.size() << " corners";
  }
}

} // namespace
