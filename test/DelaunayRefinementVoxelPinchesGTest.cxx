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

// RemoveVoxelPinches against brute force: afterwards no label, the background included, meets another only along
// a voxel edge or at a voxel corner (no 2 x 2 x 2 block where a label holds exactly one diagonal of a face, exactly
// two opposite corners, or all but two opposite corners); no tissue voxel becomes background (the union of the
// tissues only grows, as a closing would); two tissues meeting along a curved interface keep their volumes (the
// smaller one is not peeled off layer by layer). The pinch test here walks the faces and corners itself; it does
// not use the table the implementation uses.

#include "DelaunayRefinementVoxelPinches.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <set>
#include <utility>
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

  Label
  At(std::size_t i, std::size_t j, std::size_t k) const
  {
    return labels[i + size[0] * (j + size[1] * k)];
  }
};

Grid
EmptyGrid(const Size & size)
{
  return { size, std::vector<Label>(size[0] * size[1] * size[2], BackgroundLabel) };
}

/** Whether `label` is pinched in the block of 2 x 2 x 2 voxels with lowest corner (i, j, k): on one of its faces it
 * holds exactly one diagonal, or it holds exactly two opposite corners of the block, or all but two. */
bool
IsPinchedInBlock(const Grid & grid, std::size_t i, std::size_t j, std::size_t k, Label label)
{
  const auto has = [&](std::size_t di, std::size_t dj, std::size_t dk) {
    return grid.At(i + di, j + dj, k + dk) == label;
  };
  // Faces: fix one axis at 0 or 1, the other two run around the square.
  for (int axis = 0; axis < 3; ++axis)
  {
    for (std::size_t side = 0; side < 2; ++side)
    {
      const auto corner = [&](std::size_t u, std::size_t v) {
        std::array<std::size_t, 3> d{};
        d[axis] = side;
        d[(axis + 1) % 3] = u;
        d[(axis + 2) % 3] = v;
        return has(d[0], d[1], d[2]);
      };
      const bool c00 = corner(0, 0);
      const bool c11 = corner(1, 1);
      const bool c10 = corner(1, 0);
      const bool c01 = corner(0, 1);
      if ((c00 && c11 && !c10 && !c01) || (!c00 && !c11 && c10 && c01))
      {
        return true;
      }
    }
  }
  int count = 0;
  for (std::size_t dk = 0; dk < 2; ++dk)
  {
    for (std::size_t dj = 0; dj < 2; ++dj)
    {
      for (std::size_t di = 0; di < 2; ++di)
      {
        count += has(di, dj, dk) ? 1 : 0;
      }
    }
  }
  for (std::size_t di = 0; di < 2; ++di)
  {
    for (std::size_t dj = 0; dj < 2; ++dj)
    {
      // Corner (di, dj, 0) and its opposite (1 - di, 1 - dj, 1).
      const bool here = has(di, dj, 0);
      const bool opposite = has(1 - di, 1 - dj, 1);
      if ((count == 2 && here && opposite) || (count == 6 && !here && !opposite))
      {
        return true;
      }
    }
  }
  return false;
}

std::size_t
CountPinches(const Grid & grid)
{
  std::size_t pinches = 0;
  for (std::size_t k = 0; k + 1 < grid.size[2]; ++k)
  {
    for (std::size_t j = 0; j + 1 < grid.size[1]; ++j)
    {
      for (std::size_t i = 0; i + 1 < grid.size[0]; ++i)
      {
        std::set<Label> labels;
        for (std::size_t corner = 0; corner < 8; ++corner)
        {
          labels.insert(grid.At(i + (corner & 1), j + ((corner >> 1) & 1), k + ((corner >> 2) & 1)));
        }
        for (const Label label : labels)
        {
          pinches += IsPinchedInBlock(grid, i, j, k, label) ? 1 : 0;
        }
      }
    }
  }
  return pinches;
}

