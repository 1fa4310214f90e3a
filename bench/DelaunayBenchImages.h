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
#ifndef DelaunayBenchImages_h
#define DelaunayBenchImages_h

#include "DelaunayImageToMeshSurfaceExtraction.h"

#include "itkImage.h"

#include <string>
#include <vector>

/** \namespace delaunay_bench
 * \brief The benchmark of issue #6: our refinement against CGAL's Mesh_3 on the same label images. */
namespace delaunay_bench
{

/** Every benchmark image: 0 is the background, each other value a tissue. Eight bits are what CGAL's Image_3
 * is given, and every label used here is small. */
using LabelImage = itk::Image<uint8_t, 3>;

/** A label image and the surface sampling distances δ (mm) it is meshed with. */
struct BenchImage
{
  std::string         name;
  std::string         description;
  LabelImage::Pointer image;
  std::vector<double> deltas;
};

/** The benchmark's images: generated spheres and tori (64³, 128³; 1 mm voxels), the brain mask and the k-means
 * tissues of ITK's examples (from `dataDirectory`), and the brain mask resampled to 1 mm. `quick` keeps one
 * small δ-list per kind of image, for a short run. */
std::vector<BenchImage>
MakeBenchImages(bool quick, const std::string & dataDirectory);

/** The image as the module's fidelity measures want it (DelaunayImageToMeshSurfaceExtraction.h). */
delaunay_refinement::LabelVolume
ToLabelVolume(const LabelImage & image);

/** CGAL's Image_3 has an origin and a spacing but no direction matrix: a rotated image cannot be compared.
 * \throws std::invalid_argument when the direction is not the identity. */
void
RequireIdentityDirection(const LabelImage & image, const std::string & name);

} // namespace delaunay_bench

#endif
