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
#ifndef DelaunayImageToMeshSurfaceExtraction_h
#define DelaunayImageToMeshSurfaceExtraction_h

#include "DelaunayRefinementTypes.h"

#include <array>
#include <vector>

namespace delaunay_refinement
{

/** A label image in physical space, without any ITK or VTK type: voxel (i, j, k) is
 * Labels()[i + size[0] * (j + size[1] * k)] and its centre is origin + direction * (spacing ⊙ (i, j, k)). */
struct LabelVolume
{
  std::array<std::size_t, 3> size{ { 0, 0, 0 } };
  /** The labels, when the volume holds them. */
  std::vector<Label> labels;
  /** Else the labels of someone else's buffer, size[0] × size[1] × size[2] of them, which must outlive the volume
   * (itk::ViewLabelVolume: an ITK image's): a copy of a large segmentation was most of the quality report's time
   * (13 MB of fresh memory on the brain mask resampled to 1 mm). */
  const Label *                        borrowedLabels{ nullptr };
  Vector3                              origin{ { 0.0, 0.0, 0.0 } };
  std::array<double, 3>                spacing{ { 1.0, 1.0, 1.0 } };
  std::array<std::array<double, 3>, 3> direction{
    { { { 1.0, 0.0, 0.0 } }, { { 0.0, 1.0, 0.0 } }, { { 0.0, 0.0, 1.0 } } }
  };

  std::size_t
  NumberOfVoxels() const
  {
    return size[0] * size[1] * size[2];
  }

  /** The labels, held or borrowed. */
  const Label *
  Labels() const
  {
    return borrowedLabels != nullptr ? borrowedLabels : labels.data();
  }

  /** Physical position of a (continuous) voxel index. */
  Vector3
  IndexToPhysical(const Vector3 & index) const
  {
    Vector3 point = origin;
    for (int row = 0; row < 3; ++row)
    {
      for (int column = 0; column < 3; ++column)
      {
        point[row] += direction[row][column] * spacing[column] * index[column];
      }
    }
    return point;
  }
};

/** A triangle surface in physical space. */
struct TriangleSurface
{
  std::vector<Vector3>                 points;
  std::vector<std::array<uint32_t, 3>> triangles;
};

/** The marching-cubes surfaces of every non-zero label region of `volume` (VTK's discrete flying edges), in
 * physical space: object/background boundaries and tissue interfaces (an interface appears once per side).
 * The volume is padded with background first, so regions touching its border are closed there, as the
 * mesher closes them. The reference surface for fidelity measurements. */
DelaunayImageToMesh_EXPORT TriangleSurface
ExtractLabelSurfaces(const LabelVolume & volume);

} // namespace delaunay_refinement

#endif
