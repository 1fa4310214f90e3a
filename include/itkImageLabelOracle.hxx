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
#ifndef itkImageLabelOracle_hxx
#define itkImageLabelOracle_hxx

#include "itkImageLabelOracle.h"

#include "itkLinearInterpolateImageFunction.h"
#include "itkMultiThreaderBase.h"
#include "itkNearestNeighborInterpolateImageFunction.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace itk
{

template <typename TInputImage, typename TVoxelLabel>
ImageLabelOracle<TInputImage, TVoxelLabel>::ImageLabelOracle(const InputImageType *   image,
                                                             const InterpolatorType * interpolator,
                                                             ImageLabelMapping        mapping)
  : m_Image(image)
  , m_Interpolator(interpolator)
  , m_Mapping(std::move(mapping))
  , m_Selection(m_Mapping)
  , m_LabelsAreVoxelwise(
      dynamic_cast<const NearestNeighborInterpolateImageFunction<InputImageType, double> *>(interpolator) != nullptr)
  , m_LabelsCarryIntoValues(
      m_Mapping.useIsoValue &&
      dynamic_cast<const LinearInterpolateImageFunction<InputImageType, double> *>(interpolator) != nullptr)
{
  const auto & spacing = image->GetSpacing();
  m_SurfaceTolerance = 1e-4 * *std::min_element(spacing.Begin(), spacing.End());
  BuildLabelImage(image);
  if (m_NumberOfObjectVoxels > 0)
  {
    BuildNearestInterfaceMap();
  }
  SetUpCheckpoint(1.0);
  m_SettingUp = false;
}

template <typename TInputImage, typename TVoxelLabel>
void
ImageLabelOracle<TInputImage, TVoxelLabel>::SetUpCheckpoint(double fraction) const
{
  if (m_SettingUp && m_Mapping.keepGoing && !m_Mapping.keepGoing(fraction))
  {
    throw delaunay_refinement::RefinementAborted("The oracle's set-up was aborted by the progress observer");
  }
}

/** The oracle's own label image covers the object's voxels and one voxel of background around them (the input's
 * buffered region padded by one voxel, cropped to that): every interface voxel is in it, and the feature transform
 * does no work on background far from the object. */
template <typename TInputImage, typename TVoxelLabel>
void
ImageLabelOracle<TInputImage, TVoxelLabel>::BuildLabelImage(const InputImageType * image)
{
  const auto & buffered = image->GetBufferedRegion();
  IndexType    lowest;
  IndexType    highest;
  lowest.Fill(NumericTraits<IndexValueType>::max());
  highest.Fill(NumericTraits<IndexValueType>::NonpositiveMin());
  ImageLabelSelection::Lookup<typename InputImageType::PixelType> lookup(m_Selection);
  ImageLabelSelection::ForEachRow(
    *image, buffered, [&](const auto * row, const IndexType & first, SizeValueType length) {
      SizeValueType firstObjectVoxel = length;
      SizeValueType lastObjectVoxel = 0;
      for (SizeValueType i = 0; i < length; ++i)
      {
        if (lookup(row[i]) != delaunay_refinement::BackgroundLabel)
        {
          ++m_NumberOfObjectVoxels;
          firstObjectVoxel = std::min(firstObjectVoxel, i);
          lastObjectVoxel = i;
        }
      }
      if (firstObjectVoxel < length)
      {
        lowest[0] = std::min(lowest[0], first[0] + static_cast<IndexValueType>(firstObjectVoxel));
        highest[0] = std::max(highest[0], first[0] + static_cast<IndexValueType>(lastObjectVoxel));
        for (unsigned int axis = 1; axis < 3; ++axis)
        {
          lowest[axis] = std::min(lowest[axis], first[axis]);
          highest[axis] = std::max(highest[axis], first[axis]);
        }
      }
    });
  SetUpCheckpoint(SetUpProgressAfter::bounds);
  auto kept = buffered;
  if (m_NumberOfObjectVoxels > 0)
  {
    kept.SetIndex(lowest);
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      kept.SetSize(axis, static_cast<SizeValueType>(highest[axis] - lowest[axis] + 1));
    }
  }
  kept.PadByRadius(1);
  m_LabelImage = m_Selection.template SelectedLabelImage<TVoxelLabel>(*image, kept);
  m_BufferStrides = { 1, kept.GetSize()[0], kept.GetSize()[0] * kept.GetSize()[1] };
  SetUpCheckpoint(SetUpProgressAfter::selection);
  if (m_Mapping.regularizationRadius > 0.0 && LabelsAreRegularizable() && m_NumberOfObjectVoxels > 0)
  {
    // Regularisation only moves labels between voxels that are already inside the object's padded bounds.
    const auto & spacing = image->GetSpacing();
    m_RegularizationReport = delaunay_refinement::RegularizeLabels(
      m_LabelImage->GetBufferPointer(),
      { kept.GetSize()[0], kept.GetSize()[1], kept.GetSize()[2] },
      { spacing[0], spacing[1], spacing[2] },
      m_Mapping.regularizationRadius,
      [this](double done) {
        SetUpCheckpoint(SetUpProgressAfter::selection +
                        done * (SetUpProgressAfter::regularization - SetUpProgressAfter::selection));
        return true;
      },
      m_Mapping.numberOfThreads);
    CountObjectVoxels();
  }
  SetUpCheckpoint(SetUpProgressAfter::regularization);
  if (m_Mapping.joinDiagonalVoxels && LabelsAreRegularizable())
  {
    // A changed voxel is in a block with an object voxel, so within one voxel of the object's bounds; the label
    // image's border of background holds it. Voxels change between tissues too, so the object is counted again.
    m_NumberOfJoiningVoxels =
      delaunay_refinement::RemoveVoxelPinches(m_LabelImage->GetBufferPointer(),
                                              { kept.GetSize()[0], kept.GetSize()[1], kept.GetSize()[2] },
                                              nullptr,
                                              m_Mapping.numberOfThreads);
    CountObjectVoxels();
  }
  if (m_LabelsCarryIntoValues && (m_RegularizationReport.changedVoxels > 0 || m_NumberOfJoiningVoxels > 0))
  {
    CarryLabelsIntoValues(nullptr);
  }
  SetUpCheckpoint(SetUpProgressAfter::pinchRemoval);
  if (m_NumberOfObjectVoxels == 0)
  {
    return;
  }
  // Two voxels of margin: an interpolator's surface lies within one voxel of the object's voxel centres.
  for (unsigned int corner = 0; corner < 8; ++corner)
  {
    ContinuousIndex<double, 3> index;
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      index[axis] = (corner >> axis) & 1 ? highest[axis] + 2.0 : lowest[axis] - 2.0;
    }
    PointType point;
    m_LabelImage->TransformContinuousIndexToPhysicalPoint(index, point);
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      m_ObjectBounds.lower[axis] = corner == 0 ? point[axis] : std::min(m_ObjectBounds.lower[axis], point[axis]);
      m_ObjectBounds.upper[axis] = corner == 0 ? point[axis] : std::max(m_ObjectBounds.upper[axis], point[axis]);
    }
  }
}

