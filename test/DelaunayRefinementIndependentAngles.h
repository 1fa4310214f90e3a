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
#ifndef DelaunayRefinementIndependentAngles_h
#define DelaunayRefinementIndependentAngles_h

// Dihedral and planar angles computed by the tests themselves, not with the library's metric code (a report or a
// check that skipped an edge or a corner would disagree). ITK-free: the core's tests and the filter's share them.

#include "DelaunayRefinementTypes.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace delaunay_refinement
{

/** The smallest dihedral angle of the mesh in degrees, computed here from the face normals (the angle at the edge
 * two faces share is 180° minus the angle between their outward normals), not with the library's metric code, which
 * projects the two other corners off each edge: a report or a check that skipped an edge would disagree. */
inline double
SmallestDihedralAngleFromNormals(const TetrahedralMesh & mesh)
{
  using Vector = std::array<double, 3>;
  const auto difference = [](const Vector & a, const Vector & b) {
    return Vector{ a[0] - b[0], a[1] - b[1], a[2] - b[2] };
  };
  const auto cross = [](const Vector & a, const Vector & b) {
    return Vector{ a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
  };
  const auto dot = [](const Vector & a, const Vector & b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  // Each face's corners ordered so that the normals all point out of the tetrahedron, or all into it when it is
  // negatively oriented: the angle between two of them is the same either way.
  constexpr int faces[4][3] = { { 1, 2, 3 }, { 0, 3, 2 }, { 0, 1, 3 }, { 0, 2, 1 } };
  double        smallest = 180.0;
  for (const auto & tetrahedron : mesh.tetrahedra)
  {
    std::array<Vector, 4> corner{};
    for (int k = 0; k < 4; ++k)
    {
      corner[k] = mesh.points[tetrahedron[k]];
    }
    std::array<Vector, 4> normals{};
    for (int face = 0; face < 4; ++face)
    {
      const Vector & a = corner[faces[face][0]];
      Vector         normal = cross(difference(corner[faces[face][1]], a), difference(corner[faces[face][2]], a));
      const double   length = std::sqrt(dot(normal, normal));
      for (double & component : normal)
      {
        component /= length;
      }
      normals[face] = normal;
    }
    for (int first = 0; first < 4; ++first)
    {
      for (int second = first + 1; second < 4; ++second)
      {
        const double cosine = std::clamp(-dot(normals[first], normals[second]), -1.0, 1.0);
        smallest = std::min(smallest, std::acos(cosine) * 180.0 / 3.14159265358979323846);
      }
    }
  }
  return smallest;
}

/** The smallest angle of the triangle (a, b, c) in degrees, from the dot products of its edges, not with the
 * library's metric code. */
inline double
SmallestPlanarAngle(const Vector3 & a, const Vector3 & b, const Vector3 & c)
{
  const std::array<const Vector3 *, 3> corners{ &a, &b, &c };
  double                               smallest = 180.0;
  for (int corner = 0; corner < 3; ++corner)
  {
    const Vector3 & apex = *corners[corner];
    const Vector3 & next = *corners[(corner + 1) % 3];
    const Vector3 & last = *corners[(corner + 2) % 3];
    double          dot = 0.0;
    double          nextLength = 0.0;
    double          lastLength = 0.0;
    for (int axis = 0; axis < 3; ++axis)
    {
      dot += (next[axis] - apex[axis]) * (last[axis] - apex[axis]);
      nextLength += (next[axis] - apex[axis]) * (next[axis] - apex[axis]);
      lastLength += (last[axis] - apex[axis]) * (last[axis] - apex[axis]);
    }
    const double cosine = std::clamp(dot / std::sqrt(nextLength * lastLength), -1.0, 1.0);
    smallest = std::min(smallest, std::acos(cosine) * 180.0 / 3.14159265358979323846);
  }
  return smallest;
}

} // namespace delaunay_refinement

#endif // DelaunayRefinementIndependentAngles_h
