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
#ifndef DelaunayRefinementMesher_h
#define DelaunayRefinementMesher_h

#include "DelaunayRefinementOracle.h"
#include "DelaunayRefinementParameters.h"

#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace delaunay_refinement
{

/** What the refinement did, counted per rule. */
struct RefinementStatistics
{
  std::size_t insertionsR1{ 0 };
  std::size_t insertionsR2{ 0 };
  std::size_t insertionsR3{ 0 };
  std::size_t insertionsR4{ 0 };
  /** Insertions by the R4' variant (minimum dihedral angle); of them, the points on the surface (feature
   * vertices), those that changed a boundary or interface triangle, and those that failed the acceptance test (a
   * free vertex or an angle <= 30° on a boundary, docs/algorithm.md, "R4′ picks its point"). */
  std::size_t insertionsR4Dihedral{ 0 };
  std::size_t sliverSplitsOnSurface{ 0 };
  std::size_t sliverSplitsChangingBoundary{ 0 };
  std::size_t sliverSplitsFailingAcceptance{ 0 };
  /** Slivers, and tetrahedra flat to rounding, removed by moving one of their corners (docs/algorithm.md, "R4′
   * moves a vertex"). */
  std::size_t sliverPerturbations{ 0 };
  /** Slivers R4' left unsplit as caps on the background, for the flat-cap step to peel off. */
  std::size_t sliverCapsLeftToPeel{ 0 };
  /** Of those, the ones the flat-cap step could not peel off (a boundary would have become non-manifold), split
   * after all. */
  std::size_t sliverCapsThatCouldNotBePeeled{ 0 };
  std::size_t insertionsE1{ 0 };
  std::size_t insertionsE2{ 0 };
  std::size_t insertionsE3{ 0 };
  /** Free (and, for E1/E3, non-box-edge box) vertices removed. */
  std::size_t deletedVertices{ 0 };
  /** Queue entries of tetrahedra that no longer existed: skipped when popped, or removed from the queue. */
  std::size_t staleQueueEntries{ 0 };
  /** R2 circumcentres outside the box whose box exit point fell on an edge or a vertex of the hull triangulation
   * instead of inside one of its facets, so that no box facet could be chosen (measure zero; expected 0). */
  std::size_t unresolvedBoxEncroachments{ 0 };
  /** Rounds of local refinement for manifoldness, the zones of smaller δ they created, and the boundary
   * places (vertex and label) still non-manifold at the end. */
  std::size_t manifoldRefinementRounds{ 0 };
  /** Rounds of the topology regularisation, and the balls in which it changed the oracle's labels (the places'
   * balls and those of the voxel pinches mended after them). */
  std::size_t topologyRegularizationRounds{ 0 };
  /** Whether the rounds stopped because they had inserted more vertices than their budget allows (the places left
   * are in remainingNonManifoldVertices; docs/algorithm.md, "Topology", step 2). */
  bool        topologyRegularizationBudgetReached{ false };
  std::size_t regularizedPlaces{ 0 };
  std::size_t manifoldRefinementZones{ 0 };
  std::size_t remainingNonManifoldVertices{ 0 };
  /** Tetrahedra given a neighbour's label where a boundary was not a manifold (relabelNonManifoldPlaces). */
  std::size_t topologyRelabelledTetrahedra{ 0 };
  /** Tetrahedra flat to rounding on a boundary, given the label beyond it (docs/algorithm.md, "Flat caps"). */
  std::size_t flatCapsRelabelled{ 0 };
  /** Tetrahedra flat to rounding inside a tissue removed from the output by an edge removal (docs/algorithm.md,
   * "Flat tetrahedra inside a tissue"). */
  std::size_t flatTetrahedraRemovedByEdgeRemoval{ 0 };
  /** Tetrahedra flat to rounding that the edge removal could not take out, removed by a move of a corner that may
   * break Lemma 2's spacing (docs/algorithm.md, "Flat tetrahedra inside a tissue"). */
  std::size_t flatTetrahedraMovedBelowSpacing{ 0 };
  /** Parts of the labels (LabelPartCensus) that held no tetrahedron while holding a ball of diameter δ, which the
   * refinement then sampled at a smaller δ around their largest ball (docs/algorithm.md, "Topology"), in how many
   * rounds; and the parts without a tetrahedron at the end, thick or not, with the oracle's measure of each (none
   * without a census). */
  std::size_t               thickPartsRefined{ 0 };
  std::size_t               thickPartRounds{ 0 };
  std::vector<UnmeshedPart> unmeshedParts;
  /** The smallest local δ the refinement used (δ itself unless the manifold refinement or a thick part refined
   * somewhere): Lemma 2's edge bounds hold with it. */
  double finestSurfaceSamplingDistance{ 0.0 };
  /** Vertices of the final triangulation, box vertices included. */
  std::size_t triangulationVertices{ 0 };
  double      refinementSeconds{ 0.0 };
  double      extractionSeconds{ 0.0 };
};

/** Progress of a running refinement, reported to the observer. */
struct RefinementProgress
{
  std::size_t vertices{ 0 };
  std::size_t pendingTetrahedra{ 0 };
  std::size_t processedTetrahedra{ 0 };
  /** A rough, monotone estimate in [0, 1). */
  double fraction{ 0.0 };
};

/** Called every few thousand operations; returning false aborts the refinement (RefinementAborted). */
using ProgressObserver = std::function<bool(const RefinementProgress &)>;

/** Thrown when the triangulation would exceed RefinementParameters::maximumNumberOfVertices. */
class DelaunayImageToMesh_EXPORT VertexLimitExceeded : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/** Thrown when the sliver removal (R4′, RefinementParameters::minimumDihedralAngle > 0) makes a pass of the
 * refinement grow beyond its budget (docs/algorithm.md, "When sliver removal does not end"): nothing proves that it
 * ends, and where it does not, R4 and R4′ keep making work for each other until the vertex cap. */
class DelaunayImageToMesh_EXPORT SliverRemovalWithoutEnd : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/** Thrown when the progress observer asked to stop. */
class DelaunayImageToMesh_EXPORT RefinementAborted : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/** Runs the Delaunay refinement of docs/algorithm.md on `oracle` and returns the tetrahedra whose circumcentre is
 * inside the object, each labelled with the oracle's label there, and the boundary triangles.
 *
 * With a `regularizer` (usually the oracle itself), where a boundary comes out non-manifold the oracle's labels
 * are regularised there and the refinement resumes (RefinementParameters::topologyRegularizationRounds).
 *
 * With a `census` (usually the oracle itself), every part of the labels that holds a ball of diameter δ and no
 * tetrahedron is sampled more finely until it holds one, and the parts left without one are listed in the
 * statistics (RefinementStatistics::unmeshedParts): nothing is lost silently.
 *
 * Throws std::invalid_argument for invalid parameters, VertexLimitExceeded, SliverRemovalWithoutEnd,
 * RefinementAborted. An oracle with empty ObjectBounds() gives an empty mesh. Deterministic: the same oracle and
 * parameters give the same mesh. */
DelaunayImageToMesh_EXPORT TetrahedralMesh
RefineMesh(const LabelOracle & oracle, const RefinementParameters & parameters,
           RefinementStatistics * statistics = nullptr, const ProgressObserver & observer = {},
           TopologyRegularizer * regularizer = nullptr, const LabelPartCensus * census = nullptr);

} // namespace delaunay_refinement

#endif
