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
#ifndef DelaunayRefinementLabelRegularization_h
#define DelaunayRefinementLabelRegularization_h

#include "DelaunayRefinementTypes.h"

#include <array>
#include <cstddef>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

namespace delaunay_refinement
{

/** What the regularisation did to one label (BackgroundLabel included). Volumes in voxels. */
struct LabelRegularizationChange
{
  Label       label{ BackgroundLabel };
  std::size_t voxelsBefore{ 0 };
  std::size_t voxelsAfter{ 0 };
  /** Voxels that left this label (thinner than the scale) and voxels that joined it (a neighbour's thin part). */
  std::size_t voxelsRemoved{ 0 };
  std::size_t voxelsAdded{ 0 };
  /** Face-connected components before and after. */
  std::size_t componentsBefore{ 0 };
  std::size_t componentsAfter{ 0 };
  /** Components of the input that lost every voxel: thinner than the scale everywhere. */
  std::size_t componentsRemoved{ 0 };
};

/** What RegularizeLabels() did, label by label in increasing order. */
struct LabelRegularizationReport
{
  double                                 radius{ 0.0 };
  std::size_t                            changedVoxels{ 0 };
  std::vector<LabelRegularizationChange> labels;
};

/** Regularises a label image at a physical scale: every label, the background included, is opened with a ball of
 * `radius`, and every voxel that its own label's opening removed takes the label of the nearest voxel (physical
 * distance between centres) that survived its own label's opening. Voxels are cubes, distances are measured between
 * centres: the erosion keeps a voxel whose nearest voxel of another label is farther than radius + h/2 (h the
 * smallest spacing), the dilation gives back the label's voxels within radius + h of a survivor, those farther than
 * radius + h/2 from every survivor only when no face neighbour of their label is lost (no fin is left at the root of
 * a removed part). Opening the background closes the tissues, so one rule removes a tissue's parts thinner than
 * about 2 × radius (bridges, sheets, speckle) and fills its slits and gaps thinner than that, for every label alike
 * and with no label favoured.
 * Every part of a label that holds a ball of radius + h/2 around a voxel centre stays. A voxel no label survives
 * near (every label thin everywhere) keeps its label, except where the erosion's reach (radius + h/2) is at least
 * the grid's length along an axis: there every tissue is within the reach of the background outside the grid, so
 * every tissue voxel becomes background (the object is thinner than the scale everywhere).
 *
 * `labels` is a dense grid, voxel (i, j, k) at labels[i + size[0] * (j + size[1] * k)], with `spacing` between
 * voxel centres along each axis (the direction of the axes does not matter: distances are kept by rotations).
 * Both reaches are lengthened by LatticeTieMargin (relative), so that a voxel at a reach's lattice distance is within
 * it whatever the radius's last bits.
 * Outside the grid is background. Deterministic: the result depends on the labels, spacing and radius only. A
 * radius of 0 changes nothing. `keepGoing` is asked, on the calling thread, between passes over the grid and between
 * the steps of each label's opening (a fraction of a second each on the largest images), with a rough fraction of the
 * work done (0 to 1, never decreasing); when it says no, RefinementAborted is thrown and the labels are as they were.
 * The labels' openings, the component counts and the passes of the distance transform run on up to `numberOfThreads`
 * threads; the result does not depend on their number. A grid with more than 4294967295 runs of equal labels along x,
 * or rows that long, throws std::length_error (the counts are kept in 32 bits). The labels may be stored in any
 * IsVoxelLabelType; the result is the same. */
template <typename TVoxelLabel>
LabelRegularizationReport
RegularizeLabels(TVoxelLabel * labels, const std::array<std::size_t, 3> & size, const Vector3 & spacing, double radius,
                 const std::function<bool(double)> & keepGoing = {}, unsigned int numberOfThreads = 1);

/** A face-connected part of one label's voxels (FindUnmarkedParts). */
struct LabelPart
{
  Label       label{ BackgroundLabel };
  std::size_t voxels{ 0 };
  /** The centre of the part's largest ball: a voxel (an offset into the grid), the first in the grid's order whose
   * centre is farthest from every voxel cube outside the part (another label, another part of the label, beyond the
   * grid); and that distance, the ball's radius, measured up to the limit asked for. */
  std::size_t deepestVoxel{ 0 };
  double      radius{ 0.0 };
};

/** The parts of a label image, found once (a component count, about a pass over the labels) and asked for the
 * unmarked ones as often as wanted while the labels stay as they were (FindUnmarkedParts). */
class DelaunayImageToMesh_EXPORT LabelParts
{
public:
  template <typename TVoxelLabel>
  LabelParts(const TVoxelLabel * labels, const std::array<std::size_t, 3> & size, const Vector3 & spacing,
             unsigned int numberOfThreads = 1);
  ~LabelParts();
  LabelParts(const LabelParts &) = delete;
  LabelParts &
  operator=(const LabelParts &) = delete;

