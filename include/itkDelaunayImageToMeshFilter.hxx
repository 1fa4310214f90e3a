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
#ifndef itkDelaunayImageToMeshFilter_hxx
#define itkDelaunayImageToMeshFilter_hxx

#include "itkDelaunayImageToMeshFilter.h"
#include "itkImageLabelOracle.h"
#include "itkImageLabelSelection.h"

#include "itkLinearInterpolateImageFunction.h"
#include "itkNearestNeighborInterpolateImageFunction.h"
#include "itkTetrahedronCell.h"
#include "itkTriangleCell.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <memory>
#include <sstream>

namespace itk
{

template <typename TInputImage, typename TOutputMesh>
DelaunayImageToMeshFilter<TInputImage, TOutputMesh>::DelaunayImageToMeshFilter()
{
  this->SetNumberOfRequiredOutputs(2);
  this->ProcessObject::SetNthOutput(1, this->MakeOutput(1));
}

template <typename TInputImage, typename TOutputMesh>
void
DelaunayImageToMeshFilter<TInputImage, TOutputMesh>::SetIsoValue(double isoValue)
{
  if (m_IsoValue != isoValue || !m_UseIsoValue)
  {
    m_IsoValue = isoValue;
    m_UseIsoValue = true;
    this->Modified();
  }
}

template <typename TInputImage, typename TOutputMesh>
void
DelaunayImageToMeshFilter<TInputImage, TOutputMesh>::SetLabels(const LabelListType & labels)
{
  if (m_Labels != labels)
  {
    m_Labels = labels;
    this->Modified();
  }
}

template <typename TInputImage, typename TOutputMesh>
void
DelaunayImageToMeshFilter<TInputImage, TOutputMesh>::AddLabel(LabelType label)
{
  m_Labels.push_back(label);
  this->Modified();
}

template <typename TInputImage, typename TOutputMesh>
void
DelaunayImageToMeshFilter<TInputImage, TOutputMesh>::ClearLabels()
{
  if (!m_Labels.empty())
  {
    m_Labels.clear();
    this->Modified();
  }
}

template <typename TInputImage, typename TOutputMesh>
auto
DelaunayImageToMeshFilter<TInputImage, TOutputMesh>::GetInterfaceLabel(SizeValueType cellId, unsigned int side) const
  -> LabelType
{
  if (cellId >= m_InterfaceLabels.size() || side > 1)
  {
    itkExceptionMacro(<< "GetInterfaceLabel(" << cellId << ", " << side << "): the valid ranges are cellId in [0, "
                      << m_InterfaceLabels.size() << ") and side in {0, 1}.");
  }
  return m_InterfaceLabels[cellId][side];
}

template <typename TInputImage, typename TOutputMesh>
auto
DelaunayImageToMeshFilter<TInputImage, TOutputMesh>::GetInterfaceMesh() -> OutputMeshType *
{
  return itkDynamicCastInDebugMode<OutputMeshType *>(this->ProcessObject::GetOutput(1));
}

template <typename TInputImage, typename TOutputMesh>
void
DelaunayImageToMeshFilter<TInputImage, TOutputMesh>::ValidateInput(const InputImageType * image) const
{
  if (image == nullptr)
  {
    itkExceptionMacro(<< "The input image is not set.");
  }
  const auto & region = image->GetBufferedRegion();
  if (region.GetNumberOfPixels() == 0)
  {
    itkExceptionMacro(<< "The input image's buffered region is empty (size " << region.GetSize()
                      << "): there is nothing to mesh.");
  }
  ValidateGrid(*image);
  // Where each label is a tissue, a value must round to a label (ImageLabelSelection::RoundsToALabel()): one beyond
  // them, clamped, would join another tissue or become a label the file never held (a 32-bit unsigned
  // 4,000,000,000). With an iso-value only the values' order matters; merged or selected labels meet no other label
  // by rounding.
  using Selection = ImageLabelSelection;
  const bool     valuesAreLabels = !m_UseIsoValue && !m_MergeLabels && m_Labels.empty();
  constexpr bool mayNotBeFinite = std::is_floating_point_v<InputPixelType>;
  constexpr bool mayNotBeALabel =
    mayNotBeFinite ||
    !Selection::RoundsToALabel(static_cast<double>(NumericTraits<InputPixelType>::NonpositiveMin())) ||
    !Selection::RoundsToALabel(static_cast<double>(NumericTraits<InputPixelType>::max()));
  if (!mayNotBeFinite && !(valuesAreLabels && mayNotBeALabel))
  {
    return;
  }
  // Tested branch-free over the raw buffer a block at a time, which the compiler vectorises: an iterator's
  // bookkeeping per voxel would cost more than the test. Only a failing block is searched for the voxel the message
  // names.
  const auto rejected = [valuesAreLabels](InputPixelType pixel) {
    const double value = static_cast<double>(pixel);
    return !std::isfinite(value) | (valuesAreLabels & !Selection::RoundsToALabel(value));
  };
  const InputPixelType * const values = image->GetBufferPointer();
  const SizeValueType          count = region.GetNumberOfPixels();
  constexpr SizeValueType      block = 4096;
  for (SizeValueType first = 0; first < count; first += block)
  {
    const SizeValueType end = std::min(count, first + block);
    bool                anyRejected = false;
    for (SizeValueType offset = first; offset < end; ++offset)
    {
      anyRejected |= rejected(values[offset]);
    }
    if (!anyRejected)
    {
      continue;
    }
    const auto   offset = static_cast<SizeValueType>(std::find_if(values + first, values + end, rejected) - values);
    const double value = static_cast<double>(values[offset]);
    const auto   index = image->ComputeIndex(static_cast<OffsetValueType>(offset));
    if (!std::isfinite(value))
    {
      itkExceptionMacro(<< "The input image holds a non-finite value (" << values[offset] << ") at index " << index
                        << "; every voxel value must be finite.");
    }
    itkExceptionMacro(<< "The input image holds the value " << std::setprecision(17) << value << " at index " << index
                      << ", which rounds to no label: each label is a tissue, and labels are the integers in ["
                      << -Selection::LargestLabel << ", " << Selection::LargestLabel
                      << "] (MergeLabels, Labels or an IsoValue read other values).");
  }
}

template <typename TInputImage, typename TOutputMesh>
void
DelaunayImageToMeshFilter<TInputImage, TOutputMesh>::ValidateGrid(const InputImageType & image) const
{
  // Distances are measured with the spacing along each voxel axis: ITK's readers turn a negative spacing into a
  // positive one and a flipped direction column (ImageFileReader), and the regularisation's reach, the automatic δ
  // and the finest local δ all take it as a length.
  const auto & spacing = image.GetSpacing();
  for (unsigned int axis = 0; axis < ImageDimension; ++axis)
  {
    if (!(spacing[axis] > 0.0 && std::isfinite(spacing[axis])))
    {
      itkExceptionMacro(<< "The input image's spacing " << spacing << " is not positive and finite along axis " << axis
                        << ": the valid range is (0, inf). Give a negative spacing's sign to the direction's column "
                           "instead, as ITK's image readers do.");
    }
  }
  // The oracle and the regularisation measure distances along the voxel axes, one spacing each (a diagonal metric in
  // index space): a sheared grid would have every distance, and so every guarantee, silently wrong.
  const auto & direction = image.GetDirection();
  double       deviation = 0.0;
  for (unsigned int i = 0; i < ImageDimension; ++i)
  {
    for (unsigned int j = 0; j < ImageDimension; ++j)
    {
      double dot = 0.0;
      for (unsigned int k = 0; k < ImageDimension; ++k)
      {
        dot += direction[k][i] * direction[k][j];
      }
      deviation = std::max(deviation, std::abs(dot - (i == j ? 1.0 : 0.0)));
    }
  }
  if (!(deviation <= DirectionOrthonormalityTolerance))
  {
    std::ostringstream rows;
    for (unsigned int i = 0; i < ImageDimension; ++i)
    {
      rows << (i == 0 ? "[" : ", ") << '[' << direction[i][0] << ", " << direction[i][1] << ", " << direction[i][2]
           << ']';
    }
    itkExceptionMacro(<< "The input image's direction (rows) " << rows.str()
                      << "] is not orthonormal: the dot products of its columns differ from the identity's by "
                      << deviation << ", beyond " << DirectionOrthonormalityTolerance
                      << ". The mesher measures distances along the voxel axes, which must be perpendicular unit "
                         "directions; resample the image onto an orthonormal grid (itk::ResampleImageFilter) first.");
  }
}

template <typename TInputImage, typename TOutputMesh>
double
DelaunayImageToMeshFilter<TInputImage, TOutputMesh>::ResolveSurfaceSamplingDistance(const InputImageType * image) const
{
  // Any value but the automatic 0 goes to the core as it is: ValidateParameters() holds the valid range.
  if (m_SurfaceSamplingDistance != 0.0)
  {
    return m_SurfaceSamplingDistance;
  }
  const auto & spacing = image->GetSpacing();
  return 4.0 * *std::max_element(spacing.Begin(), spacing.End());
}

template <typename TInputImage, typename TOutputMesh>
auto
DelaunayImageToMeshFilter<TInputImage, TOutputMesh>::MakeInterpolator(const InputImageType * image) const
  -> InterpolatorPointer
{
  InterpolatorPointer interpolator = m_Interpolator;
  if (interpolator.IsNull())
  {
    if (m_UseIsoValue)
    {
      interpolator = LinearInterpolateImageFunction<InputImageType, double>::New();
    }
    else
    {
      interpolator = NearestNeighborInterpolateImageFunction<InputImageType, double>::New();
    }
  }
  interpolator->SetInputImage(image);
  return interpolator;
}

template <typename TInputImage, typename TOutputMesh>
void
DelaunayImageToMeshFilter<TInputImage, TOutputMesh>::ThrowProcessAborted(const char * description) const
{
  ProcessAborted aborted(__FILE__, __LINE__);
  aborted.SetLocation(ITK_LOCATION);
  aborted.SetDescription(description);
  throw aborted;
}

template <typename TInputImage, typename TOutputMesh>
template <typename TVoxelLabel>
SizeValueType
DelaunayImageToMeshFilter<TInputImage, TOutputMesh>::RefineWithVoxelLabels(
  const InputImageType * image, const InterpolatorType * interpolator, const ImageLabelMapping & mapping,
  const delaunay_refinement::RefinementParameters & parameters)
{
  std::unique_ptr<ImageLabelOracle<InputImageType, TVoxelLabel>> oraclePointer;
  try
  {
    oraclePointer = std::make_unique<ImageLabelOracle<InputImageType, TVoxelLabel>>(image, interpolator, mapping);
  }
  catch (const delaunay_refinement::RefinementAborted & error)
  {
    ThrowProcessAborted(error.what());
  }
  ImageLabelOracle<InputImageType, TVoxelLabel> & oracle = *oraclePointer;
  // The oracle's label image outlives the oracle (the local regularisation changes it in place until then). It is
  // kept as it is stored, and made LabelType when asked for (GetObjectLabelImage()).
  const typename Image<TVoxelLabel, 3>::ConstPointer voxelLabels = oracle.GetLabelImage();
  m_ObjectLabelImage = nullptr;
  m_MakeObjectLabelImage = [voxelLabels] { return AsLabelImage(voxelLabels.GetPointer()); };
  m_SelectedLabelImage = nullptr;
  m_MakeSelectedLabelImage = nullptr;
  m_RegularizationReport = oracle.GetRegularizationReport();
  m_NumberOfJoiningVoxels = oracle.GetNumberOfJoiningVoxels();
  if (oracle.GetNumberOfObjectVoxels() == 0 && m_RegularizationReport.changedVoxels > 0)
  {
    itkExceptionMacro(<< "Every part of the object is thinner than the regularisation scale: the opening with radius "
                      << "RegularizationScale x SurfaceSamplingDistance (delta) = " << m_RegularizationScale << " x "
                      << m_EffectiveSurfaceSamplingDistance << " mm removed all of its "
                      << m_RegularizationReport.changedVoxels
                      << " voxels; choose a smaller SurfaceSamplingDistance (delta), or RegularizationScale 0 to mesh "
                         "the voxels as they are.");
  }
  if (oracle.GetNumberOfObjectVoxels() == 0)
  {
    std::ostringstream notInImage;
    for (const LabelType label : m_SelectedLabelsNotInImage)
    {
      notInImage << (notInImage.tellp() == 0 ? "; the selected labels not in the image: " : ", ") << label;
    }
    itkExceptionMacro(<< "No voxel of the input is part of the object ("
                      << (m_UseIsoValue ? "no value >= the iso-value" : "no voxel carries a selected label")
                      << notInImage.str() << "): there is nothing to mesh.");
  }
  this->UpdateProgress(SetUpProgressShare);
  const delaunay_refinement::ProgressObserver observer =
    [this](const delaunay_refinement::RefinementProgress & progress) {
      this->UpdateProgress(SetUpProgressShare + (0.99f - SetUpProgressShare) * static_cast<float>(progress.fraction));
      return !this->GetAbortGenerateData();
    };

  try
  {
    m_RefinedMesh =
      delaunay_refinement::RefineMesh(oracle, parameters, &m_RefinementStatistics, observer, &oracle, &oracle);
  }
  catch (const delaunay_refinement::RefinementAborted & error)
  {
    ThrowProcessAborted(error.what());
  }
  catch (const delaunay_refinement::VertexLimitExceeded & error)
  {
    itkExceptionMacro(<< error.what() << " (MaximumNumberOfVertices = " << m_MaximumNumberOfVertices << ")");
  }
  catch (const delaunay_refinement::SliverRemovalWithoutEnd & error)
  {
    itkExceptionMacro(<< error.what() << " (MinimumDihedralAngle = " << m_MinimumDihedralAngle << ", valid range [0, "
                      << delaunay_refinement::ParameterLimits::LargestMinimumDihedralAngle
                      << "], 0 = off; RadiusEdgeBound = " << m_RadiusEdgeBound << ")");
  }
  m_NumberOfLocallyRegularizedVoxels = oracle.GetNumberOfLocallyRegularizedVoxels();
  m_NumberOfJoiningVoxels = oracle.GetNumberOfJoiningVoxels();
  const SizeValueType numberOfObjectVoxels = oracle.GetNumberOfObjectVoxels();
  const bool          labelsDifferFromTheSelection = oracle.LabelsDifferFromTheSelection();
  // The selection is made again from the input, once the oracle's per-voxel buffers are freed, rather than copied
  // before the labels change and kept through the refinement: that copy was as large as the label image and made
  // the peak memory (13 MB of 186 on the 1 mm brain mask). It is stored like the oracle's labels, and made LabelType
  // when asked for (GetSelectedLabelImage()).
  oraclePointer.reset();
  if (labelsDifferFromTheSelection)
  {
    const typename Image<TVoxelLabel, 3>::ConstPointer selected =
      ImageLabelSelection(mapping).template SelectedLabelImage<TVoxelLabel>(*image, voxelLabels->GetBufferedRegion());
    m_MakeSelectedLabelImage = [selected] { return AsLabelImage(selected.GetPointer()); };
  }
  else
  {
    m_MakeSelectedLabelImage = [this] { return typename ObjectLabelImageType::ConstPointer(GetObjectLabelImage()); };
  }
  return numberOfObjectVoxels;
}

template <typename TInputImage, typename TOutputMesh>
template <typename TVoxelLabel>
auto
DelaunayImageToMeshFilter<TInputImage, TOutputMesh>::AsLabelImage(const Image<TVoxelLabel, 3> * voxelLabels) ->
  typename ObjectLabelImageType::ConstPointer
{
  if constexpr (std::is_same_v<TVoxelLabel, LabelType>)
  {
    return voxelLabels;
  }
  else
  {
    auto labels = ObjectLabelImageType::New();
    labels->CopyInformation(voxelLabels);
    labels->SetRegions(voxelLabels->GetBufferedRegion());
    labels->Allocate();
    const SizeValueType count = voxelLabels->GetBufferedRegion().GetNumberOfPixels();
    delaunay_refinement::AdviseHugePages(labels->GetBufferPointer(), count * sizeof(LabelType));
    std::copy_n(voxelLabels->GetBufferPointer(), count, labels->GetBufferPointer());
    return labels;
  }
}

template <typename TInputImage, typename TOutputMesh>
void
DelaunayImageToMeshFilter<TInputImage, TOutputMesh>::GenerateData()
{
  const InputImageType * image = this->GetInput();
  m_SelectedLabelsNotInImage.clear();
  ValidateInput(image);
  m_EffectiveSurfaceSamplingDistance = ResolveSurfaceSamplingDistance(image);

  delaunay_refinement::RefinementParameters parameters;
  parameters.surfaceSamplingDistance = m_EffectiveSurfaceSamplingDistance;
  parameters.radiusEdgeBound = m_RadiusEdgeBound;
  parameters.minimumDihedralAngle = m_MinimumDihedralAngle;
  parameters.maximumNumberOfVertices = m_MaximumNumberOfVertices;
  parameters.manifoldRefinementLevels = m_ManifoldRefinementLevels;
  parameters.topologyRegularizationRounds = m_TopologyRegularizationRounds;
  parameters.relabelNonManifoldPlaces = m_RelabelNonManifoldPlaces;
  parameters.refineThickParts = m_RefineThickParts;
  // A bridge or slit one voxel thick (a joined diagonal contact is one) needs samples closer than a voxel; below
  // half a voxel, finer sampling would resolve the corners where voxels still touch diagonally (two tissues, or
  // at a vertex): never more manifold.
  const auto & spacing = image->GetSpacing();
  parameters.minimumSurfaceSamplingDistance = 0.5 * *std::min_element(spacing.Begin(), spacing.End());
  try
  {
    delaunay_refinement::ValidateParameters(parameters);
  }
  catch (const std::invalid_argument & error)
  {
    itkExceptionMacro(<< error.what());
  }

  if (!(m_RegularizationScale >= 0.0 && m_RegularizationScale <= LargestRegularizationScale))
  {
    itkExceptionMacro(<< "Invalid RegularizationScale = " << m_RegularizationScale
                      << ": the valid range is [0, 0.5] (a fraction of delta; 0 = no regularisation)");
  }

  if (!m_UseIsoValue)
  {
    for (const LabelType label : m_Labels)
    {
      // The voxels' values round to labels of this range (ImageLabelSelection::RoundsToALabel()): a selected label
      // beyond it could never be meshed. A selected 0 is the background, as it always is.
      if (!ImageLabelSelection::RoundsToALabel(static_cast<double>(label)))
      {
        itkExceptionMacro(<< "Invalid label " << label << " in Labels: the valid labels are the integers in ["
                          << -std::numeric_limits<LabelType>::max() << ", " << std::numeric_limits<LabelType>::max()
                          << "].");
      }
    }
  }

  this->UpdateProgress(0.0f);
  const InterpolatorPointer interpolator = MakeInterpolator(image);
  const ImageLabelMapping   mapping{ m_Labels,
                                   m_MergeLabels,
                                   m_UseIsoValue,
                                   m_IsoValue,
                                   m_JoinDiagonalVoxels,
                                   m_RegularizationScale * m_EffectiveSurfaceSamplingDistance,
                                   [this](double setUpFraction) {
                                     this->UpdateProgress(SetUpProgressShare * static_cast<float>(setUpFraction));
                                     return !this->GetAbortGenerateData();
                                   },
                                   std::min(this->GetNumberOfWorkUnits(),
                                            this->GetMultiThreader()->GetMaximumNumberOfThreads()) };
  const ImageLabelSelection selection(mapping);
  m_SelectedLabelsNotInImage = selection.SelectedLabelsNotIn(*image);
  // The label image is the refinement's largest buffer with the nearest-interface map: in one byte a voxel where
  // every selected label fits, it takes a quarter of the memory it took in four (bench/README.md, "The label image
  // in one byte a voxel").
  SizeValueType numberOfObjectVoxels = 0;
  m_BytesPerVoxelLabel = selection.BytesPerVoxelLabel(*image);
  switch (m_BytesPerVoxelLabel)
  {
    case 1:
      numberOfObjectVoxels = RefineWithVoxelLabels<uint8_t>(image, interpolator, mapping, parameters);
      break;
    case 2:
      numberOfObjectVoxels = RefineWithVoxelLabels<uint16_t>(image, interpolator, mapping, parameters);
      break;
    default:
      numberOfObjectVoxels = RefineWithVoxelLabels<LabelType>(image, interpolator, mapping, parameters);
      break;
  }
  if (m_RefinedMesh.tetrahedra.empty())
  {
    itkExceptionMacro(<< "The refinement produced no tetrahedron: the object (" << numberOfObjectVoxels
                      << " voxels) is too small for SurfaceSamplingDistance (delta) = "
                      << m_EffectiveSurfaceSamplingDistance << " mm; choose a smaller delta.");
  }
  FillOutputs(m_RefinedMesh);
  this->UpdateProgress(1.0f);
}

template <typename TInputImage, typename TOutputMesh>
void
DelaunayImageToMeshFilter<TInputImage, TOutputMesh>::FillOutputs(const delaunay_refinement::TetrahedralMesh & mesh)
{
  using CellType = typename OutputMeshType::CellType;
  using CellAutoPointer = typename CellType::CellAutoPointer;
  using CellPixelType = typename OutputMeshType::CellPixelType;
  using PointType = typename OutputMeshType::PointType;
  using PointIdentifier = typename OutputMeshType::PointIdentifier;

  OutputMeshType * tetrahedra = this->GetOutput();
  OutputMeshType * interfaces = this->GetInterfaceMesh();
  tetrahedra->Initialize();
  interfaces->Initialize();

  auto points = OutputMeshType::PointsContainer::New();
  points->Reserve(mesh.points.size());
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
  {
    PointType point;
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      point[axis] = mesh.points[i][axis];
    }
    points->SetElement(i, point);
  }
  tetrahedra->SetPoints(points);
  interfaces->SetPoints(points);

