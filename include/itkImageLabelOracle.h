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
#ifndef itkImageLabelOracle_h
#define itkImageLabelOracle_h

#include "DelaunayRefinementLabelRegularization.h"
#include "DelaunayRefinementLargeBuffers.h"
#include "DelaunayRefinementOracle.h"
#include "DelaunayRefinementVoxelPinches.h"

#include "itkImage.h"
#include "itkImageLabelSelection.h"
#include "itkInterpolateImageFunction.h"

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <utility>
#include <vector>

namespace itk
{

/** \class ImageLabelOracle
 * \brief The refinement's view of an image: labels from an ITK interpolator, closest surface points from an
 * exact Euclidean feature transform of the label interfaces, snapped onto the interpolator's surface.
 *
 * Labels: in label mode the interpolated value is rounded to a label and kept if it is selected (every
 * non-zero label when none is selected); in iso-value mode the label is 1 where the interpolated value is
 * >= the iso-value. Outside the image's buffered region every label is 0, so an object touching the border
 * is closed as if the image continued with background. All geometry is in physical space (spacing, origin
 * and direction of the image).
 *
 * With a nearest-neighbour interpolator the labels are those of the voxels: the oracle then reads them from its
 * own label image, and the surface between two voxels of different labels is the face they share, so that
 * surface points need no bisection. With an iso-value and linear interpolation a voxel's label is the side of the
 * iso-value its value is on; the regularisation changes those labels as a label image's, and the oracle then
 * interpolates a copy of the values in which each changed voxel's is on its new side (CarryLabelsIntoValues()).
 *
 * Not an itk::Object: it is the adaptor between an image and the ITK-free refinement core.
 *
 * TVoxelLabel is how the label image stores a label (a delaunay_refinement::IsVoxelLabelType): the filter chooses
 * the narrowest type every selected label fits in (ImageLabelSelection::BytesPerVoxelLabel), so that the label
 * image of most segmentations takes one byte a voxel instead of four. The meshes are the same whichever it is.
 *
 * \ingroup DelaunayImageToMesh
 */
template <typename TInputImage, typename TVoxelLabel = delaunay_refinement::Label>
class ITK_TEMPLATE_EXPORT ImageLabelOracle
  : public delaunay_refinement::LabelOracle
  , public delaunay_refinement::TopologyRegularizer
  , public delaunay_refinement::LabelPartCensus
{
public:
  static constexpr unsigned int ImageDimension = TInputImage::ImageDimension;
  static_assert(ImageDimension == 3, "ImageLabelOracle needs a 3-D image");
  static_assert(delaunay_refinement::IsVoxelLabelType<TVoxelLabel>, "labels are stored as Label, uint16_t or uint8_t");

  using InputImageType = TInputImage;
  using InterpolatorType = InterpolateImageFunction<InputImageType, double>;
  using LabelType = delaunay_refinement::Label;
  using VoxelLabelType = TVoxelLabel;
  using LabelImageType = Image<VoxelLabelType, 3>;
  using IndexType = typename LabelImageType::IndexType;
  using PointType = typename LabelImageType::PointType;
  using Vector3 = delaunay_refinement::Vector3;

  ImageLabelOracle(const InputImageType * image, const InterpolatorType * interpolator, ImageLabelMapping mapping);

  LabelType
  LabelAt(const Vector3 & point) const override;

  delaunay_refinement::AxisAlignedBox
  ObjectBounds() const override;

  delaunay_refinement::SurfacePoint
  ClosestSurfacePoint(const Vector3 & query) const override;

  /** With voxelwise labels, from one read of the feature transform at the voxel nearest to `query`; otherwise
   * the default, which decides nothing (a smoothing interpolator's surface can lie anywhere near the faces). */
  delaunay_refinement::SurfaceDistanceBounds
  BoundSurfaceDistance(const Vector3 & query) const override;

  double
  SurfaceTolerance() const override;

  /** With voxelwise labels, or an iso-value's side of linear interpolation (whose changed voxels get values on their
   * new side, CarryLabelsIntoValues()): in the ball around each place (voxel centres within `radius`, the label image's
   * outer layer of background excepted), the place's label takes every voxel when it holds at least half of them,
   * else gives its voxels to the label most frequent among the others there (the smaller on a tie). Then the
   * diagonal contacts near the changed voxels are joined again (when asked); a ball whose every change that undid
   * takes the other choice, and the contacts near it are joined again. The feature transform is updated. No ball is
   * returned when the labels end as they were, nor for other interpolators, which define their own surface. A
   * returned ball reaches a voxel diagonal past every voxel it changed: the trilinear values change in the cubes
   * around a changed voxel's centre. */
  std::vector<delaunay_refinement::Ball>
  RegularizeAround(const std::vector<delaunay_refinement::NonManifoldPlace> & places, double radius) override;

  /** Voxels whose label RegularizeAround() changed, over all calls. */
  /** The parts of the labels as regularised (face-connected voxels of one label) that hold none of `points` of
   * their label. For an iso-surface of linear interpolation each part's ball is the one its interpolated values surely
   * hold, the voxels' ball less a voxel diagonal; none for other interpolators, which define their own parts. */
  std::vector<delaunay_refinement::UnmeshedPart>
  PartsHoldingNone(const delaunay_refinement::LabelledPoints & points, double radiusLimit,
                   double maximumVolume = std::numeric_limits<double>::infinity()) const override;

  SizeValueType
  GetNumberOfLocallyRegularizedVoxels() const
  {
    return m_NumberOfLocallyRegularizedVoxels;
  }

  /** Number of voxels that carry a selected label (or are >= the iso-value). */
  SizeValueType
  GetNumberOfObjectVoxels() const
  {
    return m_NumberOfObjectVoxels;
  }

  /** The voxel labels the oracle sees: the object's voxels (with the joining voxels, if any) and one voxel of
   * background around them (the input's region padded by one voxel, cropped to that); every voxel outside it is
   * background. */
  const LabelImageType *
  GetLabelImage() const
  {
    return m_LabelImage;
  }

  /** The interface voxel (one with a face neighbour of another label in GetLabelImage()) nearest to the centre of
   * the label image's voxel `index`, from the feature transform, which is exact at voxel centres (of equally near
   * ones, any); false when the label image has no interface voxel. */
  bool
  NearestInterfaceVoxel(const IndexType & index, IndexType & nearest) const;

  /** Whether the regularisation, the joining of diagonal voxels or the local regularisation changed a voxel: then
   * the label image is no longer the selection (ImageLabelSelection::SelectedLabelImage gives that). */
  bool
  LabelsDifferFromTheSelection() const
  {
    return LabelsAreRegularizable() && (m_RegularizationReport.changedVoxels > 0 || m_NumberOfJoiningVoxels > 0 ||
                                        m_NumberOfLocallyRegularizedVoxels > 0);
  }

  /** What the regularisation (ImageLabelMapping::regularizationRadius) did to each label. */
  const delaunay_refinement::LabelRegularizationReport &
  GetRegularizationReport() const
  {
    return m_RegularizationReport;
  }

  /** How many voxels changed label to remove voxel pinches (ImageLabelMapping::joinDiagonalVoxels). */
  SizeValueType
  GetNumberOfJoiningVoxels() const
  {
    return m_NumberOfJoiningVoxels;
  }

private:
  /** The offset in the label image's buffer of the voxel nearest `point` (the nearest-neighbour interpolator's
   * arithmetic); false outside the buffer, where every voxel is background. */
  bool
  VoxelOffsetAt(const Vector3 & point, SizeValueType & offset) const;
  void
  BuildLabelImage(const InputImageType * image);
  /** The feature transform of the current labels into m_NearestInterfaceVoxel. */
  void
  BuildNearestInterfaceMap();
  /** The map after labels changed near the given z-slices only (RegularizeAround; each slice within a voxel of a
   * changed voxel, in increasing order; `originals` holds each changed voxel's label before the change, and is
   * swapped with the labels and back). The result is the full build's, bit for bit, with no per-voxel buffer beside
   * the map: the passes along x and y stay within a slice, so a column's values after them can change in those
   * slices only; each slice's values with the labels before and after the change say which columns changed, and the
   * pass along z is redone on those columns alone, from every slice's values there (the marking and the pass along
   * x of each slice, and the pass along y on the lines through those columns). Where those columns' values would
   * take more than a byte per voxel, the whole map is made again instead. */
  void
  UpdateNearestInterfaceMap(const std::vector<SizeValueType> & slices, std::map<std::size_t, TVoxelLabel> & originals);
  /** One z-slice's nearest interface voxels after the marking and the pass along x (its own rows' interface
   * voxels), into `values` (the slice's voxels in buffer order). */
  void
  MakeRowValuesOfSlice(SizeValueType slice, uint32_t * values) const;
  /** One z-slice's nearest interface voxels after the passes along x and y (its own interface voxels) into
   * `values`, as the full build has them before its pass along z. */
  void
  MakeValuesOfSlice(SizeValueType slice, uint32_t * values) const;
  /** Whether the regularisation may change the labels: voxel labels, or an iso-value's side of linear
   * interpolation, whose voxels' values can follow their labels. */
  bool
  LabelsAreRegularizable() const
  {
    return m_LabelsAreVoxelwise || m_LabelsCarryIntoValues;
  }
  /** The length of a voxel's diagonal: how far the values a point interpolates, or a changed voxel's cube, reach. */
  double
  VoxelDiagonal() const
  {
    const auto & spacing = m_LabelImage->GetSpacing();
    return std::sqrt(spacing[0] * spacing[0] + spacing[1] * spacing[1] + spacing[2] * spacing[2]);
  }
  /** With m_LabelsCarryIntoValues: gives each voxel of the label image at `offsets` (every voxel when null) that
   * lies in the input a value on its label's side of the iso-value: the input's own where that is on the side, else
   * its mirror image in the iso-value (2 iso - value, moved to the side where the type's rounding or range would
   * keep it off it). The mirror keeps how far the voxel is from the iso-value, so that the surface between a changed
   * voxel and its neighbours stays as far from their centres as it was from the changed voxel's own. */
  void
  CarryLabelsIntoValues(const std::vector<SizeValueType> * offsets);
  /** Changes the labels in one ball (RegularizeAround), by the majority's choice or, with `otherChoice`, by the other
   * one (a fill for a cut, a cut for a fill); appends each voxel it changes to `changes`. */
  void
  RegularizeBall(const delaunay_refinement::NonManifoldPlace & place, double radius, bool otherChoice,
                 std::vector<delaunay_refinement::VoxelChange> & changes);
  void
  CountObjectVoxels();
  /** Marks the interface voxels of the z-slices [firstSlice, endSlice) in `values`, which holds those slices'
   * voxels (values[0] is the first voxel of firstSlice): each gets its own buffer offset, the others are left. */
  void
  MarkInterfaceVoxels(SizeValueType firstSlice, SizeValueType endSlice, uint32_t * values) const;
  /** Lines along y or z that one pass reads and writes together: one 64-byte cache line of the map per voxel along
   * the axis, where one line at a time would read a cache line for every one of its voxels. */
  static constexpr SizeValueType LinesPerGather = 16;
  /** Scratch space of one pass of the feature transform along lines of `length` voxels `step` apart. */
  struct LowerEnvelope
  {
    LowerEnvelope(SizeValueType length, double step)
      : position(length)
      , positionSquared(length)
      , height(length)
      , liftedHeight(length)
      , site(length)
      , parabola(length)
      , leftBoundary(length)
      , gathered(length * LinesPerGather)
    {
      for (SizeValueType t = 0; t < length; ++t)
      {
        position[t] = static_cast<double>(t) * step;
        positionSquared[t] = position[t] * position[t];
      }
    }
    /** Voxel t's position along the line, and its square: the same for every line of a pass. */
    std::vector<double> position;
    std::vector<double> positionSquared;
    std::vector<double> height;
    /** height + positionSquared: the parabola's value at the line's origin. */
    std::vector<double>        liftedHeight;
    std::vector<uint32_t>      site;
    std::vector<SizeValueType> parabola;
    std::vector<double>        leftBoundary;
    /** The map's values on up to LinesPerGather adjacent lines, voxel by voxel along the axis. */
    std::vector<uint32_t> gathered;
  };
  /** The pass along `axis` on the lines firstLine..endLine - 1, numbered in memory order of their first voxel. */
  void
  PropagateNearestInterfaceAlong(unsigned int axis, SizeValueType firstLine, SizeValueType endLine);
  /** The whole image's pass along `axis`, its lines shared among the threads (InParallel()); during the set-up,
   * the set-up's progress goes from `firstFraction` to `endFraction` over the pass. */
  void
  PropagateNearestInterfaceAlongInParallel(unsigned int axis, double firstFraction, double endFraction);
  /** Calls work(first, end) on consecutive ranges covering [0, count) of items of `voxelsPerItem` voxels each, on
   * up to m_Mapping.numberOfThreads threads (fewer for small images). The calls must not depend on each other.
   * During the set-up the items go in rounds of about SetUpRoundVoxels voxels, with a SetUpCheckpoint() after each
   * (the set-up's progress from `firstFraction` to `endFraction`), so that an abort is honoured within a round. */
  template <typename TWork>
  void
  InParallel(SizeValueType count, SizeValueType voxelsPerItem, const TWork & work, double firstFraction = 0.0,
             double endFraction = 0.0) const;
  /** During the set-up (the constructor): reports `fraction` of the set-up done through
   * ImageLabelMapping::keepGoing and throws RefinementAborted when it says no. Afterwards nothing: the refinement
   * reports its own progress, and the map's rebuilds then are a part of it. Called on the caller's thread only. */
  void
  SetUpCheckpoint(double fraction) const;
  /** How far the set-up is after each of its steps, as a fraction of its work: rough shares from a profile of a
   * large image meshed coarsely (38 M voxels at 8 mm, bench/README.md, "At 1e3134b"), where the set-up is most of
   * the run. */
  struct SetUpProgressAfter
  {
    static constexpr double bounds = 0.03;
    static constexpr double selection = 0.06;
    static constexpr double regularization = 0.40;
    static constexpr double pinchRemoval = 0.48;
    static constexpr double marking = 0.55;
    static constexpr double passAlongX = 0.65;
    static constexpr double passAlongY = 0.80;
  };
  /** Voxels per round of a set-up pass between two checkpoints: about 20-80 ms of one thread's work. */
  static constexpr SizeValueType SetUpRoundVoxels = SizeValueType{ 1 } << 21;
  /** The pass on the line along `axis` from `lineStart` (whose offset within its block is less than the line's
   * stride), whose map values are at values[t * valueStride] for its voxels t (the map itself or a gathered copy). */
  void
  PropagateNearestInterfaceAlongLine(unsigned int axis, SizeValueType lineStart, uint32_t * values,
                                     SizeValueType valueStride, LowerEnvelope & envelope) const;
  /** The pass along x on one row, whose map values are `row`: its sites are the interface voxels themselves. */
  void
  PropagateNearestInterfaceAlongRow(uint32_t * row) const;
  double
  SquaredDistanceAlongLowerAxes(const SizeValueType * coordinates, SizeValueType lowerOffset, unsigned int axis) const;
  LabelType
  VoxelLabelAt(const Vector3 & point) const;
  using InterfaceVoxelCandidates = std::array<uint32_t, 8>;
  InterfaceVoxelCandidates
  InterfaceVoxelsAround(const ContinuousIndex<double, 3> & queryIndex) const;
  /** A voxel's coordinates in the label image's buffer (from its first voxel) from its 32-bit buffer offset. */
  std::array<uint32_t, 3>
  BufferCoordinatesOf(uint32_t offset) const;
  /** Physical distance between two points given by their continuous indices in the label image. */
  double
  IndexDistance(const double * a, const double * b) const;
  /** A face between an interface voxel and its neighbour of another label: the surface crosses the segment
   * between their centres. */
  struct InterfaceFace
  {
    IndexType voxel;
    IndexType neighbor;
    /** From the query to the face's centre. */
    double distance;
  };
  /** The interface face whose centre is nearest to `query`. */
  InterfaceFace
  NearestInterfaceFace(const Vector3 & query) const;
  Vector3
  CenterOf(const IndexType & index) const;
  /** The centre of the face shared by two face-neighbour voxels. */
  Vector3
  FaceCenterOf(const IndexType & voxel, const IndexType & neighbor) const;

  typename InputImageType::ConstPointer   m_Image;
  typename InterpolatorType::ConstPointer m_Interpolator;
  ImageLabelMapping                       m_Mapping;
  ImageLabelSelection                     m_Selection;
  /** Whether LabelAt() is the label of the nearest voxel (a nearest-neighbour interpolator). */
  bool m_LabelsAreVoxelwise;
  /** Whether LabelAt() is an iso-value's side of the linearly interpolated values: then the value at a voxel centre
   * is the voxel's, its side is the voxel's label, and a voxel whose label the regularisation changes gets a value on
   * its new side (CarryLabelsIntoValues()), so that the interpolated surface follows the regularised voxels. */
  bool m_LabelsCarryIntoValues;
  /** The input's values on the label image's voxels inside the input, with the changed voxels' carried; once it
   * exists, LabelAt() interpolates it instead of the input (iso-value mode). */
  typename InputImageType::Pointer m_CarriedValues;
  /** True in the constructor only (SetUpCheckpoint()). */
  bool m_SettingUp{ true };
  /** The parts of the labels for PartsHoldingNone(), found at its first call and again after RegularizeAround()
   * changed the labels. */
  mutable std::unique_ptr<delaunay_refinement::LabelParts> m_LabelParts;
  typename LabelImageType::Pointer                         m_LabelImage;
  /** For each voxel of m_LabelImage (by buffer offset), the buffer offset of the nearest interface voxel. */
  delaunay_refinement::LargeVector<uint32_t> m_NearestInterfaceVoxel;
  /** Buffer offset steps of m_LabelImage along each axis. */
  std::array<SizeValueType, 3>                   m_BufferStrides{};
  delaunay_refinement::AxisAlignedBox            m_ObjectBounds;
  SizeValueType                                  m_NumberOfObjectVoxels{ 0 };
  SizeValueType                                  m_NumberOfJoiningVoxels{ 0 };
  SizeValueType                                  m_NumberOfLocallyRegularizedVoxels{ 0 };
  delaunay_refinement::LabelRegularizationReport m_RegularizationReport;
  double                                         m_SurfaceTolerance{ 0.0 };
};

} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkImageLabelOracle.hxx"
#  include "itkImageLabelOracleRegularization.hxx"
#endif

#endif