/** Voxels with a face neighbour of another label, the voxels the surface passes next to, are their own nearest
 * interface voxel; in the z-slices [firstSlice, endSlice), whose face neighbours in the slices beside count too. */
template <typename TInputImage, typename TVoxelLabel>
void
ImageLabelOracle<TInputImage, TVoxelLabel>::MarkInterfaceVoxels(SizeValueType firstSlice, SizeValueType endSlice,
                                                                uint32_t * values) const
{
  const auto &        size = m_LabelImage->GetBufferedRegion().GetSize();
  const TVoxelLabel * labels = m_LabelImage->GetBufferPointer();
  const SizeValueType strides[3] = { 1, size[0], size[0] * size[1] };
  const SizeValueType beforeFirst = firstSlice > 0 ? firstSlice - 1 : 0;
  const SizeValueType firstOffset = firstSlice * strides[2];
  SizeValueType       offset = beforeFirst * strides[2];
  for (SizeValueType k = beforeFirst; k < endSlice; ++k)
  {
    for (SizeValueType j = 0; j < size[1]; ++j)
    {
      for (SizeValueType i = 0; i < size[0]; ++i, ++offset)
      {
        const SizeValueType coordinates[3] = { i, j, k };
        for (unsigned int axis = 0; axis < 3; ++axis)
        {
          const SizeValueType next = offset + strides[axis];
          if (coordinates[axis] + 1 < size[axis] && labels[offset] != labels[next])
          {
            if (k >= firstSlice)
            {
              values[offset - firstOffset] = static_cast<uint32_t>(offset);
            }
            const SizeValueType nextSlice = axis == 2 ? k + 1 : k;
            if (nextSlice >= firstSlice && nextSlice < endSlice)
            {
              values[next - firstOffset] = static_cast<uint32_t>(next);
            }
          }
        }
      }
    }
  }
}

/** Squared physical distance along the axes before `axis` from a voxel whose coordinates on those axes
 * are `coordinates` to the voxel at `lowerOffset` within the same lower-axes block (the buffer offset minus the
 * part due to `axis` and the axes after it). Called once per voxel and pass: one 32-bit division at most. */
template <typename TInputImage, typename TVoxelLabel>
double
ImageLabelOracle<TInputImage, TVoxelLabel>::SquaredDistanceAlongLowerAxes(const SizeValueType * coordinates,
                                                                          SizeValueType         lowerOffset,
                                                                          unsigned int          axis) const
{
  if (axis == 0)
  {
    return 0.0;
  }
  const auto &   spacing = m_LabelImage->GetSpacing();
  const auto     offset = static_cast<uint32_t>(lowerOffset);
  const auto     rowLength = static_cast<uint32_t>(m_BufferStrides[1]);
  const uint32_t row = axis == 1 ? 0 : offset / rowLength;
  const double   differences[2] = {
      (static_cast<double>(coordinates[0]) - static_cast<double>(offset - row * rowLength)) * spacing[0],
    axis == 1 ? 0.0 : (static_cast<double>(coordinates[1]) - static_cast<double>(row)) * spacing[1]
  };
  return axis == 1 ? differences[0] * differences[0]
                   : differences[0] * differences[0] + differences[1] * differences[1];
}

/** One pass of the separable exact Euclidean feature transform (Felzenszwalb and Huttenlocher's lower envelope of
 * parabolas, each carrying its interface voxel): afterwards every voxel knows the nearest of the interface voxels
 * that the earlier passes gave to the voxels of its line along `axis`. Those earlier passes moved interface voxels
 * along the lower axes only, so a voxel and its interface voxel differ along the lower axes only. */
