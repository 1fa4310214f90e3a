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
#ifndef itkDelaunayImageToMeshFilter_h
#define itkDelaunayImageToMeshFilter_h

#include "DelaunayRefinementLabelRegularization.h"
#include "DelaunayRefinementMesher.h"

#include "itkImage.h"
#include "itkImageToMeshFilter.h"
#include "itkInterpolateImageFunction.h"
#include "itkMesh.h"

#include <functional>
#include <vector>

namespace itk
{

struct ImageLabelMapping;

/** \class DelaunayImageToMeshFilter
 * \brief Meshes a segmented 3-D image into tetrahedra with guaranteed quality and fidelity, by Delaunay
 * refinement straight from the image (Foteinos, Chernikov and Chrisochoides).
 *
 * The refinement samples the object's surface while it meshes the volume, starting from the eight corners of
 * a box. With the default radius-edge bound ρ = 2 and no minimum dihedral angle:
 * - every tetrahedron has radius-edge ratio < ρ;
 * - every boundary (and tissue-interface) triangle has all planar angles > 30°;
 * - for δ small against the local feature size, the boundary is a closed 2-manifold isotopic to the
 *   object's surface, within O(δ²) of it.
 *
 * The oracle is an InterpolateImageFunction on the input: nearest neighbour by default (label images),
 * linear interpolation with an iso-value for gray images (SetIsoValue()), or any other ITK interpolator
 * (e.g. LabelImageGaussianInterpolateImageFunction for smooth labels). Each selected label is a tissue;
 * interfaces between tissues are meshed conformingly. A voxel's label is its value rounded to the nearest integer,
 * which must lie in [-2147483647, 2147483647] (the labels the output's cell data can hold) when each label is a
 * tissue: a larger value is refused, not clamped into another tissue. Every value must be finite. Outside the image
 * everything is background, so objects touching the border are closed there. All geometry is in physical space:
 * spacing (positive), origin and direction, which must be orthonormal (DirectionOrthonormalityTolerance).
 *
 * Output 0: the tetrahedra (TetrahedronCell), their tissue label as cell data. Output 1: the boundary and
 * interface triangles (TriangleCell) on the same points, oriented outwards from the tissue whose label is
 * their cell data; GetInterfaceLabels() gives the label on each side.
 *
 * Threads: the set-up's passes over every voxel (the oracle's nearest-interface map, the regularisation's opening
 * and distance transform) run on min(GetNumberOfWorkUnits(), the threader's maximum number of threads) threads; the
 * refinement is sequential. The mesh is the same whatever the number of threads.
 *
 * \ingroup DelaunayImageToMesh
 */
template <typename TInputImage, typename TOutputMesh>
class ITK_TEMPLATE_EXPORT DelaunayImageToMeshFilter : public ImageToMeshFilter<TInputImage, TOutputMesh>
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(DelaunayImageToMeshFilter);

  static constexpr unsigned int ImageDimension = TInputImage::ImageDimension;
  static_assert(ImageDimension == 3,
                "DelaunayImageToMeshFilter meshes 3-D images only: TInputImage must have ImageDimension == 3.");
  static_assert(TOutputMesh::PointDimension == 3,
                "DelaunayImageToMeshFilter makes tetrahedra: TOutputMesh must have PointDimension == 3.");

  using Self = DelaunayImageToMeshFilter;
  using Superclass = ImageToMeshFilter<TInputImage, TOutputMesh>;
  using Pointer = SmartPointer<Self>;
  using ConstPointer = SmartPointer<const Self>;

  itkNewMacro(Self);
  itkTypeMacro(DelaunayImageToMeshFilter, ImageToMeshFilter);

  using InputImageType = TInputImage;
  using InputPixelType = typename InputImageType::PixelType;
  using OutputMeshType = TOutputMesh;
  using OutputMeshPointer = typename OutputMeshType::Pointer;
  using InterpolatorType = InterpolateImageFunction<InputImageType, double>;
  using InterpolatorPointer = typename InterpolatorType::Pointer;
  using LabelType = int32_t;
  using LabelListType = std::vector<LabelType>;
  using LabelPairType = std::array<LabelType, 2>;
  using LabelPairListType = std::vector<LabelPairType>;
  using ObjectLabelImageType = Image<LabelType, 3>;

