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
#ifndef itkTetrahedralMeshVoxelizer_hxx
#define itkTetrahedralMeshVoxelizer_hxx

#include "itkTetrahedralMeshVoxelizer.h"

#include "itkCommonEnums.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace itk
{
namespace tetrahedral_mesh_voxelizer_detail
{

using IndexSpacePoint = std::array<double, 3>;

/** A tetrahedron in the reference's continuous index space, prepared for barycentric tests. */
struct IndexSpaceTetrahedron
{
  IndexSpacePoint firstCorner;
  /** Inverse of the matrix whose columns are the edges from the first corner: maps q - firstCorner to the
   * barycentric coordinates of corners 1, 2 and 3. */
  std::array<std::array<double, 3>, 3> inverseEdges;
  IndexSpacePoint                      lower;
  IndexSpacePoint                      upper;
};

/** Barycentric coordinates are tested against this instead of 0, so that a voxel centre on a shared facet is
 * not lost to rounding by both tetrahedra; in index units it is far below a voxel. */
constexpr double BarycentricSlack = 1e-10;

/** False for a flat tetrahedron, which contains no voxel centre worth keeping. */
inline bool
PrepareTetrahedron(const std::array<IndexSpacePoint, 4> & corners, IndexSpaceTetrahedron & tetrahedron)
{
  double edge[3][3];
  for (unsigned int column = 0; column < 3; ++column)
  {
    for (unsigned int row = 0; row < 3; ++row)
    {
      edge[row][column] = corners[column + 1][row] - corners[0][row];
    }
  }
  const double cofactor00 = edge[1][1] * edge[2][2] - edge[1][2] * edge[2][1];
  const double cofactor01 = edge[1][2] * edge[2][0] - edge[1][0] * edge[2][2];
  const double cofactor02 = edge[1][0] * edge[2][1] - edge[1][1] * edge[2][0];
  const double determinant = edge[0][0] * cofactor00 + edge[0][1] * cofactor01 + edge[0][2] * cofactor02;
  if (!(std::abs(determinant) > 0.0) || !std::isfinite(determinant))
  {
    return false;
  }
  const double inverse = 1.0 / determinant;
  auto &       m = tetrahedron.inverseEdges;
  m[0] = { { cofactor00 * inverse,
             (edge[0][2] * edge[2][1] - edge[0][1] * edge[2][2]) * inverse,
             (edge[0][1] * edge[1][2] - edge[0][2] * edge[1][1]) * inverse } };
  m[1] = { { cofactor01 * inverse,
             (edge[0][0] * edge[2][2] - edge[0][2] * edge[2][0]) * inverse,
             (edge[0][2] * edge[1][0] - edge[0][0] * edge[1][2]) * inverse } };
  m[2] = { { cofactor02 * inverse,
             (edge[0][1] * edge[2][0] - edge[0][0] * edge[2][1]) * inverse,
             (edge[0][0] * edge[1][1] - edge[0][1] * edge[1][0]) * inverse } };
  tetrahedron.firstCorner = corners[0];
  tetrahedron.lower = corners[0];
  tetrahedron.upper = corners[0];
  for (const IndexSpacePoint & corner : corners)
  {
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      tetrahedron.lower[axis] = std::min(tetrahedron.lower[axis], corner[axis]);
      tetrahedron.upper[axis] = std::max(tetrahedron.upper[axis], corner[axis]);
    }
  }
  return true;
}

inline bool
Contains(const IndexSpaceTetrahedron & tetrahedron, const IndexSpacePoint & point)
{
  const double offset[3] = { point[0] - tetrahedron.firstCorner[0],
                             point[1] - tetrahedron.firstCorner[1],
                             point[2] - tetrahedron.firstCorner[2] };
  double       sum = 0.0;
  for (const auto & row : tetrahedron.inverseEdges)
  {
    const double coordinate = row[0] * offset[0] + row[1] * offset[1] + row[2] * offset[2];
    if (coordinate < -BarycentricSlack)
    {
      return false;
    }
    sum += coordinate;
  }
  return sum <= 1.0 + BarycentricSlack;
}

template <typename TMesh>
IndexSpacePoint
ToIndexSpace(const TMesh & mesh, typename TMesh::PointIdentifier pointId, const ImageBase<3> & referenceGrid)
{
  const auto       meshPoint = mesh.GetPoint(pointId);
  Point<double, 3> physicalPoint;
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    physicalPoint[axis] = static_cast<double>(meshPoint[axis]);
  }
  const auto continuousIndex = referenceGrid.TransformPhysicalPointToContinuousIndex<double>(physicalPoint);
  return { { continuousIndex[0], continuousIndex[1], continuousIndex[2] } };
}