template <typename TInputImage, typename TVoxelLabel>
void
ImageLabelOracle<TInputImage, TVoxelLabel>::PropagateNearestInterfaceAlong(unsigned int axis, SizeValueType firstLine,
                                                                           SizeValueType endLine)
{
  const auto & size = m_LabelImage->GetBufferedRegion().GetSize();
  if (axis == 0)
  {
    for (SizeValueType line = firstLine; line < endLine; ++line)
    {
      PropagateNearestInterfaceAlongRow(m_NearestInterfaceVoxel.data() + line * size[0]);
    }
    return;
  }
  const SizeValueType stride = m_BufferStrides[axis];
  const SizeValueType length = size[axis];
  LowerEnvelope       envelope(length, m_LabelImage->GetSpacing()[axis]);
  uint32_t * const    map = m_NearestInterfaceVoxel.data();
  // Line `line` starts in block line / stride (a block: a z-slice along y, the image along z), at line % stride in
  // it: consecutive lines of a block are next to each other along x, so a few of them are gathered at once.
  for (SizeValueType line = firstLine; line < endLine;)
  {
    const SizeValueType lowerOffset = line % stride;
    const SizeValueType lines = std::min({ LinesPerGather, endLine - line, stride - lowerOffset });
    const SizeValueType lineStart = (line / stride) * stride * length + lowerOffset;
    for (SizeValueType t = 0; t < length; ++t)
    {
      std::copy_n(map + lineStart + t * stride, lines, envelope.gathered.data() + t * lines);
    }
    for (SizeValueType gatheredLine = 0; gatheredLine < lines; ++gatheredLine)
    {
      PropagateNearestInterfaceAlongLine(
        axis, lineStart + gatheredLine, envelope.gathered.data() + gatheredLine, lines, envelope);
    }
    for (SizeValueType t = 0; t < length; ++t)
    {
      std::copy_n(envelope.gathered.data() + t * lines, lines, map + lineStart + t * stride);
    }
    line += lines;
  }
}

/** Along x every site is an interface voxel at height 0, and the lower envelope of their parabolas is each site's
 * between the midpoints to its neighbours: the voxels between two sites take the nearer, found with the same
 * arithmetic as the envelope (the boundary as PropagateNearestInterfaceAlongLine() computes it, a voxel exactly on
 * it taking the left site), so the map is the same bit for bit without the envelope's bookkeeping. */
template <typename TInputImage, typename TVoxelLabel>
void
ImageLabelOracle<TInputImage, TVoxelLabel>::PropagateNearestInterfaceAlongRow(uint32_t * row) const
{
  constexpr uint32_t  none = std::numeric_limits<uint32_t>::max();
  const double        step = m_LabelImage->GetSpacing()[0];
  const SizeValueType length = m_LabelImage->GetBufferedRegion().GetSize()[0];
  SizeValueType       previous = length;
  for (SizeValueType t = 0; t < length; ++t)
  {
    if (row[t] == none)
    {
      continue;
    }
    if (previous == length)
    {
      std::fill(row, row + t, row[t]);
    }
    else
    {
      const double previousPosition = static_cast<double>(previous) * step;
      const double position = static_cast<double>(t) * step;
      const double boundary =
        (position * position - previousPosition * previousPosition) / (2.0 * (position - previousPosition));
      for (SizeValueType between = previous + 1; between < t; ++between)
      {
        row[between] = boundary < static_cast<double>(between) * step ? row[t] : row[previous];
      }
    }
    previous = t;
  }
  if (previous < length)
  {
    std::fill(row + previous + 1, row + length, row[previous]);
  }
}

template <typename TInputImage, typename TVoxelLabel>
void
ImageLabelOracle<TInputImage, TVoxelLabel>::PropagateNearestInterfaceAlongLine(unsigned int    axis,
                                                                               SizeValueType   lineStart,
                                                                               uint32_t *      values,
                                                                               SizeValueType   valueStride,
                                                                               LowerEnvelope & envelope) const
{
  constexpr uint32_t    none = std::numeric_limits<uint32_t>::max();
  constexpr double      infinity = std::numeric_limits<double>::infinity();
  const auto &          size = m_LabelImage->GetBufferedRegion().GetSize();
  const SizeValueType   length = size[axis];
  const SizeValueType   stride = m_BufferStrides[axis];
  const SizeValueType   lowerOffset = lineStart % stride;
  const double * const  position = envelope.position.data();
  const double * const  positionSquared = envelope.positionSquared.data();
  double * const        height = envelope.height.data();
  double * const        liftedHeight = envelope.liftedHeight.data();
  uint32_t * const      site = envelope.site.data();
  SizeValueType * const parabola = envelope.parabola.data();
  double * const        leftBoundary = envelope.leftBoundary.data();
  // Where the parabolas of voxels p < q meet: (h_q + x_q² - h_p - x_p²) / (2 (x_q - x_p)), evaluated in that order.
  const auto intersection = [&](SizeValueType p, SizeValueType q) {
    return (liftedHeight[q] - height[p] - positionSquared[p]) / (2.0 * (position[q] - position[p]));
  };
  const SizeValueType lineCoordinates[2] = { lowerOffset % size[0], lowerOffset / size[0] };
  for (SizeValueType t = 0; t < length; ++t)
  {
    const SizeValueType offset = lineStart + t * stride;
    site[t] = values[t * valueStride];
    height[t] = site[t] == none
                  ? infinity
                  : SquaredDistanceAlongLowerAxes(lineCoordinates, site[t] - (offset - lowerOffset), axis);
    liftedHeight[t] = height[t] + positionSquared[t];
  }
  SizeValueType parabolas = 0;
  for (SizeValueType q = 0; q < length; ++q)
  {
    if (site[q] == none)
    {
      continue;
    }
    double boundary = -infinity;
    while (parabolas > 0 && (boundary = intersection(parabola[parabolas - 1], q)) <= leftBoundary[parabolas - 1])
    {
      --parabolas;
      boundary = -infinity;
    }
    parabola[parabolas] = q;
    leftBoundary[parabolas] = boundary;
    ++parabolas;
  }
  SizeValueType current = 0;
  for (SizeValueType t = 0; t < length && parabolas > 0; ++t)
  {
    while (current + 1 < parabolas && leftBoundary[current + 1] < position[t])
    {
      ++current;
    }
    values[t * valueStride] = site[parabola[current]];
  }
}

