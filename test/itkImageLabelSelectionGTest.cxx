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

// ImageLabelSelection::SelectedLabelImage reads raw rows and looks labels up from a table (8-bit pixels) or by
// remembering the last value (others): each voxel must still carry LabelOf(its value), with the geometry of the
// input, and background where the region leaves the input's buffered region.

#include "itkImageLabelSelection.h"

#include "itkImageRegionConstIterator.h"
#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkImageRegionIterator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

namespace
{

/** A 7 x 5 x 4 image starting at index (2, -1, 3), oblique and anisotropic, of values in runs of one to three voxels:
 * integers spread over 256 values with zeros among them, or for floating-point pixels fractions and a NaN. */
template <typename TPixel>
typename itk::Image<TPixel, 3>::Pointer
ImageOfManyValues()
{
  using ImageType = itk::Image<TPixel, 3>;
  auto                           image = ImageType::New();
  typename ImageType::RegionType region;
  region.SetIndex({ { 2, -1, 3 } });
  region.SetSize({ { 7, 5, 4 } });
  image->SetRegions(region);
  typename ImageType::SpacingType spacing;
  spacing[0] = 0.5;
  spacing[1] = 1.25;
  spacing[2] = 2.0;
  image->SetSpacing(spacing);
  typename ImageType::PointType origin;
  origin[0] = -3.0;
  origin[1] = 4.0;
  origin[2] = 1.5;
  image->SetOrigin(origin);
  typename ImageType::DirectionType direction;
  direction.SetIdentity();
  direction(0, 0) = 0.0;
  direction(0, 1) = 1.0;
  direction(1, 0) = 1.0;
  direction(1, 1) = 0.0;
  image->SetDirection(direction);
  image->Allocate();
  std::size_t count = 0;
  for (itk::ImageRegionIterator<ImageType> it(image, region); !it.IsAtEnd(); ++it, ++count)
  {
    // Runs of one to three equal values: the remembered value must change with the run.
    const auto step = static_cast<int>(count / (1 + count % 3));
    if constexpr (std::is_floating_point_v<TPixel>)
    {
      it.Set(count == 17 ? std::numeric_limits<TPixel>::quiet_NaN() : static_cast<TPixel>(0.75 * (step % 9) - 2.0));
    }
    else
    {
      // Every fourth run background, the others spread over 256 values (negative ones for signed pixels).
      const int value = step % 4 == 0 ? 0 : (step * 37) % 256 - (std::is_signed_v<TPixel> ? 128 : 0);
      it.Set(static_cast<TPixel>(value));
    }
  }
  return image;
}

template <typename TPixel>
void
ExpectEveryVoxelIsLabelOf(const itk::ImageLabelMapping & mapping, const std::string & what)
{
  const auto                                           image = ImageOfManyValues<TPixel>();
  const itk::ImageLabelSelection                       selection(mapping);
  itk::ImageLabelSelection::LabelImageType::RegionType region = image->GetBufferedRegion();
  // One voxel of margin on every side: outside the input's buffered region is background.
  region.PadByRadius(1);
  const auto labels = selection.SelectedLabelImage(*image, region);
  ASSERT_EQ(labels->GetBufferedRegion(), region) << what;
  EXPECT_EQ(labels->GetOrigin(), image->GetOrigin()) << what;
  EXPECT_EQ(labels->GetSpacing(), image->GetSpacing()) << what;
  EXPECT_EQ(labels->GetDirection(), image->GetDirection()) << what;
  std::size_t objectVoxels = 0;
  for (itk::ImageRegionConstIteratorWithIndex<itk::ImageLabelSelection::LabelImageType> it(labels, region);
       !it.IsAtEnd();
       ++it)
  {
    const auto & index = it.GetIndex();
    const auto   expected = image->GetBufferedRegion().IsInside(index)
                              ? selection.LabelOf(static_cast<double>(image->GetPixel(index)))
                              : delaunay_refinement::BackgroundLabel;
    ASSERT_EQ(it.Get(), expected) << what << ", index " << index;
    objectVoxels += expected != delaunay_refinement::BackgroundLabel ? 1 : 0;
  }
  // The case must select some voxels and leave others out, or it tells nothing.
  EXPECT_GT(objectVoxels, 0u) << what;
  EXPECT_LT(objectVoxels, image->GetBufferedRegion().GetNumberOfPixels()) << what;
}

template <typename TPixel>
void
ExpectEveryMappingIsLabelOf(const std::string & type)
{
  itk::ImageLabelMapping everyLabel;
  ExpectEveryVoxelIsLabelOf<TPixel>(everyLabel, type + ", every non-zero label");
  itk::ImageLabelMapping someLabels;
  someLabels.selectedLabels = { 1, -91, 74, 3, -54 };
  ExpectEveryVoxelIsLabelOf<TPixel>(someLabels, type + ", selected labels");
  itk::ImageLabelMapping merged = someLabels;
  merged.mergeLabels = true;
  ExpectEveryVoxelIsLabelOf<TPixel>(merged, type + ", selected labels merged");
  itk::ImageLabelMapping iso;
  iso.useIsoValue = true;
  iso.isoValue = 0.5;
  ExpectEveryVoxelIsLabelOf<TPixel>(iso, type + ", iso-value");
}

} // namespace

