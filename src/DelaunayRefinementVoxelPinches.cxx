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
#include "DelaunayRefinementVoxelPinches.h"

#include "DelaunayRefinementParallel.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <deque>
#include <limits>
#include <optional>
#include <set>
#include <unordered_map>
#include <utility>
#include <vector>

namespace delaunay_refinement
{
namespace
{

/** Voxel i of a 2 x 2 x 2 cube sits at (i & 1, (i >> 1) & 1, (i >> 2) & 1) from its lowest corner; a label's
 * presence in the cube is an 8-bit mask. */
using CubeMask = unsigned int;

/** Whether a set of voxels (bit set) and its complement in the cube can meet there other than along a 2-manifold:
 * on one of the cube's six faces the set holds exactly one diagonal, or it holds exactly two opposite corners of the
 * cube, or all but two opposite corners. These are the critical configurations of a well-composed binary image
 * (Latecki 1997); a set without them has a voxel surface that is a 2-manifold. */
class CriticalConfigurations
{
public:
  CriticalConfigurations()
  {
    constexpr std::array<std::array<int, 4>, 6> faces{ { { { 0, 1, 3, 2 } },
                                                         { { 4, 5, 7, 6 } },
                                                         { { 0, 1, 5, 4 } },
                                                         { { 2, 3, 7, 6 } },
                                                         { { 0, 2, 6, 4 } },
                                                         { { 1, 3, 7, 5 } } } };
    for (CubeMask mask = 0; mask < 256; ++mask)
    {
      bool critical = false;
      for (const auto & face : faces)
      {
        // Around the face's cycle: set, unset, set, unset (either way round) is one diagonal.
        const bool b0 = (mask >> face[0]) & 1;
        const bool b1 = (mask >> face[1]) & 1;
        const bool b2 = (mask >> face[2]) & 1;
        const bool b3 = (mask >> face[3]) & 1;
        critical = critical || (b0 == b2 && b1 == b3 && b0 != b1);
      }
      for (int corner = 0; corner < 4; ++corner)
      {
        const CubeMask opposite = (1u << corner) | (1u << (7 - corner));
        critical = critical || mask == opposite || mask == (255u & ~opposite);
      }
      m_Critical[mask] = critical;
    }
  }

  bool
  operator()(CubeMask mask) const
  {
    return m_Critical[mask];
  }

private:
  std::array<bool, 256> m_Critical{};
};

template <typename TVoxelLabel>
class VoxelPinchRemover
{
public:
  VoxelPinchRemover(TVoxelLabel * labels, const std::array<std::size_t, 3> & size, unsigned int numberOfThreads)
    : m_Labels(labels)
    , m_Size(size)
    , m_Strides{ { 1, size[0], size[0] * size[1] } }
    , m_NumberOfThreads(std::max(1u, numberOfThreads))
  {
    for (int corner = 0; corner < 8; ++corner)
    {
      m_CornerOffsets[corner] =
        (corner & 1) * m_Strides[0] + ((corner >> 1) & 1) * m_Strides[1] + ((corner >> 2) & 1) * m_Strides[2];
    }
    RankLabels();
    m_HasChanged.assign(size[0] * size[1] * size[2], false);
    m_LoweredOnce.assign(size[0] * size[1] * size[2], false);
  }

  /** Looks at every block of the grid, in order. Only a block with a pinch can change anything, and a block has one
   * when the scan reaches it only if it had one at the start or a voxel of it changed since: the scan visits those,
   * found first on several threads (the labels are only read then), and in the same order, so the result is that
   * of looking at every block. */
  void
  Run()
  {
    if (m_Size[0] < 2 || m_Size[1] < 2 || m_Size[2] < 2)
    {
      return;
    }
    const std::vector<std::size_t> pinched = PinchedBlocks();
    auto                           nextPinched = pinched.begin();
    while (nextPinched != pinched.end() || !m_ChangedAhead.empty())
    {
      const std::size_t block = std::min(nextPinched != pinched.end() ? *nextPinched : NoBlock,
                                         !m_ChangedAhead.empty() ? *m_ChangedAhead.begin() : NoBlock);
      m_ScanPosition = block;
      nextPinched = std::upper_bound(nextPinched, pinched.end(), block);
      m_ChangedAhead.erase(m_ChangedAhead.begin(), m_ChangedAhead.upper_bound(block));
      m_Pending.push_back(block);
      ProcessPending();
    }
    m_ScanPosition = NoBlock;
  }