template <typename TInputImage, typename TVoxelLabel>
void
ImageLabelOracle<TInputImage, TVoxelLabel>::BuildNearestInterfaceMap()
{
  const SizeValueType numberOfVoxels = m_LabelImage->GetBufferedRegion().GetNumberOfPixels();
  if (numberOfVoxels >= std::numeric_limits<uint32_t>::max())
  {
    itkGenericExceptionMacro(<< "ImageLabelOracle: the padded image has " << numberOfVoxels
                             << " voxels; at most 4294967294 are supported.");
  }
  const auto &        size = m_LabelImage->GetBufferedRegion().GetSize();
  const SizeValueType sliceSize = size[0] * size[1];
  m_NearestInterfaceVoxel.assign(numberOfVoxels, std::numeric_limits<uint32_t>::max());
  // A slice range's marking writes its own slices only (see MarkInterfaceVoxels()).
  InParallel(
    size[2],
    sliceSize,
    [this, sliceSize](SizeValueType first, SizeValueType end) {
      MarkInterfaceVoxels(first, end, m_NearestInterfaceVoxel.data() + first * sliceSize);
    },
    SetUpProgressAfter::pinchRemoval,
    SetUpProgressAfter::marking);
  PropagateNearestInterfaceAlongInParallel(0, SetUpProgressAfter::marking, SetUpProgressAfter::passAlongX);
  PropagateNearestInterfaceAlongInParallel(1, SetUpProgressAfter::passAlongX, SetUpProgressAfter::passAlongY);
  PropagateNearestInterfaceAlongInParallel(2, SetUpProgressAfter::passAlongY, 1.0);
}

template <typename TInputImage, typename TVoxelLabel>
void
ImageLabelOracle<TInputImage, TVoxelLabel>::MakeRowValuesOfSlice(SizeValueType slice, uint32_t * values) const
{
  const auto & size = m_LabelImage->GetBufferedRegion().GetSize();
  std::fill(values, values + size[0] * size[1], std::numeric_limits<uint32_t>::max());
  MarkInterfaceVoxels(slice, slice + 1, values);
  for (SizeValueType row = 0; row < size[1]; ++row)
  {
    PropagateNearestInterfaceAlongRow(values + row * size[0]);
  }
}

template <typename TInputImage, typename TVoxelLabel>
void
ImageLabelOracle<TInputImage, TVoxelLabel>::MakeValuesOfSlice(SizeValueType slice, uint32_t * values) const
{
  const auto & size = m_LabelImage->GetBufferedRegion().GetSize();
  MakeRowValuesOfSlice(slice, values);
  LowerEnvelope envelope(size[1], m_LabelImage->GetSpacing()[1]);
  for (SizeValueType x = 0; x < size[0]; ++x)
  {
    PropagateNearestInterfaceAlongLine(1, slice * size[0] * size[1] + x, values + x, size[0], envelope);
  }
}

template <typename TInputImage, typename TVoxelLabel>
void
ImageLabelOracle<TInputImage, TVoxelLabel>::PropagateNearestInterfaceAlongInParallel(unsigned int axis,
                                                                                     double       firstFraction,
                                                                                     double       endFraction)
{
  const SizeValueType length = m_LabelImage->GetBufferedRegion().GetSize()[axis];
  InParallel(
    m_NearestInterfaceVoxel.size() / length,
    length,
    [this, axis](SizeValueType first, SizeValueType end) { PropagateNearestInterfaceAlong(axis, first, end); },
    firstFraction,
    endFraction);
}

