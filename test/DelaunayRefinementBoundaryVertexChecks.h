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
#ifndef DelaunayRefinementBoundaryVertexChecks_h
#define DelaunayRefinementBoundaryVertexChecks_h

// Lemma 5 (with ρ >= 2 and a uniform δ, every boundary triangle has only feature vertices: docs/algorithm.md,
// "Guarantees") checked on the mesh the refinement produced, from the vertex kinds it exports. ITK-free: the core's
// tests, the filter's tests and the randomized checks share it.

#include "DelaunayRefinementTypes.h"

#include <cstdint>
#include <vector>

namespace delaunay_refinement
{

/** The corners of `mesh`'s boundary triangles that are not feature vertices, in the triangles' order: a vertex is
 * listed once per boundary triangle it is a corner of. */
inline std::vector<uint32_t>
NonFeatureBoundaryCorners(const TetrahedralMesh & mesh)
{
  std::vector<uint32_t> corners;
  for (const auto & triangle : mesh.boundaryTriangles)
  {
    for (const uint32_t vertex : triangle)
    {
      if (mesh.pointKinds.at(vertex) != VertexKind::Feature)
      {
        corners.push_back(vertex);
      }
    }
  }
  return corners;
}

} // namespace delaunay_refinement

#endif