TEST(RemoveVoxelPinches, AnEdgeContactGetsOneJoiningVoxel)
{
  Grid grid = EmptyGrid({ { 4, 4, 3 } });
  grid.At(1, 1, 1) = 3;
  grid.At(2, 2, 1) = 3;
  ASSERT_EQ(CountPinches(grid), 4u); // The label and the background, in the two blocks around the edge.
  EXPECT_EQ(RemoveVoxelPinches(grid.labels.data(), grid.size), 1u);
  EXPECT_EQ(CountPinches(grid), 0u);
  // Both candidates have one face neighbour of label 3: the tie goes to the lower corner of the block.
  EXPECT_EQ(grid.At(2, 1, 1), 3);
  EXPECT_EQ(grid.At(1, 2, 1), BackgroundLabel);
}

/** The same edge contact at every place along a long row, alone in uniform labels: the pass skips uniform blocks
 * several at a time along a row, and must stop at the contact wherever it is in such a run, at either of the run's
 * ends or after the last whole run. */
TEST(RemoveVoxelPinches, AnEdgeContactAnywhereAlongALongRowIsFound)
{
  const std::size_t length = 52;
  for (std::size_t x = 1; x + 2 < length; ++x)
  {
    for (const bool lowerFirst : { true, false })
    {
      Grid grid = EmptyGrid({ { length, 4, 3 } });
      grid.At(x, lowerFirst ? 1 : 2, 1) = 3;
      grid.At(x + 1, lowerFirst ? 2 : 1, 1) = 3;
      ASSERT_EQ(CountPinches(grid), 4u) << "x " << x;
      EXPECT_EQ(RemoveVoxelPinches(grid.labels.data(), grid.size), 1u) << "x " << x;
      EXPECT_EQ(CountPinches(grid), 0u) << "x " << x;
    }
  }
}

TEST(RemoveVoxelPinches, ACornerContactIsJoinedByAFaceConnectedPath)
{
  Grid grid = EmptyGrid({ { 4, 4, 4 } });
  grid.At(1, 1, 1) = 2;
  grid.At(2, 2, 2) = 2;
  ASSERT_GT(CountPinches(grid), 0u);
  EXPECT_EQ(RemoveVoxelPinches(grid.labels.data(), grid.size), 2u);
  EXPECT_EQ(CountPinches(grid), 0u);
}

TEST(RemoveVoxelPinches, TwoTissuesAcrossAnEdgeAreSettledByTheLargerOne)
{
  // Tissue 1 (three voxels) and tissue 2 (two voxels) alternate around the edge at x = 2, y = 2 (a checkerboard);
  // the larger tissue joins across it.
  Grid grid = EmptyGrid({ { 5, 5, 3 } });
  grid.At(1, 1, 1) = 1;
  grid.At(2, 2, 1) = 1;
  grid.At(3, 2, 1) = 1;
  grid.At(2, 1, 1) = 2;
  grid.At(1, 2, 1) = 2;
  EXPECT_GT(RemoveVoxelPinches(grid.labels.data(), grid.size), 0u);
  EXPECT_EQ(CountPinches(grid), 0u);
  EXPECT_EQ(grid.At(1, 1, 1), 1);
  EXPECT_EQ(grid.At(2, 2, 1), 1);
}

TEST(RemoveVoxelPinches, TwoTissuesOfOneSizeAcrossAnEdgeAreSettledByTheLargerLabel)
{
  // Tissues 1 and 2, two voxels each, alternate around the edge at x = 2, y = 2: of two tissues of one size the
  // smaller label gives way (ties by value), whichever comes first in the buffer, so the result is the same whatever
  // the labels' order in the image.
  Grid grid = EmptyGrid({ { 4, 4, 3 } });
  grid.At(1, 1, 1) = 1;
  grid.At(2, 2, 1) = 1;
  grid.At(2, 1, 1) = 2;
  grid.At(1, 2, 1) = 2;
  EXPECT_GT(RemoveVoxelPinches(grid.labels.data(), grid.size), 0u);
  EXPECT_EQ(CountPinches(grid), 0u);
  EXPECT_EQ(grid.At(2, 1, 1), 2);
  EXPECT_EQ(grid.At(1, 2, 1), 2);
  EXPECT_EQ(grid.At(1, 1, 1), 2) << "the smaller label gives way";
}