template <typename TInputImage, typename TVoxelLabel>
template <typename TWork>
void
ImageLabelOracle<TInputImage, TVoxelLabel>::InParallel(SizeValueType count, SizeValueType voxelsPerItem,
                                                       const TWork & work, double firstFraction,
                                                       double endFraction) const
{
  // Below this many voxels per thread, starting a thread costs more than it saves.
  constexpr SizeValueType minimumVoxelsPerThread = 1 << 16;
  const auto              runInParallel = [this, voxelsPerItem, &work](SizeValueType first, SizeValueType end) {
    const SizeValueType items = end - first;
    const SizeValueType ranges = std::max<SizeValueType>(
      1, std::min<SizeValueType>({ m_Mapping.numberOfThreads, items * voxelsPerItem / minimumVoxelsPerThread, items }));
    const SizeValueType perRange = (items + ranges - 1) / ranges;
    const auto          run = [&](SizeValueType range) {
      work(first + std::min(items, range * perRange), first + std::min(items, (range + 1) * perRange));
    };
    if (ranges == 1)
    {
      run(0);
      return;
    }
    const MultiThreaderBase::Pointer threader = MultiThreaderBase::New();
    threader->SetNumberOfWorkUnits(static_cast<ThreadIdType>(ranges));
    threader->ParallelizeArray(0, ranges, run, nullptr);
  };
  if (!m_SettingUp)
  {
    runInParallel(0, count);
    return;
  }
  // The items are independent: rounds of them give the same result as one run.
  const SizeValueType itemsPerRound =
    std::max<SizeValueType>(1, SetUpRoundVoxels / std::max<SizeValueType>(1, voxelsPerItem));
  for (SizeValueType first = 0; first < count; first += itemsPerRound)
  {
    const SizeValueType end = std::min(count, first + itemsPerRound);
    runInParallel(first, end);
    SetUpCheckpoint(firstFraction +
                    (endFraction - firstFraction) * static_cast<double>(end) / static_cast<double>(count));
  }
}

template <typename TInputImage, typename TVoxelLabel>
void
ImageLabelOracle<TInputImage, TVoxelLabel>::UpdateNearestInterfaceMap(const std::vector<SizeValueType> &   slices,
                                                                      std::map<std::size_t, TVoxelLabel> & originals)
{
  if (slices.empty())
  {
    return;
  }
  const auto &        size = m_LabelImage->GetBufferedRegion().GetSize();
  const SizeValueType sliceSize = size[0] * size[1];
  // Each slice of the update is made twice, and every slice once more: from half of the slices on, the whole map
  // costs less.
  if (2 * slices.size() >= size[2])
  {
    BuildNearestInterfaceMap();
    return;
  }
  TVoxelLabel * const labels = m_LabelImage->GetBufferPointer();
  const auto          swapLabels = [&] {
    for (auto & [offset, label] : originals)
    {
      std::swap(labels[offset], label);
    }
  };
  std::vector<bool>     columnChanged(sliceSize, false);
  std::vector<uint32_t> before(sliceSize);
  std::vector<uint32_t> after(sliceSize);
  for (const SizeValueType slice : slices)
  {
    swapLabels();
    MakeValuesOfSlice(slice, before.data());
    swapLabels();
    MakeValuesOfSlice(slice, after.data());
    for (SizeValueType column = 0; column < sliceSize; ++column)
    {
      columnChanged[column] = columnChanged[column] || before[column] != after[column];
    }
  }
  std::vector<SizeValueType> columns;
  for (SizeValueType column = 0; column < sliceSize; ++column)
  {
    if (columnChanged[column])
    {
      columns.push_back(column);
    }
  }
  if (columns.empty())
  {
    return;
  }
  // The changed columns' values, column by column: a byte per voxel of the map at most, or the whole map again.
  const SizeValueType numberOfVoxels = m_NearestInterfaceVoxel.size();
  if (columns.size() * size[2] * sizeof(uint32_t) > numberOfVoxels)
  {
    BuildNearestInterfaceMap();
    return;
  }
  // The lines along y through the changed columns: one per x among them, in increasing order.
  std::vector<SizeValueType> linesAlongY;
  for (const SizeValueType column : columns)
  {
    linesAlongY.push_back(column % size[0]);
  }
  std::sort(linesAlongY.begin(), linesAlongY.end());
  linesAlongY.erase(std::unique(linesAlongY.begin(), linesAlongY.end()), linesAlongY.end());
  std::vector<uint32_t> columnValues(columns.size() * size[2]);
  InParallel(size[2], sliceSize, [&](SizeValueType first, SizeValueType end) {
    std::vector<uint32_t> values(sliceSize);
    LowerEnvelope         envelope(size[1], m_LabelImage->GetSpacing()[1]);
    for (SizeValueType slice = first; slice < end; ++slice)
    {
      MakeRowValuesOfSlice(slice, values.data());
      for (const SizeValueType x : linesAlongY)
      {
        PropagateNearestInterfaceAlongLine(1, slice * sliceSize + x, values.data() + x, size[0], envelope);
      }
      for (SizeValueType index = 0; index < columns.size(); ++index)
      {
        columnValues[index * size[2] + slice] = values[columns[index]];
      }
    }
  });
  LowerEnvelope envelope(size[2], m_LabelImage->GetSpacing()[2]);
  for (SizeValueType index = 0; index < columns.size(); ++index)
  {
    uint32_t * const values = columnValues.data() + index * size[2];
    PropagateNearestInterfaceAlongLine(2, columns[index], values, 1, envelope);
    for (SizeValueType slice = 0; slice < size[2]; ++slice)
    {
      m_NearestInterfaceVoxel[columns[index] + slice * sliceSize] = values[slice];
    }
  }
}

