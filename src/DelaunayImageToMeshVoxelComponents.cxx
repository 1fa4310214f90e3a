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
#include "DelaunayImageToMeshVoxelComponents.h"
#include "DelaunayImageToMeshVtkLabelImage.h"

#include <vtkImageConnectivityFilter.h>
#include <vtkImageData.h>
#include <vtkNew.h>

namespace delaunay_refinement
{

std::size_t
CountVoxelComponents(const LabelVolume & volume, Label label)
{
  vtkNew<vtkImageData> image;
  FillPaddedImage(volume, image);
  vtkNew<vtkImageConnectivityFilter> connectivity;
  connectivity->SetInputData(image);
  // The range is converted to the image's integer type: a margin such as label ± 0.5 would take in label - 1.
  connectivity->SetScalarRange(label, label);
  connectivity->SetExtractionModeToAllRegions();
  connectivity->GenerateRegionExtentsOff();
  connectivity->Update();
  return static_cast<std::size_t>(connectivity->GetNumberOfExtractedRegions());
}

} // namespace delaunay_refinement
