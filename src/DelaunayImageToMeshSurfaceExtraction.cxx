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
#include "DelaunayImageToMeshSurfaceExtraction.h"
#include "DelaunayImageToMeshVtkLabelImage.h"

#include <vtkCellArray.h>
#include <vtkDiscreteFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <set>

namespace delaunay_refinement
{

TriangleSurface
ExtractLabelSurfaces(const LabelVolume & volume)
{
  TriangleSurface surface;
  std::set<Label> labels(volume.Labels(), volume.Labels() + volume.NumberOfVoxels());
  labels.erase(BackgroundLabel);
  if (labels.empty())
  {
    return surface;
  }
  vtkNew<vtkImageData> image;
  FillPaddedImage(volume, image);
  vtkNew<vtkDiscreteFlyingEdges3D> flyingEdges;
  flyingEdges->SetInputData(image);
  flyingEdges->ComputeNormalsOff();
  flyingEdges->ComputeGradientsOff();
  flyingEdges->ComputeScalarsOff();
  int contour = 0;
  for (const Label label : labels)
  {
    flyingEdges->SetValue(contour++, static_cast<double>(label));
  }
  flyingEdges->Update();
  vtkPolyData * polyData = flyingEdges->GetOutput();

  vtkPoints *     points = polyData->GetPoints();
  const vtkIdType numberOfPoints = points ? points->GetNumberOfPoints() : 0;
  surface.points.reserve(static_cast<std::size_t>(numberOfPoints));
  for (vtkIdType i = 0; i < numberOfPoints; ++i)
  {
    double index[3];
    points->GetPoint(i, index);
    surface.points.push_back(volume.IndexToPhysical({ { index[0], index[1], index[2] } }));
  }
  vtkCellArray *    polygons = polyData->GetPolys();
  vtkIdType         cellSize = 0;
  const vtkIdType * cellPoints = nullptr;
  for (polygons->InitTraversal(); polygons->GetNextCell(cellSize, cellPoints);)
  {
    if (cellSize == 3)
    {
      surface.triangles.push_back({ static_cast<uint32_t>(cellPoints[0]),
                                    static_cast<uint32_t>(cellPoints[1]),
                                    static_cast<uint32_t>(cellPoints[2]) });
    }
  }
  return surface;
}

} // namespace delaunay_refinement