template <typename TInputImage, typename TVoxelLabel>
bool
ImageLabelOracle<TInputImage, TVoxelLabel>::VoxelOffsetAt(const Vector3 & point, SizeValueType & offset) const
{
  // The same arithmetic as the nearest-neighbour interpolator's, on the padded label image (same geometry). The
  // overload that returns the index skips the region test, which the buffer test below makes redundant.
  const auto continuousIndex =
    m_LabelImage->template TransformPhysicalPointToContinuousIndex<double>(PointType(point.data()));
  const auto & buffered = m_Image->GetBufferedRegion();
  const auto & cropped = m_LabelImage->GetBufferedRegion();
  offset = 0;
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    const double first = static_cast<double>(buffered.GetIndex()[axis]) - 0.5;
    const double end = first + static_cast<double>(buffered.GetSize()[axis]);
    if (!(continuousIndex[axis] >= first && continuousIndex[axis] < end))
    {
      return false;
    }
    // Outside the object's cropped neighbourhood every voxel is background.
    const IndexValueType coordinate =
      Math::RoundHalfIntegerUp<IndexValueType>(continuousIndex[axis]) - cropped.GetIndex()[axis];
    if (coordinate < 0 || static_cast<SizeValueType>(coordinate) >= cropped.GetSize()[axis])
    {
      return false;
    }
    offset += static_cast<SizeValueType>(coordinate) * m_BufferStrides[axis];
  }
  return true;
}

template <typename TInputImage, typename TVoxelLabel>
auto
ImageLabelOracle<TInputImage, TVoxelLabel>::VoxelLabelAt(const Vector3 & point) const -> LabelType
{
  SizeValueType offset = 0;
  return VoxelOffsetAt(point, offset) ? m_LabelImage->GetBufferPointer()[offset] : delaunay_refinement::BackgroundLabel;
}

template <typename TInputImage, typename TVoxelLabel>
auto
ImageLabelOracle<TInputImage, TVoxelLabel>::LabelAt(const Vector3 & point) const -> LabelType
{
  if (m_LabelsAreVoxelwise)
  {
    return VoxelLabelAt(point);
  }
  // ITK's IsInsideBuffer() admits continuous indices up to the largest double below the buffer's last half
  // voxel, where ITK's rounding (2x + 0.5, rounded to even) can give the next index: on an axis whose last
  // index is 0 (a one-slice image), 0.49999999999999994 rounds to 1 and an interpolator that reads the nearest
  // voxel reads past the buffer. Bisection towards the border of the image converges on exactly such points,
  // so the nearest voxel must be in the buffer too.
  const InputImageType &     values = m_CarriedValues ? *m_CarriedValues : *m_Image;
  const PointType            physicalPoint(point.data());
  ContinuousIndex<double, 3> continuousIndex;
  values.TransformPhysicalPointToContinuousIndex(physicalPoint, continuousIndex);
  IndexType nearestIndex;
  nearestIndex.CopyWithRound(continuousIndex);
  if (!m_Interpolator->IsInsideBuffer(continuousIndex) || !values.GetBufferedRegion().IsInside(nearestIndex))
  {
    return delaunay_refinement::BackgroundLabel;
  }
  return m_Selection.LabelOf(m_Interpolator->EvaluateAtContinuousIndex(continuousIndex));
}

template <typename TInputImage, typename TVoxelLabel>
delaunay_refinement::AxisAlignedBox
ImageLabelOracle<TInputImage, TVoxelLabel>::ObjectBounds() const
{
  if (m_NumberOfObjectVoxels == 0)
  {
    return { { { 1.0, 1.0, 1.0 } }, { { 0.0, 0.0, 0.0 } } };
  }
  return m_ObjectBounds;
}

template <typename TInputImage, typename TVoxelLabel>
auto
ImageLabelOracle<TInputImage, TVoxelLabel>::CenterOf(const IndexType & index) const -> Vector3
{
  PointType point;
  m_LabelImage->TransformIndexToPhysicalPoint(index, point);
  return { point[0], point[1], point[2] };
}

/** The interface voxels nearest to the eight voxel centres around `query` (the feature transform is exact at
 * voxel centres only, and on an anisotropic grid the face nearest to a point need not belong to the interface
 * voxel nearest to its nearest centre), as buffer offsets, in the order of the corners (repeats included). */
template <typename TInputImage, typename TVoxelLabel>
auto
ImageLabelOracle<TInputImage, TVoxelLabel>::InterfaceVoxelsAround(const ContinuousIndex<double, 3> & queryIndex) const
  -> InterfaceVoxelCandidates
{
  const auto &  region = m_LabelImage->GetBufferedRegion();
  SizeValueType lowerCornerOffset = 0;
  SizeValueType cornerSteps[3];
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    const double        first = static_cast<double>(region.GetIndex()[axis]);
    const SizeValueType size = region.GetSize()[axis];
    const double        highestLowerCorner = std::max(first, first + static_cast<double>(size) - 2.0);
    const auto          lowerCorner =
      static_cast<SizeValueType>(std::floor(std::clamp(queryIndex[axis], first, highestLowerCorner)) - first);
    lowerCornerOffset += lowerCorner * m_BufferStrides[axis];
    cornerSteps[axis] = lowerCorner + 1 < size ? m_BufferStrides[axis] : 0;
  }
  InterfaceVoxelCandidates candidates{};
  for (unsigned int corner = 0; corner < 8; ++corner)
  {
    SizeValueType offset = lowerCornerOffset;
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      offset += ((corner >> axis) & 1) * cornerSteps[axis];
    }
    candidates[corner] = m_NearestInterfaceVoxel[offset];
  }
  return candidates;
}

