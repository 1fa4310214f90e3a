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
#ifndef itkTetrahedralMeshVoxelizer_h
#define itkTetrahedralMeshVoxelizer_h

#include "itkImage.h"
#include "itkImageBase.h"

namespace itk
{

/** \brief Voxelises a labelled tetrahedral mesh onto the grid of a reference image.
 *
 * Every voxel of `referenceGrid`'s largest possible region gets the cell data (the label) of the tetrahedron
 * that contains the voxel's centre, and 0 where no tetrahedron does. Voxel centres are taken in physical
 * space, so the reference's origin, spacing and direction are honoured, and the output carries them. A
 * tetrahedron without cell data counts as label 1; cells other than tetrahedra are ignored. A centre on a
 * facet shared by two tetrahedra takes the label of the one that comes first in the mesh's cell order.
 *
 * The mesh points are mapped to the reference's continuous index space first: that map is affine, so it keeps
 * barycentric coordinates, and in index space the voxel centres are the integer points. The candidate voxels
 * of a tetrahedron are then exactly the integer points of its index-space bounding box, i.e. the reference grid
 * itself is the bucket grid, and each candidate is kept if its barycentric coordinates are all >= 0. The cost is
 * the total number of voxels in the tetrahedra's bounding boxes, a small multiple of the voxels the mesh covers
 * (well under a second for 128 × 128 × 62 voxels and 10^5 tetrahedra).
 *
 * \tparam TLabelImage  A 3-D image type whose pixel type holds the labels (e.g. Image<uint8_t, 3>).
 * \tparam TMesh        An itk::Mesh with PointDimension 3, whose cells include TetrahedronCells.
 * \param mesh           The tetrahedral mesh, in the same physical space as `referenceGrid`.
 * \param referenceGrid  The grid to voxelise onto; only its geometry and largest possible region are used.
 * \returns A new image on the reference grid.
 *
 * \ingroup DelaunayImageToMesh
 */
template <typename TLabelImage, typename TMesh>
typename TLabelImage::Pointer
VoxelizeTetrahedralMesh(const TMesh & mesh, const ImageBase<3> & referenceGrid);

} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkTetrahedralMeshVoxelizer.hxx"
#endif

#endif
