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
#ifndef DelaunayRefinementGeometry_h
#define DelaunayRefinementGeometry_h

#include "DelaunayRefinementTypes.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace delaunay_refinement
{

constexpr double Pi = 3.14159265358979323846;

inline double
RadiansToDegrees(double radians)
{
  return radians * 180.0 / Pi;
}

inline double
DegreesToRadians(double degrees)
{
  return degrees * Pi / 180.0;
}

/** Length of the shortest of the six edges. */
inline double
ShortestEdgeLength(const std::array<Vector3, 4> & corners)
{
  double shortest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 4; ++i)
  {
    for (int j = i + 1; j < 4; ++j)
    {
      shortest = std::min(shortest, Distance(corners[i], corners[j]));
    }
  }
  return shortest;
}

/** Length of the shortest of a triangle's three edges. */
inline double
ShortestEdgeLength(const Vector3 & a, const Vector3 & b, const Vector3 & c)
{
  return std::sqrt(std::min({ SquaredNorm(a - b), SquaredNorm(b - c), SquaredNorm(c - a) }));
}

/** Signed volume: positive when (p1 - p0, p2 - p0, p3 - p0) is a right-handed frame. */
inline double
SignedVolume(const std::array<Vector3, 4> & corners)
{
  return Dot(corners[1] - corners[0], Cross(corners[2] - corners[0], corners[3] - corners[0])) / 6.0;
}

/** A normal (not unit) of the face opposite corner `face`, pointing away from that corner. */
inline Vector3
OutwardFaceNormal(const std::array<Vector3, 4> & corners, int face)
{
  const Vector3 & a = corners[(face + 1) & 3];
  const Vector3 & b = corners[(face + 2) & 3];
  const Vector3 & c = corners[(face + 3) & 3];
  const Vector3   normal = Cross(b - a, c - a);
  return Dot(normal, corners[face] - a) > 0.0 ? -1.0 * normal : normal;
}

/** The six interior dihedral angles, in degrees. The dihedral angle at edge (i, j) is the angle between the
 * two faces that share it, i.e. 180° minus the angle between their outward normals. */
inline std::array<double, 6>
DihedralAngles(const std::array<Vector3, 4> & corners)
{
  std::array<Vector3, 4> normals;
  for (int k = 0; k < 4; ++k)
  {
    normals[k] = OutwardFaceNormal(corners, k);
  }
  std::array<double, 6> angles{};
  int                   next = 0;
  for (int k = 0; k < 4; ++k)
  {
    for (int l = k + 1; l < 4; ++l)
    {
      const double lengths = Norm(normals[k]) * Norm(normals[l]);
      const double cosine = lengths > 0.0 ? std::clamp(Dot(normals[k], normals[l]) / lengths, -1.0, 1.0) : 1.0;
      angles[next++] = 180.0 - RadiansToDegrees(std::acos(cosine));
    }
  }
  return angles;
}

/** The cosine of the smallest dihedral angle: what MinimumDihedralAngle() takes the arc cosine of, for tests
 * against a bound that are asked of every new tetrahedron and need no angle. */
inline double
CosineOfSmallestDihedralAngle(const std::array<Vector3, 4> & corners)
{
  std::array<Vector3, 4> normals;
  std::array<double, 4>  lengths{};
  for (int k = 0; k < 4; ++k)
  {
    normals[k] = OutwardFaceNormal(corners, k);
    lengths[k] = Norm(normals[k]);
  }
  double largest = -1.0;
  for (int k = 0; k < 4; ++k)
  {
    for (int l = k + 1; l < 4; ++l)
    {
      const double product = lengths[k] * lengths[l];
      const double cosine = product > 0.0 ? std::clamp(Dot(normals[k], normals[l]) / product, -1.0, 1.0) : 1.0;
      largest = std::max(largest, -cosine);
    }
  }
  return largest;
}

inline double
MinimumDihedralAngle(const std::array<Vector3, 4> & corners)
{
  const std::array<double, 6> angles = DihedralAngles(corners);
  return *std::min_element(angles.begin(), angles.end());
}

/** R4's test: whether a tetrahedron with these corners and this (cached) squared circumradius reaches the
 * radius-edge bound ρ. Within rounding of ρ counts as reaching it: the circumradius cached by the refinement and the
 * one a user recomputes from the written coordinates differ in the last bits, and the bound is a promise about the
 * latter (a randomized case met 1.0000000000000056 >= ρ = 1). */
