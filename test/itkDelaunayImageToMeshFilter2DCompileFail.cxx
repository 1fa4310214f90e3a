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

// Must NOT compile: the filter meshes 3-D images only, and says so in a static_assert. The test
// itkDelaunayImageToMeshFilter2DCompileFailTest compiles this file with -fsyntax-only and passes when the
// compiler prints that message.

#include "itkDelaunayImageToMeshFilter.h"
#include "itkImage.h"
#include "itkMesh.h"

int
main()
{
  using SliceType = itk::Image<unsigned char, 2>;
  using MeshType = itk::Mesh<int, 3>;
  const auto filter = itk::DelaunayImageToMeshFilter<SliceType, MeshType>::New();
  return filter.IsNull() ? 1 : 0;
}
