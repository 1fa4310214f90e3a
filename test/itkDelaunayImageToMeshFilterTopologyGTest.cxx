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

// Topology at the scale of δ (docs/algorithm.md, "Topology"), with the filter's defaults, on generated hostile
// shapes: one-voxel bridges and slits, contacts along a voxel edge and at a corner, thin sheets, two tissues
// touching along an edge, and speckle of three tissues, for δ from 1 to 6 times the largest voxel spacing. Every
// tissue's boundary and the union's must be closed 2-manifolds, counted here independently of the library's
// topology code for the edges; every block thick enough must be in the mesh; the quality bounds must hold.

#include "DelaunayRefinementManifoldChecks.h"
#include "DelaunayRefinementMeshQuality.h"
#include "itkDelaunayImageToMeshFilter.h"
#include "itkDelaunayImageToMeshFilterTestHelpers.h"
#include "itkImageRegionConstIterator.h"
#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkImageRegionIterator.h"
#include "itkLinearInterpolateImageFunction.h"
#include "itkNearestNeighborInterpolateImageFunction.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>

namespace
{

namespace dr = delaunay_refinement;
using itk::delaunay_image_to_mesh_test::ATetrahedronOfTheLabelContains;
using itk::delaunay_image_to_mesh_test::MeshType;
using itk::delaunay_image_to_mesh_test::PhysicalCenterOf;
using ImageType = itk::Image<uint8_t, 3>;
using FilterType = itk::DelaunayImageToMeshFilter<ImageType, MeshType>;

enum class HostileShape
{
  OneVoxelBridge,
  OneVoxelSlit,
  EdgeContact,
  CornerContact,
  ThinSheet,
  TwoTissuesAlongAnEdge,
  Speckle
};

const char *
NameOf(HostileShape shape)
{
  switch (shape)
  {
    case HostileShape::OneVoxelBridge:
      return "OneVoxelBridge";
    case HostileShape::OneVoxelSlit:
      return "OneVoxelSlit";
    case HostileShape::EdgeContact:
      return "EdgeContact";
    case HostileShape::CornerContact:
      return "CornerContact";
    case HostileShape::ThinSheet:
      return "ThinSheet";
    case HostileShape::TwoTissuesAlongAnEdge:
      return "TwoTissuesAlongAnEdge";
    case HostileShape::Speckle:
      return "Speckle";
  }
  return "Unknown";
}

/** Relative slack for bounds met to the last bits (the angles are computed again from the written points). */
constexpr double RoundingSlack = 1e-9;

/** The largest voxel spacing: δ runs over 1 to 6 times it. */
constexpr double LargestSpacing = 1.5;

/** Blocks 14 × 14 × 10 voxels (14 × 14 × 15 mm): they hold a ball of diameter 6 × LargestSpacing = 9 mm. */
struct Block
{
  std::array<int, 3> lower;
  std::array<int, 3> upper;
  uint8_t            label;
};

/** The voxel at the middle of a block (the upper of the two middle ones where its size is even). */
ImageType::IndexType
CenterOf(const Block & block)
{
  return { { (block.lower[0] + block.upper[0]) / 2,
             (block.lower[1] + block.upper[1]) / 2,
             (block.lower[2] + block.upper[2]) / 2 } };
}

void
Fill(ImageType & image, const Block & block)
{
  for (int k = block.lower[2]; k < block.upper[2]; ++k)
  {
    for (int j = block.lower[1]; j < block.upper[1]; ++j)
    {
      for (int i = block.lower[0]; i < block.upper[0]; ++i)
      {
        image.SetPixel({ { i, j, k } }, block.label);
      }
    }
  }
}

/** The image of a shape, and its thick blocks: each must be in the mesh at every δ, as a tetrahedron of its label
 * around its centre (a block that holds a ball of diameter δ is not regularised away, whatever else of its label is
 * meshed). */
struct HostileImage
{
  ImageType::Pointer image;
  std::vector<Block> thickBlocks;
};

HostileImage
MakeHostileImage(HostileShape shape)
{
  auto image = ImageType::New();
  image->SetRegions(ImageType::SizeType{ { 40, 36, 26 } });
  const double spacing[3] = { 1.0, 1.2, LargestSpacing };
  image->SetSpacing(spacing);
  const double origin[3] = { -12.5, 3.25, 40.0 };
  image->SetOrigin(origin);
  image->Allocate();
  image->FillBuffer(0);
  const Block  left{ { { 3, 3, 3 } }, { { 17, 17, 13 } }, 1 };
  HostileImage result{ image, { left } };
  switch (shape)
  {
    case HostileShape::OneVoxelBridge: {
      const Block right{ { { 20, 3, 3 } }, { { 34, 17, 13 } }, 1 };
      Fill(*image, left);
      Fill(*image, right);
      Fill(*image, { { { 17, 9, 7 } }, { { 20, 10, 8 } }, 1 });
      result.thickBlocks = { left, right };
      break;
    }
    case HostileShape::OneVoxelSlit:
      Fill(*image, { { { 3, 3, 3 } }, { { 34, 30, 13 } }, 1 });
      Fill(*image, { { { 18, 3, 3 } }, { { 19, 24, 13 } }, 0 });
      // The two sides of the slit.
      result.thickBlocks = { { { { 3, 3, 3 } }, { { 18, 24, 13 } }, 1 }, { { { 19, 3, 3 } }, { { 34, 24, 13 } }, 1 } };
      break;
    case HostileShape::EdgeContact: {
      const Block touching{ { { 17, 17, 3 } }, { { 31, 31, 13 } }, 1 };
      Fill(*image, left);
      Fill(*image, touching);
      result.thickBlocks = { left, touching };
      break;
    }
    case HostileShape::CornerContact: {
      const Block touching{ { { 17, 17, 13 } }, { { 31, 31, 23 } }, 1 };
      Fill(*image, left);
      Fill(*image, touching);
      result.thickBlocks = { left, touching };
      break;
    }
    case HostileShape::ThinSheet:
      Fill(*image, left);
      Fill(*image, { { { 17, 3, 7 } }, { { 30, 17, 8 } }, 1 });
      break;
    case HostileShape::TwoTissuesAlongAnEdge: {
      const Block diagonal{ { { 17, 17, 3 } }, { { 31, 31, 13 } }, 2 };
      const Block beside{ { { 17, 3, 3 } }, { { 31, 17, 13 } }, 1 };
      Fill(*image, left);
      Fill(*image, diagonal);
      Fill(*image, beside);
      result.thickBlocks = { left, diagonal, beside };
      break;
    }
    case HostileShape::Speckle: {
      // The blocks' centres are outside the speckle.
      const Block second{ { { 20, 3, 3 } }, { { 34, 17, 13 } }, 2 };
      const Block third{ { { 3, 19, 3 } }, { { 17, 33, 13 } }, 3 };
      Fill(*image, left);
      Fill(*image, second);
      Fill(*image, third);
      // Interleaved speckle of the three tissues between the blocks, from a fixed linear congruential sequence.
      uint32_t state = 12345u;
      for (int k = 3; k < 16; ++k)
      {
        for (int j = 12; j < 24; ++j)
        {
          for (int i = 12; i < 25; ++i)
          {
            state = state * 1664525u + 1013904223u;
            const uint32_t draw = (state >> 16) % 5;
            if (draw < 3)
            {
              image->SetPixel({ { i, j, k } }, static_cast<uint8_t>(draw + 1));
            }
          }
        }
      }
      result.thickBlocks = { left, second, third };
      break;
    }
  }
  return result;
}

/** The filter with its defaults on a hostile shape at δ. */
FilterType::Pointer
MeshedHostileShape(const HostileImage & hostile, double delta)
{
  auto filter = FilterType::New();
  filter->SetInput(hostile.image);
  filter->SetSurfaceSamplingDistance(delta);
  filter->Update();
  return filter;
}

/** The bounds every mesh keeps with the defaults: radius-edge < ρ, no inverted tetrahedron, boundary angles > 30°,
 * and the smallest dihedral angle at least σ (the default σ removes slivers), the angle computed from the face
 * normals here as well as with the library's metric. */
template <typename TFilter>
void
ExpectQualityBounds(const TFilter & filter)
{
  const dr::TetrahedralMesh &  mesh = filter.GetRefinedMesh();
  const dr::TetrahedronQuality quality = dr::ComputeTetrahedronQuality(mesh);
  EXPECT_LT(quality.maximumRadiusEdgeRatio, filter.GetRadiusEdgeBound());
  EXPECT_EQ(quality.invertedTetrahedra, 0u);
  EXPECT_GT(dr::ComputeBoundaryTopology(mesh).minimumPlanarAngle, 30.0);
  const double sigma = filter.GetMinimumDihedralAngle();
  EXPECT_GE(quality.minimumDihedralAngle, sigma * (1.0 - RoundingSlack)) << "sigma " << sigma;
  EXPECT_GE(itk::delaunay_image_to_mesh_test::SmallestDihedralAngleFromNormals(mesh), sigma * (1.0 - RoundingSlack))
    << "sigma " << sigma;
}

/** Expects every tissue's boundary and the union's to be closed 2-manifolds, the edges and vertices counted
 * independently of the library's topology code as well; returns each boundary's components and genus, for the log. */
std::string
EveryBoundaryIsAClosedManifold(const dr::TetrahedralMesh & mesh)
{
  std::set<dr::Label> boundaries(mesh.tetrahedronLabels.begin(), mesh.tetrahedronLabels.end());
  boundaries.insert(dr::BackgroundLabel);
  std::ostringstream summary;
  for (const dr::Label label : boundaries)
  {
    SCOPED_TRACE(label == dr::BackgroundLabel ? std::string("the union of the tissues")
                                              : "tissue " + std::to_string(label));
    const dr::SurfaceTopology  topology = dr::ComputeLabelBoundaryTopology(mesh, label);
    const dr::NonManifoldCount independent =
      dr::CountNonManifoldPlaces(mesh.boundaryTriangles, mesh.boundaryTriangleLabels, label);
    EXPECT_EQ(independent.edges, 0u);
    EXPECT_EQ(independent.vertices, 0u);
    EXPECT_EQ(topology.nonManifoldEdges, 0u);
    EXPECT_EQ(topology.nonManifoldVertices, 0u);
    summary << " label " << label << ": " << topology.numberOfComponents << " components, genus " << topology.totalGenus
            << ";";
  }
  return summary.str();
}

class HostileShapes : public testing::TestWithParam<std::tuple<HostileShape, int>>
{};

TEST_P(HostileShapes, EveryBoundaryIsAClosedManifoldAndThickBlocksStay)
{
  const HostileShape          shape = std::get<0>(GetParam());
  const double                delta = std::get<1>(GetParam()) * LargestSpacing;
  const HostileImage          hostile = MakeHostileImage(shape);
  const auto                  filter = MeshedHostileShape(hostile, delta);
  const dr::TetrahedralMesh & mesh = filter->GetRefinedMesh();
  ASSERT_FALSE(mesh.tetrahedra.empty());

  for (const Block & block : hostile.thickBlocks)
  {
    EXPECT_TRUE(ATetrahedronOfTheLabelContains(mesh, block.label, PhysicalCenterOf(*hostile.image, CenterOf(block))))
      << "the block of tissue " << static_cast<int>(block.label) << " from voxel " << block.lower[0] << ", "
      << block.lower[1] << ", " << block.lower[2] << " holds a ball of diameter delta, but no tetrahedron of its "
      << "label contains its centre";
  }
  ExpectQualityBounds(*filter);
  std::cout << NameOf(shape) << " delta " << delta << ": " << mesh.tetrahedra.size() << " tetrahedra, "
            << filter->GetRegularizationReport().changedVoxels << " voxels regularised, "
            << filter->GetNumberOfLocallyRegularizedVoxels() << " locally;" << EveryBoundaryIsAClosedManifold(mesh)
            << "\n";
}

// Issue #14's bar on the hostile shapes: the topology costs at most 1.3 × the tetrahedra of the method alone (no
// regularisation, no topology rounds, no relabelling, diagonal voxels kept, no finer sampling of thick parts) at the
// same δ. A sheet thinner than the scale left a one-voxel fin along its root, which the refinement sampled: at
// δ = 4 × the largest spacing the thin sheet had 59 tetrahedra against the method alone's 42 (1.40 ×).
TEST_P(HostileShapes, TheTopologyAddsAtMost30PercentToTheMethodAlonesTetrahedra)
{
  const HostileImage hostile = MakeHostileImage(std::get<0>(GetParam()));
  const double       delta = std::get<1>(GetParam()) * LargestSpacing;
  const auto         defaults = MeshedHostileShape(hostile, delta);
  auto               alone = FilterType::New();
  alone->SetInput(hostile.image);
  alone->SetSurfaceSamplingDistance(delta);
  alone->SetRegularizationScale(0.0);
  alone->SetTopologyRegularizationRounds(0);
  alone->SetRelabelNonManifoldPlaces(false);
  alone->SetJoinDiagonalVoxels(false);
  alone->SetRefineThickParts(false);
  alone->Update();
  const std::size_t withTopology = defaults->GetRefinedMesh().tetrahedra.size();
  const std::size_t methodAlone = alone->GetRefinedMesh().tetrahedra.size();
  ASSERT_GT(methodAlone, 0u);
  EXPECT_LE(static_cast<double>(withTopology), 1.3 * static_cast<double>(methodAlone))
    << withTopology << " tetrahedra against the method alone's " << methodAlone;
}

// δ is the resolution (issue #14): at δ = 3 × the largest spacing (4.5 mm) the regularisation's ball (0.4 δ = 1.8 mm)
// closes slits thinner than about 3.6 mm. The only such part of the image is the 3 mm gap between the blocks (x from 17
// to 19), which the background's opening fills where it is farther from the open background than the scale; the
// blocks and the open background stay as they are, and the report counts exactly the voxels that changed. Checked on
// the labels the filter meshed against the input's, not on the filter's account alone: a regularisation skipped, or
// skipped and reported as done, fails here (the mutation check's no-regularization had been caught by fingerprints
// only).
TEST(Regularization, ClosesTheGapThinnerThanTheScaleOnlyAndCountsEveryVoxel)
{
  const HostileImage hostile = MakeHostileImage(HostileShape::OneVoxelBridge);
  auto               filter = FilterType::New();
  filter->SetInput(hostile.image);
  filter->SetSurfaceSamplingDistance(3.0 * LargestSpacing);
  filter->Update();
  ASSERT_EQ(filter->GetNumberOfLocallyRegularizedVoxels(), 0u) << "the topology rounds changed labels as well";

  const auto * meshed = filter->GetObjectLabelImage();
  ASSERT_NE(meshed, nullptr);
  std::size_t changed = 0;
  std::size_t changedOutsideTheGap = 0;
  std::size_t filled = 0;
  for (itk::ImageRegionConstIteratorWithIndex<FilterType::ObjectLabelImageType> it(meshed, meshed->GetBufferedRegion());
       !it.IsAtEnd();
       ++it)
  {
    const auto & index = it.GetIndex();
    const int    input = hostile.image->GetBufferedRegion().IsInside(index) ? hostile.image->GetPixel(index) : 0;
    if (it.Get() != input)
    {
      ++changed;
      changedOutsideTheGap += index[0] < 17 || index[0] > 19 ? 1 : 0;
      filled += input == 0 && it.Get() == 1 ? 1 : 0;
    }
  }
  EXPECT_GT(changed, 0u) << "the gap thinner than the scale was not closed";
  EXPECT_EQ(changedOutsideTheGap, 0u) << "a part thicker than the scale changed";
  EXPECT_EQ(filled, changed) << "a voxel changed otherwise than from the gap's background to the blocks' tissue";

  const dr::LabelRegularizationReport & report = filter->GetRegularizationReport();
  EXPECT_EQ(report.changedVoxels, changed);
  const auto tissue = std::find_if(report.labels.begin(),
                                   report.labels.end(),
                                   [](const dr::LabelRegularizationChange & change) { return change.label == 1; });
  ASSERT_NE(tissue, report.labels.end());
  EXPECT_EQ(tissue->voxelsAdded, changed);
  EXPECT_EQ(tissue->voxelsRemoved, 0u);
  EXPECT_EQ(tissue->voxelsAfter, tissue->voxelsBefore + changed);
  EXPECT_EQ(tissue->componentsAfter, 1u);
}

// GetSelectedLabelImage() is the segmentation the mesh stands for: the input's labels, whatever the regularisation,
// the joining of diagonal voxels and the topology rounds' local regularisation did to the labels the oracle meshed.
// The filter selects them from the input again after the refinement (it no longer keeps a copy through it), and with
// the regularisation and the joining off the oracle's label image is the only other copy, which the local
// regularisation changes in place.
TEST(SelectedLabelImage, IsTheInputsLabelsAfterTheLabelsChangedLocally)
{
  const HostileImage hostile = MakeHostileImage(HostileShape::Speckle);
  auto               filter = FilterType::New();
  filter->SetInput(hostile.image);
  filter->SetSurfaceSamplingDistance(LargestSpacing);
  filter->SetRegularizationScale(0.0);
  filter->SetJoinDiagonalVoxels(false);
  filter->SetRelabelNonManifoldPlaces(false);
  filter->Update();
  ASSERT_GT(filter->GetNumberOfLocallyRegularizedVoxels(), 0u) << "the case no longer exercises what it tests";

  const auto * selected = filter->GetSelectedLabelImage();
  const auto * meshed = filter->GetObjectLabelImage();
  ASSERT_NE(selected, nullptr);
  ASSERT_EQ(selected->GetBufferedRegion(), meshed->GetBufferedRegion());
  std::size_t compared = 0;
  std::size_t differFromTheMeshedLabels = 0;
  for (itk::ImageRegionConstIteratorWithIndex<FilterType::ObjectLabelImageType> it(selected,
                                                                                   selected->GetBufferedRegion());
       !it.IsAtEnd();
       ++it)
  {
    const auto & index = it.GetIndex();
    const int    expected = hostile.image->GetBufferedRegion().IsInside(index) ? hostile.image->GetPixel(index) : 0;
    ASSERT_EQ(it.Get(), expected) << "at voxel " << index;
    differFromTheMeshedLabels += meshed->GetPixel(index) != it.Get() ? 1 : 0;
    ++compared;
  }
  EXPECT_GT(compared, 0u);
  EXPECT_GT(differFromTheMeshedLabels, 0u) << "the local regularisation changed no label the oracle meshed";
}

// ---- Iso-surfaces of gray images --------------------------------------------------------------------------------

/** A hostile shape as gray values around `isoValue`: every voxel of a tissue (any non-zero label) above it and every
 * background voxel below it, by a magnitude from a fixed linear congruential sequence (2 % to 100 % of
 * `largestMagnitude`), so that the interpolated surface crosses the segments between voxel centres at irregular
 * fractions. For an integer type the values are rounded away from the iso-value. */
template <typename TValue>
typename itk::Image<TValue, 3>::Pointer
GrayImageOf(const HostileImage & hostile, double isoValue, double largestMagnitude)
{
  using GrayImageType = itk::Image<TValue, 3>;
  auto gray = GrayImageType::New();
  gray->CopyInformation(hostile.image);
  gray->SetRegions(hostile.image->GetBufferedRegion());
  gray->Allocate();
  uint32_t                                 state = 2718281u;
  itk::ImageRegionConstIterator<ImageType> label(hostile.image, hostile.image->GetBufferedRegion());
  for (itk::ImageRegionIterator<GrayImageType> value(gray, gray->GetBufferedRegion()); !value.IsAtEnd();
       ++value, ++label)
  {
    state = state * 1664525u + 1013904223u;
    const double magnitude = (0.02 + 0.98 * static_cast<double>(state >> 8) / 16777216.0) * largestMagnitude;
    const double above = isoValue + magnitude;
    const double below = isoValue - magnitude;
    if constexpr (std::is_integral_v<TValue>)
    {
      value.Set(static_cast<TValue>(label.Get() != 0 ? std::ceil(above) : std::floor(below)));
    }
    else
    {
      value.Set(static_cast<TValue>(label.Get() != 0 ? above : below));
    }
  }
  return gray;
}

/** The oracle of an iso-surface regularises the voxels' sides of the iso-value and carries them into the values it
 * interpolates (docs/algorithm.md, "Topology"): at every voxel centre inside the image its label must be the voxel's
 * regularised label, after the set-up and after a local regularisation, and some must differ from the input's side. */
template <typename TValue>
void
ExpectInterpolatedLabelsFollowTheRegularisedVoxels(double isoValue, double largestMagnitude)
{
  using GrayImageType = itk::Image<TValue, 3>;
  const HostileImage hostile = MakeHostileImage(HostileShape::Speckle);
  const auto         gray = GrayImageOf<TValue>(hostile, isoValue, largestMagnitude);
  auto               interpolator = itk::LinearInterpolateImageFunction<GrayImageType, double>::New();
  interpolator->SetInputImage(gray);
  itk::ImageLabelMapping mapping;
  mapping.useIsoValue = true;
  mapping.isoValue = isoValue;
  mapping.joinDiagonalVoxels = true;
  mapping.regularizationRadius = 0.4 * 3.0 * LargestSpacing;
  itk::ImageLabelOracle<GrayImageType> oracle(gray, interpolator, mapping);
  ASSERT_TRUE(oracle.LabelsDifferFromTheSelection()) << "the regularisation changed no voxel: the case tests nothing";

  const auto expectAgreement = [&](const char * when) {
    const auto * labels = oracle.GetLabelImage();
    std::size_t  checked = 0;
    std::size_t  changed = 0;
    for (itk::ImageRegionConstIteratorWithIndex<std::remove_pointer_t<decltype(labels)>> it(
           labels, labels->GetBufferedRegion());
         !it.IsAtEnd();
         ++it)
    {
      const auto & index = it.GetIndex();
      if (!gray->GetBufferedRegion().IsInside(index))
      {
        continue;
      }
      typename GrayImageType::PointType centre;
      gray->TransformIndexToPhysicalPoint(index, centre);
      const dr::Label regularised = it.Get() != dr::BackgroundLabel ? 1 : dr::BackgroundLabel;
      const double    input = static_cast<double>(gray->GetPixel(index));
      ASSERT_EQ(oracle.LabelAt({ { centre[0], centre[1], centre[2] } }), regularised)
        << when << ": voxel " << index << ", input value " << input << " against the iso-value " << isoValue;
      changed += (input >= isoValue) != (regularised != dr::BackgroundLabel) ? 1 : 0;
      ++checked;
    }
    EXPECT_GT(checked, 0u);
    EXPECT_GT(changed, 0u) << when << ": no voxel is on another side than the input's";
  };
  expectAgreement("after the set-up");

  // A place at the left block's corner voxel (3, 3, 3), where the ball holds more background than tissue: the
  // tissue's voxels there are cut.
  typename GrayImageType::PointType corner;
  gray->TransformIndexToPhysicalPoint({ { 3, 3, 3 } }, corner);
  const dr::NonManifoldPlace place{ { { corner[0], corner[1], corner[2] } }, 1 };
  ASSERT_FALSE(oracle.RegularizeAround({ place }, 2.5 * LargestSpacing).empty())
    << "the local regularisation changed nothing";
  expectAgreement("after a local regularisation");
}

TEST(IsoSurfaceRegularisation, FloatValuesFollowTheRegularisedVoxels)
{
  ExpectInterpolatedLabelsFollowTheRegularisedVoxels<float>(0.0, 3.0);
}

TEST(IsoSurfaceRegularisation, ByteValuesAroundAFractionalIsoValueFollowTheRegularisedVoxels)
{
  ExpectInterpolatedLabelsFollowTheRegularisedVoxels<uint8_t>(127.5, 100.0);
}

/** An iso-surface's census of parts (docs/algorithm.md, "Topology", step 4) measures the ball the interpolated
 * values surely hold: its voxels' part's ball less a voxel diagonal. Against the census of the same voxels as labels
 * (nearest neighbour), asked for a ball a diagonal larger: the same parts, each with its radius a diagonal smaller. */
TEST(IsoSurfaceRegularisation, TheCensusMeasuresTheVoxelsBallLessADiagonal)
{
  using GrayImageType = itk::Image<float, 3>;
  const HostileImage hostile = MakeHostileImage(HostileShape::OneVoxelBridge);
  const auto         gray = GrayImageOf<float>(hostile, 0.0, 3.0);
  auto               linear = itk::LinearInterpolateImageFunction<GrayImageType, double>::New();
  linear->SetInputImage(gray);
  itk::ImageLabelMapping isoMapping;
  isoMapping.useIsoValue = true;
  const itk::ImageLabelOracle<GrayImageType> iso(gray, linear, isoMapping);
  auto nearest = itk::NearestNeighborInterpolateImageFunction<ImageType, double>::New();
  nearest->SetInputImage(hostile.image);
  const itk::ImageLabelOracle<ImageType> voxels(hostile.image, nearest, itk::ImageLabelMapping{});

  const auto & spacing = hostile.image->GetSpacing();
  const double diagonal = std::sqrt(spacing[0] * spacing[0] + spacing[1] * spacing[1] + spacing[2] * spacing[2]);
  const double limit = 3.0;
  const dr::LabelledPoints none = [](const std::function<void(const dr::LabelledPoint &)> &) {};
  const auto               isoParts = iso.PartsHoldingNone(none, limit);
  const auto               voxelParts = voxels.PartsHoldingNone(none, limit + diagonal);
  ASSERT_EQ(isoParts.size(), voxelParts.size());
  ASSERT_FALSE(isoParts.empty());
  for (std::size_t part = 0; part < isoParts.size(); ++part)
  {
    EXPECT_EQ(isoParts[part].center, voxelParts[part].center);
    EXPECT_DOUBLE_EQ(isoParts[part].radius, std::max(voxelParts[part].radius - diagonal, 0.0));
    EXPECT_DOUBLE_EQ(isoParts[part].volume, voxelParts[part].volume);
  }
  // The bridge's blocks hold a ball of 3 mm around a voxel centre: more than a diagonal (2.2 mm) is left.
  EXPECT_GT(isoParts.front().radius, 0.0);
}

/** The hostile shapes as iso-surfaces (GrayImageOf), meshed with the filter's defaults: every boundary a closed
 * manifold, every bound kept, for δ from 1 to 6 times the largest spacing. Before the regularisation reached
 * iso-surfaces, an iso-surface of ITK's raw T1 image kept 9 to 31 non-manifold vertices at every δ tried. */
class HostileIsoSurfaces : public testing::TestWithParam<std::tuple<HostileShape, int>>
{};

TEST_P(HostileIsoSurfaces, EveryBoundaryIsAClosedManifold)
{
  using GrayImageType = itk::Image<float, 3>;
  using GrayFilterType = itk::DelaunayImageToMeshFilter<GrayImageType, MeshType>;
  const HostileShape shape = std::get<0>(GetParam());
  const double       delta = std::get<1>(GetParam()) * LargestSpacing;
  const HostileImage hostile = MakeHostileImage(shape);
  auto               filter = GrayFilterType::New();
  filter->SetInput(GrayImageOf<float>(hostile, 0.0, 3.0));
  filter->SetIsoValue(0.0);
  filter->SetSurfaceSamplingDistance(delta);
  filter->Update();
  const dr::TetrahedralMesh & mesh = filter->GetRefinedMesh();
  ASSERT_FALSE(mesh.tetrahedra.empty());
  const std::string summary = EveryBoundaryIsAClosedManifold(mesh);
  ExpectQualityBounds(*filter);
  // Every tissue is inside the iso-surface: each thick block is meshed as its object, label 1.
  for (const Block & block : hostile.thickBlocks)
  {
    EXPECT_TRUE(ATetrahedronOfTheLabelContains(mesh, 1, PhysicalCenterOf(*hostile.image, CenterOf(block))))
      << "no tetrahedron contains the centre of the block from voxel " << block.lower[0] << ", " << block.lower[1]
      << ", " << block.lower[2];
  }
  std::cout << NameOf(shape) << " as an iso-surface, delta " << delta << ": " << mesh.tetrahedra.size()
            << " tetrahedra, " << filter->GetRegularizationReport().changedVoxels << " voxels regularised, "
            << filter->GetNumberOfJoiningVoxels() << " at pinches, " << filter->GetNumberOfLocallyRegularizedVoxels()
            << " locally;" << summary << "\n";
}

std::string
CaseName(const testing::TestParamInfo<std::tuple<HostileShape, int>> & info)
{
  return std::string(NameOf(std::get<0>(info.param))) + "_delta" + std::to_string(std::get<1>(info.param)) + "x";
}

/** δ from 1 to 6 times the largest spacing (issue #14's bar). */
const auto DeltaMultiples = testing::Values(1, 2, 3, 4, 5, 6);

INSTANTIATE_TEST_SUITE_P(ShapesAndDeltas, HostileShapes,
                         testing::Combine(testing::Values(HostileShape::OneVoxelBridge, HostileShape::OneVoxelSlit,
                                                          HostileShape::EdgeContact, HostileShape::CornerContact,
                                                          HostileShape::ThinSheet, HostileShape::TwoTissuesAlongAnEdge),
                                          DeltaMultiples),
                         CaseName);
// Speckle of three tissues interleaved voxel by voxel. At δ = the largest spacing it kept a few non-manifold vertices
// on the union's boundary after every regularisation round (each ball of radius δ left new one-voxel rims), until
// the relabelling at non-manifold places (docs/algorithm.md, "Topology") mended them.
INSTANTIATE_TEST_SUITE_P(Speckle, HostileShapes,
                         testing::Combine(testing::Values(HostileShape::Speckle), DeltaMultiples), CaseName);
INSTANTIATE_TEST_SUITE_P(ShapesAndDeltas, HostileIsoSurfaces,
                         testing::Combine(testing::Values(HostileShape::OneVoxelBridge, HostileShape::OneVoxelSlit,
                                                          HostileShape::EdgeContact, HostileShape::CornerContact,
                                                          HostileShape::ThinSheet, HostileShape::Speckle),
                                          DeltaMultiples),
                         CaseName);

} // namespace
