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
#ifndef DelaunayImageToMeshVtkLabelImage_h
#define DelaunayImageToMeshVtkLabelImage_h

#include "DelaunayImageToMeshSurfaceExtraction.h"

class vtkImageData;

namespace delaunay_refinement
{

/** Copies `volume` into `image` in index space (VTK 9.1's flying edges ignores image direction), padded by one
 * background voxel on every side, as VTK_INT scalars: the image VTK's filters read the segmentation from. */
void
FillPaddedImage(const LabelVolume & volume, vtkImageData * image);

} // namespace delaunay_refinement

#endif