TEST(ImageLabelSelection, SelectedLabelImageIsLabelOfEveryVoxel)
{
  ExpectEveryMappingIsLabelOf<unsigned char>("unsigned char");
  ExpectEveryMappingIsLabelOf<signed char>("signed char");
  ExpectEveryMappingIsLabelOf<short>("short");
  ExpectEveryMappingIsLabelOf<uint16_t>("uint16_t");
  ExpectEveryMappingIsLabelOf<float>("float");
  ExpectEveryMappingIsLabelOf<double>("double");
}

/** A region beside the image's, sharing no voxel with it: all background. */
TEST(ImageLabelSelection, ARegionMissingTheImageIsBackground)
{
  const auto                                           image = ImageOfManyValues<unsigned char>();
  itk::ImageLabelSelection::LabelImageType::RegionType region = image->GetBufferedRegion();
  region.SetIndex(0, region.GetIndex(0) + static_cast<itk::IndexValueType>(region.GetSize(0)) + 3);
  const auto labels = itk::ImageLabelSelection(itk::ImageLabelMapping{}).SelectedLabelImage(*image, region);
  ASSERT_EQ(labels->GetBufferedRegion(), region);
  for (itk::ImageRegionConstIterator<itk::ImageLabelSelection::LabelImageType> it(labels, region); !it.IsAtEnd(); ++it)
  {
    ASSERT_EQ(it.Get(), delaunay_refinement::BackgroundLabel);
  }
}

/** A floating-point value is rounded to the nearest label (README, "Inputs"), not truncated: label images resampled
 * with a linear interpolator or stored as float carry values a little off their labels, on either side. The test
 * above compares every voxel with LabelOf() itself, so this pins LabelOf() down. */
TEST(ImageLabelSelection, AValueTakesTheNearestLabel)
{
  const itk::ImageLabelSelection everyLabel{ itk::ImageLabelMapping{} };
  EXPECT_EQ(everyLabel.LabelOf(2.0), 2);
  EXPECT_EQ(everyLabel.LabelOf(1.6), 2);
  EXPECT_EQ(everyLabel.LabelOf(2.4), 2);
  EXPECT_EQ(everyLabel.LabelOf(1.9999), 2);
  EXPECT_EQ(everyLabel.LabelOf(-1.6), -2);
  EXPECT_EQ(everyLabel.LabelOf(-2.4), -2);
  EXPECT_EQ(everyLabel.LabelOf(0.4), delaunay_refinement::BackgroundLabel);
  EXPECT_EQ(everyLabel.LabelOf(-0.4), delaunay_refinement::BackgroundLabel);
  EXPECT_EQ(everyLabel.LabelOf(0.6), 1);

  itk::ImageLabelMapping onlyThree;
  onlyThree.selectedLabels = { 3 };
  const itk::ImageLabelSelection selection(onlyThree);
  EXPECT_EQ(selection.LabelOf(2.7), 3);
  EXPECT_EQ(selection.LabelOf(3.3), 3);
  EXPECT_EQ(selection.LabelOf(2.3), delaunay_refinement::BackgroundLabel);
}

namespace
{

/** The bytes BytesPerVoxelLabel() gives hold every label SelectedLabelImage() makes, and SelectedLabelImage() in
 * that type holds the same labels as in LabelType. */
template <typename TPixel>
unsigned int
BytesPerVoxelLabelThatHoldsEveryLabel(const typename itk::Image<TPixel, 3>::Pointer & image,
                                      const itk::ImageLabelMapping & mapping, const std::string & what)
{
  const itk::ImageLabelSelection selection(mapping);
  const auto                     region = image->GetBufferedRegion();
  const auto                     labels = selection.SelectedLabelImage(*image, region);
  const unsigned int             bytes = selection.BytesPerVoxelLabel(*image);
  const auto                     expectTheSameLabels = [&](const auto & narrow) {
    itk::ImageRegionConstIterator<itk::ImageLabelSelection::LabelImageType> label(labels, region);
    for (itk::ImageRegionConstIterator<std::remove_reference_t<decltype(*narrow)>> it(narrow, region); !it.IsAtEnd();
         ++it, ++label)
    {
      ASSERT_EQ(static_cast<delaunay_refinement::Label>(it.Get()), label.Get()) << what;
    }
  };
  switch (bytes)
  {
    case 1:
      expectTheSameLabels(selection.SelectedLabelImage<uint8_t>(*image, region));
      break;
    case 2:
      expectTheSameLabels(selection.SelectedLabelImage<uint16_t>(*image, region));
      break;
    default:
      EXPECT_EQ(bytes, 4u) << what;
  }
  return bytes;
}

template <typename TPixel>
typename itk::Image<TPixel, 3>::Pointer
ImageWithOneVoxelOf(TPixel value)
{
  auto image = ImageOfManyValues<TPixel>();
  image->SetPixel(image->GetBufferedRegion().GetIndex(), value);
  return image;
}

} // namespace