TEST(RemoveVoxelPinches, ADiagonalStaircaseBecomesFaceConnected)
{
  Grid grid = EmptyGrid({ { 9, 9, 3 } });
  for (std::size_t step = 1; step <= 7; ++step)
  {
    grid.At(step, step, 1) = 1;
  }
  EXPECT_EQ(RemoveVoxelPinches(grid.labels.data(), grid.size), 6u);
  EXPECT_EQ(CountPinches(grid), 0u);
}

/** A ball of tissue 2 (radius 5 mm) cut into a larger one of tissue 1 (radius 7 mm, centres 8 mm apart), both in
 * the background, on voxels of 1 x 1.25 x 1.5 mm (the command-line tests' image): their digital interface has
 * pinches. Mending them changes a few voxels on either side; a remover that always settles a tissue/tissue pinch
 * against the smaller tissue peels it off. */
TEST(RemoveVoxelPinches, TwoTissuesAlongACurvedInterfaceKeepTheirVolumes)
{
  Grid                        grid = EmptyGrid({ { 30, 26, 20 } });
  const std::array<double, 3> spacing{ { 1.0, 1.25, 1.5 } };
  const std::array<double, 3> large{ { 14.5, 12.5 * 1.25 - 3.0, 9.5 * 1.5 } };
  const std::array<double, 3> small{ { 14.5, 12.5 * 1.25 + 5.0, 9.5 * 1.5 } };
  const auto                  inside =
    [&spacing](const std::array<double, 3> & centre, double radius, std::size_t i, std::size_t j, std::size_t k) {
      const double x = static_cast<double>(i) * spacing[0] - centre[0];
      const double y = static_cast<double>(j) * spacing[1] - centre[1];
      const double z = static_cast<double>(k) * spacing[2] - centre[2];
      return x * x + y * y + z * z <= radius * radius;
    };
  std::map<Label, std::size_t> before;
  for (std::size_t k = 1; k + 1 < grid.size[2]; ++k)
  {
    for (std::size_t j = 1; j + 1 < grid.size[1]; ++j)
    {
      for (std::size_t i = 1; i + 1 < grid.size[0]; ++i)
      {
        grid.At(i, j, k) = inside(small, 5.0, i, j, k) ? 2 : inside(large, 7.0, i, j, k) ? 1 : BackgroundLabel;
        ++before[grid.At(i, j, k)];
      }
    }
  }
  const std::size_t pinchesBefore = CountPinches(grid);
  ASSERT_GT(pinchesBefore, 10u);
  const std::vector<Label> original = grid.labels;
  EXPECT_GT(RemoveVoxelPinches(grid.labels.data(), grid.size), 0u);
  EXPECT_EQ(CountPinches(grid), 0u);
  std::map<Label, std::size_t> after;
  std::size_t                  tissue2Lost = 0;
  for (std::size_t v = 0; v < original.size(); ++v)
  {
    ++after[grid.labels[v]];
    tissue2Lost += original[v] == 2 && grid.labels[v] != 2 ? 1 : 0;
  }
  // The interface has 16 pinched blocks: a remover biased against the smaller tissue takes 1.4 % of it here (and
  // more where the interface is longer); one that mends on both sides takes less than 1 % of either.
  const double tissue2 = static_cast<double>(before[2]);
  EXPECT_LT(static_cast<double>(tissue2Lost), 0.01 * tissue2) << "of " << before[2] << " voxels of tissue 2";
  EXPECT_NEAR(static_cast<double>(after[2]), tissue2, 0.02 * tissue2);
  EXPECT_NEAR(static_cast<double>(after[1]), static_cast<double>(before[1]), 0.02 * static_cast<double>(before[1]));
}

