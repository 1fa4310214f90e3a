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

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <type_traits>
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
  /** With nearest-neighbour labels, or an iso-value of linear interpolation (whose voxels carry their labels into
   * their values: ImageLabelOracle): remove the voxel pinches of every label, the background included (see
   * delaunay_refinement::RemoveVoxelPinches), so that every label's voxel surface is a 2-manifold. Off here (the
   * voxels as they are); the filter turns it on. */
  bool joinDiagonalVoxels{ false };
  /** With nearest-neighbour labels, or an iso-value of linear interpolation: open every label, the background
   * included, with a ball of this radius (physical units) before anything else (see
   * delaunay_refinement::RegularizeLabels). 0 = the voxels as they are. */
  double regularizationRadius{ 0.0 };
  /** Asked now and then during the oracle's set-up (between its passes over the voxels, and between rounds of a few
   * million voxels of the nearest-interface map's passes) with the fraction of the set-up done, a rough monotone
   * estimate in [0, 1]: returning false aborts it (RefinementAborted). On a large image meshed coarsely the set-up is
   * most of the run (bench/README.md, "At 1e3134b": 3.4 of 4 s on 38 M voxels), so the filter reports it as progress.
   */
  std::function<bool(double setUpFraction)> keepGoing;
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
    m_SelectedLabels.erase(std::unique(m_SelectedLabels.begin(), m_SelectedLabels.end()), m_SelectedLabels.end());
  }

  /** The largest label; the labels are the integers of magnitude up to it (the output's cell data holds them). */
  static constexpr double LargestLabel = static_cast<double>(std::numeric_limits<LabelType>::max());

  /** Whether the value rounds to a label (NaN and infinities do not). */
  static constexpr bool
  RoundsToALabel(double value)
  {
    return (value < 0.0 ? -value : value) < LargestLabel + 0.5;
  }

  /** The label nearest to a value that RoundsToALabel(). */
  static LabelType
  NearestLabel(double value)
  {
    return static_cast<LabelType>(std::lround(value));
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
    if (!RoundsToALabel(value))
    {
      // It rounds to no label, so no selected one (the filter refuses such a value where each label is a tissue);
      // merged without a selection, every non-zero value is the object.
      return m_MergeLabels && m_SelectedLabels.empty() ? 1 : delaunay_refinement::BackgroundLabel;
    }
    const LabelType label = NearestLabel(value);
    if (label == delaunay_refinement::BackgroundLabel ||
        !(m_SelectedLabels.empty() || std::binary_search(m_SelectedLabels.begin(), m_SelectedLabels.end(), label)))
    {
      return delaunay_refinement::BackgroundLabel;
    }
    return m_MergeLabels ? 1 : label;
  }

  /** The label of every value of a pixel type, as LabelOf() gives it, without its cost per voxel: 8-bit values
   * from a table of all 256, others by remembering the last value (label images are runs of equal values). */
  template <typename TPixel>
  class Lookup
  {
  public:
    explicit Lookup(const ImageLabelSelection & selection)
      : m_Selection(selection)
    {
      if constexpr (UsesTable)
      {
        for (unsigned int value = 0; value < m_Table.size(); ++value)
        {
          m_Table[value] = selection.LabelOf(static_cast<double>(static_cast<TPixel>(value)));
        }
      }
    }

    LabelType
    operator()(TPixel value)
    {
      if constexpr (UsesTable)
      {
        return m_Table[static_cast<unsigned char>(value)];
      }
      else
      {
        // NaN never equals the last value, and is looked up each time: LabelOf() makes it background.
        if (!(m_Valid && value == m_LastValue))
        {
          m_Valid = true;
          m_LastValue = value;
          m_LastLabel = m_Selection.LabelOf(static_cast<double>(value));
        }
        return m_LastLabel;
      }
    }

  private:
    static constexpr bool UsesTable = std::is_integral_v<TPixel> && sizeof(TPixel) == 1;

    const ImageLabelSelection & m_Selection;
    std::array<LabelType, 256>  m_Table{};
    bool                        m_Valid{ false };
    TPixel                      m_LastValue{};
    LabelType                   m_LastLabel{ delaunay_refinement::BackgroundLabel };
  };

  /** Calls `f(row, first, length)` for each row along x of `region`, which lies inside `image`'s buffered region:
   * `row` points at the pixel at index `first`, the row's first, followed by the row's other `length` - 1 along x.
   * A pass over raw rows, where an image iterator's bookkeeping per voxel was most of the cost of selecting the
   * labels. */
  template <typename TImage, typename TFunction>
  static void
  ForEachRow(TImage & image, const ImageRegion<3> & region, TFunction && f)
  {
    const SizeValueType length = region.GetSize(0);
    if (region.GetNumberOfPixels() == 0)
    {
      return;
    }
    for (IndexValueType k = 0; k < static_cast<IndexValueType>(region.GetSize(2)); ++k)
    {
      for (IndexValueType j = 0; j < static_cast<IndexValueType>(region.GetSize(1)); ++j)
      {
        Index<3> first = region.GetIndex();
        first[1] += j;
        first[2] += k;
        f(image.GetBufferPointer() + image.ComputeOffset(first), first, length);
      }
    }
  }

  /** The bytes a voxel needs to store every label this selection gives the voxels of `image` (1, 2 or 4: uint8_t,
   * uint16_t or LabelType, SelectedLabelImage()'s TVoxelLabel): one for an iso-value, merged labels, or labels within
   * 0-255; two for labels within 0-65535; four for the rest (negative labels, larger ones). From the selected labels
   * when there are some, else from the pixel type where it decides (8-bit unsigned), else from a pass over the image
   * (16-bit and float segmentations, as NIfTI and NRRD files often store them, mostly hold labels below 256). */
  template <typename TInputImage>
  unsigned int
  BytesPerVoxelLabel(const TInputImage & image) const
  {
    using PixelType = typename TInputImage::PixelType;
    if (m_UseIsoValue || m_MergeLabels)
    {
      return 1;
    }
    LabelType lowest = delaunay_refinement::BackgroundLabel;
    LabelType highest = delaunay_refinement::BackgroundLabel;
    if (!m_SelectedLabels.empty())
    {
      lowest = std::min(lowest, m_SelectedLabels.front());
      highest = std::max(highest, m_SelectedLabels.back());
    }
    else if constexpr (std::is_integral_v<PixelType> && std::is_unsigned_v<PixelType> && sizeof(PixelType) == 1)
    {
      highest = static_cast<LabelType>(std::numeric_limits<PixelType>::max());
    }
    else
    {
      Lookup<PixelType> lookup(*this);
      ForEachRow(image, image.GetBufferedRegion(), [&](const PixelType * row, const Index<3> &, SizeValueType length) {
        for (SizeValueType i = 0; i < length; ++i)
        {
          const LabelType label = lookup(row[i]);
          lowest = std::min(lowest, label);
          highest = std::max(highest, label);
        }
      });
    }
    if (lowest >= 0 && highest <= std::numeric_limits<uint8_t>::max())
    {
      return 1;
    }
    return lowest >= 0 && highest <= std::numeric_limits<uint16_t>::max() ? 2 : 4;
  }

  /** The selected labels that no voxel of `image`'s buffered region rounds to, in increasing order: nothing of them
   * can be in the mesh, and a selection is how a user says what must be (a label mistyped, or a tissue another
   * segmentation of the series lacks). Empty without a selection and with an iso-value, which selects no label. One
   * pass over the raw rows that looks a value up only where it changes (label images are runs of equal values), and
   * stops once every selected label is found. */
  template <typename TInputImage>
  std::vector<LabelType>
  SelectedLabelsNotIn(const TInputImage & image) const
  {
    using PixelType = typename TInputImage::PixelType;
    if (m_UseIsoValue || m_SelectedLabels.empty())
    {
      return {};
    }
    std::vector<bool> found(m_SelectedLabels.size(), false);
    std::size_t       missing = m_SelectedLabels.size();
    bool              valid = false;
    PixelType         last{};
    ForEachRow(image, image.GetBufferedRegion(), [&](const PixelType * row, const Index<3> &, SizeValueType length) {
      for (SizeValueType i = 0; i < length && missing > 0; ++i)
      {
        // NaN never equals the last value, and rounds to no label.
        if (valid && row[i] == last)
        {
          continue;
        }
        valid = true;
        last = row[i];
        const double value = static_cast<double>(row[i]);
        if (!RoundsToALabel(value))
        {
          continue;
        }
        const LabelType label = NearestLabel(value);
        const auto      at = std::lower_bound(m_SelectedLabels.begin(), m_SelectedLabels.end(), label);
        if (at != m_SelectedLabels.end() && *at == label && !found[at - m_SelectedLabels.begin()])
        {
          found[at - m_SelectedLabels.begin()] = true;
          --missing;
        }
      }
    });
    std::vector<LabelType> notFound;
    for (std::size_t i = 0; i < m_SelectedLabels.size(); ++i)
    {
      if (!found[i])
      {
        notFound.push_back(m_SelectedLabels[i]);
      }
    }
    return notFound;
  }

  /** A new image over `region`, in the geometry of `image`: each voxel the label of the voxel of `image` there,
   * background outside `image`'s buffered region; stored as TVoxelLabel, which must hold every label
   * (BytesPerVoxelLabel()). */
  template <typename TVoxelLabel = LabelType, typename TInputImage>
  typename Image<TVoxelLabel, 3>::Pointer
  SelectedLabelImage(const TInputImage & image, const typename LabelImageType::RegionType & region) const
  {
    static_assert(delaunay_refinement::IsVoxelLabelType<TVoxelLabel>,
                  "labels are stored as Label, uint16_t or uint8_t");
    using VoxelLabelImageType = Image<TVoxelLabel, 3>;
    auto labels = VoxelLabelImageType::New();
    labels->SetRegions(region);
    labels->SetOrigin(image.GetOrigin());
    labels->SetSpacing(image.GetSpacing());
    labels->SetDirection(image.GetDirection());
    labels->Allocate();
    delaunay_refinement::AdviseHugePages(labels->GetBufferPointer(), region.GetNumberOfPixels() * sizeof(TVoxelLabel));
    auto insideImage = region;
    // Crop() leaves a region that misses the image's as it was, and says so.
    const bool meetsTheImage = insideImage.Crop(image.GetBufferedRegion());
    if (!meetsTheImage || insideImage != region)
    {
      labels->FillBuffer(delaunay_refinement::BackgroundLabel);
    }
    if (!meetsTheImage)
    {
      return labels;
    }
    Lookup<typename TInputImage::PixelType> lookup(*this);
    VoxelLabelImageType &                   output = *labels;
    ForEachRow(image, insideImage, [&lookup, &output](const auto * row, const Index<3> & first, SizeValueType length) {
      TVoxelLabel * const labelRow = output.GetBufferPointer() + output.ComputeOffset(first);
      for (SizeValueType i = 0; i < length; ++i)
      {
        labelRow[i] = static_cast<TVoxelLabel>(lookup(row[i]));
      }
    });
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
