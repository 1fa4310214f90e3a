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
#ifndef DelaunayRefinementTypes_h
#define DelaunayRefinementTypes_h

#include "DelaunayImageToMeshExport.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

/** \namespace delaunay_refinement
 * \brief The ITK-free refinement core of the DelaunayImageToMesh module.
 *
 * Nothing in this namespace knows about ITK, and no CGAL type appears in its headers, so it can be tested on
 * analytic shapes and parsed by CastXML. */
namespace delaunay_refinement
{

/** A point or vector in physical space (millimetres for medical images). */
using Vector3 = std::array<double, 3>;

/** A tissue label; 0 is the background (outside every object). */
using Label = int32_t;

constexpr Label BackgroundLabel = 0;

/** The types a grid of voxel labels may be stored in (the label image, the regularisation, the pinch removal, the
 * census of parts): Label, or uint16_t or uint8_t when every label of the grid fits, which is most segmentations.
 * Those are read and written as Label; the narrower types take a half or a quarter of the memory, and a voxel pass
 * touches as much less. */
template <typename T>
inline constexpr bool IsVoxelLabelType =
  std::is_same_v<T, Label> || std::is_same_v<T, uint16_t> || std::is_same_v<T, uint8_t>;

inline Vector3
operator+(const Vector3 & a, const Vector3 & b)
{
  return { a[0] + b[0], a[1] + b[1], a[2] + b[2] };
}

inline Vector3
operator-(const Vector3 & a, const Vector3 & b)
{
  return { a[0] - b[0], a[1] - b[1], a[2] - b[2] };
}

inline Vector3
operator*(double s, const Vector3 & a)
{
  return { s * a[0], s * a[1], s * a[2] };
}

inline double
Dot(const Vector3 & a, const Vector3 & b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

inline Vector3
Cross(const Vector3 & a, const Vector3 & b)
{
  return { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
}

inline double
SquaredNorm(const Vector3 & a)
{
  return Dot(a, a);
}

inline double
Norm(const Vector3 & a)
{
  return std::sqrt(Dot(a, a));
}

inline double
Distance(const Vector3 & a, const Vector3 & b)
{
  return Norm(a - b);
}

/** A voxel whose label changed: its offset in a dense grid and the label it had before. */
struct VoxelChange
{
  std::size_t offset{ 0 };
  Label       before{ 0 };
};

/** An axis-aligned box in physical space. */
struct AxisAlignedBox
{
  Vector3 lower{ { 0.0, 0.0, 0.0 } };
  Vector3 upper{ { 0.0, 0.0, 0.0 } };

  bool
  IsEmpty() const
  {
    return !(lower[0] <= upper[0] && lower[1] <= upper[1] && lower[2] <= upper[2]);
  }
};

/** A ball in physical space. */
struct Ball
{
  Vector3 center{ { 0.0, 0.0, 0.0 } };
  double  radius{ 0.0 };
};

/** Kind of a mesh vertex, as the algorithm defines it. */
enum class VertexKind : uint8_t
{
  /** On the bounding box but not on one of its 12 edges. */
  BoxFace = 0,
  /** On one of the 12 edges of the bounding box (the 8 corners included). */
  BoxEdge = 1,
  /** On the object surface (inserted by R1 or R3). */
  Feature = 2,
  /** Anywhere else (inserted by R2 or R4 as a circumcentre). */
  Free = 3
};

/** The tetrahedral mesh produced by the refinement.
 *
 * Points are re-indexed densely (every point is used by at least one tetrahedron). Tetrahedra are positively
 * oriented: (p1 - p0) . ((p2 - p0) x (p3 - p0)) > 0. Boundary triangles are every facet whose two sides carry
 * different labels (object/background and tissue/tissue interfaces); each is oriented so that its normal
 * (p1 - p0) x (p2 - p0) points from the side labelled `boundaryTriangleLabels[i][0]` (always a tetrahedron of
 * the mesh) towards the side labelled `boundaryTriangleLabels[i][1]` (background or another tissue). An
 * interface between two tissues appears once, seen from the tissue with the smaller label. */
struct TetrahedralMesh
{
  std::vector<Vector3>                 points;
  std::vector<VertexKind>              pointKinds;
  std::vector<std::array<uint32_t, 4>> tetrahedra;
  std::vector<Label>                   tetrahedronLabels;
  std::vector<std::array<uint32_t, 3>> boundaryTriangles;
  std::vector<std::array<Label, 2>>    boundaryTriangleLabels;
  /** The surface sampling distance the refinement used at each point when it ended (docs/algorithm.md, "Local
   * sampling distance"): δ, or less inside the zones of finer sampling (around small parts, and of the opt-in
   * manifold refinement), or the finer δ of a zone made for a part left without a tetrahedron for the free vertices
   * R2 inserted outside it because their circumballs met it. Lemma 2's edge bounds hold
   * with the smaller value of an edge's two ends where the sizing is uniform, and with the finest value next to zones
   * (R3's threshold there is also a facet's shortest edge, which carries a zone's δ beyond it). Exported so that
   * tests check edges against the sizing actually used rather than against the refinement's statistics. */
  std::vector<double> pointSamplingDistances;
  /** The tetrahedra (indices, increasing) whose label is not the one at their circumcentre but a neighbour's, given
   * where a boundary was not a 2-manifold (docs/algorithm.md, "Topology"). */
  std::vector<uint32_t> topologyRelabelledTetrahedra;
  /** The points (indices, increasing) moved to remove a tetrahedron flat to rounding that nothing else removed: their
   * edges keep only LastResortSpacingFraction of Lemma 2's bounds (docs/algorithm.md, "Flat tetrahedra inside a
   * tissue"). Empty in almost every mesh. */
  std::vector<uint32_t> pointsMovedBelowSpacing;
};

/** The share of Lemma 2's edge bounds that a move removing a tetrahedron flat to rounding must keep when no move
 * keeps all of it and no edge removal takes the tetrahedron out (TetrahedralMesh::pointsMovedBelowSpacing). */
constexpr double LastResortSpacingFraction = 0.99;

} // namespace delaunay_refinement

#endif