  /** Looks at the blocks holding the given voxels, in the order Run() would. In labels where no other block holds
   * a pinch the removal can mend, this is what Run() does: a block changes only when a voxel in it changes, and then
   * it is looked at again. */
  void
  RunAround(const std::vector<std::size_t> & changedVoxels)
  {
    if (m_Size[0] < 2 || m_Size[1] < 2 || m_Size[2] < 2)
    {
      return;
    }
    std::vector<std::size_t> blocks;
    for (const std::size_t voxel : changedVoxels)
    {
      ForEachCubeHolding(voxel, [&blocks](std::size_t cube, int) { blocks.push_back(cube); });
    }
    std::sort(blocks.begin(), blocks.end());
    blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
    for (const std::size_t block : blocks)
    {
      m_Pending.push_back(block);
      ProcessPending();
    }
  }

  /** How many voxels have a label that differs from the one they had (a voxel may change more than once, and end
   * where it began); `changes`, when given, receives them in increasing order, with the label they had. */
  std::size_t
  ReportChanges(std::vector<VoxelChange> * changes) const
  {
    std::vector<VoxelChange> differing;
    for (const VoxelChange & original : m_Originals)
    {
      if (m_Labels[original.offset] != original.before)
      {
        differing.push_back(original);
      }
    }
    const std::size_t count = differing.size();
    if (changes)
    {
      std::sort(differing.begin(), differing.end(), [](const VoxelChange & a, const VoxelChange & b) {
        return a.offset < b.offset;
      });
      *changes = std::move(differing);
    }
    return count;
  }

private:
  /** Labels in the order in which they give way: the background first, then the tissues from the fewest voxels to
   * the most (ties by value). A voxel's rank goes down at most once; every other change raises it, so the process
   * ends. */
  void
  RankLabels()
  {
    // Labels come in long runs: count a run at a time rather than hash every voxel, each thread its own layers.
    const std::size_t                                   layerSize = m_Strides[2];
    std::vector<std::unordered_map<Label, std::size_t>> countsByLayer(m_Size[2]);
    detail::ForEachRangeInParallel(
      m_Size[2], m_NumberOfThreads, MinimumLayersPerThread, [&](std::size_t firstLayer, std::size_t endLayer) {
        std::unordered_map<Label, std::size_t> & counts = countsByLayer[firstLayer];
        const std::size_t                        end = endLayer * layerSize;
        for (std::size_t offset = firstLayer * layerSize; offset < end;)
        {
          const Label       label = m_Labels[offset];
          const std::size_t runStart = offset;
          while (offset < end && m_Labels[offset] == label)
          {
            ++offset;
          }
          counts[label] += offset - runStart;
        }
      });
    std::unordered_map<Label, std::size_t> counts;
    for (const auto & layerCounts : countsByLayer)
    {
      for (const auto & [label, count] : layerCounts)
      {
        counts[label] += count;
      }
    }
    std::vector<std::pair<Label, std::size_t>> ordered(counts.begin(), counts.end());
    std::sort(ordered.begin(), ordered.end(), [](const auto & a, const auto & b) {
      const bool aBackground = a.first == BackgroundLabel;
      const bool bBackground = b.first == BackgroundLabel;
      if (aBackground != bBackground)
      {
        return aBackground;
      }
      return a.second != b.second ? a.second < b.second : a.first < b.first;
    });
    for (std::size_t rank = 0; rank < ordered.size(); ++rank)
    {
      m_Rank[ordered[rank].first] = rank;
    }
  }

  std::size_t
  RankOf(Label label) const
  {
    return m_Rank.at(label);
  }

  std::array<std::size_t, 3>
  CoordinatesOf(std::size_t offset) const
  {
    return { { offset % m_Size[0], (offset / m_Size[0]) % m_Size[1], offset / m_Strides[2] } };
  }

  /** A change to be made in a cube: voxel `offset` takes `label`; `support` is how many of its face neighbours
   * already carry that label. */
  struct Change
  {
    std::size_t offset;
    Label       label;
    int         support;
  };

  void
  ProcessPending()
  {
    while (!m_Pending.empty())
    {
      const std::size_t cube = m_Pending.front();
      m_Pending.pop_front();
      CheckCube(cube);
    }
  }

