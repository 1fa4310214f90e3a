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

// The basic driver test: every Set/Get of itk::DelaunayImageToMeshFilter with its documented default, then
// one run on a generated ball, whose two outputs are checked for consistency with each other and with the
// core's result, and for the two quality guarantees.

#include "itkDelaunayImageToMeshFilter.h"
#include "itkDelaunayImageToMeshFilterTestHelpers.h"
#include "itkNearestNeighborInterpolateImageFunction.h"
#include "itkTestingMacros.h"

#include <cstdlib>
#include <iostream>

namespace
{

using namespace itk::delaunay_image_to_mesh_test;
using FilterType = itk::DelaunayImageToMeshFilter<LabelImageType, MeshType>;

/** A 10 mm ball in a 0.5 mm grid: the automatic δ (4 × the largest spacing) is 2 mm. */
LabelImageType::Pointer
MakeTestBall()
{
  const LabelImageType::SizeType size{ { 48, 48, 48 } };
  LabelImageType::SpacingType    spacing;
  spacing.Fill(0.5);
  LabelImageType::PointType origin;
  origin.Fill(-12.0);
  LabelImageType::DirectionType direction;
  direction.SetIdentity();
  return MakeBallImage(size, spacing, origin, direction, { { -0.3, 0.2, 0.1 } }, 10.0);
}

int
ExerciseDefaultsAndSetGet(FilterType * filter)
{
  ITK_TEST_EXPECT_EQUAL(filter->GetSurfaceSamplingDistance(), 0.0);
  ITK_TEST_EXPECT_EQUAL(filter->GetEffectiveSurfaceSamplingDistance(), 0.0);
  ITK_TEST_EXPECT_EQUAL(filter->GetRadiusEdgeBound(), 2.0);
  ITK_TEST_EXPECT_EQUAL(filter->GetMinimumDihedralAngle(), 10.0);
  ITK_TEST_EXPECT_EQUAL(filter->GetMaximumNumberOfVertices(), itk::SizeValueType{ 10000000 });
  ITK_TEST_SET_GET_NULL_VALUE(filter->GetInterpolator());
  ITK_TEST_EXPECT_EQUAL(filter->GetIsoValue(), 0.0);
  ITK_TEST_EXPECT_TRUE(!filter->GetUseIsoValue());
  ITK_TEST_EXPECT_TRUE(filter->GetLabels().empty());
  ITK_TEST_EXPECT_TRUE(filter->GetInterfaceLabels().empty());
  ITK_TEST_EXPECT_EQUAL(filter->GetNumberOfIndexedOutputs(), 2u);
  ITK_TEST_EXPECT_TRUE(filter->GetInterfaceMesh() != nullptr);

  filter->SetSurfaceSamplingDistance(2.5);
  ITK_TEST_SET_GET_VALUE(2.5, filter->GetSurfaceSamplingDistance());
  filter->SetRadiusEdgeBound(1.5);
  ITK_TEST_SET_GET_VALUE(1.5, filter->GetRadiusEdgeBound());
  filter->SetMinimumDihedralAngle(10.0);
  ITK_TEST_SET_GET_VALUE(10.0, filter->GetMinimumDihedralAngle());
  filter->SetMaximumNumberOfVertices(12345);
  ITK_TEST_SET_GET_VALUE(itk::SizeValueType{ 12345 }, filter->GetMaximumNumberOfVertices());

  auto interpolator = itk::NearestNeighborInterpolateImageFunction<LabelImageType, double>::New();
  filter->SetInterpolator(interpolator);
  ITK_TEST_SET_GET_VALUE(interpolator.GetPointer(), filter->GetInterpolator());

  ITK_TEST_SET_GET_BOOLEAN(filter, UseIsoValue, false);
  filter->SetIsoValue(0.5);
  ITK_TEST_SET_GET_VALUE(0.5, filter->GetIsoValue());
  ITK_TEST_EXPECT_TRUE(filter->GetUseIsoValue());
  // Setting the same iso-value again must not mark the filter modified.
  const itk::ModifiedTimeType afterIsoValue = filter->GetMTime();
  filter->SetIsoValue(0.5);
  ITK_TEST_EXPECT_EQUAL(filter->GetMTime(), afterIsoValue);

  const FilterType::LabelListType labels{ 3, 1, 2 };
  filter->SetLabels(labels);
  ITK_TEST_EXPECT_TRUE(filter->GetLabels() == labels);
  const itk::ModifiedTimeType afterLabels = filter->GetMTime();
  filter->SetLabels(labels);
  ITK_TEST_EXPECT_EQUAL(filter->GetMTime(), afterLabels);
  return EXIT_SUCCESS;
}

void
RestoreDefaults(FilterType * filter)
{
  filter->SetSurfaceSamplingDistance(0.0);
  filter->SetRadiusEdgeBound(2.0);
  filter->SetMinimumDihedralAngle(0.0);
  filter->SetMaximumNumberOfVertices(10000000);
  filter->SetInterpolator(nullptr);
  // SetIsoValue() switches the iso-value mode on: switch it off afterwards.
  filter->SetIsoValue(0.0);
  filter->UseIsoValueOff();
  filter->SetLabels({});
}

/** Both outputs share one point set; output 0 holds only tetrahedra, output 1 only triangles; everything
 * matches GetRefinedMesh(). */
int
CheckOutputs(FilterType * filter)
{
  const MeshType *            tetrahedra = filter->GetOutput();
  const MeshType *            interfaces = filter->GetInterfaceMesh();
  const dr::TetrahedralMesh & refined = filter->GetRefinedMesh();
  ITK_TEST_EXPECT_TRUE(tetrahedra->GetNumberOfCells() > 0);
  ITK_TEST_EXPECT_EQUAL(tetrahedra->GetNumberOfCells(), refined.tetrahedra.size());
  ITK_TEST_EXPECT_EQUAL(tetrahedra->GetNumberOfPoints(), refined.points.size());
  ITK_TEST_EXPECT_EQUAL(interfaces->GetNumberOfPoints(), refined.points.size());
  ITK_TEST_EXPECT_EQUAL(interfaces->GetNumberOfCells(), refined.boundaryTriangles.size());
  ITK_TEST_EXPECT_EQUAL(filter->GetInterfaceLabels().size(), refined.boundaryTriangles.size());
  for (auto cell = tetrahedra->GetCells()->Begin(); cell != tetrahedra->GetCells()->End(); ++cell)
  {
    ITK_TEST_EXPECT_TRUE(cell.Value()->GetType() == itk::CellGeometryEnum::TETRAHEDRON_CELL);
    MeshType::CellPixelType label = 0;
    ITK_TEST_EXPECT_TRUE(tetrahedra->GetCellData(cell.Index(), &label));
    ITK_TEST_EXPECT_EQUAL(label, 1);
  }
  for (auto cell = interfaces->GetCells()->Begin(); cell != interfaces->GetCells()->End(); ++cell)
  {
    ITK_TEST_EXPECT_TRUE(cell.Value()->GetType() == itk::CellGeometryEnum::TRIANGLE_CELL);
  }
  for (const auto & labels : filter->GetInterfaceLabels())
  {
    ITK_TEST_EXPECT_EQUAL(labels[0], 1);
    ITK_TEST_EXPECT_EQUAL(labels[1], 0);
  }
  ITK_TEST_EXPECT_TRUE(filter->GetRefinementStatistics().triangulationVertices >= refined.points.size());
  return EXIT_SUCCESS;
}

/** docs/algorithm.md's two quality guarantees at ρ = 2, and a closed boundary. */
int
CheckGuarantees(FilterType * filter)
{
  const dr::TetrahedralMesh    mesh = TetrahedralMeshFromOutputs(*filter);
  const dr::TetrahedronQuality quality = dr::ComputeTetrahedronQuality(mesh);
  const dr::SurfaceTopology    boundary = dr::ComputeBoundaryTopology(mesh);
  std::cout << mesh.tetrahedra.size() << " tetrahedra, max radius-edge " << quality.maximumRadiusEdgeRatio
            << ", min boundary planar angle " << boundary.minimumPlanarAngle << std::endl;
  ITK_TEST_EXPECT_TRUE(quality.maximumRadiusEdgeRatio < 2.0);
  ITK_TEST_EXPECT_TRUE(boundary.minimumPlanarAngle > 30.0);
  ITK_TEST_EXPECT_EQUAL(quality.invertedTetrahedra, 0u);
  ITK_TEST_EXPECT_TRUE(boundary.IsClosedManifold());
  ITK_TEST_EXPECT_EQUAL(boundary.numberOfComponents, 1);
  ITK_TEST_EXPECT_EQUAL(boundary.totalGenus, 0);
  ITK_TEST_EXPECT_TRUE(CheckBoundaryAgainstTetrahedra(mesh).IsConsistent());
  return EXIT_SUCCESS;
}

} // namespace

