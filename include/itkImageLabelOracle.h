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

#include "DelaunayRefinementOracle.h"

#include "itkDanielssonDistanceMapImageFilter.h"
#include "itkImage.h"
#include "itkInterpolateImageFunction.h"

#include <vector>

namespace itk
{

/** How voxel values become the labels the refinement sees. */
struct ImageLabelMapping
{
  /** The labels to mesh; empty = every non-zero label. */
  std::vector<delaunay_refinement::Label> selectedLabels;
  /** Mesh every selected label as one object, labelled 1 (a mask whose values encode something else). */
  bool mergeLabels{ false };
  /** Gray values: label 1 where the interpolated value is >= isoValue, 0 elsewhere. */
  bool   useIsoValue{ false };
  double isoValue{ 0.0 };
};

/** \class ImageLabelOracle
 * \brief The refinement's view of an image: labels from an ITK interpolator, closest surface points from a
 * Danielsson feature map of the label interfaces, snapped onto the interpolator's surface by bisection.
 *
 * Labels: in label mode the interpolated value is rounded to a label and kept if it is selected (every
 * non-zero label when none is selected); in iso-value mode the label is 1 where the interpolated value is
 * >= the iso-value. Outside the image's buffered region every label is 0, so an object touching the border
 * is closed as if the image continued with background. All geometry is in physical space (spacing, origin
 * and direction of the image).
 *
 * Not an itk::Object: it is the adaptor between an image and the ITK-free refinement core.
 *
 * \ingroup DelaunayImageToMesh
 */
template <typename TInputImage>
class ITK_TEMPLATE_EXPORT ImageLabelOracle : public delaunay_refinement::LabelOracle
{
public:
  static constexpr unsigned int ImageDimension = TInputImage::ImageDimension;
  static_assert(ImageDimension == 3, "ImageLabelOracle needs a 3-D image");

  using InputImageType = TInputImage;
  using InterpolatorType = InterpolateImageFunction<InputImageType, double>;
  using LabelType = delaunay_refinement::Label;
  using LabelImageType = Image<LabelType, 3>;
  using InterfaceImageType = Image<unsigned char, 3>;
  using DistanceImageType = Image<float, 3>;
  using FeatureMapFilterType = DanielssonDistanceMapImageFilter<InterfaceImageType, DistanceImageType>;
  using FeatureOffsetImageType = typename FeatureMapFilterType::VectorImageType;
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

  double
  SurfaceTolerance() const override;

  /** Number of voxels that carry a selected label (or are >= the iso-value). */
  SizeValueType
  GetNumberOfObjectVoxels() const
  {
    return m_NumberOfObjectVoxels;
  }

  /** The voxel labels the oracle sees, padded by one voxel of background all around. */
  const LabelImageType *
  GetLabelImage() const
  {
    return m_LabelImage;
  }

  /** The label a voxel value maps to. */
  LabelType
  MapValue(double value) const;

private:
  void
  BuildLabelImage(const InputImageType * image);
  void
  BuildFeatureMap();
  Vector3
  CenterOf(const IndexType & index) const;
  IndexType
  NearestIndexInGrid(const Vector3 & point) const;

  typename InputImageType::ConstPointer    m_Image;
  typename InterpolatorType::ConstPointer  m_Interpolator;
  ImageLabelMapping                        m_Mapping;
  typename LabelImageType::Pointer         m_LabelImage;
  typename FeatureOffsetImageType::Pointer m_FeatureOffsets;
  delaunay_refinement::AxisAlignedBox      m_ObjectBounds;
  SizeValueType                            m_NumberOfObjectVoxels{ 0 };
  double                                   m_SurfaceTolerance{ 0.0 };
};

} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkImageLabelOracle.hxx"
#endif

#endif