/** Of the faces between a candidate interface voxel and a face neighbour of another label, the one whose centre is
 * nearest to `query`: its two voxels; ties go to the voxel with the smaller buffer offset, then to the first face in
 * axis order. Face centres, not the faces' closest points: they lie on the surface that marching cubes and CGAL's
 * labelled-image domain see (half-way between voxel centres), where the corners of the voxels' staircase do not.
 * Works on 32-bit buffer offsets (the padded image has fewer than 2^32 voxels): this is the oracle's hot path. */
template <typename TInputImage, typename TVoxelLabel>
auto
ImageLabelOracle<TInputImage, TVoxelLabel>::NearestInterfaceFace(const Vector3 & query) const -> InterfaceFace
{
  const auto queryIndex =
    m_LabelImage->template TransformPhysicalPointToContinuousIndex<double>(PointType(query.data()));
  const auto &                   region = m_LabelImage->GetBufferedRegion();
  const auto &                   spacing = m_LabelImage->GetSpacing();
  const TVoxelLabel *            labels = m_LabelImage->GetBufferPointer();
  const InterfaceVoxelCandidates candidates = InterfaceVoxelsAround(queryIndex);
  const uint32_t                 strides[3] = { 1,
                                                static_cast<uint32_t>(m_BufferStrides[1]),
                                                static_cast<uint32_t>(m_BufferStrides[2]) };
  const uint32_t                 sizes[3] = { static_cast<uint32_t>(region.GetSize()[0]),
                                              static_cast<uint32_t>(region.GetSize()[1]),
                                              static_cast<uint32_t>(region.GetSize()[2]) };
  uint32_t                       nearestVoxel = 0;
  uint32_t                       nearestNeighbor = 0;
  double                         nearestSquaredDistance = std::numeric_limits<double>::infinity();
  for (unsigned int corner = 0; corner < 8; ++corner)
  {
    const uint32_t voxel = candidates[corner];
    if (std::find(candidates.begin(), candidates.begin() + corner, voxel) != candidates.begin() + corner)
    {
      continue;
    }
    const LabelType               label = labels[voxel];
    const std::array<uint32_t, 3> coordinates = BufferCoordinatesOf(voxel);
    double                        center[3];
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      center[axis] = static_cast<double>(region.GetIndex()[axis]) + static_cast<double>(coordinates[axis]);
    }
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      for (const int step : { -1, 1 })
      {
        const bool     inside = step < 0 ? coordinates[axis] > 0 : coordinates[axis] + 1 < sizes[axis];
        const uint32_t neighbor = step < 0 ? voxel - strides[axis] : voxel + strides[axis];
        if (!inside || labels[neighbor] == label)
        {
          continue;
        }
        // In index space the metric is diagonal (orthonormal direction, one spacing per axis).
        double squaredDistance = 0.0;
        for (unsigned int other = 0; other < 3; ++other)
        {
          const double faceCenter = center[other] + (other == axis ? 0.5 * step : 0.0);
          const double difference = (faceCenter - queryIndex[other]) * spacing[other];
          squaredDistance += difference * difference;
        }
        if (squaredDistance < nearestSquaredDistance ||
            (squaredDistance == nearestSquaredDistance && voxel < nearestVoxel))
        {
          nearestSquaredDistance = squaredDistance;
          nearestVoxel = voxel;
          nearestNeighbor = neighbor;
        }
      }
    }
  }
  return { m_LabelImage->ComputeIndex(static_cast<OffsetValueType>(nearestVoxel)),
           m_LabelImage->ComputeIndex(static_cast<OffsetValueType>(nearestNeighbor)),
           std::sqrt(nearestSquaredDistance) };
}

template <typename TInputImage, typename TVoxelLabel>
bool
ImageLabelOracle<TInputImage, TVoxelLabel>::NearestInterfaceVoxel(const IndexType & index, IndexType & nearest) const
{
  const auto & region = m_LabelImage->GetBufferedRegion();
  if (m_NearestInterfaceVoxel.empty() || !region.IsInside(index))
  {
    return false;
  }
  const uint32_t voxel = m_NearestInterfaceVoxel[static_cast<SizeValueType>(m_LabelImage->ComputeOffset(index))];
  if (voxel == std::numeric_limits<uint32_t>::max())
  {
    return false;
  }
  nearest = m_LabelImage->ComputeIndex(static_cast<OffsetValueType>(voxel));
  return true;
}

template <typename TInputImage, typename TVoxelLabel>
std::array<uint32_t, 3>
ImageLabelOracle<TInputImage, TVoxelLabel>::BufferCoordinatesOf(uint32_t offset) const
{
  const auto stride1 = static_cast<uint32_t>(m_BufferStrides[1]);
  const auto size1 = static_cast<uint32_t>(m_LabelImage->GetBufferedRegion().GetSize()[1]);
  return { offset % stride1, (offset / stride1) % size1, offset / static_cast<uint32_t>(m_BufferStrides[2]) };
}

template <typename TInputImage, typename TVoxelLabel>
double
ImageLabelOracle<TInputImage, TVoxelLabel>::IndexDistance(const double * a, const double * b) const
{
  // In index space the metric is diagonal (orthonormal direction, one spacing per axis).
  const auto & spacing = m_LabelImage->GetSpacing();
  double       squaredDistance = 0.0;
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    const double difference = (a[axis] - b[axis]) * spacing[axis];
    squaredDistance += difference * difference;
  }
  return std::sqrt(squaredDistance);
}