inline bool
ReachesRadiusEdgeBound(double squaredCircumradius, const std::array<Vector3, 4> & corners, double radiusEdgeBound)
{
  constexpr double RoundingMargin = 1e-12;
  return std::sqrt(squaredCircumradius) >= radiusEdgeBound * ShortestEdgeLength(corners) * (1.0 - RoundingMargin);
}

/** R4′'s test, written once for the rules and for the steps that must not give a tissue what R4′ would split:
 * σ in degrees, off for σ = 0. Compares cosines, which fall as angles grow: cos σ is computed once. */
class DihedralAngleBound
{
public:
  explicit DihedralAngleBound(double minimumDihedralAngle)
    : m_IsOn(minimumDihedralAngle > 0.0)
    , m_CosineOfSigma(std::cos(DegreesToRadians(minimumDihedralAngle)))
  {}

  /** Whether σ > 0: with σ = 0 no tetrahedron is a sliver. */
  bool
  IsOn() const
  {
    return m_IsOn;
  }

  /** Whether a tetrahedron has a dihedral angle below σ (never while σ = 0). */
  bool
  IsSliver(const std::array<Vector3, 4> & corners) const
  {
    return m_IsOn && CosineOfSmallestDihedralAngle(corners) > m_CosineOfSigma;
  }

  /** Whether a smallest dihedral angle with this cosine reaches σ. */
  bool
  IsReachedBy(double cosineOfSmallestAngle) const
  {
    return cosineOfSmallestAngle <= m_CosineOfSigma;
  }

private:
  bool   m_IsOn;
  double m_CosineOfSigma;
};

/** A tetrahedron is flat to rounding when its volume is at most this × its shortest edge cubed: ten times what the
 * output promises (1e-6), so that the promise survives coordinates rounded on output; a regular one has 0.118.
 * Its circumcentre, and so the label there, is then numerically arbitrary (docs/algorithm.md, "Flat caps"). */
constexpr double FlatVolumeFraction = 1e-5;

/** Volume / shortest edge cubed: 0 for a flat tetrahedron, 0.118 for a regular one. */
inline double
VolumeOverShortestEdgeCubed(const std::array<Vector3, 4> & corners)
{
  const double shortest = ShortestEdgeLength(corners);
  const double volume =
    std::abs(Dot(corners[1] - corners[0], Cross(corners[2] - corners[0], corners[3] - corners[0]))) / 6.0;
  return volume / (shortest * shortest * shortest);
}

inline bool
IsFlatToRounding(const std::array<Vector3, 4> & corners)
{
  return !(VolumeOverShortestEdgeCubed(corners) > FlatVolumeFraction);
}

/** Circumcentre of a tetrahedron (the point equidistant from its four corners). Not finite for a flat one. */
inline Vector3
TetrahedronCircumcenter(const std::array<Vector3, 4> & corners)
{
  const Vector3 b = corners[1] - corners[0];
  const Vector3 c = corners[2] - corners[0];
  const Vector3 d = corners[3] - corners[0];
  const double  denominator = 2.0 * Dot(b, Cross(c, d));
  const Vector3 numerator = SquaredNorm(b) * Cross(c, d) + SquaredNorm(c) * Cross(d, b) + SquaredNorm(d) * Cross(b, c);
  return corners[0] + (1.0 / denominator) * numerator;
}

/** Circumradius / shortest edge. */
inline double
RadiusEdgeRatio(const std::array<Vector3, 4> & corners)
{
  return Distance(TetrahedronCircumcenter(corners), corners[0]) / ShortestEdgeLength(corners);
}

/** The three planar angles of a triangle, in degrees. */
inline std::array<double, 3>
PlanarAngles(const Vector3 & a, const Vector3 & b, const Vector3 & c)
{
  const auto angleAt = [](const Vector3 & apex, const Vector3 & p, const Vector3 & q) {
    const Vector3 u = p - apex;
    const Vector3 v = q - apex;
    const double  lengths = Norm(u) * Norm(v);
    const double  cosine = lengths > 0.0 ? std::clamp(Dot(u, v) / lengths, -1.0, 1.0) : 1.0;
    return RadiansToDegrees(std::acos(cosine));
  };
  return { angleAt(a, b, c), angleAt(b, c, a), angleAt(c, a, b) };
}