  /** How many blocks FirstNonUniformBlock() looks at together: their 2 x 2 x (BlocksAtOnce + 1) voxels are compared
   * without a branch, which the compiler vectorises, and a pass over uniform labels skips them all at once (the
   * pass over the grid was a fifth of the set-up's regularisation and pinch removal on the brain mask resampled to
   * 1 mm). */
  static constexpr std::size_t BlocksAtOnce = 16;

  /** The first block of the row of blocks starting at `rowStart`, from the `first`-th on, that is not uniform, by
   * its place in the row; m_Size[0] - 1 (past the row's last block) when there is none. */
  std::size_t
  FirstNonUniformBlock(std::size_t rowStart, std::size_t first) const
  {
    const std::size_t                        blocks = m_Size[0] - 1;
    const TVoxelLabel *                      row = m_Labels + rowStart;
    const std::array<const TVoxelLabel *, 4> rows{
      row, row + m_Strides[1], row + m_Strides[2], row + m_Strides[1] + m_Strides[2]
    };
    std::size_t i = first;
    for (; i + BlocksAtOnce <= blocks; i += BlocksAtOnce)
    {
      const TVoxelLabel label = rows[0][i];
      uint32_t          differs = 0;
      for (const TVoxelLabel * line : rows)
      {
        for (std::size_t voxel = i; voxel <= i + BlocksAtOnce; ++voxel)
        {
          differs |= static_cast<uint32_t>(line[voxel] ^ label);
        }
      }
      if (differs != 0)
      {
        break;
      }
    }
    // The block is in the chunk the loop above stopped at, or in the row's last, shorter chunk.
    for (; i < blocks; ++i)
    {
      if (!IsUniform(rowStart + i))
      {
        return i;
      }
    }
    return blocks;
  }

  bool
  IsUniform(std::size_t cube) const
  {
    const Label first = m_Labels[cube];
    for (int corner = 1; corner < 8; ++corner)
    {
      if (m_Labels[cube + m_CornerOffsets[corner]] != first)
      {
        return false;
      }
    }
    return true;
  }

  /** The blocks that hold a pinch in the labels as they are, in increasing order; each thread looks at its own
   * layers of blocks. */
  std::vector<std::size_t>
  PinchedBlocks() const
  {
    const std::size_t                     layers = m_Size[2] - 1;
    std::vector<std::vector<std::size_t>> byLayer(layers);
    detail::ForEachRangeInParallel(
      layers, m_NumberOfThreads, MinimumLayersPerThread, [&](std::size_t firstLayer, std::size_t endLayer) {
        for (std::size_t k = firstLayer; k < endLayer; ++k)
        {
          for (std::size_t j = 0; j + 1 < m_Size[1]; ++j)
          {
            const std::size_t rowStart = m_Strides[1] * j + m_Strides[2] * k;
            // Most blocks hold one label: a pinch needs two.
            for (std::size_t i = FirstNonUniformBlock(rowStart, 0); i + 1 < m_Size[0];
                 i = FirstNonUniformBlock(rowStart, i + 1))
            {
              if (IsPinched(rowStart + i))
              {
                byLayer[k].push_back(rowStart + i);
              }
            }
          }
        }
      });
    std::vector<std::size_t> pinched;
    for (const std::vector<std::size_t> & layer : byLayer)
    {
      pinched.insert(pinched.end(), layer.begin(), layer.end());
    }
    return pinched;
  }

  /** Whether some label of the block holds a critical configuration there. */
  bool
  IsPinched(std::size_t cube) const
  {
    return ForEachPinchedLabel(LabelsOf(cube), [](Label, CubeMask) { return true; });
  }

  /** Mends the block's first pinch, in the order of its labels' first corners, that a change can mend. */
  void
  CheckCube(std::size_t cube)
  {
    if (IsUniform(cube))
    {
      return;
    }
    const std::array<Label, 8> labels = LabelsOf(cube);
    ForEachPinchedLabel(labels, [&](Label label, CubeMask mask) {
      const std::optional<Change> change = BestChange(cube, labels, label, mask);
      if (change)
      {
        Apply(*change);
      }
      return change.has_value();
    });
  }

  std::array<Label, 8>
  LabelsOf(std::size_t cube) const
  {
    std::array<Label, 8> labels;
    for (int corner = 0; corner < 8; ++corner)
    {
      labels[corner] = m_Labels[cube + m_CornerOffsets[corner]];
    }
    return labels;
  }

