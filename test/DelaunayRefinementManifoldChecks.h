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
#ifndef DelaunayRefinementManifoldChecks_h
#define DelaunayRefinementManifoldChecks_h

// Issue #14's per-tissue manifold check, computed from the produced mesh without the library's topology code (neither
// the refinement's link tests nor the quality report's SurfaceTopology): a tissue's boundary is its triangles against
// any other label, the union's (keyed by the background label) those against the background; it is a closed
// 2-manifold when every edge is in exactly two of its triangles and every vertex's link (the edges opposite the
// vertex in its triangles) is one cycle.

#include "DelaunayRefinementTypes.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace delaunay_refinement
{

struct NonManifoldCount
{
  std::size_t edges{ 0 };
  std::size_t vertices{ 0 };

  bool
  None() const
  {
    return edges == 0 && vertices == 0;
  }
};

/** Whether the boundary triangle with side labels `sides` belongs to `label`'s boundary (BackgroundLabel: the
 * union's, whose triangles have the background on one side). */
inline bool
IsOnBoundaryOf(const std::array<Label, 2> & sides, Label label)
{
  if (label == BackgroundLabel)
  {
    return (sides[0] == BackgroundLabel) != (sides[1] == BackgroundLabel);
  }
  return sides[0] != sides[1] && (sides[0] == label || sides[1] == label);
}

/** Whether the edges, each a pair of vertex indices, make one cycle: every end in exactly two edges, and a walk
 * along them from the first edge visits them all before it comes back. */
inline bool
IsOneCycle(const std::vector<std::pair<uint32_t, uint32_t>> & edges)
{
  std::map<uint32_t, std::vector<std::size_t>> edgesAt;
  for (std::size_t index = 0; index < edges.size(); ++index)
  {
    edgesAt[edges[index].first].push_back(index);
    edgesAt[edges[index].second].push_back(index);
  }
  for (const auto & entry : edgesAt)
  {
    if (entry.second.size() != 2)
    {
      return false;
    }
  }
  std::size_t walked = 1;
  std::size_t through = 0;
  uint32_t    at = edges[0].second;
  while (at != edges[0].first)
  {
    const std::vector<std::size_t> & here = edgesAt.at(at);
    through = here[0] == through ? here[1] : here[0];
    at = edges[through].first == at ? edges[through].second : edges[through].first;
    ++walked;
  }
  return walked == edges.size();
}

/** The edges and vertices where `label`'s boundary in the mesh's boundary triangles (`triangles`, with their side
 * labels `sides`) is not a manifold. */
inline NonManifoldCount
CountNonManifoldPlaces(const std::vector<std::array<uint32_t, 3>> & triangles,
                       const std::vector<std::array<Label, 2>> & sides, Label label)
{
  std::map<std::pair<uint32_t, uint32_t>, int>                   trianglesPerEdge;
  std::map<uint32_t, std::vector<std::pair<uint32_t, uint32_t>>> link;
  for (std::size_t t = 0; t < triangles.size(); ++t)
  {
    if (!IsOnBoundaryOf(sides[t], label))
    {
      continue;
    }
    const std::array<uint32_t, 3> & triangle = triangles[t];
    for (int corner = 0; corner < 3; ++corner)
    {
      const uint32_t a = triangle[corner];
      const uint32_t b = triangle[(corner + 1) % 3];
      const uint32_t opposite = triangle[(corner + 2) % 3];
      ++trianglesPerEdge[{ std::min(a, b), std::max(a, b) }];
      link[opposite].emplace_back(a, b);
    }
  }
  NonManifoldCount places;
  for (const auto & entry : trianglesPerEdge)
  {
    places.edges += entry.second != 2 ? 1 : 0;
  }
  for (const auto & entry : link)
  {
    places.vertices += IsOneCycle(entry.second) ? 0 : 1;
  }
  return places;
}

} // namespace delaunay_refinement

#endif