  /** δ, the surface sampling distance in physical units (mm): smaller is finer and closer to the surface.
   * 0 (the default) picks 4 × the largest voxel spacing. Valid: 0 or a value in (0, 1e30]
   * (delaunay_refinement::ParameterLimits). */
  itkSetMacro(SurfaceSamplingDistance, double);
  itkGetConstMacro(SurfaceSamplingDistance, double);
  /** δ under the paper's name, the same parameter: ITK Python's functional form then reads
   * itk.delaunay_image_to_mesh_filter(image, delta=2.0). */
  void
  SetDelta(double delta)
  {
    this->SetSurfaceSamplingDistance(delta);
  }
  double
  GetDelta() const
  {
    return this->GetSurfaceSamplingDistance();
  }

  /** ρ, the radius-edge bound: every tetrahedron's circumradius / shortest edge is < ρ. Default 2 (the
   * paper's guarantees); valid: finite, >= 1. */
  itkSetMacro(RadiusEdgeBound, double);
  itkGetConstMacro(RadiusEdgeBound, double);

  /** σ, a minimum dihedral angle in degrees (the R4' variant, which removes slivers). Default 10; 0 = off, the
   * paper's method, whose bounds are proven; valid: [0, 20]. With σ > 0 the bounds are measured, not proven
   * (RefinementParameters::minimumDihedralAngle says what was measured). */
  itkSetMacro(MinimumDihedralAngle, double);
  itkGetConstMacro(MinimumDihedralAngle, double);

  /** The old topology repair, an opt-in: where a boundary is still non-manifold after the regularisation, δ is
   * halved locally and the refinement resumed, at most this many times (down to δ / 2^levels, never below half
   * the smallest voxel spacing). It resolves detail toward the voxel instead of removing it: meshes several
   * times larger, and δ no longer controls their size. Every guarantee holds with the local δ. Default 0 (off);
   * valid: [0, 10]. */
  itkSetMacro(ManifoldRefinementLevels, unsigned int);
  itkGetConstMacro(ManifoldRefinementLevels, unsigned int);

  /** Remove the voxel pinches of every label, the background included, before meshing: where two voxels of a label
   * touch only along an edge or at a corner, or two voxels of the rest touch so across it, one voxel of the block
   * changes label, never a tissue's to the background, so the union of the tissues only grows (see
   * delaunay_refinement::RemoveVoxelPinches). There the voxels' own surface is not a manifold, so a mesh of them
   * as they are would not be one either; afterwards every label's voxel surface is a 2-manifold (a well-composed
   * label image). With nearest-neighbour labels (the default interpolator), and with an iso-value and linear
   * interpolation, whose changed voxels get values on their new side; other interpolators define their own surface.
   * Default on. The name is the option's first meaning (joining a tissue across the background). */
  itkSetMacro(JoinDiagonalVoxels, bool);
  itkGetConstMacro(JoinDiagonalVoxels, bool);
  itkBooleanMacro(JoinDiagonalVoxels);
  /** How many voxels the last update changed to remove voxel pinches (JoinDiagonalVoxels). */
  itkGetConstMacro(NumberOfJoiningVoxels, SizeValueType);