  /** Calls `f(label, mask)` for each label of a block (its eight `labels`) that holds a critical configuration
   * there, `mask` its voxels in the block, in the order of the labels' first corners, until `f` returns true;
   * returns whether it did. */
  template <typename TFunction>
  bool
  ForEachPinchedLabel(const std::array<Label, 8> & labels, TFunction && f) const
  {
    for (int corner = 0; corner < 8; ++corner)
    {
      const Label label = labels[corner];
      if (std::find(labels.begin(), labels.begin() + corner, label) != labels.begin() + corner)
      {
        continue;
      }
      CubeMask mask = 0;
      for (int other = 0; other < 8; ++other)
      {
        mask |= static_cast<CubeMask>(labels[other] == label) << other;
      }
      if (m_IsCritical(mask) && f(label, mask))
      {
        return true;
      }
    }
    return false;
  }

  /** The pinched label either takes one of the block's voxels from another label (it joins there) or gives one of
   * its voxels to another label of the block (it is cut there). A change that raises the voxel's rank is always
   * allowed; one that lowers it only when it removes more pinches around the voxel than it makes, and only once per
   * voxel, so that the process ends. Of the allowed changes: first those after which the label is no longer pinched
   * in the block, then the fewest pinches around the voxel after the change, then the voxel with the most face
   * neighbours of its new label, then raising the rank, joining before cutting, then the lower corner. Voxels on
   * the grid's border never change. None when no change is allowed. */
  std::optional<Change>
  BestChange(std::size_t cube, const std::array<Label, 8> & labels, Label pinched, CubeMask mask) const
  {
    std::optional<Change> best;
    std::array<int, 5>    bestScore{};
    const auto            consider = [&](const Change & change, Label from, bool joins, CubeMask maskAfter) {
      const int  pinchesMade = PinchesMadeBy(change.offset, from, change.label);
      const bool raisesRank = RankOf(change.label) > RankOf(from);
      if (!raisesRank && (change.label == BackgroundLabel || pinchesMade >= 0 || m_LoweredOnce[change.offset]))
      {
        return;
      }
      const std::array<int, 5> score{
        { m_IsCritical(maskAfter) ? 0 : 1, -pinchesMade, change.support, raisesRank ? 1 : 0, joins ? 1 : 0 }
      };
      if (!best || score > bestScore)
      {
        best = change;
        bestScore = score;
      }
    };
    for (int corner = 0; corner < 8; ++corner)
    {
      const std::size_t offset = cube + m_CornerOffsets[corner];
      if (IsOnBorder(offset))
      {
        continue;
      }
      if (labels[corner] != pinched)
      {
        consider({ offset, pinched, FaceNeighboursWith(offset, pinched) }, labels[corner], true, mask | (1u << corner));
        continue;
      }
      // Each other label of the block once (a label met again would give the same change).
      for (int other = 0; other < 8; ++other)
      {
        const Label label = labels[other];
        if (label != pinched && std::find(labels.begin(), labels.begin() + other, label) == labels.begin() + other)
        {
          consider({ offset, label, FaceNeighboursWith(offset, label) }, pinched, false, mask & ~(1u << corner));
        }
      }
    }
    return best;
  }

  /** How many more pinched (label, block) pairs the blocks around `offset` hold after it changes from `from` to
   * `to` than before: only those two labels' presence changes there. */
  int
  PinchesMadeBy(std::size_t offset, Label from, Label to) const
  {
    int made = 0;
    ForEachCubeHolding(offset, [&](std::size_t cube, int corner) {
      CubeMask fromMask = 0;
      CubeMask toMask = 0;
      for (int other = 0; other < 8; ++other)
      {
        const Label label = m_Labels[cube + m_CornerOffsets[other]];
        fromMask |= static_cast<CubeMask>(label == from) << other;
        toMask |= static_cast<CubeMask>(label == to) << other;
      }
      const CubeMask bit = 1u << corner;
      made +=
        m_IsCritical(fromMask & ~bit) + m_IsCritical(toMask | bit) - m_IsCritical(fromMask) - m_IsCritical(toMask);
    });
    return made;
  }

