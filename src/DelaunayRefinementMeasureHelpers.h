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
#ifndef DelaunayRefinementMeasureHelpers_h
#define DelaunayRefinementMeasureHelpers_h

// What the mesh measures share (DelaunayRefinementMeshQuality.cxx, DelaunayRefinementSurfaceTopology.cxx): the
// cell types, the angle between two vectors, and the check of vertex indices that guards every public measure.

#include "DelaunayRefinementTypes.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{

constexpr double DegreesPerRadian = 180.0 / 3.14159265358979323846;

using Tetrahedron = std::array<uint32_t, 4>;
using Triangle = std::array<uint32_t, 3>;

/** Angle between two vectors in degrees. atan2 stays accurate near 0° and 180°, where acos of a normalised dot
 * product loses half its digits. A zero vector gives 0°. */
inline double
AngleBetween(const Vector3 & u, const Vector3 & v)
{
  return std::atan2(Norm(Cross(u, v)), Dot(u, v)) * DegreesPerRadian;
}

/** Throws std::invalid_argument, naming `caller` and the kind of cell, for a vertex index out of range: the
 * measures index the points without checking. */
template <std::size_t NumberOfCorners>
void
CheckVertexIndices(const char * caller, const char * cellName, const std::vector<Vector3> & points,
                   const std::vector<std::array<uint32_t, NumberOfCorners>> & cells)
{
  for (const auto & cell : cells)
  {
    for (const uint32_t index : cell)
    {
      if (index >= points.size())
      {
        throw std::invalid_argument(std::string(caller) + ": " + cellName + " vertex index " + std::to_string(index) +
                                    " is out of range (number of points: " + std::to_string(points.size()) + ")");
      }
    }
  }
}

} // namespace detail
} // namespace delaunay_refinement

#endif