  /** δ is the mesh's resolution: before meshing, every label (the background included) is opened with a ball of
   * radius RegularizationScale × δ, and the voxels an opening removed take the label of the nearest voxel that
   * survived (delaunay_refinement::RegularizeLabels). A tissue's parts thinner than 2 × RegularizationScale × δ
   * (one-voxel bridges, sheets, speckle, contacts along a voxel edge) go to their neighbours, and its slits and
   * gaps thinner than that are filled; every part that holds a ball of that radius stays. What changed is in
   * GetRegularizationReport(). With nearest-neighbour labels (the default interpolator), and with an iso-value and
   * linear interpolation (the changed voxels' values are carried to their new side). Default
   * DefaultRegularizationScale; 0 = the voxels as they are; valid: [0, 0.5] (a ball of diameter δ always stays). */
  itkSetMacro(RegularizationScale, double);
  itkGetConstMacro(RegularizationScale, double);
  static constexpr double DefaultRegularizationScale = 0.4;
  /** Beyond half of δ the opening would remove parts that hold a ball of diameter δ. */
  static constexpr double LargestRegularizationScale = 0.5;

  /** The input's direction must be orthonormal (a rotation, or a reflection) to this tolerance on the dot products
   * of its columns, or the filter refuses it: distances are measured along the voxel axes. A grid sheared by the
   * acquisition (a CT gantry tilt) must be resampled first. Cosines written to six decimals (DICOM files often are)
   * stay within it; the distances it lets through are off by at most 0.015 %. */
  static constexpr double DirectionOrthonormalityTolerance = 1e-4;

  /** Where a boundary still comes out non-manifold after the refinement and the relabelling
   * (RelabelNonManifoldPlaces), the labels are regularised in a ball of radius δ around each such place (the place's
   * label fills the ball or leaves it, whichever changes fewer voxels) and the refinement resumes there, at most
   * this many rounds. With nearest-neighbour labels, and with an iso-value and linear interpolation. The rounds also
   * stop once they have inserted more than a few times the vertices the mesh had when they began
   * (GetTopologyRegularizationBudgetReached(); docs/algorithm.md, "Topology", step 2); the places left are counted in
   * GetNumberOfRemainingNonManifoldVertices(). Default
   * delaunay_refinement::RefinementParameters{}.topologyRegularizationRounds; 0 = never; valid: [0, 20]. */
  itkSetMacro(TopologyRegularizationRounds, unsigned int);
  itkGetConstMacro(TopologyRegularizationRounds, unsigned int);
  /** How many voxels the last update's local regularisation (TopologyRegularizationRounds) changed. */
  itkGetConstMacro(NumberOfLocallyRegularizedVoxels, SizeValueType);
  /** The bytes a voxel of the label image took during the last update: 1, 2 or 4, the fewest that hold every
   * selected label (1 for an iso-value, merged labels, or labels within 0-255; 2 within 0-65535). The label image and
   * the nearest-interface map are the refinement's largest buffers besides the mesh. */
  itkGetConstMacro(BytesPerVoxelLabel, unsigned int);

  /** Where a boundary comes out non-manifold, first give tetrahedra there the label of a neighbour when that mends
   * the place, keeps the boundary made of surface samples and keeps its angles above 30° (a cone cut off, a gap
   * filled, within the place's star); the regularisation rounds then see only the places this could not mend. Those
   * tetrahedra no longer carry the label at their circumcentre: how many, in
   * GetNumberOfTopologyRelabelledTetrahedra(). Default
   * delaunay_refinement::RefinementParameters{}.relabelNonManifoldPlaces (on). */
  itkSetMacro(RelabelNonManifoldPlaces, bool);
  itkGetConstMacro(RelabelNonManifoldPlaces, bool);
  itkBooleanMacro(RelabelNonManifoldPlaces);
  /** Every part of a tissue that holds a ball of diameter δ gets tetrahedra: a small thin part is sampled more
   * finely, and a part the mesh still lost is sampled again more finely (docs/algorithm.md, "Topology", step 4).
   * Off, such a part may be left without a tetrahedron; it is listed all the same (GetRefinementStatistics()'s
   * unmeshedParts, the report's parts_without_tetrahedra). Default
   * delaunay_refinement::RefinementParameters{}.refineThickParts (on). */
  itkSetMacro(RefineThickParts, bool);
  itkGetConstMacro(RefineThickParts, bool);
  itkBooleanMacro(RefineThickParts);
  /** How many output tetrahedra the last update relabelled at non-manifold places (RelabelNonManifoldPlaces).
   * Reads the member, not GetRefinementStatistics(), which the wrapping parser does not see. */
  SizeValueType
  GetNumberOfTopologyRelabelledTetrahedra() const
  {
    return static_cast<SizeValueType>(m_RefinementStatistics.topologyRelabelledTetrahedra);
  }

