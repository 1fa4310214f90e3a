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

// JoinDiagonalVoxels against brute force: after it, no object voxel pair touches only along an edge with
// background on the other diagonal; only background voxels changed, each to a label of a voxel it now joins.

#include "DelaunayRefinementVoxelPinches.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

namespace delaunay_refinement
{
namespace
{

using Size = std::array<std::size_t, 3>;

struct Grid
{
  Size               size;
  std::vector<Label> labels;

  Label &
  At(std::size_t i, std::size_t j, std::size_t k)
  {
    return labels[i + size[0] * (j + size[1] * k)];
  }
};

Grid
EmptyGrid(const Size & size)
{
  return { size, std::vector<Label>(size[0] * size[1] * size[2], BackgroundLabel) };
}

/** Voxel edges with all four voxels in the grid, one diagonal of one non-zero label, the other background. */
std::size_t
CountObjectBackgroundPinches(const Grid & grid)
{
  const Size  strides{ { 1, grid.size[0], grid.size[0] * grid.size[1] } };
  std::size_t pinches = 0;
  for (int first = 0; first < 3; ++first)
  {
    for (int second = first + 1; second < 3; ++second)
    {
      for (std::size_t k = 0; k < grid.size[2]; ++k)
      {
        for (std::size_t j = 0; j < grid.size[1]; ++j)
        {
          for (std::size_t i = 0; i < grid.size[0]; ++i)
          {
            const Size c{ { i, j, k } };
            if (c[first] + 1 >= grid.size[first] || c[second] + 1 >= grid.size[second])
            {
              continue;
            }
            const std::size_t a = i + strides[1] * j + strides[2] * k;
            const Label       v00 = grid.labels[a];
            const Label       v10 = grid.labels[a + strides[first]];
            const Label       v01 = grid.labels[a + strides[second]];
            const Label       v11 = grid.labels[a + strides[first] + strides[second]];
            pinches += (v00 != BackgroundLabel && v00 == v11 && v10 == BackgroundLabel && v01 == BackgroundLabel) ||
                       (v10 != BackgroundLabel && v10 == v01 && v00 == BackgroundLabel && v11 == BackgroundLabel);
          }
        }
      }
    }
  }
  return pinches;
}

bool
HasFaceNeighbourLabelled(const Grid & grid, std::size_t voxel, Label label)
{
  const Size strides{ { 1, grid.size[0], grid.size[0] * grid.size[1] } };
  const Size coordinates{ { voxel % grid.size[0], (voxel / grid.size[0]) % grid.size[1], voxel / strides[2] } };
  for (int axis = 0; axis < 3; ++axis)
  {
    if ((coordinates[axis] > 0 && grid.labels[voxel - strides[axis]] == label) ||
        (coordinates[axis] + 1 < grid.size[axis] && grid.labels[voxel + strides[axis]] == label))
    {
      return true;
    }
  }
  return false;
}

TEST(JoinDiagonalVoxels, OnePinchGetsOneJoiningVoxel)
{
  Grid grid = EmptyGrid({ { 4, 4, 3 } });
  grid.At(1, 1, 1) = 3;
  grid.At(2, 2, 1) = 3;
  ASSERT_EQ(CountObjectBackgroundPinches(grid), 1u);
  EXPECT_EQ(JoinDiagonalVoxels(grid.labels.data(), grid.size), 1u);
  EXPECT_EQ(CountObjectBackgroundPinches(grid), 0u);
  // Both candidates have one face neighbour of label 3: the tie goes to the one along the block's first axis.
  EXPECT_EQ(grid.At(2, 1, 1), 3);
  EXPECT_EQ(grid.At(1, 2, 1), BackgroundLabel);
}

TEST(JoinDiagonalVoxels, ContactsBetweenTissuesAndAtAVertexStay)
{
  Grid grid = EmptyGrid({ { 5, 5, 5 } });
  // Two voxels of tissue 1 across an edge whose other voxels are tissue 2 and background.
  grid.At(1, 1, 1) = 1;
  grid.At(2, 2, 1) = 1;
  grid.At(2, 1, 1) = 2;
  // Two voxels of tissue 4 touching at a vertex only.
  grid.At(1, 1, 3) = 4;
  grid.At(2, 2, 4) = 4;
  const std::vector<Label> before = grid.labels;
  EXPECT_EQ(JoinDiagonalVoxels(grid.labels.data(), grid.size), 0u);
  EXPECT_EQ(grid.labels, before);
}

TEST(JoinDiagonalVoxels, ADiagonalStaircaseBecomesFaceConnected)
{
  Grid grid = EmptyGrid({ { 9, 9, 3 } });
  for (std::size_t step = 1; step <= 7; ++step)
  {
    grid.At(step, step, 1) = 1;
  }
  EXPECT_EQ(JoinDiagonalVoxels(grid.labels.data(), grid.size), 6u);
  EXPECT_EQ(CountObjectBackgroundPinches(grid), 0u);
}

/** Random speckle of three labels: every object/background pinch goes, only background voxels change, each to
 * a label of one of its face neighbours; the result is deterministic and a second pass changes nothing. */
TEST(JoinDiagonalVoxels, RandomSpeckle)
{
  uint64_t   state = 20261122;
  const auto next = [&state]() {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
  };
  std::size_t totalJoined = 0;
  for (int gridNumber = 0; gridNumber < 50; ++gridNumber)
  {
    Grid           grid = EmptyGrid({ { 2 + next() % 12, 2 + next() % 12, 2 + next() % 12 } });
    const uint64_t density = 1 + next() % 7;
    for (Label & label : grid.labels)
    {
      label = next() % 10 < density ? static_cast<Label>(1 + next() % 3) : BackgroundLabel;
    }
    const std::vector<Label> before = grid.labels;
    const std::size_t        joined = JoinDiagonalVoxels(grid.labels.data(), grid.size);
    totalJoined += joined;
    EXPECT_EQ(CountObjectBackgroundPinches(grid), 0u) << "grid " << gridNumber;
    std::size_t changed = 0;
    for (std::size_t v = 0; v < before.size(); ++v)
    {
      if (grid.labels[v] != before[v])
      {
        ++changed;
        EXPECT_EQ(before[v], BackgroundLabel) << "grid " << gridNumber << ", voxel " << v;
        EXPECT_TRUE(HasFaceNeighbourLabelled(grid, v, grid.labels[v])) << "grid " << gridNumber << ", voxel " << v;
      }
    }
    EXPECT_EQ(changed, joined) << "grid " << gridNumber;
    Grid again{ grid.size, before };
    JoinDiagonalVoxels(again.labels.data(), again.size);
    EXPECT_EQ(again.labels, grid.labels) << "grid " << gridNumber;
    EXPECT_EQ(JoinDiagonalVoxels(grid.labels.data(), grid.size), 0u) << "grid " << gridNumber;
  }
  EXPECT_GT(totalJoined, 100u);
}

} // namespace
} // namespace delaunay_refinement
