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
#ifndef DelaunayRefinementHandMadeCube_h
#define DelaunayRefinementHandMadeCube_h

// The bounding box of the tests that place vertices by hand: the eight corners of a cube around the origin, far from
// the points placed inside it, so that those points' cells are the Delaunay triangulation's of the points alone.

#include "DelaunayRefinementMeshState.h"

#include <array>
#include <vector>

/** Makes `state` a triangulation of the eight corners of the cube of half side `halfSide` around the origin, with no
 * queue to tell of new cells (the hand-made tests ask the rules and repairs of chosen cells themselves). */
inline void
StartWithCubeCorners(delaunay_refinement::detail::MeshState & state, double halfSide)
{
  state.SetNewCellsHook([](const std::vector<delaunay_refinement::detail::CellHandle> &) {});
  std::array<delaunay_refinement::Vector3, 8> corners{};
  for (int corner = 0; corner < 8; ++corner)
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      corners[corner][axis] = (corner >> axis) & 1 ? halfSide : -halfSide;
    }
  }
  state.InsertBoxCorners(corners);
}

#endif