  /** Whether the last update's regularisation rounds stopped at their budget of inserted vertices
   * (TopologyRegularizationRounds). Reads the member, as GetNumberOfTopologyRelabelledTetrahedra() does. */
  bool
  GetTopologyRegularizationBudgetReached() const
  {
    return m_RefinementStatistics.topologyRegularizationBudgetReached;
  }
  /** How many (vertex, boundary) places the last update left non-manifold: 0 when every tissue's boundary and the
   * union's are closed manifolds at every vertex the repair looked at (the report counts them from the mesh). */
  SizeValueType
  GetNumberOfRemainingNonManifoldVertices() const
  {
    return static_cast<SizeValueType>(m_RefinementStatistics.remainingNonManifoldVertices);
  }

  /** A cap on the vertices of the triangulation; reaching it raises an exception. Default 10,000,000. */
  itkSetMacro(MaximumNumberOfVertices, SizeValueType);
  itkGetConstMacro(MaximumNumberOfVertices, SizeValueType);

  /** The interpolator that labels points (its input is set by the filter). Default: nearest neighbour;
   * linear when an iso-value is set and no interpolator was given. */
  itkSetObjectMacro(Interpolator, InterpolatorType);
  itkGetModifiableObjectMacro(Interpolator, InterpolatorType);

  /** Treat the image as gray values: the object is where the interpolated value is >= IsoValue (label 1). */
  void
  SetIsoValue(double isoValue);
  itkGetConstMacro(IsoValue, double);
  /** Whether an iso-value is in use (set by SetIsoValue, cleared by UseIsoValueOff()). Default off. */
  itkSetMacro(UseIsoValue, bool);
  itkGetConstMacro(UseIsoValue, bool);
  itkBooleanMacro(UseIsoValue);

  /** The labels to mesh, each as a tissue. Empty (the default) = every non-zero label. Each must be a label, an
   * integer in [-2147483647, 2147483647]: the update refuses -2147483648. A selected 0 is the background. */
  void
  SetLabels(const LabelListType & labels);
  const LabelListType &
  GetLabels() const
  {
    return m_Labels;
  }
  /** After an update: the labels of GetLabels() that no voxel of the input carries, in increasing order (empty
   * without a selection, and with an iso-value). Nothing of them is in the mesh, and the selection is how a user
   * said what must be: the report lists them, as it lists a tissue the mesh lost. Where no selected label is in the
   * image, the update fails instead, naming them. */
  const LabelListType &
  GetSelectedLabelsNotInImage() const
  {
    return m_SelectedLabelsNotInImage;
  }
  /** Mesh every selected label as one object, labelled 1: for masks whose values encode something other than
   * tissues. Default off (each selected label is a tissue). */
  itkSetMacro(MergeLabels, bool);
  itkGetConstMacro(MergeLabels, bool);
  itkBooleanMacro(MergeLabels);

  /** Adds one label to mesh (the form scripting languages use). */
  void
  AddLabel(LabelType label);
  /** Back to the default: every non-zero label. */
  void
  ClearLabels();

  /** Output 1: boundary and interface triangles. */
  OutputMeshType *
  GetInterfaceMesh();

  /** Output 0, the tetrahedra. */
  OutputMeshType *
  GetOutput()
  {
    return Superclass::GetOutput();
  }
  /** Output `index` (0: tetrahedra, 1: GetInterfaceMesh()). ITK 5.2's ImageToMeshFilter hides MeshSource's
   * overload, and ITK Python's functional form calls it for a filter with two outputs:
   * `tetrahedra, interface = itk.delaunay_image_to_mesh_filter(image, delta=2.0)`. */
  OutputMeshType *
  GetOutput(unsigned int index)
  {
    return itkDynamicCastInDebugMode<OutputMeshType *>(this->ProcessObject::GetOutput(index));
  }