/** The filter stores the label image in the fewest bytes every selected label fits in: one for an iso-value, merged
 * labels or labels within 0-255 (most segmentations), two within 0-65535, four otherwise. */
TEST(ImageLabelSelection, BytesPerVoxelLabelIsTheFewestThatHoldEveryLabel)
{
  itk::ImageLabelMapping everyLabel;
  itk::ImageLabelMapping someLabels;
  someLabels.selectedLabels = { 1, 74, 3 };
  itk::ImageLabelMapping withNegative = someLabels;
  withNegative.selectedLabels.push_back(-54);
  itk::ImageLabelMapping merged = withNegative;
  merged.mergeLabels = true;
  itk::ImageLabelMapping iso;
  iso.useIsoValue = true;
  iso.isoValue = 0.5;
  // 8-bit unsigned pixels: from the type.
  EXPECT_EQ(BytesPerVoxelLabelThatHoldsEveryLabel<uint8_t>(ImageOfManyValues<uint8_t>(), everyLabel, "uint8"), 1u);
  // Selected labels: from the selection, whatever the type.
  EXPECT_EQ(BytesPerVoxelLabelThatHoldsEveryLabel<uint16_t>(ImageOfManyValues<uint16_t>(), someLabels, "uint16 some"),
            1u);
  EXPECT_EQ(BytesPerVoxelLabelThatHoldsEveryLabel<short>(ImageOfManyValues<short>(), someLabels, "short some"), 1u);
  EXPECT_EQ(BytesPerVoxelLabelThatHoldsEveryLabel<short>(ImageOfManyValues<short>(), withNegative, "short negative"),
            4u);
  // Merged labels and iso-values are 0 and 1.
  EXPECT_EQ(BytesPerVoxelLabelThatHoldsEveryLabel<short>(ImageOfManyValues<short>(), merged, "short merged"), 1u);
  EXPECT_EQ(BytesPerVoxelLabelThatHoldsEveryLabel<float>(ImageOfManyValues<float>(), iso, "float iso"), 1u);
  // Other types: from the labels the image holds. 16-bit segmentations mostly hold labels below 256.
  auto wide = ImageOfManyValues<uint16_t>();
  EXPECT_EQ(BytesPerVoxelLabelThatHoldsEveryLabel<uint16_t>(wide, everyLabel, "uint16 within 0-255"), 1u);
  wide->SetPixel(wide->GetBufferedRegion().GetIndex(), 300);
  EXPECT_EQ(BytesPerVoxelLabelThatHoldsEveryLabel<uint16_t>(wide, everyLabel, "uint16 with 300"), 2u);
  EXPECT_EQ(BytesPerVoxelLabelThatHoldsEveryLabel<short>(ImageOfManyValues<short>(), everyLabel, "short, negative"),
            4u);
  EXPECT_EQ(BytesPerVoxelLabelThatHoldsEveryLabel<float>(ImageOfManyValues<float>(), everyLabel, "float, negative"),
            4u);
  auto nonNegative = ImageOfManyValues<int>();
  for (itk::ImageRegionIterator<itk::Image<int, 3>> it(nonNegative, nonNegative->GetBufferedRegion()); !it.IsAtEnd();
       ++it)
  {
    it.Set(std::abs(it.Get()));
  }
  EXPECT_EQ(BytesPerVoxelLabelThatHoldsEveryLabel<int>(nonNegative, everyLabel, "int within 0-255"), 1u);
  nonNegative->SetPixel(nonNegative->GetBufferedRegion().GetIndex(), 256);
  EXPECT_EQ(BytesPerVoxelLabelThatHoldsEveryLabel<int>(nonNegative, everyLabel, "int with 256"), 2u);
  nonNegative->SetPixel(nonNegative->GetBufferedRegion().GetIndex(), 65535);
  EXPECT_EQ(BytesPerVoxelLabelThatHoldsEveryLabel<int>(nonNegative, everyLabel, "int with 65535"), 2u);
  nonNegative->SetPixel(nonNegative->GetBufferedRegion().GetIndex(), 65536);
  EXPECT_EQ(BytesPerVoxelLabelThatHoldsEveryLabel<int>(nonNegative, everyLabel, "int with 65536"), 4u);
  EXPECT_EQ(
    BytesPerVoxelLabelThatHoldsEveryLabel<double>(ImageWithOneVoxelOf<double>(300.2), someLabels, "double, selected"),
    1u);
}

