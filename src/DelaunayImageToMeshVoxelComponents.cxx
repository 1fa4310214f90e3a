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
#include "DelaunayImageToMeshVoxelComponents.h"

#include <array>
#include <vector>

namespace delaunay_refinement
{

std::map<Label, std::size_t>
CountVoxelComponents(const LabelVolume & volume, const std::vector<Label> & labels)
{
  std::map<Label, std::size_t> counts;
  for (const Label label : labels)
  {
    counts[label] = 0;
  }
  if (counts.empty())
  {
    return counts;
  }
  // The volume as the mesh sees it: one layer of background around it, so that the background's parts that reach
  // the border are one component.
  const std::array<std::size_t, 3> padded{ { volume.size[0] + 2, volume.size[1] + 2, volume.size[2] + 2 } };
  const std::array<std::size_t, 3> strides{ { 1, padded[0], padded[0] * padded[1] } };
  const auto                       labelAt = [&](std::size_t i, std::size_t j, std::size_t k) {
    if (i == 0 || j == 0 || k == 0 || i + 1 == padded[0] || j + 1 == padded[1] || k + 1 == padded[2])
    {
      return BackgroundLabel;
    }
    return volume.Labels()[(i - 1) + volume.size[0] * ((j - 1) + volume.size[1] * (k - 1))];
  };
  std::vector<bool>                       visited(padded[0] * padded[1] * padded[2], false);
  std::vector<std::array<std::size_t, 3>> front;
  // Runs of one label are long along x: whether a label is counted is looked up once per run.
  Label         runLabel = labelAt(0, 0, 0);
  std::size_t * runCount = nullptr;
  if (const auto found = counts.find(runLabel); found != counts.end())
  {
    runCount = &found->second;
  }
  for (std::size_t k = 0; k < padded[2]; ++k)
  {
    for (std::size_t j = 0; j < padded[1]; ++j)
    {
      for (std::size_t i = 0; i < padded[0]; ++i)
      {
        const std::size_t offset = i * strides[0] + j * strides[1] + k * strides[2];
        if (visited[offset])
        {
          continue;
        }
        const Label label = labelAt(i, j, k);
        if (label != runLabel)
        {
          runLabel = label;
          const auto found = counts.find(label);
          runCount = found == counts.end() ? nullptr : &found->second;
        }
        if (runCount == nullptr)
        {
          continue;
        }
        // A new component: flood it through face neighbours.
        ++*runCount;
        visited[offset] = true;
        front.assign(1, { { i, j, k } });
        while (!front.empty())
        {
          const std::array<std::size_t, 3> voxel = front.back();
          front.pop_back();
          for (int axis = 0; axis < 3; ++axis)
          {
            for (const int step : { -1, 1 })
            {
              std::array<std::size_t, 3> neighbor = voxel;
              if ((step < 0 && neighbor[axis] == 0) || (step > 0 && neighbor[axis] + 1 == padded[axis]))
              {
                continue;
              }
              neighbor[axis] = step < 0 ? neighbor[axis] - 1 : neighbor[axis] + 1;
              const std::size_t neighborOffset =
                neighbor[0] * strides[0] + neighbor[1] * strides[1] + neighbor[2] * strides[2];
              if (!visited[neighborOffset] && labelAt(neighbor[0], neighbor[1], neighbor[2]) == label)
              {
                visited[neighborOffset] = true;
                front.push_back(neighbor);
              }
            }
          }
        }
      }
    }
  }
  return counts;
}

std::size_t
CountVoxelComponents(const LabelVolume & volume, Label label)
{
  return CountVoxelComponents(volume, std::vector<Label>{ label }).at(label);
}

} // namespace delaunay_refinement