  for (std::size_t i = 0; i < mesh.tetrahedra.size(); ++i)
  {
    CellAutoPointer cell;
    cell.TakeOwnership(new TetrahedronCell<CellType>);
    for (unsigned int corner = 0; corner < 4; ++corner)
    {
      cell->SetPointId(corner, static_cast<PointIdentifier>(mesh.tetrahedra[i][corner]));
    }
    tetrahedra->SetCell(i, cell);
    tetrahedra->SetCellData(i, static_cast<CellPixelType>(mesh.tetrahedronLabels[i]));
  }

  m_InterfaceLabels.assign(mesh.boundaryTriangleLabels.begin(), mesh.boundaryTriangleLabels.end());
  for (std::size_t i = 0; i < mesh.boundaryTriangles.size(); ++i)
  {
    CellAutoPointer cell;
    cell.TakeOwnership(new TriangleCell<CellType>);
    for (unsigned int corner = 0; corner < 3; ++corner)
    {
      cell->SetPointId(corner, static_cast<PointIdentifier>(mesh.boundaryTriangles[i][corner]));
    }
    interfaces->SetCell(i, cell);
    interfaces->SetCellData(i, static_cast<CellPixelType>(mesh.boundaryTriangleLabels[i][0]));
  }
  // A point set whose buffered region differs from its requested one is out of date for ITK's pipeline
  // (PointSet::RequestedRegionIsOutsideOfTheBufferedRegion), which would mesh again on every Update(), also when a
  // downstream filter (ITK's FEM registration, say) pulls the mesh: both outputs hold what was requested, as ITK's
  // own mesh filters declare.
  tetrahedra->SetBufferedRegion(tetrahedra->GetRequestedRegion());
  interfaces->SetBufferedRegion(interfaces->GetRequestedRegion());
}