  /** Calls f(cube, corner) for each block of 2 x 2 x 2 voxels inside the grid that holds the voxel, `corner` being
   * the voxel's place in it: a change of the voxel can make or unmake a critical configuration in those only. */
  template <typename TFunction>
  void
  ForEachCubeHolding(std::size_t offset, TFunction && f) const
  {
    const std::array<std::size_t, 3> coordinates = CoordinatesOf(offset);
    for (int corner = 0; corner < 8; ++corner)
    {
      std::size_t cube = offset;
      bool        inside = true;
      for (int axis = 0; axis < 3; ++axis)
      {
        const std::size_t step = (corner >> axis) & 1;
        inside = inside && step <= coordinates[axis] && coordinates[axis] - step + 1 < m_Size[axis];
        cube -= step * m_Strides[axis];
      }
      if (inside)
      {
        f(cube, corner);
      }
    }
  }

  bool
  IsOnBorder(std::size_t offset) const
  {
    const std::array<std::size_t, 3> coordinates = CoordinatesOf(offset);
    for (int axis = 0; axis < 3; ++axis)
    {
      if (coordinates[axis] == 0 || coordinates[axis] + 1 == m_Size[axis])
      {
        return true;
      }
    }
    return false;
  }

  void
  Apply(const Change & change)
  {
    if (RankOf(change.label) < RankOf(m_Labels[change.offset]))
    {
      m_LoweredOnce[change.offset] = true;
    }
    if (!m_HasChanged[change.offset])
    {
      m_HasChanged[change.offset] = true;
      m_Originals.push_back({ change.offset, m_Labels[change.offset] });
    }
    m_Labels[change.offset] = static_cast<TVoxelLabel>(change.label);
    ForEachCubeHolding(change.offset, [this](std::size_t cube, int) {
      m_Pending.push_back(cube);
      if (cube > m_ScanPosition)
      {
        m_ChangedAhead.insert(cube);
      }
    });
  }

  int
  FaceNeighboursWith(std::size_t offset, Label label) const
  {
    const std::array<std::size_t, 3> coordinates = CoordinatesOf(offset);
    int                              count = 0;
    for (int axis = 0; axis < 3; ++axis)
    {
      count += coordinates[axis] > 0 && m_Labels[offset - m_Strides[axis]] == label;
      count += coordinates[axis] + 1 < m_Size[axis] && m_Labels[offset + m_Strides[axis]] == label;
    }
    return count;
  }

  TVoxelLabel *                          m_Labels;
  const std::array<std::size_t, 3>       m_Size;
  const std::array<std::size_t, 3>       m_Strides;
  const unsigned int                     m_NumberOfThreads;
  std::array<std::size_t, 8>             m_CornerOffsets{};
  std::unordered_map<Label, std::size_t> m_Rank;
  const CriticalConfigurations           m_IsCritical;
  std::vector<bool>                      m_HasChanged;
  std::vector<bool>                      m_LoweredOnce;
  std::deque<std::size_t>                m_Pending;
  std::vector<VoxelChange>               m_Originals;
  /** The fewest layers along z a thread counts labels or looks for pinches in: fewer cost more to start than they
   * save. */
  static constexpr std::size_t MinimumLayersPerThread = 8;
  /** No block: the scan is not running (RunAround), or has no block left. */
  static constexpr std::size_t NoBlock = std::numeric_limits<std::size_t>::max();
  /** The block Run()'s scan is at, and the blocks past it that hold a voxel changed since the scan began. */
  std::size_t           m_ScanPosition{ NoBlock };
  std::set<std::size_t> m_ChangedAhead;
};

} // namespace

template <typename TVoxelLabel>
std::size_t
RemoveVoxelPinches(TVoxelLabel * labels, const std::array<std::size_t, 3> & size, std::vector<VoxelChange> * changes,
                   unsigned int numberOfThreads)
{
  static_assert(IsVoxelLabelType<TVoxelLabel>, "labels are stored as Label, uint16_t or uint8_t");
  VoxelPinchRemover<TVoxelLabel> remover(labels, size, numberOfThreads);
  remover.Run();
  return remover.ReportChanges(changes);
}

template <typename TVoxelLabel>
std::size_t
RemoveVoxelPinchesAround(TVoxelLabel * labels, const std::array<std::size_t, 3> & size,
                         const std::vector<std::size_t> & changedVoxels, std::vector<VoxelChange> * changes)
{
  VoxelPinchRemover<TVoxelLabel> remover(labels, size, 1);
  remover.RunAround(changedVoxels);
  return remover.ReportChanges(changes);
}

DelaunayRefinement_InstantiateVoxelPinches(, Label);
DelaunayRefinement_InstantiateVoxelPinches(, uint16_t);
DelaunayRefinement_InstantiateVoxelPinches(, uint8_t);

} // namespace delaunay_refinement
