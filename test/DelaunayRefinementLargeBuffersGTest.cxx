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

// The buffers of one value per voxel (DelaunayRefinementLargeBuffers.h): values survive a vector's growth across
// the size where its memory moves to huge pages, large memory is aligned to a huge page, the advice on memory
// allocated elsewhere leaves its contents alone; and the regularisation, whose buffers are such, gives a grid of
// a few million voxels the labels its definition asks for.

#include "DelaunayRefinementLabelRegularization.h"
#include "DelaunayRefinementLargeBuffers.h"
#include "DelaunayRefinementMesher.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <new>
#include <numeric>
#include <vector>

namespace delaunay_refinement
{
namespace
{

/** Large memory is aligned to a huge page where it asks for them (Linux); anything goes elsewhere. */
bool
IsAlignedToAHugePage(const void * memory)
{
#if defined(__linux__)
  return reinterpret_cast<std::uintptr_t>(memory) % LargeBufferBytes == 0;
#else
  return memory != nullptr;
#endif
}

TEST(LargeBuffers, AVectorKeepsItsValuesWhileItGrowsOntoHugePages)
{
  LargeVector<uint32_t> values;
  const uint32_t        count = 3 * LargeBufferBytes / sizeof(uint32_t) + 17;
  bool                  sawSmall = false;
  for (uint32_t value = 0; value < count; ++value)
  {
    values.push_back(value * 2654435761U);
    sawSmall = sawSmall || values.capacity() * sizeof(uint32_t) < LargeBufferBytes;
  }
  EXPECT_TRUE(sawSmall);
  EXPECT_TRUE(IsAlignedToAHugePage(values.data()));
  for (uint32_t value = 0; value < count; ++value)
  {
    ASSERT_EQ(values[value], value * 2654435761U) << "at " << value;
  }
  const LargeVector<uint32_t> copy = values;
  EXPECT_EQ(copy, values);
  values.resize(10);
  values.shrink_to_fit();
  EXPECT_EQ(values.size(), 10U);
  EXPECT_EQ(values[9], 9U * 2654435761U);
}

TEST(LargeBuffers, AnUninitializedArrayIsWritableEndToEnd)
{
  const std::size_t                 count = LargeBufferBytes / sizeof(double) + 1;
  UninitializedLargeArray<double>   large(count);
  UninitializedLargeArray<uint32_t> small(100);
  EXPECT_TRUE(IsAlignedToAHugePage(large.get()));
  for (std::size_t index = 0; index < count; ++index)
  {
    large[index] = static_cast<double>(index);
  }
  for (std::size_t index = 0; index < 100; ++index)
  {
    small[index] = static_cast<uint32_t>(index);
  }
  EXPECT_EQ(large[0], 0.0);
  EXPECT_EQ(large[count - 1], static_cast<double>(count - 1));
  EXPECT_EQ(small[99], 99U);
}

TEST(LargeBuffers, AdviceLeavesTheContentsAlone)
{
  std::vector<uint8_t> bytes(3 * LargeBufferBytes + 12345);
  std::iota(bytes.begin(), bytes.end(), uint8_t{ 7 });
  const std::vector<uint8_t> before = bytes;
  AdviseHugePages(bytes.data() + 3, bytes.size() - 3);
  AdviseHugePages(bytes.data(), 100); // no whole huge page inside: nothing to advise
  EXPECT_EQ(bytes, before);
}

/** A count whose bytes do not fit a size_t is refused as such (std::bad_array_new_length), before its size in bytes
 * wraps around: 2^61 + 2^18 doubles are 2^64 + 2 MiB bytes, which wrap to 2 MiB, a large buffer (not std::allocator's,
 * which would refuse the count itself) far smaller than asked for. Counts whose bytes fit are allocated. */
TEST(LargeBuffers, ACountWhoseBytesDoNotFitIsRefused)
{
  LargeBufferAllocator<double> allocator;
  const std::size_t            wrapsToALargeBuffer = (std::size_t{ 1 } << 61) + (std::size_t{ 1 } << 18);
  EXPECT_THROW(allocator.allocate(wrapsToALargeBuffer), std::bad_array_new_length);
  EXPECT_THROW(allocator.allocate(std::size_t(-1)), std::bad_array_new_length);
  const std::size_t large = LargeBufferBytes / sizeof(double);
  double *          memory = allocator.allocate(large);
  memory[large - 1] = 1.0;
  allocator.deallocate(memory, large);
}

/** A grid of a few million voxels (its flags and lists are large buffers): a block of label 1 crossed by a sheet
 * of label 2 one voxel thick, and a cube of label 2 far wider than the scale. Opened at a radius of one voxel, the
 * sheet goes to the block around it, and the cube and the rest of the block stay. */
TEST(LargeBuffers, TheRegularisationOfAGridOfMillionsOfVoxelsFollowsItsDefinition)
{
  const std::array<std::size_t, 3> size{ { 200, 120, 110 } };
  ASSERT_GE(size[0] * size[1] * size[2], LargeBufferBytes);
  std::vector<Label> labels(size[0] * size[1] * size[2], BackgroundLabel);
  const auto offset = [&size](std::size_t i, std::size_t j, std::size_t k) { return i + size[0] * (j + size[1] * k); };
  const auto inBlock = [](std::size_t i, std::size_t j, std::size_t k) {
    return i >= 10 && i < 120 && j >= 10 && j < 110 && k >= 10 && k < 100;
  };
  const auto inSheet = [](std::size_t i, std::size_t, std::size_t) { return i == 60; };
  const auto inCube = [](std::size_t i, std::size_t j, std::size_t k) {
    return i >= 140 && i < 190 && j >= 30 && j < 80 && k >= 30 && k < 80;
  };
  for (std::size_t k = 0; k < size[2]; ++k)
  {
    for (std::size_t j = 0; j < size[1]; ++j)
    {
      for (std::size_t i = 0; i < size[0]; ++i)
      {
        if (inBlock(i, j, k))
        {
          labels[offset(i, j, k)] = inSheet(i, j, k) ? 2 : 1;
        }
        else if (inCube(i, j, k))
        {
          labels[offset(i, j, k)] = 2;
        }
      }
    }
  }
  const LabelRegularizationReport report = RegularizeLabels(labels.data(), size, { { 1.0, 1.0, 1.0 } }, 1.0, {}, 2);
  std::size_t                     sheetVoxels = 0;
  for (std::size_t k = 0; k < size[2]; ++k)
  {
    for (std::size_t j = 0; j < size[1]; ++j)
    {
      for (std::size_t i = 0; i < size[0]; ++i)
      {
        const Label label = labels[offset(i, j, k)];
        // The block's and the cube's voxels more than the reach (1.5 voxels) and the dilation's (2) inside keep
        // their labels; the edges and corners of the block and the cube are rounded by the opening.
        const bool deepInBlock = i >= 13 && i < 117 && j >= 13 && j < 107 && k >= 13 && k < 97;
        const bool deepInCube = i >= 143 && i < 187 && j >= 33 && j < 77 && k >= 33 && k < 77;
        if (deepInBlock && inSheet(i, j, k))
        {
          ++sheetVoxels;
          ASSERT_EQ(label, 1) << "sheet voxel " << i << " " << j << " " << k;
        }
        else if (deepInBlock)
        {
          ASSERT_EQ(label, 1) << "block voxel " << i << " " << j << " " << k;
        }
        else if (deepInCube)
        {
          ASSERT_EQ(label, 2) << "cube voxel " << i << " " << j << " " << k;
        }
        else if (!inBlock(i, j, k) && !inCube(i, j, k))
        {
          ASSERT_EQ(label, BackgroundLabel) << "background voxel " << i << " " << j << " " << k;
        }
      }
    }
  }
  EXPECT_EQ(sheetVoxels, 94U * 84U);
  EXPECT_GE(report.changedVoxels, sheetVoxels);
}

} // namespace
} // namespace delaunay_refinement
