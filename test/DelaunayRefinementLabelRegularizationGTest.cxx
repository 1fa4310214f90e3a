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

// RegularizeLabels against its definition, computed by brute force on small random grids: a voxel survives its
// label's erosion when every voxel of another label (the grid's outside is background) is farther than
// r + h/2, survives the dilation when a survivor of the erosion of its own label is within r + h/2, or within r + h
// and no face neighbour of its label is lost (neither a survivor nor within r + h of one), and every voxel
// that did not survive takes the label of a nearest surviving voxel of the grid. The grids are wider than a
// machine word along x and anisotropic, and their labels touch the grid's faces.

#include "DelaunayRefinementLabelRegularization.h"
#include "DelaunayRefinementMesher.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace delaunay_refinement
{
namespace
{

using Size = std::array<std::size_t, 3>;

struct Grid
{
  Size               size;
  Vector3            spacing;
  std::vector<Label> labels;

  Label
  At(long i, long j, long k) const
  {
    if (i < 0 || j < 0 || k < 0 || i >= static_cast<long>(size[0]) || j >= static_cast<long>(size[1]) ||
        k >= static_cast<long>(size[2]))
    {
      return BackgroundLabel;
    }
    return labels[static_cast<std::size_t>(i) +
                  size[0] * (static_cast<std::size_t>(j) + size[1] * static_cast<std::size_t>(k))];
  }

  double
  SquaredDistance(long di, long dj, long dk) const
  {
    const double x = static_cast<double>(di) * spacing[0];
    const double y = static_cast<double>(dj) * spacing[1];
    const double z = static_cast<double>(dk) * spacing[2];
    return x * x + y * y + z * z;
  }
};

/** Blobs of a few labels, speckle and thin sheets, some touching the grid's faces. */
Grid
RandomGrid(std::mt19937 & random, const Size & size, const Vector3 & spacing)
{
  Grid grid{ size, spacing, std::vector<Label>(size[0] * size[1] * size[2], BackgroundLabel) };
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto                             set = [&](long i, long j, long k, Label label) {
    if (i >= 0 && j >= 0 && k >= 0 && i < static_cast<long>(size[0]) && j < static_cast<long>(size[1]) &&
        k < static_cast<long>(size[2]))
    {
      grid.labels[static_cast<std::size_t>(i) +
                  size[0] * (static_cast<std::size_t>(j) + size[1] * static_cast<std::size_t>(k))] = label;
    }
  };
  for (int blob = 0; blob < 12; ++blob)
  {
    const Label  label = 1 + static_cast<Label>(random() % 3);
    const double ci = unit(random) * static_cast<double>(size[0]);
    const double cj = unit(random) * static_cast<double>(size[1]);
    const double ck = unit(random) * static_cast<double>(size[2]);
    const double radius = 0.5 + 3.0 * unit(random);
    for (long k = 0; k < static_cast<long>(size[2]); ++k)
    {
      for (long j = 0; j < static_cast<long>(size[1]); ++j)
      {
        for (long i = 0; i < static_cast<long>(size[0]); ++i)
        {
          const double x = (i - ci) * spacing[0];
          const double y = (j - cj) * spacing[1];
          const double z = (k - ck) * spacing[2];
          if (x * x + y * y + z * z <= radius * radius)
          {
            set(i, j, k, label);
          }
        }
      }
    }
  }
  // A one-voxel sheet and speckle of every label, the background included.
  const long sheet = static_cast<long>(random() % size[0]);
  for (long k = 0; k < static_cast<long>(size[2]); ++k)
  {
    for (long j = 0; j < static_cast<long>(size[1]); ++j)
    {
      set(sheet, j, k, 2);
    }
  }
  for (int speck = 0; speck < 40; ++speck)
  {
    set(static_cast<long>(random() % size[0]),
        static_cast<long>(random() % size[1]),
        static_cast<long>(random() % size[2]),
        static_cast<Label>(random() % 4));
  }
  return grid;
}

/** The labels each voxel may take by the definition: its own where it survives, else those of its nearest
 * survivors (its own too when no voxel survives). */
std::vector<std::set<Label>>
AllowedLabels(const Grid & grid, double radius)
{
  const double        hmin = std::min({ grid.spacing[0], grid.spacing[1], grid.spacing[2] });
  const double        reach = (radius + 0.5 * hmin) * (1.0 + LatticeTieMargin);
  const double        dilationReach = (radius + hmin) * (1.0 + LatticeTieMargin);
  std::array<long, 3> window{};
  std::array<long, 3> padding{};
  for (int axis = 0; axis < 3; ++axis)
  {
    window[axis] = static_cast<long>(std::ceil(dilationReach / grid.spacing[axis])) + 1;
    padding[axis] = 2 * window[axis];
  }
  // Whether each voxel of the grid with its padding survives its label's erosion.
  const auto inPadded = [&](long i, long j, long k) {
    return i >= -padding[0] && j >= -padding[1] && k >= -padding[2] &&
           i < static_cast<long>(grid.size[0]) + padding[0] && j < static_cast<long>(grid.size[1]) + padding[1] &&
           k < static_cast<long>(grid.size[2]) + padding[2];
  };
  const auto paddedIndex = [&](long i, long j, long k) {
    const long width = static_cast<long>(grid.size[0]) + 2 * padding[0];
    const long height = static_cast<long>(grid.size[1]) + 2 * padding[1];
    return static_cast<std::size_t>((i + padding[0]) + width * ((j + padding[1]) + height * (k + padding[2])));
  };
  const std::size_t paddedVoxels = static_cast<std::size_t>(
    (grid.size[0] + 2 * padding[0]) * (grid.size[1] + 2 * padding[1]) * (grid.size[2] + 2 * padding[2]));
  std::vector<bool> keptByErosion(paddedVoxels, true);
  for (long k = -padding[2]; k < static_cast<long>(grid.size[2]) + padding[2]; ++k)
  {
    for (long j = -padding[1]; j < static_cast<long>(grid.size[1]) + padding[1]; ++j)
    {
      for (long i = -padding[0]; i < static_cast<long>(grid.size[0]) + padding[0]; ++i)
      {
        const Label label = grid.At(i, j, k);
        for (long dk = -window[2]; dk <= window[2]; ++dk)
        {
          for (long dj = -window[1]; dj <= window[1]; ++dj)
          {
            for (long di = -window[0]; di <= window[0]; ++di)
            {
              if (grid.At(i + di, j + dj, k + dk) != label && grid.SquaredDistance(di, dj, dk) <= reach * reach)
              {
                keptByErosion[paddedIndex(i, j, k)] = false;
              }
            }
          }
        }
      }
    }
  }
  // Whether a survivor of the erosion of the voxel's own label is within `distance` of it.
  const auto nearASurvivor = [&](long i, long j, long k, double distance) {
    const Label label = grid.At(i, j, k);
    for (long dk = -window[2]; dk <= window[2]; ++dk)
    {
      for (long dj = -window[1]; dj <= window[1]; ++dj)
      {
        for (long di = -window[0]; di <= window[0]; ++di)
        {
          if (inPadded(i + di, j + dj, k + dk) && grid.At(i + di, j + dj, k + dk) == label &&
              keptByErosion[paddedIndex(i + di, j + dj, k + dk)] &&
              grid.SquaredDistance(di, dj, dk) <= distance * distance)
          {
            return true;
          }
        }
      }
    }
    return false;
  };
  // Lost by the plain opening: neither a survivor nor within the dilation's reach of one.
  const auto lostByTheOpening = [&](long i, long j, long k) {
    return !keptByErosion[paddedIndex(i, j, k)] && !nearASurvivor(i, j, k, dilationReach);
  };
  const auto survives = [&](long i, long j, long k) {
    if (keptByErosion[paddedIndex(i, j, k)] || nearASurvivor(i, j, k, reach))
    {
      return true;
    }
    if (!nearASurvivor(i, j, k, dilationReach))
    {
      return false;
    }
    // Given back by the dilation's last half voxel only: not beside a voxel of its label that the opening loses.
    const Label label = grid.At(i, j, k);
    for (const auto & [di, dj, dk] :
         { std::array<long, 3>{ -1, 0, 0 }, { 1, 0, 0 }, { 0, -1, 0 }, { 0, 1, 0 }, { 0, 0, -1 }, { 0, 0, 1 } })
    {
      if (grid.At(i + di, j + dj, k + dk) == label && lostByTheOpening(i + di, j + dj, k + dk))
      {
        return false;
      }
    }
    return true;
  };
  std::vector<std::array<long, 3>> survivors;
  std::vector<std::array<long, 3>> removed;
  for (long k = 0; k < static_cast<long>(grid.size[2]); ++k)
  {
    for (long j = 0; j < static_cast<long>(grid.size[1]); ++j)
    {
      for (long i = 0; i < static_cast<long>(grid.size[0]); ++i)
      {
        (survives(i, j, k) ? survivors : removed).push_back({ { i, j, k } });
      }
    }
  }
  std::vector<std::set<Label>> allowed(grid.labels.size());
  for (std::size_t voxel = 0; voxel < grid.labels.size(); ++voxel)
  {
    allowed[voxel].insert(grid.labels[voxel]);
  }
  for (int axis = 0; axis < 3; ++axis)
  {
    if (reach >= static_cast<double>(grid.size[axis]) * grid.spacing[axis])
    {
      // No tissue survives (every voxel is within the reach of the outside along that axis): all background.
      for (std::set<Label> & labels : allowed)
      {
        labels = { BackgroundLabel };
      }
      return allowed;
    }
  }
  for (const auto & voxel : removed)
  {
    const std::size_t index =
      static_cast<std::size_t>(voxel[0]) +
      grid.size[0] * (static_cast<std::size_t>(voxel[1]) + grid.size[1] * static_cast<std::size_t>(voxel[2]));
    if (survivors.empty())
    {
      continue;
    }
    allowed[index].clear();
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto & survivor : survivors)
    {
      const double distance =
        grid.SquaredDistance(survivor[0] - voxel[0], survivor[1] - voxel[1], survivor[2] - voxel[2]);
      if (distance < nearest)
      {
        nearest = distance;
        allowed[index].clear();
      }
      if (distance == nearest)
      {
        allowed[index].insert(grid.At(survivor[0], survivor[1], survivor[2]));
      }
    }
  }
  return allowed;
}

/** Face-connected components of each label by flood fill, independent of the library's run-based count: for each
 * label, the number of its components, and how many of them have no voxel whose label `after` keeps. */
struct ComponentCount
{
  std::size_t components{ 0 };
  std::size_t lostWhole{ 0 };
};

std::map<Label, ComponentCount>
CountComponentsByFloodFill(const Grid & grid, const std::vector<Label> & after)
{
  std::map<Label, ComponentCount>  counts;
  std::vector<bool>                seen(grid.labels.size(), false);
  std::vector<std::array<long, 3>> stack;
  const auto                       offsetOf = [&grid](long i, long j, long k) {
    return static_cast<std::size_t>(i) +
           grid.size[0] * (static_cast<std::size_t>(j) + grid.size[1] * static_cast<std::size_t>(k));
  };
  for (long k = 0; k < static_cast<long>(grid.size[2]); ++k)
  {
    for (long j = 0; j < static_cast<long>(grid.size[1]); ++j)
    {
      for (long i = 0; i < static_cast<long>(grid.size[0]); ++i)
      {
        if (seen[offsetOf(i, j, k)])
        {
          continue;
        }
        const Label label = grid.At(i, j, k);
        bool        keepsAVoxel = false;
        seen[offsetOf(i, j, k)] = true;
        stack.push_back({ { i, j, k } });
        while (!stack.empty())
        {
          const std::array<long, 3> voxel = stack.back();
          stack.pop_back();
          keepsAVoxel = keepsAVoxel || after[offsetOf(voxel[0], voxel[1], voxel[2])] == label;
          for (int axis = 0; axis < 3; ++axis)
          {
            for (const long step : { -1L, 1L })
            {
              std::array<long, 3> next = voxel;
              next[axis] += step;
              if (next[axis] < 0 || next[axis] >= static_cast<long>(grid.size[axis]) ||
                  seen[offsetOf(next[0], next[1], next[2])] || grid.At(next[0], next[1], next[2]) != label)
              {
                continue;
              }
              seen[offsetOf(next[0], next[1], next[2])] = true;
              stack.push_back(next);
            }
          }
        }
        ++counts[label].components;
        counts[label].lostWhole += keepsAVoxel ? 0 : 1;
      }
    }
  }
  return counts;
}

/** Every label's counts of components in the report, against flood fills of the labels before and after. */
void
ExpectComponentsAsCounted(const LabelRegularizationReport & report, const Grid & before,
                          const std::vector<Label> & after, const std::string & where)
{
  const std::map<Label, ComponentCount> counted = CountComponentsByFloodFill(before, after);
  const Grid                            regularised{ before.size, before.spacing, after };
  const std::map<Label, ComponentCount> countedAfter = CountComponentsByFloodFill(regularised, after);
  for (const LabelRegularizationChange & change : report.labels)
  {
    const auto found = counted.find(change.label);
    const auto foundAfter = countedAfter.find(change.label);
    EXPECT_EQ(change.componentsBefore, found == counted.end() ? 0 : found->second.components)
      << where << ", label " << change.label;
    EXPECT_EQ(change.componentsRemoved, found == counted.end() ? 0 : found->second.lostWhole)
      << where << ", label " << change.label;
    EXPECT_EQ(change.componentsAfter, foundAfter == countedAfter.end() ? 0 : foundAfter->second.components)
      << where << ", label " << change.label;
  }
  // Every label of the grid before is in the report.
  for (const auto & [label, count] : counted)
  {
    EXPECT_TRUE(std::any_of(report.labels.begin(),
                            report.labels.end(),
                            [label = label](const auto & change) { return change.label == label; }))
      << where << ", label " << label;
  }
}

struct RegularizationCase
{
  Size    size;
  Vector3 spacing;
};

class LabelRegularizationAgainstDefinition : public ::testing::TestWithParam<RegularizationCase>
{};

TEST_P(LabelRegularizationAgainstDefinition, EveryVoxelTakesTheLabelTheDefinitionAllows)
{
  const RegularizationCase parameters = GetParam();
  std::mt19937             random(20261124);
  const double             hmin = std::min({ parameters.spacing[0], parameters.spacing[1], parameters.spacing[2] });
  std::size_t              changedInAll = 0;
  for (int trial = 0; trial < 3; ++trial)
  {
    const Grid grid = RandomGrid(random, parameters.size, parameters.spacing);
    for (const double radius : { 0.4 * hmin, 1.0 * hmin, 1.7 * hmin, 2.6 * hmin })
    {
      std::vector<Label>                 labels = grid.labels;
      const LabelRegularizationReport    report = RegularizeLabels(labels.data(), grid.size, grid.spacing, radius);
      const std::vector<std::set<Label>> allowed = AllowedLabels(grid, radius);
      std::size_t                        changed = 0;
      std::size_t                        wrong = 0;
      std::ostringstream                 firstWrong;
      for (std::size_t voxel = 0; voxel < labels.size(); ++voxel)
      {
        changed += labels[voxel] != grid.labels[voxel] ? 1 : 0;
        if (allowed[voxel].count(labels[voxel]) == 0)
        {
          if (wrong++ == 0)
          {
            firstWrong << "voxel " << voxel << " was " << grid.labels[voxel] << ", became " << labels[voxel];
          }
        }
      }
      EXPECT_EQ(wrong, 0U) << "trial " << trial << ", radius " << radius << ": " << firstWrong.str();
      EXPECT_EQ(report.changedVoxels, changed) << "trial " << trial << ", radius " << radius;
      std::size_t removedInReport = 0;
      std::size_t addedInReport = 0;
      for (const LabelRegularizationChange & change : report.labels)
      {
        removedInReport += change.voxelsRemoved;
        addedInReport += change.voxelsAdded;
        const std::size_t after = static_cast<std::size_t>(std::count(labels.begin(), labels.end(), change.label));
        EXPECT_EQ(change.voxelsAfter, after) << "label " << change.label;
        EXPECT_EQ(change.voxelsBefore + change.voxelsAdded - change.voxelsRemoved, after) << "label " << change.label;
      }
      EXPECT_EQ(removedInReport, changed);
      EXPECT_EQ(addedInReport, changed);
      ExpectComponentsAsCounted(
        report, grid, labels, "trial " + std::to_string(trial) + ", radius " + std::to_string(radius));
      changedInAll += changed;
    }
  }
  // The grids are made to have parts thinner than the radii: a regularisation that changes nothing fails here.
  EXPECT_GT(changedInAll, 0U);
}

INSTANTIATE_TEST_SUITE_P(Grids, LabelRegularizationAgainstDefinition,
                         ::testing::Values(RegularizationCase{ { { 70, 9, 7 } }, { { 1.0, 1.0, 1.0 } } },
                                           RegularizationCase{ { { 66, 8, 9 } }, { { 0.7, 1.1, 1.9 } } },
                                           RegularizationCase{ { { 129, 6, 5 } }, { { 1.3, 0.9, 0.6 } } },
                                           // Two voxels along z: the larger radii reach past the grid along z
                                           // (no tissue survives), and at 1.7 h the background outside the grid
                                           // is cut at one grid length.
                                           RegularizationCase{ { { 66, 6, 2 } }, { { 0.3, 0.7, 0.25 } } },
                                           RegularizationCase{ { { 67, 7, 2 } }, { { 0.2, 0.7, 0.25 } } }),
                         [](const ::testing::TestParamInfo<RegularizationCase> & info) {
                           return "Grid" + std::to_string(info.param.size[0]) + "x" +
                                  std::to_string(info.param.size[1]) + "x" + std::to_string(info.param.size[2]);
                         });

/** A radius whose reach is a distance of the voxel lattice (users choose round δ, and the lattice's distances are
 * round) gives the same labels as that radius changed in its last bits: which side of the reach a voxel at that
 * distance falls on must not follow the rounding (LatticeTieMargin). Before the margin, the k-means
 * tissues at δ = 5 mm (radius 2 mm, reach 3 mm on voxels of 2 × 3 × 2 mm) gave 57,695 tetrahedra, and 67,339 at
 * δ (1 − 10⁻¹²). */
TEST(LabelRegularization, RadiusesOnTheLatticeFollowTheRadiusNotItsLastBits)
{
  struct TieCase
  {
    Vector3      spacing;
    double       radius;
    const char * tie;
  };
  std::mt19937 random(20261130);
  for (const TieCase & tie :
       { TieCase{ { { 0.4, 0.6, 0.4 } }, 0.4, "erosion reach 0.6 = the y spacing (the k-means tissues' tie, scaled)" },
         TieCase{ { { 1.0, 1.0, 1.0 } }, 1.5, "erosion reach 2 = two voxels" },
         TieCase{ { { 1.0, 1.0, 1.0 } }, 1.0, "dilation reach 2 = two voxels" },
         TieCase{ { { 1.0, 1.0, 1.0 } }, 0.5, "erosion reach 1 = one voxel" } })
  {
    const Grid         grid = RandomGrid(random, { { 60, 9, 8 } }, tie.spacing);
    std::vector<Label> atTheRadius = grid.labels;
    RegularizeLabels(atTheRadius.data(), grid.size, grid.spacing, tie.radius);
    EXPECT_NE(atTheRadius, grid.labels) << tie.tie << ": the grid should have parts thinner than the radius";
    for (const double perturbation : { -1e-12, 1e-12, -1e-9 })
    {
      std::vector<Label> perturbed = grid.labels;
      RegularizeLabels(perturbed.data(), grid.size, grid.spacing, tie.radius * (1.0 + perturbation));
      const auto differing = std::inner_product(perturbed.begin(),
                                                perturbed.end(),
                                                atTheRadius.begin(),
                                                std::size_t{ 0 },
                                                std::plus<>(),
                                                std::not_equal_to<>());
      EXPECT_EQ(differing, 0U) << tie.tie << ": radius " << tie.radius << " x (1 + " << perturbation << ")";
    }
  }
}

TEST(LabelRegularization, ZeroRadiusChangesNothing)
{
  std::mt19937                    random(7);
  const Grid                      grid = RandomGrid(random, { { 40, 6, 6 } }, { { 1.0, 1.0, 1.0 } });
  std::vector<Label>              labels = grid.labels;
  const LabelRegularizationReport report = RegularizeLabels(labels.data(), grid.size, grid.spacing, 0.0);
  EXPECT_EQ(labels, grid.labels);
  EXPECT_EQ(report.changedVoxels, 0U);
}

TEST(LabelRegularization, AbortLeavesTheLabelsAsTheyWere)
{
  std::mt19937       random(11);
  const Grid         grid = RandomGrid(random, { { 40, 6, 6 } }, { { 1.0, 1.0, 1.0 } });
  std::vector<Label> labels = grid.labels;
  EXPECT_THROW(RegularizeLabels(labels.data(), grid.size, grid.spacing, 1.5, [](double) { return false; }),
               RefinementAborted);
  EXPECT_EQ(labels, grid.labels);
}

/** A block of speckle removed whole, whose inner voxels are far from every survivor. The grid is 30 voxels of 1 mm
 * a side, all label 1 but for a block of 20 voxels a side in its middle (voxels 5 to 24 along each axis), where each
 * voxel takes label 2, 3 or 4 at random. At a radius of 1.7 mm the erosion's reach is 2.2 mm: a speckle voxel
 * survives its label's erosion only when all 32 voxels within 2.2 mm of it share its label, which does not happen
 * here (the test checks that every speckle voxel went). Label 1 keeps every voxel: layers 2 of the shell are 3 mm
 * from both the outside and the block, so they survive the erosion, and every other voxel of label 1 is within
 * 2 mm of them, inside the erosion's own reach. So every voxel of the block takes label 1, its only survivor's label.
 * The block's centre is 10 mm from the nearest survivor (layer 4 or 25), farther than the search around each
 * removed voxel reaches (the dilation's reach, 2.7 mm, and two voxels): those voxels' nearest survivors come from
 * the transform over the far voxels' box. A regularisation that left them unassigned would leave speckle in the
 * middle of label 1. */
TEST(LabelRegularization, AThickBlockOfSpeckleTakesTheLabelOfSurvivorsBeyondTheSearch)
{
  const Size         size{ { 30, 30, 30 } };
  const Vector3      spacing{ { 1.0, 1.0, 1.0 } };
  std::vector<Label> labels(size[0] * size[1] * size[2], 1);
  std::mt19937       random(20261203);
  std::size_t        speckle = 0;
  for (std::size_t k = 5; k < 25; ++k)
  {
    for (std::size_t j = 5; j < 25; ++j)
    {
      for (std::size_t i = 5; i < 25; ++i)
      {
        labels[i + size[0] * (j + size[1] * k)] = static_cast<Label>(2 + random() % 3);
        ++speckle;
      }
    }
  }
  ASSERT_EQ(speckle, 8000U);
  const LabelRegularizationReport report = RegularizeLabels(labels.data(), size, spacing, 1.7);
  EXPECT_EQ(static_cast<std::size_t>(std::count(labels.begin(), labels.end(), Label{ 1 })), labels.size())
    << "voxels left with another label than 1";
  EXPECT_EQ(report.changedVoxels, speckle);
  for (const LabelRegularizationChange & change : report.labels)
  {
    if (change.label == 1)
    {
      EXPECT_EQ(change.voxelsAdded, speckle);
      EXPECT_EQ(change.voxelsRemoved, 0U);
      EXPECT_EQ(change.componentsAfter, 1U);
    }
    else
    {
      EXPECT_EQ(change.voxelsAfter, 0U) << "label " << change.label;
      EXPECT_EQ(change.voxelsRemoved, change.voxelsBefore) << "label " << change.label;
      EXPECT_EQ(change.componentsRemoved, change.componentsBefore) << "label " << change.label;
    }
  }
}

/** Speckle of three labels on a grid with a ball of label 1: every label's opening has work to do, and the speckle's
 * voxels take their nearest survivor's label. */
std::vector<Label>
SpeckleAroundABall(const Size & size, uint32_t seed)
{
  std::vector<Label> labels(size[0] * size[1] * size[2], BackgroundLabel);
  std::mt19937       random(seed);
  std::size_t        voxel = 0;
  for (std::size_t k = 0; k < size[2]; ++k)
  {
    for (std::size_t j = 0; j < size[1]; ++j)
    {
      for (std::size_t i = 0; i < size[0]; ++i, ++voxel)
      {
        const double di = static_cast<double>(i) - 0.5 * static_cast<double>(size[0]);
        const double dj = static_cast<double>(j) - 0.5 * static_cast<double>(size[1]);
        const double dk = static_cast<double>(k) - 0.5 * static_cast<double>(size[2]);
        labels[voxel] = di * di + dj * dj + dk * dk < 400.0 ? 1 : static_cast<Label>(random() % 3);
      }
    }
  }
  return labels;
}

// The progress the regularisation reports: a fraction of its work, in [0, 1], never decreasing, moving through its
// steps and within the labels' openings (on a large image one label's opening is a fraction of a second, and the
// command-line bar sat still through all of them when only the end of each step was reported); and an abort asked
// for within the openings stops the run there, the labels as they were.
TEST(LabelRegularization, ReportsItsProgressAndStopsWithinTheOpenings)
{
  const Size          size{ { 60, 56, 52 } };
  const Vector3       spacing{ { 1.0, 0.9, 1.1 } };
  const auto          original = SpeckleAroundABall(size, 20261130);
  std::vector<Label>  labels = original;
  std::vector<double> fractions;
  RegularizeLabels(
    labels.data(),
    size,
    spacing,
    1.5,
    [&fractions](double fraction) {
      fractions.push_back(fraction);
      return true;
    },
    1);
  ASSERT_FALSE(fractions.empty());
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_GE(fractions.front(), 0.0);
  EXPECT_LE(fractions.back(), 1.0);
  std::vector<double> distinct = fractions;
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  // Four labels (the background included), each opening reporting after three of its steps, and the steps around.
  EXPECT_GE(distinct.size(), 12U) << "the regularisation reported " << distinct.size() << " distinct fractions";
  // Within a label's opening: the openings lie between the component count (0.05) and the nearest survivors' step,
  // which begins at 0.85.
  const std::size_t insideOpenings =
    std::count_if(distinct.begin(), distinct.end(), [](double fraction) { return fraction > 0.05 && fraction < 0.85; });
  EXPECT_GE(insideOpenings, 8U);

  std::vector<Label>  aborted = original;
  std::vector<double> untilAbort;
  EXPECT_THROW(RegularizeLabels(
                 aborted.data(),
                 size,
                 spacing,
                 1.5,
                 [&untilAbort](double fraction) {
                   // The first fraction past the component count: whichever thread opens what, the calling thread
                   // reports one within its first opening (an abort at a later fraction would depend on the
                   // threads' timing: the calling thread may have no opening left by then).
                   untilAbort.push_back(fraction);
                   return fraction <= 0.05;
                 },
                 2),
               RefinementAborted);
  EXPECT_EQ(aborted, original);
  ASSERT_FALSE(untilAbort.empty());
  EXPECT_LT(untilAbort.back(), 0.85) << "the abort was seen only after the openings";
}

TEST(LabelRegularization, TheNumberOfThreadsDoesNotChangeTheResult)
{
  // Speckle of every label around two balls, on a grid large enough for several threads: the speckle goes, and
  // the voxels deep in it, far from the balls and from the grid's outside, take the distance transform, whose
  // passes the threads share; the components are counted in slabs of the grid, one per thread, whose faces the
  // speckle's components cross.
  const Size    size{ { 90, 80, 70 } };
  const Vector3 spacing{ { 0.8, 1.0, 1.2 } };
  Grid          grid{ size, spacing, std::vector<Label>(size[0] * size[1] * size[2], BackgroundLabel) };
  std::mt19937  random(20261126);
  for (Label & label : grid.labels)
  {
    label = static_cast<Label>(random() % 4);
  }
  for (long k = 0; k < static_cast<long>(size[2]); ++k)
  {
    for (long j = 0; j < static_cast<long>(size[1]); ++j)
    {
      for (long i = 0; i < static_cast<long>(size[0]); ++i)
      {
        const double first = grid.SquaredDistance(i - 20, j - 40, k - 35);
        const double second = grid.SquaredDistance(i - 70, j - 30, k - 30);
        Label &      label = grid.labels[static_cast<std::size_t>(i) +
                                    size[0] * (static_cast<std::size_t>(j) + size[1] * static_cast<std::size_t>(k))];
        label = first < 12.0 * 12.0 ? 1 : (second < 9.0 * 9.0 ? 2 : label);
      }
    }
  }
  std::vector<Label>              oneThread = grid.labels;
  const LabelRegularizationReport report = RegularizeLabels(oneThread.data(), size, spacing, 1.5, {}, 1);
  // Most of the speckle changes label: the transform had work to do.
  EXPECT_GT(report.changedVoxels, grid.labels.size() / 2);
  ExpectComponentsAsCounted(report, grid, oneThread, "1 thread");
  for (const unsigned int threads : { 2U, 3U, 4U, 8U })
  {
    std::vector<Label>              labels = grid.labels;
    const LabelRegularizationReport threaded = RegularizeLabels(labels.data(), size, spacing, 1.5, {}, threads);
    EXPECT_EQ(labels, oneThread) << threads << " threads";
    EXPECT_EQ(threaded.changedVoxels, report.changedVoxels) << threads << " threads";
    ExpectComponentsAsCounted(threaded, grid, labels, std::to_string(threads) + " threads");
  }
}

// ---- FindUnmarkedParts against its definition, by brute force -------------------------------------------------

/** The parts FindUnmarkedParts must find: face-connected voxels of one non-background label (a flood fill, outside
 * the grid background), those
 * holding no marked voxel, in the order of their first voxel; each with the largest clearance of its voxels up to
 * `limit` (the distance from the voxel's centre to the nearest cube outside the part, the grid's outside included, by
 * a scan of every voxel within reach) and the first voxel that has it. */
std::vector<LabelPart>
UnmarkedPartsByDefinition(const Grid & grid, const std::vector<std::size_t> & marked, double limit)
{
  const std::size_t                     count = grid.labels.size();
  const std::size_t                     none = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t>              partOf(count, none);
  std::vector<std::vector<std::size_t>> voxelsOf;
  const auto                            indexOf = [&](std::size_t voxel) {
    return std::array<long, 3>{ { static_cast<long>(voxel % grid.size[0]),
                                  static_cast<long>(voxel / grid.size[0] % grid.size[1]),
                                  static_cast<long>(voxel / (grid.size[0] * grid.size[1])) } };
  };
  const auto offsetOf = [&](long i, long j, long k) {
    return static_cast<std::size_t>(i) +
           grid.size[0] * (static_cast<std::size_t>(j) + grid.size[1] * static_cast<std::size_t>(k));
  };
  for (std::size_t seed = 0; seed < count; ++seed)
  {
    if (grid.labels[seed] == BackgroundLabel || partOf[seed] != none)
    {
      continue;
    }
    voxelsOf.emplace_back();
    std::vector<std::size_t> stack{ seed };
    partOf[seed] = voxelsOf.size() - 1;
    while (!stack.empty())
    {
      const std::size_t voxel = stack.back();
      stack.pop_back();
      voxelsOf.back().push_back(voxel);
      const std::array<long, 3> index = indexOf(voxel);
      for (int neighbour = 0; neighbour < 6; ++neighbour)
      {
        std::array<long, 3> next = index;
        next[neighbour / 2] += neighbour % 2 ? 1 : -1;
        if (grid.At(next[0], next[1], next[2]) == grid.labels[seed])
        {
          const std::size_t offset = offsetOf(next[0], next[1], next[2]);
          if (partOf[offset] == none)
          {
            partOf[offset] = partOf[seed];
            stack.push_back(offset);
          }
        }
      }
    }
  }
  std::vector<bool> isMarked(voxelsOf.size(), false);
  for (const std::size_t voxel : marked)
  {
    if (partOf[voxel] != none)
    {
      isMarked[partOf[voxel]] = true;
    }
  }
  const auto gap = [](long steps, double spacing) {
    return std::max(0.0, std::abs(static_cast<double>(steps)) - 0.5) * spacing;
  };
  std::vector<LabelPart> parts;
  for (std::size_t part = 0; part < voxelsOf.size(); ++part)
  {
    if (isMarked[part])
    {
      continue;
    }
    std::vector<std::size_t> voxels = voxelsOf[part];
    std::sort(voxels.begin(), voxels.end());
    LabelPart expected{ grid.labels[voxels.front()], voxels.size(), voxels.front(), -1.0 };
    for (const std::size_t voxel : voxels)
    {
      const std::array<long, 3> index = indexOf(voxel);
      double                    clearance = limit;
      // Every cube of the grid and of the layer around it: a cube farther out is farther than the layer's.
      for (long k = -1; k <= static_cast<long>(grid.size[2]); ++k)
      {
        for (long j = -1; j <= static_cast<long>(grid.size[1]); ++j)
        {
          for (long i = -1; i <= static_cast<long>(grid.size[0]); ++i)
          {
            const long di = i - index[0];
            const long dj = j - index[1];
            const long dk = k - index[2];
            const bool inside = i >= 0 && j >= 0 && k >= 0 && i < static_cast<long>(grid.size[0]) &&
                                j < static_cast<long>(grid.size[1]) && k < static_cast<long>(grid.size[2]);
            if (inside && partOf[offsetOf(i, j, k)] == part)
            {
              continue;
            }
            const double x = gap(di, grid.spacing[0]);
            const double y = gap(dj, grid.spacing[1]);
            const double z = gap(dk, grid.spacing[2]);
            clearance = std::min(clearance, std::sqrt(x * x + y * y + z * z));
          }
        }
      }
      if (clearance > expected.radius)
      {
        expected.radius = clearance;
        expected.deepestVoxel = voxel;
      }
    }
    parts.push_back(expected);
  }
  return parts;
}

/** `found` lists the parts `expected` lists, in the same order (both that of the parts' first voxels: the
 * definition's flood fills start there), with the same labels, voxels, largest balls and their centres. */
void
ExpectTheSameParts(const std::vector<LabelPart> & found, const std::vector<LabelPart> & expected)
{
  ASSERT_EQ(found.size(), expected.size());
  for (std::size_t part = 0; part < found.size(); ++part)
  {
    EXPECT_EQ(found[part].label, expected[part].label) << "part " << part;
    EXPECT_EQ(found[part].voxels, expected[part].voxels) << "part " << part;
    EXPECT_NEAR(found[part].radius, expected[part].radius, 1e-12) << "part " << part;
    EXPECT_EQ(found[part].deepestVoxel, expected[part].deepestVoxel) << "part " << part;
  }
}

/** Random blobs, a sheet and speckle of three labels on anisotropic grids; a random tenth of the voxels marked. Every
 * unmarked part must be found, with its label, its voxels, and its largest ball's radius and centre (up to a limit
 * below the largest parts' balls, and one above every ball), whatever the number of threads. */
TEST(UnmarkedParts, AreThePartsTheDefinitionGives)
{
  std::mt19937 random(20261128);
  for (const Vector3 & spacing : { Vector3{ { 1.0, 1.0, 1.0 } }, Vector3{ { 0.7, 1.1, 1.6 } } })
  {
    for (const double limit : { 1.2, 50.0 })
    {
      const Grid               grid = RandomGrid(random, { { 70, 9, 8 } }, spacing);
      std::vector<std::size_t> marked;
      for (std::size_t voxel = 0; voxel < grid.labels.size(); ++voxel)
      {
        if (random() % 10 == 0)
        {
          marked.push_back(voxel);
        }
      }
      std::vector<LabelPart> expected = UnmarkedPartsByDefinition(grid, marked, limit);
      ASSERT_GT(expected.size(), 3U) << "the grid has too few unmarked parts to test";
      for (const unsigned int threads : { 1U, 3U })
      {
        SCOPED_TRACE("spacing " + std::to_string(spacing[2]) + ", limit " + std::to_string(limit) + ", " +
                     std::to_string(threads) + " threads");
        ExpectTheSameParts(FindUnmarkedParts(grid.labels.data(), grid.size, spacing, marked, limit, threads), expected);
      }
    }
  }
}

/** Large parts, whose largest balls are searched from their deepest voxels (thousands of voxels, clearances of many
 * voxels), beside small ones: the same answers as the definition's scan of every voxel, up to a limit inside the
 * largest balls, one between, and one beyond every ball; on grids with anisotropic spacing, for 1 and 2 threads. */
TEST(UnmarkedParts, LargePartsAreMeasuredAsTheDefinitionSays)
{
  const Size size{ { 26, 22, 18 } };
  for (const Vector3 & spacing : { Vector3{ { 1.0, 1.0, 1.0 } }, Vector3{ { 0.7, 1.1, 1.6 } } })
  {
    Grid       grid{ size, spacing, std::vector<Label>(size[0] * size[1] * size[2], BackgroundLabel) };
    const auto inside = [&](long i, long j, long k, const std::array<double, 3> & centre, double radius) {
      const double x = (static_cast<double>(i) - centre[0]) * spacing[0];
      const double y = (static_cast<double>(j) - centre[1]) * spacing[1];
      const double z = (static_cast<double>(k) - centre[2]) * spacing[2];
      return x * x + y * y + z * z <= radius * radius;
    };
    for (long k = 0; k < static_cast<long>(size[2]); ++k)
    {
      for (long j = 0; j < static_cast<long>(size[1]); ++j)
      {
        for (long i = 0; i < static_cast<long>(size[0]); ++i)
        {
          Label label = BackgroundLabel;
          // A large ball of label 1 with a small ball of label 2 and a tunnel of background in it; a second large
          // ball, of label 3, cut by the grid's faces.
          if (inside(i, j, k, { { 10.0, 10.0, 8.0 } }, 9.0))
          {
            label = inside(i, j, k, { { 12.0, 8.0, 8.0 } }, 2.5) ? 2 : (j == 10 && k == 6 ? BackgroundLabel : 1);
          }
          else if (inside(i, j, k, { { 25.0, 21.0, 17.0 } }, 8.0))
          {
            label = 3;
          }
          grid.labels[static_cast<std::size_t>(i) +
                      size[0] * (static_cast<std::size_t>(j) + size[1] * static_cast<std::size_t>(k))] = label;
        }
      }
    }
    for (const double limit : { 1.5, 3.0, 100.0 })
    {
      const std::vector<LabelPart> expected = UnmarkedPartsByDefinition(grid, {}, limit);
      const std::size_t            largest =
        std::max_element(expected.begin(), expected.end(), [](const LabelPart & a, const LabelPart & b) {
          return a.voxels < b.voxels;
        })->voxels;
      ASSERT_GT(largest, 1000U) << "the grid has no large part to test";
      for (const unsigned int threads : { 1U, 2U })
      {
        SCOPED_TRACE("spacing " + std::to_string(spacing[2]) + ", limit " + std::to_string(limit) + ", " +
                     std::to_string(threads) + " threads");
        ExpectTheSameParts(FindUnmarkedParts(grid.labels.data(), size, spacing, {}, limit, threads), expected);
      }
    }
  }
}

/** A part with no voxel marked is listed even when it is the whole of its label; a marked voxel of one part does not
 * count for another part of the same label; a size limit leaves the larger parts out. */
TEST(UnmarkedParts, AMarkCountsForItsOwnPartOnly)
{
  const Size         size{ { 12, 5, 5 } };
  std::vector<Label> labels(size[0] * size[1] * size[2], BackgroundLabel);
  const auto offset = [&](std::size_t i, std::size_t j, std::size_t k) { return i + size[0] * (j + size[1] * k); };
  for (std::size_t k = 1; k < 4; ++k)
  {
    for (std::size_t j = 1; j < 4; ++j)
    {
      labels[offset(1, j, k)] = labels[offset(2, j, k)] = labels[offset(3, j, k)] = 1;
      labels[offset(6, j, k)] = labels[offset(7, j, k)] = labels[offset(8, j, k)] = 1;
      labels[offset(10, j, k)] = 2;
    }
  }
  const std::vector<LabelPart> parts =
    FindUnmarkedParts(labels.data(), size, { { 1.0, 1.0, 1.0 } }, { offset(2, 2, 2) }, 10.0);
  ASSERT_EQ(parts.size(), 2U);
  EXPECT_EQ(parts[0].label, 1);
  EXPECT_EQ(parts[0].voxels, 27U);
  EXPECT_EQ(parts[0].deepestVoxel, offset(7, 2, 2));
  EXPECT_DOUBLE_EQ(parts[0].radius, 1.5);
  EXPECT_EQ(parts[1].label, 2);
  EXPECT_EQ(parts[1].voxels, 9U);
  EXPECT_DOUBLE_EQ(parts[1].radius, 0.5);
  // Asked for the parts of at most 9 voxels, the same labels list the second only, measured the same.
  LabelParts                   labelParts(labels.data(), size, { { 1.0, 1.0, 1.0 } });
  const std::vector<LabelPart> small = labelParts.FindUnmarked({ offset(2, 2, 2) }, 10.0, 9);
  ASSERT_EQ(small.size(), 1U);
  EXPECT_EQ(small[0].label, 2);
  EXPECT_EQ(small[0].deepestVoxel, parts[1].deepestVoxel);
  EXPECT_EQ(labelParts.FindUnmarked({ offset(2, 2, 2) }, 10.0).size(), 2U) << "asked again, all of them";
}

/** The labels stored in a narrower IsVoxelLabelType (every label fits). */
template <typename TVoxelLabel>
std::vector<TVoxelLabel>
StoredAs(const std::vector<Label> & labels)
{
  std::vector<TVoxelLabel> stored(labels.size());
  std::transform(
    labels.begin(), labels.end(), stored.begin(), [](Label label) { return static_cast<TVoxelLabel>(label); });
  return stored;
}

/** The label image is stored in one or two bytes a voxel where its labels fit (ImageLabelSelection): the
 * regularisation, its report and the parts it leaves are the same as with four. The labels are 0, 1, 2 and 200 (a
 * byte holds up to 255), on blobs, sheets and speckle. */
TEST(LabelRegularization, EveryStorageOfTheLabelsGivesTheSameResult)
{
  std::mt19937 random(20261201);
  Grid         grid = RandomGrid(random, { { 40, 30, 25 } }, { { 0.9, 1.0, 1.3 } });
  for (Label & label : grid.labels)
  {
    label = random() % 9 == 0 ? static_cast<Label>(random() % 4) : label;
    label = label == 3 ? 200 : label;
  }
  const auto regularise = [&](auto labels) {
    const LabelRegularizationReport report = RegularizeLabels(labels.data(), grid.size, grid.spacing, 1.4, {}, 2);
    std::vector<Label>              asLabels(labels.begin(), labels.end());
    return std::make_pair(asLabels, report);
  };
  const auto [expected, expectedReport] = regularise(grid.labels);
  ASSERT_GT(expectedReport.changedVoxels, grid.labels.size() / 20) << "the grid has too little to regularise";
  for (const auto & [name, result] : { std::make_pair("uint8_t", regularise(StoredAs<uint8_t>(grid.labels))),
                                       std::make_pair("uint16_t", regularise(StoredAs<uint16_t>(grid.labels))) })
  {
    SCOPED_TRACE(name);
    EXPECT_EQ(result.first, expected);
    EXPECT_EQ(result.second.changedVoxels, expectedReport.changedVoxels);
    ASSERT_EQ(result.second.labels.size(), expectedReport.labels.size());
    for (std::size_t entry = 0; entry < expectedReport.labels.size(); ++entry)
    {
      const LabelRegularizationChange & a = result.second.labels[entry];
      const LabelRegularizationChange & b = expectedReport.labels[entry];
      EXPECT_EQ(std::make_tuple(a.label,
                                a.voxelsBefore,
                                a.voxelsAfter,
                                a.voxelsRemoved,
                                a.voxelsAdded,
                                a.componentsBefore,
                                a.componentsAfter,
                                a.componentsRemoved),
                std::make_tuple(b.label,
                                b.voxelsBefore,
                                b.voxelsAfter,
                                b.voxelsRemoved,
                                b.voxelsAdded,
                                b.componentsBefore,
                                b.componentsAfter,
                                b.componentsRemoved))
        << "label " << b.label;
    }
  }
  std::vector<std::size_t> marked;
  for (std::size_t voxel = 0; voxel < grid.labels.size(); voxel += 7)
  {
    marked.push_back(voxel);
  }
  const std::vector<LabelPart> parts = FindUnmarkedParts(grid.labels.data(), grid.size, grid.spacing, marked, 3.0);
  ASSERT_GT(parts.size(), 3U) << "the grid has too few unmarked parts to test";
  ExpectTheSameParts(FindUnmarkedParts(StoredAs<uint8_t>(grid.labels).data(), grid.size, grid.spacing, marked, 3.0),
                     parts);
  ExpectTheSameParts(FindUnmarkedParts(StoredAs<uint16_t>(grid.labels).data(), grid.size, grid.spacing, marked, 3.0),
                     parts);
}

} // namespace
} // namespace delaunay_refinement