template <typename TInputImage, typename TOutputMesh>
void
DelaunayImageToMeshFilter<TInputImage, TOutputMesh>::PrintSelf(std::ostream & os, Indent indent) const
{
  Superclass::PrintSelf(os, indent);
  os << indent << "SurfaceSamplingDistance: " << m_SurfaceSamplingDistance << std::endl;
  os << indent << "EffectiveSurfaceSamplingDistance: " << m_EffectiveSurfaceSamplingDistance << std::endl;
  os << indent << "RegularizationScale: " << m_RegularizationScale << std::endl;
  os << indent << "TopologyRegularizationRounds: " << m_TopologyRegularizationRounds << std::endl;
  os << indent << "NumberOfLocallyRegularizedVoxels: " << m_NumberOfLocallyRegularizedVoxels << std::endl;
  os << indent << "RelabelNonManifoldPlaces: " << (m_RelabelNonManifoldPlaces ? "On" : "Off") << std::endl;
  os << indent << "RefineThickParts: " << (m_RefineThickParts ? "On" : "Off") << std::endl;
  os << indent << "RadiusEdgeBound: " << m_RadiusEdgeBound << std::endl;
  os << indent << "MinimumDihedralAngle: " << m_MinimumDihedralAngle << std::endl;
  os << indent << "MaximumNumberOfVertices: " << m_MaximumNumberOfVertices << std::endl;
  os << indent << "ManifoldRefinementLevels: " << m_ManifoldRefinementLevels << std::endl;
  os << indent << "MergeLabels: " << (m_MergeLabels ? "On" : "Off") << std::endl;
  os << indent << "JoinDiagonalVoxels: " << (m_JoinDiagonalVoxels ? "On" : "Off") << std::endl;
  os << indent << "NumberOfJoiningVoxels: " << m_NumberOfJoiningVoxels << std::endl;
  itkPrintSelfObjectMacro(Interpolator);
  os << indent << "IsoValue: " << m_IsoValue << std::endl;
  os << indent << "UseIsoValue: " << (m_UseIsoValue ? "On" : "Off") << std::endl;
  os << indent << "Labels:";
  for (const LabelType label : m_Labels)
  {
    os << ' ' << label;
  }
  os << (m_Labels.empty() ? " (all non-zero)" : "") << std::endl;
  os << indent << "SelectedLabelsNotInImage:";
  for (const LabelType label : m_SelectedLabelsNotInImage)
  {
    os << ' ' << label;
  }
  os << std::endl;
  os << indent << "InterfaceLabels: " << m_InterfaceLabels.size() << " pairs" << std::endl;
  os << indent << "RefinedMesh: " << m_RefinedMesh.points.size() << " points, " << m_RefinedMesh.tetrahedra.size()
     << " tetrahedra, " << m_RefinedMesh.boundaryTriangles.size() << " boundary triangles" << std::endl;
  os << indent << "RefinementStatistics: " << m_RefinementStatistics.triangulationVertices
     << " triangulation vertices, " << m_RefinementStatistics.refinementSeconds << " s, "
     << m_RefinementStatistics.manifoldRefinementZones << " manifold refinement zones, "
     << m_RefinementStatistics.remainingNonManifoldVertices << " non-manifold vertices left"
     << (m_RefinementStatistics.topologyRegularizationBudgetReached ? " (the regularisation reached its budget)" : "")
     << std::endl;
  os << indent << "ObjectLabelImage: " << m_ObjectLabelImage.GetPointer() << std::endl;
  os << indent << "BytesPerVoxelLabel: " << m_BytesPerVoxelLabel << std::endl;
}

} // namespace itk

#endif