/** xorshift64: the same numbers on every platform, unlike the standard distributions. */
class XorShift
{
public:
  explicit XorShift(uint64_t seed)
    : m_State(seed)
  {}

  uint64_t
  operator()()
  {
    m_State ^= m_State << 13;
    m_State ^= m_State >> 7;
    m_State ^= m_State << 17;
    return m_State;
  }

private:
  uint64_t m_State;
};

/** Inside the grid's background border, each voxel is a tissue (1 to `tissues`) with probability density / 10. */
void
FillWithSpeckle(Grid & grid, uint64_t density, uint64_t tissues, XorShift & next)
{
  for (std::size_t k = 1; k + 1 < grid.size[2]; ++k)
  {
    for (std::size_t j = 1; j + 1 < grid.size[1]; ++j)
    {
      for (std::size_t i = 1; i + 1 < grid.size[0]; ++i)
      {
        grid.At(i, j, k) = next() % 10 < density ? static_cast<Label>(1 + next() % tissues) : BackgroundLabel;
      }
    }
  }
}

/** Random speckle of up to four tissues: every pinch of every label goes, no tissue voxel becomes background (so
 * with one tissue only background voxels change), and no label appears that was not there; the result is
 * deterministic and a second pass changes nothing. */
TEST(RemoveVoxelPinches, RandomSpeckle)
{
  XorShift    next(20261124);
  std::size_t totalChanged = 0;
  std::size_t tissueToTissue = 0;
  for (int gridNumber = 0; gridNumber < 80; ++gridNumber)
  {
    // A border of background, as the function asks (the oracle's label image has one); one voxel inside it at
    // least, up to twelve, and up to forty along x: the pass skips uniform blocks sixteen at a time along a row,
    // and a pinch may be anywhere in such a run or after the last whole one.
    Grid           grid = EmptyGrid({ { 3 + next() % 40, 3 + next() % 12, 3 + next() % 12 } });
    const uint64_t density = 1 + next() % 8;
    const uint64_t tissues = 1 + next() % 4;
    FillWithSpeckle(grid, density, tissues, next);
    const std::vector<Label> before = grid.labels;
    const std::set<Label>    present(before.begin(), before.end());
    const std::size_t        changedCount = RemoveVoxelPinches(grid.labels.data(), grid.size);
    totalChanged += changedCount;
    EXPECT_EQ(CountPinches(grid), 0u) << "grid " << gridNumber;
    std::size_t changed = 0;
    for (std::size_t v = 0; v < before.size(); ++v)
    {
      if (grid.labels[v] == before[v])
      {
        continue;
      }
      ++changed;
      ASSERT_EQ(present.count(grid.labels[v]), 1u) << "grid " << gridNumber << ": a label that was not there";
      EXPECT_TRUE(before[v] == BackgroundLabel || grid.labels[v] != BackgroundLabel)
        << "grid " << gridNumber << ", voxel " << v << ": a tissue voxel became background";
      if (tissues == 1)
      {
        EXPECT_EQ(before[v], BackgroundLabel) << "grid " << gridNumber << ", voxel " << v;
      }
      tissueToTissue += before[v] != BackgroundLabel ? 1 : 0;
    }
    EXPECT_EQ(changed, changedCount) << "grid " << gridNumber;
    for (std::size_t k = 0; k < grid.size[2]; ++k)
    {
      for (std::size_t j = 0; j < grid.size[1]; ++j)
      {
        for (std::size_t i = 0; i < grid.size[0]; ++i)
        {
          const bool border =
            i == 0 || j == 0 || k == 0 || i + 1 == grid.size[0] || j + 1 == grid.size[1] || k + 1 == grid.size[2];
          EXPECT_TRUE(!border || grid.At(i, j, k) == BackgroundLabel) << "grid " << gridNumber << ": border changed";
        }
      }
    }
    Grid again{ grid.size, before };
    RemoveVoxelPinches(again.labels.data(), again.size);
    EXPECT_EQ(again.labels, grid.labels) << "grid " << gridNumber;
    EXPECT_EQ(RemoveVoxelPinches(grid.labels.data(), grid.size), 0u) << "grid " << gridNumber;
  }
  // The grids are made to have pinches between tissues too: a remover that does nothing, or only joins tissues
  // over the background, fails here.
  EXPECT_GT(totalChanged, 200u);
  EXPECT_GT(tissueToTissue, 20u);
}