  /** FindUnmarkedParts() on the labels as they were when this was made, among the parts of at most `maximumVoxels`
   * voxels (the larger ones are not measured). */
  std::vector<LabelPart>
  FindUnmarked(const std::vector<std::size_t> & marked, double radiusLimit,
               std::size_t maximumVoxels = std::numeric_limits<std::size_t>::max());

private:
  class Finder;
  std::unique_ptr<Finder> m_Finder;
};

/** The parts of the labels (face-connected voxels of one label, BackgroundLabel excepted) that hold none of the voxels
 * `marked` (offsets into the grid, laid out as for RegularizeLabels), in the order of their first voxel, each with its
 * largest ball up to `radiusLimit`. The mesher asks this of the regularised labels with the voxels that hold a
 * tetrahedron of their label, so that a part the mesh lost is found, meshed or reported. The components are found on
 * up to `numberOfThreads` threads; the result does not depend on their number. */
template <typename TVoxelLabel>
std::vector<LabelPart>
FindUnmarkedParts(const TVoxelLabel * labels, const std::array<std::size_t, 3> & size, const Vector3 & spacing,
                  const std::vector<std::size_t> & marked, double radiusLimit, unsigned int numberOfThreads = 1);

// Compiled in the library for each IsVoxelLabelType: declared here (EXTERN = extern), defined in the library's
// source (EXTERN empty).
#define DelaunayRefinement_InstantiateLabelRegularization(EXTERN, TVoxelLabel)                                         \
  EXTERN template DelaunayImageToMesh_EXPORT LabelRegularizationReport RegularizeLabels<TVoxelLabel>(                  \
    TVoxelLabel *,                                                                                                     \
    const std::array<std::size_t, 3> &,                                                                                \
    const Vector3 &,                                                                                                   \
    double,                                                                                                            \
    const std::function<bool(double)> &,                                                                               \
    unsigned int);                                                                                                     \
  EXTERN template DelaunayImageToMesh_EXPORT LabelParts::LabelParts(                                                   \
    const TVoxelLabel *, const std::array<std::size_t, 3> &, const Vector3 &, unsigned int);                           \
  EXTERN template DelaunayImageToMesh_EXPORT std::vector<LabelPart> FindUnmarkedParts<TVoxelLabel>(                    \
    const TVoxelLabel *,                                                                                               \
    const std::array<std::size_t, 3> &,                                                                                \
    const Vector3 &,                                                                                                   \
    const std::vector<std::size_t> &,                                                                                  \
    double,                                                                                                            \
    unsigned int)
DelaunayRefinement_InstantiateLabelRegularization(extern, Label);
DelaunayRefinement_InstantiateLabelRegularization(extern, uint16_t);
DelaunayRefinement_InstantiateLabelRegularization(extern, uint8_t);

} // namespace delaunay_refinement

#endif
