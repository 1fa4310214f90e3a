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
#ifndef DelaunayRefinementParameters_h
#define DelaunayRefinementParameters_h

#include "DelaunayImageToMeshExport.h"

#include <cstddef>
#include <string>

namespace delaunay_refinement
{

/** Parameters of the refinement (docs/algorithm.md, "Inputs"), each with its default. The default is written
 * here only: the ITK filter, the command-line program and ITK Python take theirs from RefinementParameters{}. */
struct RefinementParameters
{
  /** δ: surface sampling distance, in physical units (mm). Must be in (0, 1e30]. */
  double surfaceSamplingDistance{ 1.0 };
  /** ρ: radius-edge bound. Must be finite and >= 1. Every output tetrahedron has radius-edge ratio < ρ. */
  double radiusEdgeBound{ 2.0 };
  /** σ: minimum dihedral angle in degrees for the R4' variant; 0 disables it. Must be in [0, 20]
   * (ParameterLimits::LargestMinimumDihedralAngle says why). On by default
   * at 10°, the largest angle that keeps the mesh within 1.3 × the tetrahedra and 1.5 × the time of σ = 0 on every
   * bench image and δ (issue #15; measured paired: 10° costs 0.98-1.18 × the tetrahedra and 1.02-1.32 × the time;
   * 12° reached 1.45-1.48 × the time on the k-means tissues and the atlas phantom, 15° 1.6-2.0 ×): a finite-element
   * user should not have to know about slivers. With σ > 0 every sliver found is split at a point chosen to keep the
   * boundary's bounds, peeled off the background, or removed by moving a corner (docs/algorithm.md, "R4′ picks its
   * point", "R4′ moves a vertex"). As in the paper, nothing is proven: termination rests on maximumNumberOfVertices,
   * Lemma 2's spacing is given up and Lemma 5 with it: where none of these steps keeps the bounds (a sliver whose
   * circumcentre is within δ of the surface) the sliver is split anyway, and free vertices can reach a boundary,
   * within δ of the surface (docs/algorithm.md, "Guarantees"; RefinementStatistics::sliverSplitsFailingAcceptance
   * counts those splits). Measured on the bench's images and on the randomized suite's: dihedral angles >= σ,
   * radius-edge < ρ, boundary angles > 30° and boundary triangles narrower than δ on every mesh. σ = 0 gives the
   * paper's method, whose bounds are proven. */
  double minimumDihedralAngle{ 10.0 };
  /** Safety cap on the number of vertices of the triangulation; exceeding it throws VertexLimitExceeded. Must be
   * at least 8 (the bounding box alone has 8). */
  std::size_t maximumNumberOfVertices{ 10000000 };
  /** Where a boundary comes out non-manifold and the oracle is a TopologyRegularizer, its labels are regularised
   * in a ball of radius δ around each such place and the refinement resumes there, at most this many rounds
   * (docs/algorithm.md, "Topology"). 0 = never. Must be in [0, 20]. The rounds stop when no place is left, or
   * earlier when the places have risen twice above the count they began with (the rounds are then making things
   * worse) or the rounds have inserted their budget of vertices; the places left are reported. With
   * σ = 0 no bench image needs more than 5, but with σ > 0 R4′'s splits in layers about δ thick make new places
   * that later rounds settle (σ = 15°: the k-means tissues at 4.5 mm kept non-manifold vertices after 6 rounds,
   * 0 after 10; on the 1 mm grid at 2 mm, 1 after 10, 0 after 20). */
  unsigned int topologyRegularizationRounds{ 20 };
  /** Where a boundary comes out non-manifold, first give tetrahedra there a neighbour's label when that mends the
   * place and keeps the boundary on the surface with angles above 30° (docs/algorithm.md, "Topology"); the
   * regularisation rounds then see only the places this could not mend. */
  bool relabelNonManifoldPlaces{ true };
  /** Where the oracle is a LabelPartCensus: every part of the labels that holds a ball of diameter δ gets
   * tetrahedra. The small thin parts are sampled more finely before the refinement, and a part still without a
   * tetrahedron after it gets rounds of finer sampling (docs/algorithm.md, "Topology", step 4). Off, no part is
   * sampled more finely; the parts without a tetrahedron are listed all the same
   * (RefinementStatistics::unmeshedParts): nothing is lost silently. */
  bool refineThickParts{ true };
  /** The old repair, an opt-in: where a tissue's boundary comes out non-manifold, δ is halved locally and the
   * refinement resumed, at most this many times (down to δ / 2^levels), after the regularisation rounds. It
   * resolves detail toward the voxel instead of removing it: meshes several times larger. 0 (the default) = off.
   * Every guarantee holds with the local δ. Only isolated defects are mended: when more than 5 % of the
   * boundary vertices are non-manifold refining cannot help and is not tried. Must be in [0, 10]. */
  unsigned int manifoldRefinementLevels{ 0 };
  /** The manifold refinement never takes δ below this: about the oracle's resolution (the filter uses half the
   * smallest voxel spacing: finer sampling only resolves voxel corners that touch diagonally). 0 = no floor.
   * Must be finite and >= 0. */
  double minimumSurfaceSamplingDistance{ 0.0 };
};

/** The ends of the valid ranges that are not plain signs, written once: ValidateParameters() checks them. */
struct ParameterLimits
{
  /** Beyond it the bounding box (the object's bounds grown by 3δ) makes the fourth powers of its coordinates in
   * the circumcentre constructions overflow double precision (NaN circumcentres follow); and no object could be
   * meshed at such a δ anyway. */
  static constexpr double LargestSurfaceSamplingDistance = 1e30;
  static constexpr double SmallestRadiusEdgeBound = 1.0;
  /** Nothing proves that R4′ ends for any σ > 0. It ends in practice up to 20°: every bench image at 2-4 mm
   * (13 cases, 1.2-2.0 × the vertices and 1.0-6.2 × the time of σ = 0) and the randomized suite (σ drawn up to 20°)
   * were measured with it. Just above, it stops ending: with σ = 25° seven of the 13 cases ran over 90 s (the k-means
   * tissues at 3 and 4 mm, the atlas phantom at 2 and 4 mm, both 1 mm images), where σ = 0 takes 0.4-5 s; the brain
   * mask at 4 mm ends with 27° (3.3 × the vertices) and not with 28°. Up to 30° was accepted before, so a user could
   * ask for a refinement that never ends. */
  static constexpr double LargestMinimumDihedralAngle = 20.0;
  /** The bounding box alone has 8 vertices. */
  static constexpr std::size_t  SmallestMaximumNumberOfVertices = 8;
  static constexpr unsigned int LargestManifoldRefinementLevels = 10;
  static constexpr unsigned int LargestTopologyRegularizationRounds = 20;
};

/** The voxel lattice makes distances of round values, and users choose round δ, so a distance a rule compares with a
 * length made from δ often equals it, and which side of the test it fell on followed δ's last bits. Each such test
 * moves its tie by this fraction, to a value nobody types:
 * - R1 and R3 compare distances between surface points with the local δ, and move the tie toward inserting less
 *   (docs/algorithm.md, "Rules"): R1 counts a feature vertex up to δ (1 + LatticeTieMargin) away as within δ, so a
 *   feature vertex is still at least δ from every other (Lemma 2); R3 splits a restricted facet whose surface ball
 *   reaches δ (1 + LatticeTieMargin), so every boundary triangle's surface ball, and its circumradius, is below that.
 * - The regularisation's opening (RegularizeLabels) compares distances between voxel centres with reaches made from
 *   its radius, and lengthens both reaches by the margin, which keeps what the round value did: at δ = 5 mm on voxels
 *   of 2 × 3 × 2 mm the default scale gives an erosion reach of exactly 3 mm (ITK's k-means tissues: 57,695
 *   tetrahedra, 67,339 at δ (1 − 10⁻¹²) without the margin).
 * Far above rounding, far below anything geometric, and above the randomized suite's largest perturbation of δ
 * (1e-6). */
constexpr double LatticeTieMargin = 1e-4;

/** Throws std::invalid_argument naming the parameter, its value and the valid range. */
DelaunayImageToMesh_EXPORT void
ValidateParameters(const RefinementParameters & parameters);

/** A parameter value as the error messages print it: every digit a double holds. */
DelaunayImageToMesh_EXPORT std::string
                           DescribeValue(double value);

} // namespace delaunay_refinement

#endif
