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
#ifndef DelaunayImageToMeshQualityReport_h
#define DelaunayImageToMeshQualityReport_h

#include "DelaunayImageToMeshSurfaceExtraction.h"
#include "DelaunayRefinementLabelRegularization.h"
#include "DelaunayRefinementMeshQuality.h"
#include "DelaunayRefinementOracle.h"
#include "DelaunayRefinementTypes.h"

#include <cstddef>
#include <ostream>
#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace delaunay_refinement
{

/** How the mesher kept every tissue's boundary a manifold at the scale of δ (docs/algorithm.md, "Topology"): its
 * options as the mesher used them, and what each did in the run. */
struct TopologyRun
{
  /** The opening's radius as a fraction of δ; 0 = the voxels as they are. */
  double regularizationScale{ 0.0 };
  /** Whether voxel pinches were removed, and how many voxels changed label for it. */
  bool        joinDiagonalVoxels{ false };
  std::size_t voxelsChangedAtPinches{ 0 };
  /** Whether tetrahedra at non-manifold places may take a neighbour's label, and how many did. */
  bool        relabelNonManifoldPlaces{ false };
  std::size_t relabelledTetrahedra{ 0 };
  /** The most rounds of local regularisation allowed, the rounds made, the voxels they changed, and whether they
   * stopped at their budget of inserted vertices. */
  std::size_t regularizationRoundsAllowed{ 0 };
  std::size_t regularizationRoundsMade{ 0 };
  std::size_t locallyRegularizedVoxels{ 0 };
  bool        budgetReached{ false };
  /** Whether the parts a δ thick that got no tetrahedron were sampled more finely, and how many were. */
  bool        refineThickParts{ false };
  std::size_t thickPartsRefined{ 0 };
  /** The opt-in halving of δ where a boundary stayed non-manifold: the levels allowed, and the rounds it made. */
  std::size_t manifoldRefinementLevels{ 0 };
  std::size_t manifoldRefinementRounds{ 0 };
};

/** How a mesh was made and what it cost. The report records these as the caller gives them. */
struct MeshingRun
{
  /** The image the mesh was made from, as named by the user. */
  std::string inputFile;
  /** The mesh file written, as named by the user. */
  std::string outputFile;
  /** δ actually used, mm. */
  double surfaceSamplingDistance{ 0.0 };
  /** ρ, the radius-edge bound. */
  double radiusEdgeBound{ 0.0 };
  /** σ of the R4' variant, degrees; 0 = off. */
  double minimumDihedralAngle{ 0.0 };
  /** Wall-clock seconds of each phase, in the order they ran (e.g. read, mesh, report, write). */
  std::vector<std::pair<std::string, double>> phaseSeconds;
  /** Peak resident memory of the process, bytes (PeakResidentMemoryBytes()); 0 = not measured. */
  std::size_t peakResidentMemoryBytes{ 0 };
  /** The tissues: every non-zero label (empty), or these labels; merged into one object (label 1); or, with an
   * iso-value, the object where the interpolated value reaches it. */
  std::vector<Label>    selectedLabels;
  bool                  mergeLabels{ false };
  std::optional<double> isoValue;
  /** The selected labels that no voxel of the image carries (itk::DelaunayImageToMeshFilter::
   * GetSelectedLabelsNotInImage()): none of them is in the mesh, and the report says so as it does for a lost
   * tissue, which a label absent from the segmentation cannot be. */
  std::vector<Label> selectedLabelsNotInImage;
  /** The cap on the triangulation's vertices. */
  std::size_t maximumNumberOfVertices{ 0 };
  TopologyRun topology;
};

/** The tetrahedra carrying one label, and their boundary against the background and the other labels. */
struct LabelQuality
{
  Label       label{ BackgroundLabel };
  std::size_t vertices{ 0 };
  std::size_t tetrahedra{ 0 };
  /** Volume of the label's tetrahedra, mm³. */
  double meshVolume{ 0.0 };
  /** The label's voxels in the segmentation × the voxel volume, mm³. */
  double segmentedVolume{ 0.0 };
  /** The label's boundary: the boundary triangles with this label on one of their sides; their number,
   * manifoldness, components, genus and smallest planar angle. The genus means nothing unless the boundary is
   * a closed manifold: otherwise it is printed as "-" and written as null. */
  SurfaceTopology boundary;
  /** For a lost label (IsLost()), the face-connected pieces of its voxels in the segmentation; otherwise 0. */
  std::size_t lostComponents{ 0 };
  /** What the regularisation at the scale of δ did to the label: its components removed whole (thinner than the
   * scale everywhere), the volume it took from the label and the volume it gave to it, mm³. Added by
   * AddWhatTheMeshLeftOut(); 0 without it. */
  std::size_t regularizedComponentsRemoved{ 0 };
  double      regularizedVolumeRemoved{ 0.0 };
  double      regularizedVolumeAdded{ 0.0 };
  /** Parts of the label as meshed (after the regularisation) that hold no tetrahedron, and their volume, mm³
   * (RefinementStatistics::unmeshedParts). Added by AddWhatTheMeshLeftOut(); 0 without it. */
  std::size_t partsWithoutTetrahedra{ 0 };
  double      partsWithoutTetrahedraVolume{ 0.0 };

  /** Whether the segmentation has voxels of this label but the mesh no tetrahedron: the mesher lost it (a tissue
   * thinner than δ, say) or a later step removed it. Its boundary is then empty: it has no angle and no genus. */
  bool
  IsLost() const
  {
    return tetrahedra == 0 && segmentedVolume > 0.0;
  }
};

/** Each tetrahedron's smallest dihedral angle, counted in bins of `binWidth` degrees from 0°: counts[i] is the
 * number of tetrahedra whose smallest dihedral angle is in [i · binWidth, (i + 1) · binWidth). The bins cover
 * [0°, 90°), which holds every tetrahedron's smallest dihedral angle (at most 70.53°, the regular one's). */
struct AngleHistogram
{
  double                   binWidth{ 2.0 };
  std::vector<std::size_t> counts;
};

/** The smallest dihedral angles, in degrees, that QualityReport counts tetrahedra below. */
constexpr std::array<double, 3> SliverAngleThresholds{ { 5.0, 10.0, 15.0 } };

/** Quality and fidelity of a labelled tetrahedral mesh against the segmentation it was made from. */
struct QualityReport
{
  MeshingRun  run;
  std::size_t vertices{ 0 };
  std::size_t tetrahedra{ 0 };
  std::size_t boundaryTriangles{ 0 };
  /** Dihedral angles of all tetrahedra, degrees. */
  double minimumDihedralAngle{ 0.0 };
  double maximumDihedralAngle{ 0.0 };
  /** Tetrahedra whose smallest dihedral angle is below each of SliverAngleThresholds (5°, 10°, 15°): what an FEM
   * user asks first. */
  std::array<std::size_t, 3> tetrahedraBelowDihedralAngle{};
  /** Tetrahedra flat to rounding: volume <= 1e-6 × shortest edge cubed (expected: 0). */
  std::size_t flatTetrahedra{ 0 };
  /** Largest circumradius / shortest edge of any tetrahedron (< ρ is guaranteed). */
  double maximumRadiusEdgeRatio{ 0.0 };
  /** Tetrahedra with signed volume <= 0 or a repeated vertex (expected: 0). */
  std::size_t invertedTetrahedra{ 0 };
  /** Smallest planar angle of any boundary triangle, degrees (> 30° is guaranteed when σ = 0). */
  double minimumBoundaryPlanarAngle{ 0.0 };
  /** Non-manifold edges and vertices summed over the labels' boundaries (0 for a closed 2-manifold). The
   * boundaries are checked label by label because three labels meeting along a curve are a legitimate
   * non-manifold junction of the whole interface complex. */
  std::size_t nonManifoldEdges{ 0 };
  std::size_t nonManifoldVertices{ 0 };
  double      meshVolume{ 0.0 };
  double      segmentedVolume{ 0.0 };
  /** Whether the distance below was measured (DistanceMeasurement). */
  bool distanceMeasured{ false };
  /** Two-sided distance between the mesh's boundary triangles and the marching-cubes surface of the
   * segmentation (ExtractLabelSurfaces()), both sampled every `distanceSampleSpacing` mm. */
  DistanceStatistics distanceToMarchingCubes;
  double             distanceSampleSpacing{ 0.0 };
  AngleHistogram     minimumDihedralAngleHistogram;
  /** One entry per label of the mesh or of the segmentation, in increasing label order; a label only in the
   * segmentation is lost (LabelQuality::IsLost()). */
  std::vector<LabelQuality> labels;

  /** Whether every label's boundary is a closed 2-manifold. */
  bool
  IsManifold() const
  {
    return nonManifoldEdges == 0 && nonManifoldVertices == 0;
  }
};

/** Whether ComputeQualityReport() measures the two-sided distance to the segmentation's marching-cubes surface.
 * Everything else in the report costs a few percent of the meshing; the distance costs several times the meshing
 * on a speckled segmentation, whose marching-cubes surface has millions of triangles (the k-means tissues at δ =
 * 3 mm: 7 s meshing, 31 s distance on one core), so the command line measures it only when asked (--distance). */
enum class DistanceMeasurement
{
  Measure,
  Skip
};

/** Measures `mesh` and compares it with `segmentation`, the voxels of the labels that were meshed (every
 * other voxel 0). The distance samples are every vertex of both surfaces and points about the smallest voxel
 * spacing apart on their triangles: the marching-cubes surface has no feature smaller than a voxel, and finer
 * samples would make the report cost more than the meshing. `distanceProgress`, when given, is told how far the
 * distance measurement is (ComputeTwoSidedDistance). `report.run` is left for the caller to fill.
 * \throws std::invalid_argument if the mesh arrays are inconsistent (a label missing, a point index out of
 * range) or the segmentation's labels do not match its size. */
QualityReport
ComputeQualityReport(const TetrahedralMesh & mesh, const LabelVolume & segmentation,
                     DistanceMeasurement      distance = DistanceMeasurement::Measure,
                     const DistanceProgress & distanceProgress = {});

/** Adds to the report's labels what the mesh leaves out of the segmentation on purpose: what the regularisation at
 * the scale of δ removed and added (`regularization`, whose volumes are in voxels of `voxelVolume` mm³), and the parts
 * of the regularised labels that hold no tetrahedron (`unmeshedParts`, each thinner than δ unless the refinement's
 * rounds could not mesh it). Entries for labels the report does not list are ignored. */
void
AddWhatTheMeshLeftOut(QualityReport & report, const LabelRegularizationReport & regularization, double voxelVolume,
                      const std::vector<UnmeshedPart> & unmeshedParts);

/** Prints the report as a short table of aligned columns, for people. A lost label's row ends with "lost: N
 * component(s), V mm^3" instead of angles and genus, and the summary lists the lost labels. */
void
PrintQualityReport(const QualityReport & report, std::ostream & out);

/** Writes the report as a JSON object (nlohmann-json), for programs; non-finite numbers are written as null,
 * doubles to their last digit, bytes of file names that are not UTF-8 as U+FFFD. Keys, in this order: input,
 * output, parameters {delta_mm, radius_edge_bound, min_dihedral_angle_deg, labels ("all" or the list),
 * merge_labels, iso_value (null without one), max_vertices, regularization_scale, join_diagonal_voxels,
 * relabel_non_manifold_places, topology_rounds, refine_thick_parts, manifold_refinement_levels}, topology
 * {voxels_changed_at_pinches, relabelled_tetrahedra, regularization_rounds, locally_regularized_voxels,
 * budget_reached, thick_parts_refined, manifold_refinement_rounds}, vertices, tetrahedra,
 * boundary_triangles, quality {min_dihedral_angle_deg, max_dihedral_angle_deg, max_radius_edge_ratio,
 * min_boundary_planar_angle_deg, inverted_tetrahedra, manifold, non_manifold_edges, non_manifold_vertices},
 * mesh_volume_mm3, segmented_volume_mm3, distance_to_marching_cubes {sample_spacing_mm, samples, mean_mm,
 * percentile95_mm, max_mm} (null when not measured), labels [{label, vertices, tetrahedra, boundary_triangles,
 * mesh_volume_mm3, segmented_volume_mm3, boundary_components, boundary_genus, boundary_component_genera,
 * non_manifold_edges, non_manifold_vertices, min_planar_angle_deg, lost, regularization {components_removed,
 * volume_removed_mm3, volume_added_mm3}, parts_without_tetrahedra, parts_without_tetrahedra_mm3, and for a lost label
 * lost_components and lost_volume_mm3, its genus, genera and angle null}], min_dihedral_angle_histogram {bin_width_deg,
 * counts}, time_seconds {phase: seconds}, peak_memory_bytes. */
void
WriteQualityReportJson(const QualityReport & report, std::ostream & out);

/** WriteQualityReportJson() to a file. \throws std::runtime_error if the file cannot be written. */
void
WriteQualityReportJsonFile(const QualityReport & report, const std::string & fileName);

/** The peak resident memory of this process so far, bytes (getrusage); 0 where it cannot be measured. */
std::size_t
PeakResidentMemoryBytes();

} // namespace delaunay_refinement

#endif