  /** The label on side `side` (0: inside, the cell data; 1: the other side, 0 for background) of cell
   * `cellId` of GetInterfaceMesh(). */
  LabelType
  GetInterfaceLabel(SizeValueType cellId, unsigned int side) const;

#if !defined(ITK_WRAPPING_PARSER)
  /** For each cell of GetInterfaceMesh(): {label inside (the cell data), label on the other side}. */
  const LabelPairListType &
  GetInterfaceLabels() const
  {
    return m_InterfaceLabels;
  }
#endif

  /** The δ the last update used (resolves the 0 = automatic default). */
  itkGetConstMacro(EffectiveSurfaceSamplingDistance, double);

#if !defined(ITK_WRAPPING_PARSER)
  /** The last result as the refinement core produced it (points, kinds, tetrahedra, boundary triangles). */
  const delaunay_refinement::TetrahedralMesh &
  GetRefinedMesh() const
  {
    return m_RefinedMesh;
  }

  /** The voxel labels the last update meshed (after label selection, merging or the iso-value, with the joining
   * voxels), cropped to the object's voxels and one voxel of background around them (every voxel outside is
   * background): the reference for fidelity measurements. The filter keeps them as it meshed them, in one byte a
   * voxel where every label fits (GetBytesPerVoxelLabel()), and makes this image of LabelType at the first call
   * after an update: a caller that never asks does not pay four bytes a voxel for it. Not to be called from several
   * threads at once. */
  const ObjectLabelImageType *
  GetObjectLabelImage() const
  {
    return MadeOnce(m_ObjectLabelImage, m_MakeObjectLabelImage);
  }

  /** The voxel labels the last update selected from the input (label selection, merging or the iso-value),
   * cropped like GetObjectLabelImage(), before the regularisation, the joining of diagonal voxels and the local
   * regularisation of the topology rounds: the segmentation the mesh stands for, the reference for fidelity and for
   * tissues the regularisation removed. Kept and made like GetObjectLabelImage(), at the first call. */
  const ObjectLabelImageType *
  GetSelectedLabelImage() const
  {
    return MadeOnce(m_SelectedLabelImage, m_MakeSelectedLabelImage);
  }

  /** What the regularisation (RegularizationScale) did to each label during the last update. */
  const delaunay_refinement::LabelRegularizationReport &
  GetRegularizationReport() const
  {
    return m_RegularizationReport;
  }

  /** What the refinement did during the last update. */
  const delaunay_refinement::RefinementStatistics &
  GetRefinementStatistics() const
  {
    return m_RefinementStatistics;
  }
#endif

protected:
  DelaunayImageToMeshFilter();
  ~DelaunayImageToMeshFilter() override = default;

  void
  GenerateData() override;

