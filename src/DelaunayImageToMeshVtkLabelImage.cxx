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
#include "DelaunayImageToMeshVtkLabelImage.h"

#include <vtkImageData.h>

#include <algorithm>

namespace delaunay_refinement
{

void
FillPaddedImage(const LabelVolume & volume, vtkImageData * image)
{
  const int padded[3] = { static_cast<int>(volume.size[0]) + 2,
                          static_cast<int>(volume.size[1]) + 2,
                          static_cast<int>(volume.size[2]) + 2 };
  image->SetDimensions(padded[0], padded[1], padded[2]);
  image->SetOrigin(-1.0, -1.0, -1.0);
  image->SetSpacing(1.0, 1.0, 1.0);
  image->AllocateScalars(VTK_INT, 1);
  auto * scalars = static_cast<int *>(image->GetScalarPointer());
  std::fill(scalars, scalars + static_cast<std::size_t>(padded[0]) * padded[1] * padded[2], 0);
  for (std::size_t k = 0; k < volume.size[2]; ++k)
  {
    for (std::size_t j = 0; j < volume.size[1]; ++j)
    {
      for (std::size_t i = 0; i < volume.size[0]; ++i)
      {
        const std::size_t source = i + volume.size[0] * (j + volume.size[1] * k);
        const std::size_t target = (i + 1) + padded[0] * ((j + 1) + padded[1] * (k + 1));
        scalars[target] = volume.Labels()[source];
      }
    }
  }
}

} // namespace delaunay_refinement
