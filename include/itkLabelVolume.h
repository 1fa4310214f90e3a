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
#ifndef itkLabelVolume_h
#define itkLabelVolume_h

#include "DelaunayImageToMeshSurfaceExtraction.h"

#include "itkImage.h"

#include <type_traits>

namespace itk
{

/** The buffered voxels of a 3-D label image as the ITK-free LabelVolume, with its physical geometry: the reference
 * that fidelity measurements compare meshes with. The labels are the image's own buffer (LabelVolume::borrowedLabels),
 * not a copy, so the image must outlive the volume. */
template <typename TLabelImage>
delaunay_refinement::LabelVolume
ViewLabelVolume(const TLabelImage * image)
{
  static_assert(TLabelImage::ImageDimension == 3, "a LabelVolume is made of a 3-D image");
  static_assert(std::is_same<typename TLabelImage::PixelType, delaunay_refinement::Label>::value,
                "ViewLabelVolume needs an image of delaunay_refinement::Label");
  delaunay_refinement::LabelVolume volume;
  const auto &                     region = image->GetBufferedRegion();
  typename TLabelImage::PointType  origin;
  image->TransformIndexToPhysicalPoint(region.GetIndex(), origin);
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    volume.size[axis] = region.GetSize(axis);
    volume.origin[axis] = origin[axis];
    volume.spacing[axis] = image->GetSpacing()[axis];
    for (unsigned int column = 0; column < 3; ++column)
    {
      volume.direction[axis][column] = image->GetDirection()(axis, column);
    }
  }
  volume.borrowedLabels = image->GetBufferPointer();
  return volume;
}

} // namespace itk

#endif