/** How far above 30° a triangle's smallest angle must be, in degrees, for HasPlanarAnglesAbove30Degrees: far above
 * rounding, far below anything a mesh could show. The voxel lattice makes triangles of exactly 30° (two voxel-face
 * centres h/√2 from a third and h·√(3/2) apart), and two correct formulas give 29.999999999999996° and
 * 30.00000000000003° for one of them (found on the atlas phantom at δ = 0.70710678 mm): without the margin, whether
 * the bound holds would depend on who measures. */
constexpr double PlanarAngleBoundMarginDegrees = 1e-9;

/** A triangle whose circumradius is below this fraction of its shortest edge has every angle above 30° by
 * PlanarAngleBoundMarginDegrees: its smallest angle θ has sin θ = shortest / (2 R) > 1 / (2 (1 − c)) ≥ sin(30° + m)
 * once c ≥ √3 m (m in radians, to first order), 3.0e-11 here; 1e-10 leaves room for the rounding of R and of the
 * angle. R3 compares with it (RefinementRules::SurfaceBallThreshold), so the rule and the checks agree on ties. */
constexpr double ShortestEdgeFactorForPlanarAngleMargin = 1.0 - 1e-10;
static_assert(1.0 - ShortestEdgeFactorForPlanarAngleMargin >
                1.7320508075688772 * PlanarAngleBoundMarginDegrees * 3.141592653589793 / 180.0,
              "R3's threshold must keep the planar-angle margin");

/** Theorem 2's bound on boundary triangles: every planar angle above 30°, by PlanarAngleBoundMarginDegrees. For the
 * steps that put an existing triangle on a boundary without R3 (flat caps, the relabelling at non-manifold places,
 * R4′'s new triangles, the interface flips), which must keep it. */
inline bool
HasPlanarAnglesAbove30Degrees(const Vector3 & a, const Vector3 & b, const Vector3 & c)
{
  const std::array<double, 3> angles = PlanarAngles(a, b, c);
  return *std::min_element(angles.begin(), angles.end()) > 30.0 + PlanarAngleBoundMarginDegrees;
}

/** The circumradius of a triangle, |ab| |bc| |ca| / (4 area). Coincident corners give 0 / 0: infinity is returned
 * then, since a NaN would drop out of a maximum and hide the degenerate triangle, which has no more a circumcircle
 * than a collinear one (x / 0 = infinity). */
inline double
TriangleCircumradius(const Vector3 & a, const Vector3 & b, const Vector3 & c)
{
  const double twiceArea = Norm(Cross(b - a, c - a));
  const double circumradius = Distance(a, b) * Distance(b, c) * Distance(c, a) / (2.0 * twiceArea);
  return std::isnan(circumradius) ? std::numeric_limits<double>::infinity() : circumradius;
}

/** The point nearest to `point` on the line through the circumcentre of triangle `a`, `b`, `c` perpendicular to its
 * plane: the exact Voronoi line of a facet, every point of which is equidistant from the three corners. A point found
 * between two computed circumcentres (a restricted facet's surface ball, R3) lies on that line only up to their
 * rounding, which the circumcentres of flat tetrahedra amplify; computed from the corners, offsets from `a`, the
 * distances agree to a few ulps of the triangle's own conditioning. A degenerate triangle has no such line: `point`
 * is returned. */
inline Vector3
NearestPointOnCircumcenterAxis(const Vector3 & a, const Vector3 & b, const Vector3 & c, const Vector3 & point)
{
  const Vector3 u = b - a;
  const Vector3 v = c - a;
  const Vector3 normal = Cross(u, v);
  const double  squaredNormal = SquaredNorm(normal);
  if (!(squaredNormal > 0.0))
  {
    return point;
  }
  const Vector3 toCircumcenter =
    (1.0 / (2.0 * squaredNormal)) * (SquaredNorm(u) * Cross(v, normal) + SquaredNorm(v) * Cross(normal, u));
  const Vector3 offset = point - a - toCircumcenter;
  return a + toCircumcenter + (Dot(offset, normal) / squaredNormal) * normal;
}

} // namespace delaunay_refinement

#endif
