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

#include <deque>

namespace delaunay_refinement
{
namespace
{

/** The four voxels around an edge along the third axis: the corner with the lowest offset and the two axes of
 * the block's plane. */
struct VoxelBlock
{
  std::size_t corner;
  int         first;
  int         second;
};

class DiagonalVoxelJoiner
{
public:
  DiagonalVoxelJoiner(Label * labels, const std::array<std::size_t, 3> & size)
    : m_Labels(labels)
    , m_Size(size)
    , m_Strides{ { 1, size[0], size[0] * size[1] } }
  {}

  std::size_t
  Run()
  {
    std::size_t offset = 0;
    for (std::size_t k = 0; k < m_Size[2]; ++k)
    {
      for (std::size_t j = 0; j < m_Size[1]; ++j)
      {
        for (std::size_t i = 0; i < m_Size[0]; ++i, ++offset)
        {
          ForEachPlane([&](int first, int second) {
            if (HoldsBlock({ { i, j, k } }, first, second))
            {
              Check({ offset, first, second });
            }
          });
          ProcessPending();
        }
      }
    }
    return m_Changed;
  }

private:
  template <typename TVisit>
  static void
  ForEachPlane(TVisit && visit)
  {
    visit(0, 1);
    visit(0, 2);
    visit(1, 2);
  }

  std::array<std::size_t, 3>
  CoordinatesOf(std::size_t offset) const
  {
    return { { offset % m_Size[0], (offset / m_Size[0]) % m_Size[1], offset / m_Strides[2] } };
  }

  /** Whether all four voxels of the block in plane (first, second) with its lowest corner there are in the grid. */
  bool
  HoldsBlock(const std::array<std::size_t, 3> & lowestCorner, int first, int second) const
  {
    return lowestCorner[first] + 1 < m_Size[first] && lowestCorner[second] + 1 < m_Size[second];
  }

  void
  Check(const VoxelBlock & block)
  {
    const std::size_t lowest = block.corner;
    const std::size_t alongFirst = lowest + m_Strides[block.first];
    const std::size_t alongSecond = lowest + m_Strides[block.second];
    const std::size_t highest = alongFirst + m_Strides[block.second];
    if (!JoinIfPinched(lowest, highest, alongFirst, alongSecond))
    {
      JoinIfPinched(alongFirst, alongSecond, lowest, highest);
    }
  }

  /** Diagonal `a`-`b` of one label, the other diagonal `c`-`d` background: one of c, d takes the label. */
  bool
  JoinIfPinched(std::size_t a, std::size_t b, std::size_t c, std::size_t d)
  {
    const Label label = m_Labels[a];
    if (label == BackgroundLabel || m_Labels[b] != label || m_Labels[c] != BackgroundLabel ||
        m_Labels[d] != BackgroundLabel)
    {
      return false;
    }
    const std::size_t joining = FaceNeighboursWith(d, label) > FaceNeighboursWith(c, label) ? d : c;
    m_Labels[joining] = label;
    ++m_Changed;
    QueueBlocksAround(joining);
    return true;
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

  /** The blocks that hold `offset`: a change there can make or unmake a pinch in them only. */
  void
  QueueBlocksAround(std::size_t offset)
  {
    const std::array<std::size_t, 3> coordinates = CoordinatesOf(offset);
    ForEachPlane([&](int first, int second) {
      for (std::size_t stepFirst = 0; stepFirst < 2 && stepFirst <= coordinates[first]; ++stepFirst)
      {
        for (std::size_t stepSecond = 0; stepSecond < 2 && stepSecond <= coordinates[second]; ++stepSecond)
        {
          std::array<std::size_t, 3> corner = coordinates;
          corner[first] -= stepFirst;
          corner[second] -= stepSecond;
          if (HoldsBlock(corner, first, second))
          {
            m_Pending.push_back(
              { offset - stepFirst * m_Strides[first] - stepSecond * m_Strides[second], first, second });
          }
        }
      }
    });
  }

  void
  ProcessPending()
  {
    while (!m_Pending.empty())
    {
      const VoxelBlock block = m_Pending.front();
      m_Pending.pop_front();
      Check(block);
    }
  }

  Label *                          m_Labels;
  const std::array<std::size_t, 3> m_Size;
  const std::array<std::size_t, 3> m_Strides;
  std::deque<VoxelBlock>           m_Pending;
  std::size_t                      m_Changed{ 0 };
};

} // namespace

std::size_t
JoinDiagonalVoxels(Label * labels, const std::array<std::size_t, 3> & size)
{
  return DiagonalVoxelJoiner(labels, size).Run();
}

} // namespace delaunay_refinement