  void
  PrintSelf(std::ostream & os, Indent indent) const override;

private:
  void
  ValidateInput(const InputImageType * image) const;
  /** The grid the oracle measures along: a positive, finite spacing and an orthonormal direction. */
  void
  ValidateGrid(const InputImageType & image) const;
  double
  ResolveSurfaceSamplingDistance(const InputImageType * image) const;
  InterpolatorPointer
  MakeInterpolator(const InputImageType * image) const;
  void
  FillOutputs(const delaunay_refinement::TetrahedralMesh & mesh);
  /** The oracle's set-up and the refinement, with the label image stored in TVoxelLabel (GenerateData() chooses the
   * narrowest that holds every selected label); sets m_RefinedMesh, the label images and the reports, and returns
   * the number of object voxels. */
  template <typename TVoxelLabel>
  SizeValueType
  RefineWithVoxelLabels(const InputImageType * image, const InterpolatorType * interpolator,
                        const ImageLabelMapping &                         mapping,
                        const delaunay_refinement::RefinementParameters & parameters);
  /** The share of the progress range the oracle's set-up reports (its label image, the regularisation, the
   * nearest-interface map); the refinement reports the rest. */
  static constexpr float SetUpProgressShare = 0.1f;
  /** Makes a label image the filter keeps in another form (GetObjectLabelImage(), GetSelectedLabelImage()). */
  using MakeLabelImage = std::function<typename ObjectLabelImageType::ConstPointer()>;
  /** `image`, made by `make` first when `make` is set (which it then clears). */
  static const ObjectLabelImageType *
  MadeOnce(typename ObjectLabelImageType::ConstPointer & image, MakeLabelImage & make)
  {
    if (make)
    {
      image = make();
      make = nullptr;
    }
    return image;
  }
  /** The labels as GetObjectLabelImage() gives them: the image itself when stored as LabelType, else a copy. */
  template <typename TVoxelLabel>
  static typename ObjectLabelImageType::ConstPointer
  AsLabelImage(const Image<TVoxelLabel, 3> * voxelLabels);
  /** An abort from the progress observer, as ITK reports it. */
  [[noreturn]] void
  ThrowProcessAborted(const char * description) const;

  double m_SurfaceSamplingDistance{ 0.0 };
  double m_EffectiveSurfaceSamplingDistance{ 0.0 };
  // The refinement's defaults are the core's, written once in RefinementParameters.
  double        m_RadiusEdgeBound{ delaunay_refinement::RefinementParameters{}.radiusEdgeBound };
  double        m_MinimumDihedralAngle{ delaunay_refinement::RefinementParameters{}.minimumDihedralAngle };
  SizeValueType m_MaximumNumberOfVertices{ delaunay_refinement::RefinementParameters{}.maximumNumberOfVertices };
  unsigned int  m_ManifoldRefinementLevels{ delaunay_refinement::RefinementParameters{}.manifoldRefinementLevels };
  bool          m_MergeLabels{ false };
  bool          m_JoinDiagonalVoxels{ true };
  double        m_RegularizationScale{ DefaultRegularizationScale };
  unsigned int  m_TopologyRegularizationRounds{
    delaunay_refinement::RefinementParameters{}.topologyRegularizationRounds
  };
  bool          m_RelabelNonManifoldPlaces{ delaunay_refinement::RefinementParameters{}.relabelNonManifoldPlaces };
  bool          m_RefineThickParts{ delaunay_refinement::RefinementParameters{}.refineThickParts };
  SizeValueType m_NumberOfLocallyRegularizedVoxels{ 0 };
  unsigned int  m_BytesPerVoxelLabel{ 0 };
  SizeValueType m_NumberOfJoiningVoxels{ 0 };
  InterpolatorPointer m_Interpolator;
  double              m_IsoValue{ 0.0 };
  bool                m_UseIsoValue{ false };
  LabelListType       m_Labels;
  LabelListType       m_SelectedLabelsNotInImage;
  LabelPairListType   m_InterfaceLabels;
  // Private members and the .hxx are parsed by CastXML too: only the public accessors above are hidden from
  // the wrapping, because SWIG cannot wrap their std::array and core types.
  delaunay_refinement::TetrahedralMesh           m_RefinedMesh;
  delaunay_refinement::RefinementStatistics      m_RefinementStatistics;
  delaunay_refinement::LabelRegularizationReport m_RegularizationReport;
  /** GetObjectLabelImage() and GetSelectedLabelImage(), once made; until then the functions make them from the
   * labels as the filter keeps them. */
  mutable typename ObjectLabelImageType::ConstPointer m_ObjectLabelImage;
  mutable MakeLabelImage                              m_MakeObjectLabelImage;
  mutable typename ObjectLabelImageType::ConstPointer m_SelectedLabelImage;
  mutable MakeLabelImage                              m_MakeSelectedLabelImage;
};

} // namespace itk

#ifndef ITK_MANUAL_INSTANTIATION
#  include "itkDelaunayImageToMeshFilter.hxx"
#endif

#endif