/** Writes `label` into every voxel whose centre `tetrahedron` contains. */
template <typename TLabelImage>
void
RasterizeTetrahedron(const IndexSpaceTetrahedron & tetrahedron, typename TLabelImage::PixelType label,
                     const typename TLabelImage::RegionType & region, TLabelImage & image)
{
  IndexValueType first[3];
  IndexValueType last[3];
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    const IndexValueType regionFirst = region.GetIndex()[axis];
    const IndexValueType regionLast = regionFirst + static_cast<IndexValueType>(region.GetSize()[axis]) - 1;
    first[axis] = std::max(regionFirst, static_cast<IndexValueType>(std::ceil(tetrahedron.lower[axis])));
    last[axis] = std::min(regionLast, static_cast<IndexValueType>(std::floor(tetrahedron.upper[axis])));
    if (first[axis] > last[axis])
    {
      return;
    }
  }
  typename TLabelImage::IndexType index;
  for (index[2] = first[2]; index[2] <= last[2]; ++index[2])
  {
    for (index[1] = first[1]; index[1] <= last[1]; ++index[1])
    {
      for (index[0] = first[0]; index[0] <= last[0]; ++index[0])
      {
        const IndexSpacePoint center{
          { static_cast<double>(index[0]), static_cast<double>(index[1]), static_cast<double>(index[2]) }
        };
        if (Contains(tetrahedron, center))
        {
          image.SetPixel(index, label);
        }
      }
    }
  }
}

} // namespace tetrahedral_mesh_voxelizer_detail

template <typename TLabelImage, typename TMesh>
typename TLabelImage::Pointer
VoxelizeTetrahedralMesh(const TMesh & mesh, const ImageBase<3> & referenceGrid)
{
  static_assert(TLabelImage::ImageDimension == 3, "VoxelizeTetrahedralMesh writes 3-D images only.");
  static_assert(TMesh::PointDimension == 3, "VoxelizeTetrahedralMesh reads meshes with 3-D points only.");
  using namespace tetrahedral_mesh_voxelizer_detail;
  using LabelType = typename TLabelImage::PixelType;

  auto image = TLabelImage::New();
  image->SetRegions(referenceGrid.GetLargestPossibleRegion());
  image->SetOrigin(referenceGrid.GetOrigin());
  image->SetSpacing(referenceGrid.GetSpacing());
  image->SetDirection(referenceGrid.GetDirection());
  image->Allocate();
  image->FillBuffer(LabelType{});
  const auto & region = image->GetBufferedRegion();

  const auto * cells = mesh.GetCells();
  if (cells == nullptr)
  {
    return image;
  }
  std::vector<typename TMesh::CellIdentifier> tetrahedronIds;
  for (auto cell = cells->Begin(); cell != cells->End(); ++cell)
  {
    if (cell.Value()->GetType() == CellGeometryEnum::TETRAHEDRON_CELL)
    {
      tetrahedronIds.push_back(cell.Index());
    }
  }
  // Later tetrahedra are written first, so that on a shared facet the first one in cell order wins.
  for (auto id = tetrahedronIds.rbegin(); id != tetrahedronIds.rend(); ++id)
  {
    const auto *                   cell = cells->ElementAt(*id);
    const auto *                   pointIds = cell->GetPointIds();
    std::array<IndexSpacePoint, 4> corners;
    for (unsigned int corner = 0; corner < 4; ++corner)
    {
      corners[corner] = ToIndexSpace(mesh, pointIds[corner], referenceGrid);
    }
    IndexSpaceTetrahedron tetrahedron;
    if (!PrepareTetrahedron(corners, tetrahedron))
    {
      continue;
    }
    typename TMesh::CellPixelType cellData{};
    const LabelType label = mesh.GetCellData(*id, &cellData) ? static_cast<LabelType>(cellData) : LabelType{ 1 };
    RasterizeTetrahedron(tetrahedron, label, region, *image);
  }
  return image;
}

} // namespace itk

#endif
