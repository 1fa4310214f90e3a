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
#ifndef DelaunayRefinementVoxelPinches_h
#define DelaunayRefinementVoxelPinches_h

#include "DelaunayRefinementTypes.h"

#include <array>
#include <cstddef>

namespace delaunay_refinement
{

/** Joins the voxels of a label that touch only along a voxel edge, where their voxel surface (the nearest-neighbour
 * labels' surface) is not a manifold: wherever, of the four voxels around an edge, two diagonally opposite ones
 * carry the same non-zero label and the other two are background, one of those two takes that label (the one with
 * more face neighbours of the label; the one along the first of the block's two axes on a tie). A contact between
 * different tissues (an off-diagonal voxel of another label) is left alone.
 *
 * `labels` is a dense grid, voxel (i, j, k) at labels[i + size[0] * (j + size[1] * k)]; only edges with all four
 * voxels inside it are looked at, so it should have a background border (the image oracle's label image has one).
 * Every change adds a voxel to an object, so the process ends, after at most as many changes as there are
 * background voxels; after a change only the voxel blocks around the changed voxel are looked at again. The
 * result depends on the labels only. Returns the number of voxels that changed. */
DelaunayImageToMesh_EXPORT std::size_t
                           JoinDiagonalVoxels(Label * labels, const std::array<std::size_t, 3> & size);

} // namespace delaunay_refinement

#endif