/** Let v be the voxel centre nearest to the query q (one of the eight corners NearestInterfaceFace() looks
 * around), w its nearest interface voxel and h half the largest spacing (a face centre is within h of its voxel's
 * centre). Upper: w's interface faces are among those searched, and each is within |q - w| + h. Lower: every face
 * centre is within h of an interface voxel centre, and none of those is nearer to v than w (the feature transform is
 * exact at voxel centres), so none is nearer to q than |v - w| - |q - v|. */
template <typename TInputImage, typename TVoxelLabel>
delaunay_refinement::SurfaceDistanceBounds
ImageLabelOracle<TInputImage, TVoxelLabel>::BoundSurfaceDistance(const Vector3 & query) const
{
  if (!m_LabelsAreVoxelwise || m_NumberOfObjectVoxels == 0)
  {
    return {};
  }
  const auto queryIndex =
    m_LabelImage->template TransformPhysicalPointToContinuousIndex<double>(PointType(query.data()));
  const auto &   region = m_LabelImage->GetBufferedRegion();
  const uint32_t strides[3] = { 1,
                                static_cast<uint32_t>(m_BufferStrides[1]),
                                static_cast<uint32_t>(m_BufferStrides[2]) };
  uint32_t       voxelOffset = 0;
  double         voxel[3];
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    const double first = static_cast<double>(region.GetIndex()[axis]);
    const double lastCoordinate = static_cast<double>(region.GetSize()[axis]) - 1.0;
    // Non-negative once clamped, so truncating rounds (half up).
    const auto coordinate = static_cast<uint32_t>(std::clamp(queryIndex[axis] - first, 0.0, lastCoordinate) + 0.5);
    voxel[axis] = first + static_cast<double>(coordinate);
    voxelOffset += coordinate * strides[axis];
  }
  const std::array<uint32_t, 3> interfaceCoordinates = BufferCoordinatesOf(m_NearestInterfaceVoxel[voxelOffset]);
  double                        interfaceVoxel[3];
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    interfaceVoxel[axis] =
      static_cast<double>(region.GetIndex()[axis]) + static_cast<double>(interfaceCoordinates[axis]);
  }
  const auto & spacing = m_LabelImage->GetSpacing();
  const double halfLargestSpacing = 0.5 * *std::max_element(spacing.Begin(), spacing.End());
  const double queryToVoxel = IndexDistance(queryIndex.GetDataPointer(), voxel);
  const double voxelToInterface = IndexDistance(voxel, interfaceVoxel);
  const double queryToInterface = IndexDistance(queryIndex.GetDataPointer(), interfaceVoxel);
  // Far above the rounding of these sums and of the search's own distances.
  const double rounding = 1e-9 * (queryToVoxel + queryToInterface + halfLargestSpacing);
  return { std::max(0.0, voxelToInterface - queryToVoxel - halfLargestSpacing - rounding),
           queryToInterface + halfLargestSpacing + rounding };
}

template <typename TInputImage, typename TVoxelLabel>
auto
ImageLabelOracle<TInputImage, TVoxelLabel>::FaceCenterOf(const IndexType & voxel, const IndexType & neighbor) const
  -> Vector3
{
  ContinuousIndex<double, 3> faceCenter;
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    faceCenter[axis] = 0.5 * (static_cast<double>(voxel[axis]) + static_cast<double>(neighbor[axis]));
  }
  PointType point;
  m_LabelImage->TransformContinuousIndexToPhysicalPoint(faceCenter, point);
  return { point[0], point[1], point[2] };
}

template <typename TInputImage, typename TVoxelLabel>
delaunay_refinement::SurfacePoint
ImageLabelOracle<TInputImage, TVoxelLabel>::ClosestSurfacePoint(const Vector3 & query) const
{
  // The vector operators live in the core's namespace, which argument-dependent lookup on std::array misses.
  using delaunay_refinement::Distance;
  using delaunay_refinement::operator+;
  using delaunay_refinement::operator*;
  if (m_NumberOfObjectVoxels == 0)
  {
    return { query, std::numeric_limits<double>::infinity() };
  }
  const InterfaceFace face = NearestInterfaceFace(query);
  const Vector3       middle = FaceCenterOf(face.voxel, face.neighbor);
  if (m_LabelsAreVoxelwise)
  {
    // Nearest-neighbour labels change exactly half-way between the two voxel centres.
    return { middle, face.distance };
  }
  const Vector3 inside = CenterOf(face.voxel);
  const Vector3 across = CenterOf(face.neighbor);
  // A smoothing interpolator can disagree with the voxel labels; then bracket the surface from the query.
  for (const auto & bracket :
       { std::make_pair(inside, across), std::make_pair(query, inside), std::make_pair(query, across) })
  {
    if (LabelAt(bracket.first) != LabelAt(bracket.second))
    {
      const Vector3 crossing = SurfaceCrossing(bracket.first, bracket.second);
      return { crossing, Distance(query, crossing) };
    }
  }
  return { middle, Distance(query, middle) };
}

template <typename TInputImage, typename TVoxelLabel>
double
ImageLabelOracle<TInputImage, TVoxelLabel>::SurfaceTolerance() const
{
  return m_SurfaceTolerance;
}


} // namespace itk

#endif