int
itkDelaunayImageToMeshFilterTest(int argc, char * argv[])
{
  if (argc != 1)
  {
    std::cerr << "Usage: " << itkNameOfTestExecutableMacro(argv) << " (no arguments)" << std::endl;
    return EXIT_FAILURE;
  }

  auto filter = FilterType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(filter, DelaunayImageToMeshFilter, ImageToMeshFilter);
  if (ExerciseDefaultsAndSetGet(filter) != EXIT_SUCCESS)
  {
    return EXIT_FAILURE;
  }
  RestoreDefaults(filter);

  const auto ball = MakeTestBall();
  filter->SetInput(ball);
  ITK_TRY_EXPECT_NO_EXCEPTION(filter->Update());
  ITK_TEST_EXPECT_EQUAL(filter->GetEffectiveSurfaceSamplingDistance(), 2.0);
  if (CheckOutputs(filter) != EXIT_SUCCESS || CheckGuarantees(filter) != EXIT_SUCCESS)
  {
    return EXIT_FAILURE;
  }
  filter->Print(std::cout);

  filter->SetSurfaceSamplingDistance(-1.0);
  ITK_TRY_EXPECT_EXCEPTION(filter->Update());
  filter->SetSurfaceSamplingDistance(0.0);
  filter->SetRadiusEdgeBound(0.5);
  ITK_TRY_EXPECT_EXCEPTION(filter->Update());
  filter->SetRadiusEdgeBound(2.0);
  filter->SetLabels({ 7 });
  ITK_TRY_EXPECT_EXCEPTION(filter->Update());
  filter->SetLabels({});
  ITK_TRY_EXPECT_NO_EXCEPTION(filter->Update());

  std::cout << "Test finished." << std::endl;
  return EXIT_SUCCESS;
}
