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
#ifndef itkImageLabelSelection_h
#define itkImageLabelSelection_h

#include "DelaunayRefinementLargeBuffers.h"
#include "DelaunayRefinementTypes.h"

#include "itkImage.h"
#include "itkImageRegionConstIterator.h"
#include "itkImageRegionIterator.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <utility>
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
  /** With nearest-neighbour labels: remove the voxel pinches of every label, the background included (see
   * delaunay_refinement::RemoveVoxelPinches), so that every label's voxel surface is a 2-manifold. Off here (the
   * voxels as they are); the filter turns it on. */
  bool joinDiagonalVoxels{ false };
  /** With nearest-neighbour labels: open every label, the background included, with a ball of this radius
   * (physical units) before anything else (see delaunay_refinement::RegularizeLabels). 0 = the voxels as they
   * are. */
  double regularizationRadius{ 0.0 };
  /** Asked now and then during the regularisation: returning false aborts it (RefinementAborted). */
  std::function<bool()> keepGoing;
  /** The set-up's passes over every voxel (the regularisation's opening and distance transform, the
   * nearest-interface map) run on up to this many threads; the result does not depend on it. The filter passes its
   * number of work units. */
  unsigned int numberOfThreads{ 1 };
};

/** \class ImageLabelSelection
 * \brief The label a voxel value stands for, by an ImageLabelMapping's selection, merging or iso-value.
 *
 * Apart from ImageLabelOracle so that the filter can select the labels from the input again once the oracle and
 * its per-voxel buffers are gone (DelaunayImageToMeshFilter::GetSelectedLabelImage), instead of keeping a copy as
 * large as the label image through the refinement.
 *
 * \ingroup DelaunayImageToMesh
 */
class ImageLabelSelection
{
public:
  using LabelType = delaunay_refinement::Label;
  using LabelImageType = Image<LabelType, 3>;

  explicit ImageLabelSelection(const ImageLabelMapping & mapping)
    : m_SelectedLabels(mapping.selectedLabels)
    , m_MergeLabels(mapping.mergeLabels)
    , m_UseIsoValue(mapping.useIsoValue)
    , m_IsoValue(mapping.isoValue)
  {
    std::sort(m_SelectedLabels.begin(), m_SelectedLabels.end());
  }

  /** The label a voxel value maps to. */
  LabelType
  LabelOf(double value) const
  {
    if (m_UseIsoValue)
    {
      return value >= m_IsoValue ? 1 : delaunay_refinement::BackgroundLabel;
    }
    if (!std::isfinite(value))
    {
      return delaunay_refinement::BackgroundLabel;
    }
    constexpr double largestLabel = static_cast<double>(std::numeric_limits<LabelType>::max());
    const auto       label = static_cast<LabelType>(std::lround(std::clamp(value, -largestLabel, largestLabel)));
    if (label == delaunay_refinement::BackgroundLabel ||
        !(m_SelectedLabels.empty() || std::binary_search(m_SelectedLabels.begin(), m_SelectedLabels.end(), label)))
    {
      return delaunay_refinement::BackgroundLabel;
    }
    return m_MergeLabels ? 1 : label;
  }

  /** The last value looked up and its label: label images are runs of equal values, a run's label is looked up
   * once. */
  struct Memo
  {
    bool      valid{ false };
    double    value{ 0.0 };
    LabelType label{ delaunay_refinement::BackgroundLabel };
  };

  LabelType
  LabelOfRemembering(double value, Memo & memo) const
  {
    if (!(memo.valid && value == memo.value))
    {
      memo = { true, value, LabelOf(value) };
    }
    return memo.label;
  }

  /** A new image over `region`, in the geometry of `image`: each voxel the label of the voxel of `image` there,
   * background outside `image`'s buffered region. */
  template <typename TInputImage>
  typename LabelImageType::Pointer
  SelectedLabelImage(const TInputImage & image, const typename LabelImageType::RegionType & region) const
  {
    auto labels = LabelImageType::New();
    labels->SetRegions(region);
    labels->SetOrigin(image.GetOrigin());
    labels->SetSpacing(image.GetSpacing());
    labels->SetDirection(image.GetDirection());
    labels->Allocate();
    delaunay_refinement::AdviseHugePages(labels->GetBufferPointer(), region.GetNumberOfPixels() * sizeof(LabelType));
    labels->FillBuffer(delaunay_refinement::BackgroundLabel);
    auto insideImage = region;
    insideImage.Crop(image.GetBufferedRegion());
    Memo                                  memo;
    ImageRegionConstIterator<TInputImage> input(&image, insideImage);
    ImageRegionIterator<LabelImageType>   output(labels, insideImage);
    for (; !input.IsAtEnd(); ++input, ++output)
    {
      output.Set(LabelOfRemembering(static_cast<double>(input.Get()), memo));
    }
    return labels;
  }

private:
  std::vector<LabelType> m_SelectedLabels;
  bool                   m_MergeLabels;
  bool                   m_UseIsoValue;
  double                 m_IsoValue;
};

} // namespace itk

#endif
