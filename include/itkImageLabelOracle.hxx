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

#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkImageRegionIteratorWithIndex.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace itk
{

template <typename TInputImage>
ImageLabelOracle<TInputImage>::ImageLabelOracle(const InputImageType * image, const InterpolatorType * interpolator,
                                                ImageLabelMapping mapping)
  : m_Image(image)
  , m_Interpolator(interpolator)
  , m_Mapping(std::move(mapping))
{
  std::sort(m_Mapping.selectedLabels.begin(), m_Mapping.selectedLabels.end());
  const auto & spacing = image->GetSpacing();
  m_SurfaceTolerance = 1e-4 * *std::min_element(spacing.Begin(), spacing.End());
  BuildLabelImage(image);
  if (m_NumberOfObjectVoxels > 0)
  {
    BuildFeatureMap();
  }
}

template <typename TInputImage>
auto
ImageLabelOracle<TInputImage>::MapValue(double value) const -> LabelType
{
  if (m_Mapping.useIsoValue)
  {
    return value >= m_Mapping.isoValue ? 1 : delaunay_refinement::BackgroundLabel;
  }
  if (!std::isfinite(value))
  {
    return delaunay_refinement::BackgroundLabel;
  }
  constexpr double largestLabel = static_cast<double>(std::numeric_limits<LabelType>::max());
  const auto       label = static_cast<LabelType>(std::lround(std::clamp(value, -largestLabel, largestLabel)));
  const auto &     selected = m_Mapping.selectedLabels;
  if (label == delaunay_refinement::BackgroundLabel ||
      !(selected.empty() || std::binary_search(selected.begin(), selected.end(), label)))
  {
    return delaunay_refinement::BackgroundLabel;
  }
  return m_Mapping.mergeLabels ? 1 : label;
}

template <typename TInputImage>
void
ImageLabelOracle<TInputImage>::BuildLabelImage(const InputImageType * image)
{
  const auto & buffered = image->GetBufferedRegion();
  auto         padded = buffered;
  padded.PadByRadius(1);
  m_LabelImage = LabelImageType::New();
  m_LabelImage->SetRegions(padded);
  m_LabelImage->SetOrigin(image->GetOrigin());
  m_LabelImage->SetSpacing(image->GetSpacing());
  m_LabelImage->SetDirection(image->GetDirection());
  m_LabelImage->Allocate();
  m_LabelImage->FillBuffer(delaunay_refinement::BackgroundLabel);

  IndexType lowest;
  IndexType highest;
  lowest.Fill(NumericTraits<IndexValueType>::max());
  highest.Fill(NumericTraits<IndexValueType>::NonpositiveMin());
  for (ImageRegionConstIteratorWithIndex<InputImageType> it(image, buffered); !it.IsAtEnd(); ++it)
  {
    const LabelType label = MapValue(static_cast<double>(it.Get()));
    m_LabelImage->SetPixel(it.GetIndex(), label);
    if (label != delaunay_refinement::BackgroundLabel)
    {
      ++m_NumberOfObjectVoxels;
      for (unsigned int axis = 0; axis < 3; ++axis)
      {
        lowest[axis] = std::min(lowest[axis], it.GetIndex()[axis]);
        highest[axis] = std::max(highest[axis], it.GetIndex()[axis]);
      }
    }
  }
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

template <typename TInputImage>
void
ImageLabelOracle<TInputImage>::BuildFeatureMap()
{
  auto interfaces = InterfaceImageType::New();
  interfaces->CopyInformation(m_LabelImage);
  interfaces->SetRegions(m_LabelImage->GetBufferedRegion());
  interfaces->Allocate();
  interfaces->FillBuffer(0);
  const auto & region = m_LabelImage->GetBufferedRegion();
  for (ImageRegionIteratorWithIndex<InterfaceImageType> it(interfaces, region); !it.IsAtEnd(); ++it)
  {
    const IndexType index = it.GetIndex();
    const LabelType label = m_LabelImage->GetPixel(index);
    for (unsigned int axis = 0; axis < 3 && it.Get() == 0; ++axis)
    {
      for (const int step : { -1, 1 })
      {
        IndexType neighbor = index;
        neighbor[axis] += step;
        if (region.IsInside(neighbor) && m_LabelImage->GetPixel(neighbor) != label)
        {
          it.Set(1);
          break;
        }
      }
    }
  }
  auto featureMap = FeatureMapFilterType::New();
  featureMap->SetInput(interfaces);
  featureMap->InputIsBinaryOn();
  featureMap->UseImageSpacingOn();
  featureMap->Update();
  m_FeatureOffsets = featureMap->GetVectorDistanceMap();
}

template <typename TInputImage>
auto
ImageLabelOracle<TInputImage>::LabelAt(const Vector3 & point) const -> LabelType
{
  const PointType physicalPoint(point.data());
  if (!m_Interpolator->IsInsideBuffer(physicalPoint))
  {
    return delaunay_refinement::BackgroundLabel;
  }
  return MapValue(m_Interpolator->Evaluate(physicalPoint));
}

template <typename TInputImage>
delaunay_refinement::AxisAlignedBox
ImageLabelOracle<TInputImage>::ObjectBounds() const
{
  if (m_NumberOfObjectVoxels == 0)
  {
    return { { { 1.0, 1.0, 1.0 } }, { { 0.0, 0.0, 0.0 } } };
  }
  return m_ObjectBounds;
}

template <typename TInputImage>
auto
ImageLabelOracle<TInputImage>::CenterOf(const IndexType & index) const -> Vector3
{
  PointType point;
  m_LabelImage->TransformIndexToPhysicalPoint(index, point);
  return { point[0], point[1], point[2] };
}

template <typename TInputImage>
auto
ImageLabelOracle<TInputImage>::NearestIndexInGrid(const Vector3 & point) const -> IndexType
{
  ContinuousIndex<double, 3> continuousIndex;
  m_LabelImage->TransformPhysicalPointToContinuousIndex(PointType(point.data()), continuousIndex);
  const auto & region = m_LabelImage->GetBufferedRegion();
  IndexType    index;
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    const double first = static_cast<double>(region.GetIndex()[axis]);
    const double last = first + static_cast<double>(region.GetSize()[axis]) - 1.0;
    index[axis] = static_cast<IndexValueType>(std::lround(std::clamp(continuousIndex[axis], first, last)));
  }
  return index;
}

template <typename TInputImage>
delaunay_refinement::SurfacePoint
ImageLabelOracle<TInputImage>::ClosestSurfacePoint(const Vector3 & query) const
{
  // The vector operators live in the core's namespace, which argument-dependent lookup on std::array misses.
  using delaunay_refinement::Distance;
  using delaunay_refinement::SquaredNorm;
  using delaunay_refinement::operator+;
  using delaunay_refinement::operator-;
  using delaunay_refinement::operator*;
  if (m_NumberOfObjectVoxels == 0)
  {
    return { query, std::numeric_limits<double>::infinity() };
  }
  // The nearest interface voxel, then its neighbour across the interface nearest to the query: the surface
  // crosses the segment between their centres.
  const IndexType start = NearestIndexInGrid(query);
  const IndexType interfaceVoxel = start + m_FeatureOffsets->GetPixel(start);
  const LabelType interfaceLabel = m_LabelImage->GetPixel(interfaceVoxel);
  const auto &    region = m_LabelImage->GetBufferedRegion();
  const Vector3   inside = CenterOf(interfaceVoxel);
  Vector3         across = inside;
  double          nearestSquaredDistance = std::numeric_limits<double>::infinity();
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    for (const int step : { -1, 1 })
    {
      IndexType neighbor = interfaceVoxel;
      neighbor[axis] += step;
      if (!region.IsInside(neighbor) || m_LabelImage->GetPixel(neighbor) == interfaceLabel)
      {
        continue;
      }
      const Vector3 center = CenterOf(neighbor);
      const double  squaredDistance = SquaredNorm(query - 0.5 * (inside + center));
      if (squaredDistance < nearestSquaredDistance)
      {
        nearestSquaredDistance = squaredDistance;
        across = center;
      }
    }
  }
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
  const Vector3 middle = 0.5 * (inside + across);
  return { middle, Distance(query, middle) };
}

template <typename TInputImage>
double
ImageLabelOracle<TInputImage>::SurfaceTolerance() const
{
  return m_SurfaceTolerance;
}

} // namespace itk

#endif