/** The pinches are searched on threads, each its own layers of blocks, and mended in one pass after: the labels and
 * the changes reported are the same for any number of threads. The grids are deep enough along z for each thread
 * to get layers (eight at least). */
TEST(RemoveVoxelPinches, ThreadsDoNotChangeTheResult)
{
  XorShift    next(20261128);
  std::size_t totalChanged = 0;
  for (int gridNumber = 0; gridNumber < 24; ++gridNumber)
  {
    Grid           grid = EmptyGrid({ { 3 + next() % 30, 3 + next() % 10, 17 + next() % 50 } });
    const uint64_t tissues = 1 + next() % 4;
    FillWithSpeckle(grid, 1 + next() % 8, tissues, next);
    Grid                     sequential = grid;
    std::vector<VoxelChange> sequentialChanges;
    totalChanged += RemoveVoxelPinches(sequential.labels.data(), sequential.size, &sequentialChanges, 1);
    for (const unsigned int threads : { 2u, 3u, 8u })
    {
      Grid                     threaded = grid;
      std::vector<VoxelChange> threadedChanges;
      EXPECT_EQ(RemoveVoxelPinches(threaded.labels.data(), threaded.size, &threadedChanges, threads),
                sequentialChanges.size())
        << "grid " << gridNumber << ", " << threads << " threads";
      EXPECT_EQ(threaded.labels, sequential.labels) << "grid " << gridNumber << ", " << threads << " threads";
      ASSERT_EQ(threadedChanges.size(), sequentialChanges.size()) << "grid " << gridNumber;
      for (std::size_t change = 0; change < sequentialChanges.size(); ++change)
      {
        EXPECT_EQ(threadedChanges[change].offset, sequentialChanges[change].offset) << "grid " << gridNumber;
        EXPECT_EQ(threadedChanges[change].before, sequentialChanges[change].before) << "grid " << gridNumber;
      }
    }
  }
  EXPECT_GT(totalChanged, 500u);
}

/** The label image is stored in one or two bytes a voxel where its labels fit (ImageLabelSelection): the pinch
 * removal changes the same voxels, and reports the same changes, as with four. Tissue 4 is label 255, the largest a
 * byte holds. */
TEST(RemoveVoxelPinches, EveryStorageOfTheLabelsGivesTheSameResult)
{
  XorShift    next(20261201);
  std::size_t totalChanged = 0;
  for (int gridNumber = 0; gridNumber < 24; ++gridNumber)
  {
    Grid grid = EmptyGrid({ { 3 + next() % 30, 3 + next() % 10, 3 + next() % 20 } });
    FillWithSpeckle(grid, 1 + next() % 8, 1 + next() % 4, next);
    std::replace(grid.labels.begin(), grid.labels.end(), Label{ 4 }, Label{ 255 });
    Grid                     wide = grid;
    std::vector<VoxelChange> wideChanges;
    totalChanged += RemoveVoxelPinches(wide.labels.data(), wide.size, &wideChanges, 2);
    const auto expectTheSame = [&](auto narrow, const char * name) {
      std::vector<VoxelChange> changes;
      EXPECT_EQ(RemoveVoxelPinches(narrow.data(), grid.size, &changes, 2), wideChanges.size())
        << "grid " << gridNumber << ", " << name;
      EXPECT_EQ(std::vector<Label>(narrow.begin(), narrow.end()), wide.labels) << "grid " << gridNumber << ", " << name;
      ASSERT_EQ(changes.size(), wideChanges.size()) << "grid " << gridNumber << ", " << name;
      for (std::size_t change = 0; change < changes.size(); ++change)
      {
        EXPECT_EQ(changes[change].offset, wideChanges[change].offset) << "grid " << gridNumber << ", " << name;
        EXPECT_EQ(changes[change].before, wideChanges[change].before) << "grid " << gridNumber << ", " << name;
      }
    };
    expectTheSame(std::vector<uint8_t>(grid.labels.begin(), grid.labels.end()), "uint8_t");
    expectTheSame(std::vector<uint16_t>(grid.labels.begin(), grid.labels.end()), "uint16_t");
  }
  EXPECT_GT(totalChanged, 200u);
}

