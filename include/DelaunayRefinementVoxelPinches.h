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
#include <vector>

namespace delaunay_refinement
{

/** Removes the voxel pinches of every label, the background included, so that each label's voxels meet the rest
 * along a 2-manifold surface (a well-composed label image): nowhere in a block of 2 x 2 x 2 voxels does a label hold
 * exactly one diagonal of a face (two voxels touching along an edge only), exactly two opposite corners (touching at
 * a vertex only), or all but two opposite corners (the rest touching at a vertex only). The nearest-neighbour
 * surface of a pinched label is not a manifold there, and no mesh sampled from it can be.
 *
 * A pinch is mended by changing one voxel of the block: the pinched label either takes a voxel from another label
 * (it joins there) or gives one of its voxels to another label of the block (it is cut there). Of these changes,
 * first those after which the label is no longer pinched in the block, then those that leave the fewest pinches in
 * the eight blocks around the voxel, then the voxel with the most face neighbours of its new label, then the change
 * that raises the voxel's rank, joining before cutting, then the lower corner. Labels rank: the background lowest,
 * then the tissues from the fewest voxels to the most (ties: the smaller value lower). A change that lowers a
 * voxel's rank is allowed only when it leaves fewer pinches around the voxel, only once per voxel, and never to the
 * background: so a tissue is never cut by the background (the union of the tissues only grows, as a closing
 * would), two tissues along a digital interface give and take voxels on both sides instead of the smaller one being
 * peeled off, and the process ends (every other change raises a rank). After a change only the blocks around it are
 * looked at again. The result depends on the labels only.
 *
 * `labels` is a dense grid, voxel (i, j, k) at labels[i + size[0] * (j + size[1] * k)]; only blocks with all eight
 * voxels inside it are looked at, and voxels on its border never change, so it should have a background border (the
 * image oracle's label image has one). When no change unpinches the label in the block at once, the block is looked
 * at again after the change. Returns the number of voxels whose label differs at the end; `changes`, when given,
 * receives them in increasing order of offset, each with the label it had before. The search for the pinches
 * runs on up to `numberOfThreads` threads; the result does not depend on their number. The labels may be stored in any
 * IsVoxelLabelType; the result is the same. */
template <typename TVoxelLabel>
std::size_t
RemoveVoxelPinches(TVoxelLabel * labels, const std::array<std::size_t, 3> & size,
                   std::vector<VoxelChange> * changes = nullptr, unsigned int numberOfThreads = 1);

/** The same after the voxels at `changedVoxels` (offsets) changed in labels that had no pinch the removal could
 * mend: only the blocks holding them, and those its changes reach, are looked at, so that the cost follows the
 * change, not the grid. The ranks come from the whole grid, as above. */
template <typename TVoxelLabel>
std::size_t
RemoveVoxelPinchesAround(TVoxelLabel * labels, const std::array<std::size_t, 3> & size,
                         const std::vector<std::size_t> & changedVoxels, std::vector<VoxelChange> * changes = nullptr);

// Compiled in the library for each IsVoxelLabelType: declared here (EXTERN = extern), defined in the library's
// source (EXTERN empty).
#define DelaunayRefinement_InstantiateVoxelPinches(EXTERN, TVoxelLabel)                                                \
  EXTERN template DelaunayImageToMesh_EXPORT std::size_t RemoveVoxelPinches<TVoxelLabel>(                              \
    TVoxelLabel *, const std::array<std::size_t, 3> &, std::vector<VoxelChange> *, unsigned int);                      \
  EXTERN template DelaunayImageToMesh_EXPORT std::size_t RemoveVoxelPinchesAround<TVoxelLabel>(                        \
    TVoxelLabel *, const std::array<std::size_t, 3> &, const std::vector<std::size_t> &, std::vector<VoxelChange> *)
DelaunayRefinement_InstantiateVoxelPinches(extern, Label);
DelaunayRefinement_InstantiateVoxelPinches(extern, uint16_t);
DelaunayRefinement_InstantiateVoxelPinches(extern, uint8_t);

} // namespace delaunay_refinement

#endif
