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
#ifndef DelaunayImageToMeshVoxelComponents_h
#define DelaunayImageToMeshVoxelComponents_h

#include "DelaunayImageToMeshSurfaceExtraction.h"

#include <cstddef>
#include <map>
#include <vector>

namespace delaunay_refinement
{

/** The number of face-connected components of the voxels of each of `labels` in `volume`, padded with one layer of
 * background (as VTK's image connectivity filter counts them on the padded image, which the tests check it against):
 * how many pieces each tissue is made of in the segmentation. One flood fill over the volume for all the labels
 * together: the report asks for every lost tissue, and a pass over the whole image per lost tissue was a sixth of the
 * command-line program's run on a phantom of 575 labels of which 63 were lost (bench/README.md, "At 1946612"). A
 * label absent from the volume counts 0. */
std::map<Label, std::size_t>
CountVoxelComponents(const LabelVolume & volume, const std::vector<Label> & labels);

/** The same for one label. */
std::size_t
CountVoxelComponents(const LabelVolume & volume, Label label);

} // namespace delaunay_refinement

#endif