/** After labels without pinches change in a few boxes, RemoveVoxelPinchesAround, which looks only near the
 * changes, ends where the whole-grid pass ends, leaves no pinch, and reports each change with the label it undoes. */
TEST(RemoveVoxelPinches, AroundChangesEndsAsTheWholeGridPass)
{
  XorShift    next(20261126);
  std::size_t pinchesMade = 0;
  for (int gridNumber = 0; gridNumber < 60; ++gridNumber)
  {
    Grid           grid = EmptyGrid({ { 6 + next() % 12, 6 + next() % 12, 6 + next() % 12 } });
    const uint64_t tissues = 1 + next() % 4;
    FillWithSpeckle(grid, 5, tissues, next);
    RemoveVoxelPinches(grid.labels.data(), grid.size);
    ASSERT_EQ(CountPinches(grid), 0u) << "grid " << gridNumber;
    // A few boxes of one to three voxels a side take one label, inside the background border.
    std::vector<std::size_t> changed;
    for (int box = 0; box < 3; ++box)
    {
      const Label                label = static_cast<Label>(next() % (tissues + 1));
      std::array<std::size_t, 3> lower{};
      std::array<std::size_t, 3> extent{};
      for (int axis = 0; axis < 3; ++axis)
      {
        extent[axis] = 1 + next() % 3;
        lower[axis] = 1 + next() % (grid.size[axis] - 1 - extent[axis]);
      }
      for (std::size_t k = lower[2]; k < lower[2] + extent[2]; ++k)
      {
        for (std::size_t j = lower[1]; j < lower[1] + extent[1]; ++j)
        {
          for (std::size_t i = lower[0]; i < lower[0] + extent[0]; ++i)
          {
            if (grid.At(i, j, k) != label)
            {
              grid.At(i, j, k) = label;
              changed.push_back(i + grid.size[0] * (j + grid.size[1] * k));
            }
          }
        }
      }
    }
    pinchesMade += CountPinches(grid);
    const std::vector<Label> before = grid.labels;
    Grid                     whole = grid;
    RemoveVoxelPinches(whole.labels.data(), whole.size);
    std::vector<VoxelChange> changes;
    const std::size_t        count = RemoveVoxelPinchesAround(grid.labels.data(), grid.size, changed, &changes);
    EXPECT_EQ(CountPinches(grid), 0u) << "grid " << gridNumber;
    EXPECT_EQ(grid.labels, whole.labels) << "grid " << gridNumber;
    ASSERT_EQ(changes.size(), count) << "grid " << gridNumber;
    std::vector<Label> undone = grid.labels;
    for (std::size_t c = 0; c < changes.size(); ++c)
    {
      EXPECT_TRUE(c == 0 || changes[c - 1].offset < changes[c].offset) << "grid " << gridNumber;
      EXPECT_NE(grid.labels[changes[c].offset], changes[c].before) << "grid " << gridNumber;
      undone[changes[c].offset] = changes[c].before;
    }
    EXPECT_EQ(undone, before) << "grid " << gridNumber;
  }
  // The boxes are made to pinch the labels around them: a test where they never do proves nothing.
  EXPECT_GT(pinchesMade, 30u);
}

} // namespace
} // namespace delaunay_refinement
