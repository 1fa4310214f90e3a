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

// CountVoxelComponents, which the quality report uses to say how many pieces a lost tissue was made of: known
// counts on a hand-made volume, and VTK's image connectivity filter (face-connected, on the volume padded with
// background, as the report defines it) as an independent reference on random speckle, for one label at a time and
// for several in one pass.

#include "DelaunayImageToMeshVoxelComponents.h"

#include <gtest/gtest.h>
#include <vtkImageConnectivityFilter.h>
#include <vtkImageData.h>
#include <vtkNew.h>

#include <algorithm>
#include <cstdint>
#include <map>

namespace delaunay_refinement
{
namespace
{

LabelVolume
EmptyVolume(std::size_t x, std::size_t y, std::size_t z)
{
  LabelVolume volume;
  volume.size = { { x, y, z } };
  volume.labels.assign(x * y * z, BackgroundLabel);
  return volume;
}

Label &
At(LabelVolume & volume, std::size_t i, std::size_t j, std::size_t k)
{
  return volume.labels[i + volume.size[0] * (j + volume.size[1] * k)];
}

std::size_t
VtkComponents(const LabelVolume & volume, Label label)
{
  vtkNew<vtkImageData> image;
  image->SetDimensions(
    static_cast<int>(volume.size[0]) + 2, static_cast<int>(volume.size[1]) + 2, static_cast<int>(volume.size[2]) + 2);
  image->AllocateScalars(VTK_INT, 1);
  for (int k = 0; k < static_cast<int>(volume.size[2]) + 2; ++k)
  {
    for (int j = 0; j < static_cast<int>(volume.size[1]) + 2; ++j)
    {
      for (int i = 0; i < static_cast<int>(volume.size[0]) + 2; ++i)
      {
        const bool border = i == 0 || j == 0 || k == 0 || i == static_cast<int>(volume.size[0]) + 1 ||
                            j == static_cast<int>(volume.size[1]) + 1 || k == static_cast<int>(volume.size[2]) + 1;
        *static_cast<int *>(image->GetScalarPointer(i, j, k)) =
          border ? BackgroundLabel : volume.labels[(i - 1) + volume.size[0] * ((j - 1) + volume.size[1] * (k - 1))];
      }
    }
  }
  vtkNew<vtkImageConnectivityFilter> connectivity;
  connectivity->SetInputData(image);
  connectivity->SetScalarRange(label, label);
  connectivity->SetExtractionModeToAllRegions();
  // The default label type is unsigned char: more than 255 pieces would all be counted as 255 (the report said
  // 254 for a k-means tissue of 1,512 pieces until the flood fill replaced the filter).
  connectivity->SetLabelScalarTypeToInt();
  connectivity->Update();
  return static_cast<std::size_t>(connectivity->GetNumberOfExtractedRegions());
}

/** A 3 x 3 x 3 shell of label 1 around one background voxel, and two voxels of label 2 that touch along an edge
 * only: label 1 is one piece, label 2 two (face connectivity), the background two (outside, and the cavity). */
TEST(VoxelComponents, AHandMadeVolumeHasItsKnownCounts)
{
  LabelVolume volume = EmptyVolume(5, 5, 5);
  for (std::size_t k = 1; k <= 3; ++k)
  {
    for (std::size_t j = 1; j <= 3; ++j)
    {
      for (std::size_t i = 1; i <= 3; ++i)
      {
        At(volume, i, j, k) = (i == 2 && j == 2 && k == 2) ? BackgroundLabel : 1;
      }
    }
  }
  At(volume, 0, 0, 0) = 2;
  At(volume, 1, 1, 0) = 2;
  EXPECT_EQ(CountVoxelComponents(volume, 1), 1u);
  EXPECT_EQ(CountVoxelComponents(volume, 2), 2u);
  EXPECT_EQ(CountVoxelComponents(volume, BackgroundLabel), 2u);
  EXPECT_EQ(CountVoxelComponents(volume, 3), 0u);
}

TEST(VoxelComponents, RandomSpeckleCountsAsVtksConnectivityFilter)
{
  uint64_t   state = 20261126;
  const auto next = [&state]() {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
  };
  std::size_t components = 0;
  std::size_t mostInOneLabel = 0;
  for (int volumeNumber = 0; volumeNumber < 20; ++volumeNumber)
  {
    // Up to 40 voxels a side: enough for more than 255 pieces of one label.
    LabelVolume volume = EmptyVolume(3 + next() % 38, 3 + next() % 38, 3 + next() % 38);
    for (Label & label : volume.labels)
    {
      label = static_cast<Label>(next() % 4);
    }
    // Every label in one pass, as the report counts its lost tissues; a label absent from the volume counts 0.
    const std::map<Label, std::size_t> counts = CountVoxelComponents(volume, { 3, 0, 2, 1, 7 });
    ASSERT_EQ(counts.size(), 5u);
    EXPECT_EQ(counts.at(7), 0u);
    for (Label label = 0; label < 4; ++label)
    {
      const std::size_t count = CountVoxelComponents(volume, label);
      EXPECT_EQ(count, VtkComponents(volume, label)) << "volume " << volumeNumber << ", label " << label;
      EXPECT_EQ(counts.at(label), count) << "volume " << volumeNumber << ", label " << label << " counted with others";
      components += count;
      mostInOneLabel = std::max(mostInOneLabel, count);
    }
  }
  // Speckle of four labels is many pieces: a count stuck at 0 or 1, or at 255, fails here.
  EXPECT_GT(components, 500u);
  EXPECT_GT(mostInOneLabel, 255u);
}

} // namespace
} // namespace delaunay_refinement
