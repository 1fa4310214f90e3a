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
#ifndef DelaunayRefinementNonManifoldPlaces_h
#define DelaunayRefinementNonManifoldPlaces_h

// What a search for non-manifold places finds (ManifoldRepair): the repairs that follow it (TopologyRelabel, the
// oracle's regularisation, the halving of δ) read it.

#include "DelaunayRefinementOracle.h"
#include "DelaunayRefinementTriangulation.h"

#include <cstddef>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{

/** Where the boundaries are not 2-manifolds. */
struct NonManifoldPlaces
{
  /** Each offending boundary vertex with each label whose boundary it offends, in insertion order of the
   * vertices, then by label. */
  std::vector<NonManifoldPlace> places;
  /** The offending vertices, each once, in insertion order, and where they are. */
  std::vector<VertexHandle> vertices;
  std::vector<Vector3>      points;
  /** For each offending vertex, the index in `places` of its first place. */
  std::vector<std::size_t> firstPlace;

  /** Adds the place (vertex, label). A vertex's places are added one after the other, by increasing label. */
  void
  Add(VertexHandle vertex, const Vector3 & point, Label label)
  {
    if (vertices.empty() || vertices.back() != vertex)
    {
      vertices.push_back(vertex);
      points.push_back(point);
      firstPlace.push_back(places.size());
    }
    places.push_back({ point, label });
  }

  /** The labels whose boundaries the `index`-th offending vertex offends, in increasing order. */
  std::vector<Label>
  LabelsOf(std::size_t index) const
  {
    const std::size_t  end = index + 1 < firstPlace.size() ? firstPlace[index + 1] : places.size();
    std::vector<Label> labels;
    for (std::size_t place = firstPlace[index]; place < end; ++place)
    {
      labels.push_back(places[place].label);
    }
    return labels;
  }
};

} // namespace detail
} // namespace delaunay_refinement

#endif