namespace
{

/** The selected labels of `mapping` that no voxel of `image` rounds to, by brute force over every voxel: each
 * selected label is looked for with its own test of the voxel's value (finite, and within half of the label). */
template <typename TImage>
std::vector<delaunay_refinement::Label>
SelectedLabelsAbsentByBruteForce(const TImage & image, const itk::ImageLabelMapping & mapping)
{
  std::vector<delaunay_refinement::Label> selected = mapping.selectedLabels;
  std::sort(selected.begin(), selected.end());
  selected.erase(std::unique(selected.begin(), selected.end()), selected.end());
  std::vector<delaunay_refinement::Label> absent;
  for (const delaunay_refinement::Label label : selected)
  {
    bool present = false;
    for (itk::ImageRegionConstIterator<TImage> it(&image, image.GetBufferedRegion()); !it.IsAtEnd() && !present; ++it)
    {
      const double value = static_cast<double>(it.Get());
      present = std::isfinite(value) && std::abs(value - static_cast<double>(label)) < 0.5;
    }
    if (!present)
    {
      absent.push_back(label);
    }
  }
  return absent;
}

template <typename TPixel>
void
ExpectTheSelectedLabelsNotInTheImage(const std::vector<delaunay_refinement::Label> & selection,
                                     const std::string &                             type)
{
  const auto             image = ImageOfManyValues<TPixel>();
  itk::ImageLabelMapping mapping;
  mapping.selectedLabels = selection;
  const auto expected = SelectedLabelsAbsentByBruteForce(*image, mapping);
  // The case must hold labels found and labels not, or it tells nothing.
  ASSERT_FALSE(expected.empty()) << type;
  ASSERT_LT(expected.size(), std::set<delaunay_refinement::Label>(selection.begin(), selection.end()).size()) << type;
  EXPECT_EQ(itk::ImageLabelSelection(mapping).SelectedLabelsNotIn(*image), expected) << type;
  mapping.mergeLabels = true;
  EXPECT_EQ(itk::ImageLabelSelection(mapping).SelectedLabelsNotIn(*image), expected) << type << ", merged";
  // An iso-value selects no label, and no selection is every label there is.
  mapping.useIsoValue = true;
  EXPECT_TRUE(itk::ImageLabelSelection(mapping).SelectedLabelsNotIn(*image).empty()) << type << ", iso-value";
  EXPECT_TRUE(itk::ImageLabelSelection(itk::ImageLabelMapping{}).SelectedLabelsNotIn(*image).empty()) << type;
}

} // namespace

// The labels found are those some voxel rounds to, wherever it is in the image (the last voxel, a run that starts a
// row), repeats in the selection counted once; the labels not found come back in increasing order.
TEST(ImageLabelSelection, SelectedLabelsNotInTheImageAreThoseNoVoxelRoundsTo)
{
  // The integer images hold every fourth run 0 and the others spread over (step * 37) % 256 (minus 128 if signed).
  const auto lastValue = [](auto image) {
    const auto & region = image->GetBufferedRegion();
    return static_cast<delaunay_refinement::Label>(
      std::lround(static_cast<double>(image->GetPixel(region.GetUpperIndex()))));
  };
  const delaunay_refinement::Label lastUnsigned = lastValue(ImageOfManyValues<uint8_t>());
  const delaunay_refinement::Label lastSigned = lastValue(ImageOfManyValues<int16_t>());
  ExpectTheSelectedLabelsNotInTheImage<uint8_t>({ 255, 37, lastUnsigned, 5, 37, 1000, -3, 74 }, "uint8_t");
  ExpectTheSelectedLabelsNotInTheImage<uint16_t>({ 255, 37, lastUnsigned, 5, 37, 1000, -3, 74 }, "uint16_t");
  ExpectTheSelectedLabelsNotInTheImage<int16_t>({ -91, lastSigned, -54, 2, 3, 127, 1000 }, "int16_t");
  // Floats hold 0.75 * (step % 9) - 2, and a NaN: -2, -1.25 (-1), -0.5 (0 or -1: exactly half), 1, 1.75 (2) ...
  ExpectTheSelectedLabelsNotInTheImage<float>({ -2, -1, 1, 2, 3, 4, 5, 7 }, "float");
  ExpectTheSelectedLabelsNotInTheImage<double>({ -2, -1, 1, 2, 3, 4, 5, 7 }, "double");
}
