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
#ifndef DelaunayRefinementTestHooks_h
#define DelaunayRefinementTestHooks_h

#include "DelaunayRefinementMesher.h"

namespace delaunay_refinement
{
namespace detail
{

/** What only tests change in the refinement, to reach a step that no input known today needs but that must not go
 * untested all the same (bench/README.md, "At 8ebe0bf": what the suite never ran). RefineMesh() runs with the
 * defaults written here. */
struct RefinementTestHooks
{
  /** R1 counts a feature vertex up to δ (1 + this) away as within δ (DelaunayRefinementRules.h). 0 lets R1 put in
   * surface samples of a voxel lattice exactly δ apart again, and with them flat squares, some of which only the last
   * resort for flat tetrahedra removes: in a 24³ crop of the atlas phantom at δ = 0.70710678 mm, a hair below h/√2,
   * the edge removal takes 364 out and leaves 3 (docs/algorithm.md, "Flat tetrahedra inside a tissue"). */
  double r1TieMargin{ LatticeTieMargin };
};

/** RefineMesh() with `hooks` instead of the defaults, and without a progress observer. */
DelaunayImageToMesh_EXPORT TetrahedralMesh
RefineMeshWithTestHooks(const RefinementTestHooks & hooks, const LabelOracle & oracle,
                        const RefinementParameters & parameters, RefinementStatistics * statistics,
                        TopologyRegularizer * regularizer, const LabelPartCensus * census);

} // namespace detail
} // namespace delaunay_refinement

#endif
