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
#include "DelaunayImageToMeshQualityReport.h"
#include "DelaunayImageToMeshVoxelComponents.h"
#include "DelaunayRefinementGeometry.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <locale>
#include <map>
#include <sstream>
#include <stdexcept>

#if !defined(_WIN32)
#  include <sys/resource.h>
#endif

namespace delaunay_refinement
{
namespace
{

constexpr double HistogramRangeDegrees = 90.0;
constexpr double HistogramBinWidthDegrees = 2.0;

void
CheckInputs(const TetrahedralMesh & mesh, const LabelVolume & segmentation)
{
  const std::size_t voxels = segmentation.NumberOfVoxels();
  if (segmentation.borrowedLabels == nullptr && segmentation.labels.size() != voxels)
  {
    throw std::invalid_argument("ComputeQualityReport: the segmentation has " +
                                std::to_string(segmentation.labels.size()) + " labels for " + std::to_string(voxels) +
                                " voxels.");
  }
  for (const auto & tetrahedron : mesh.tetrahedra)
  {
    for (const uint32_t point : tetrahedron)
    {
      if (point >= mesh.points.size())
      {
        throw std::invalid_argument("ComputeQualityReport: a tetrahedron uses point index " + std::to_string(point) +
                                    ", but the mesh has only " + std::to_string(mesh.points.size()) + " points.");
      }
    }
  }
  if (mesh.tetrahedronLabels.size() != mesh.tetrahedra.size() ||
      mesh.boundaryTriangleLabels.size() != mesh.boundaryTriangles.size())
  {
    throw std::invalid_argument(
      "ComputeQualityReport: the mesh needs one label per tetrahedron (" +
      std::to_string(mesh.tetrahedronLabels.size()) + " for " + std::to_string(mesh.tetrahedra.size()) +
      ") and one label pair per boundary triangle (" + std::to_string(mesh.boundaryTriangleLabels.size()) + " for " +
      std::to_string(mesh.boundaryTriangles.size()) + ").");
  }
}

double
TetrahedronVolume(const TetrahedralMesh & mesh, const std::array<uint32_t, 4> & tetrahedron)
{
  const Vector3 & origin = mesh.points[tetrahedron[0]];
  return Dot(mesh.points[tetrahedron[1]] - origin,
             Cross(mesh.points[tetrahedron[2]] - origin, mesh.points[tetrahedron[3]] - origin)) /
         6.0;
}

/** The volume of one voxel: the spacing's product, scaled by |det(direction)| in case the direction is not
 * orthonormal. */
double
VoxelVolume(const LabelVolume & volume)
{
  const auto & d = volume.direction;
  const double determinant = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1]) -
                             d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0]) +
                             d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
  return std::abs(determinant) * volume.spacing[0] * volume.spacing[1] * volume.spacing[2];
}

/** Tetrahedra, vertices and volumes of every label of the mesh or of the segmentation. */
std::map<Label, LabelQuality>
MeasureLabels(const TetrahedralMesh & mesh, const LabelVolume & segmentation)
{
  std::map<Label, LabelQuality> labels;
  // Each label's corners, repeats included: a flag per point and label cost the number of labels times the points.
  std::map<Label, std::vector<uint32_t>> cornersOf;
  for (std::size_t i = 0; i < mesh.tetrahedra.size(); ++i)
  {
    LabelQuality & quality = labels[mesh.tetrahedronLabels[i]];
    ++quality.tetrahedra;
    quality.meshVolume += TetrahedronVolume(mesh, mesh.tetrahedra[i]);
    std::vector<uint32_t> & corners = cornersOf[mesh.tetrahedronLabels[i]];
    corners.insert(corners.end(), mesh.tetrahedra[i].begin(), mesh.tetrahedra[i].end());
  }
  for (auto & [label, corners] : cornersOf)
  {
    std::sort(corners.begin(), corners.end());
    labels[label].vertices = static_cast<std::size_t>(std::unique(corners.begin(), corners.end()) - corners.begin());
  }

  const double        voxelVolume = VoxelVolume(segmentation);
  const Label * const segmented = segmentation.Labels();
  for (std::size_t voxel = 0; voxel < segmentation.NumberOfVoxels(); ++voxel)
  {
    const Label label = segmented[voxel];
    if (label != BackgroundLabel)
    {
      labels[label].segmentedVolume += voxelVolume;
    }
  }
  using Triangles = std::vector<std::array<uint32_t, 3>>;
  const std::map<Label, Triangles> boundaryTriangles = BoundaryTrianglesByLabel(mesh);
  const Triangles                  none;
  std::vector<Label>               lost;
  for (auto & labelAndQuality : labels)
  {
    LabelQuality & quality = labelAndQuality.second;
    quality.label = labelAndQuality.first;
    const auto found = boundaryTriangles.find(quality.label);
    quality.boundary = ComputeSurfaceTopology(mesh.points, found == boundaryTriangles.end() ? none : found->second);
    if (quality.IsLost())
    {
      lost.push_back(quality.label);
    }
  }
  for (const auto & [label, components] : CountVoxelComponents(segmentation, lost))
  {
    labels[label].lostComponents = components;
  }
  return labels;
}

AngleHistogram
HistogramOf(const std::vector<double> & anglesInDegrees)
{
  AngleHistogram histogram;
  histogram.binWidth = HistogramBinWidthDegrees;
  histogram.counts.assign(static_cast<std::size_t>(HistogramRangeDegrees / HistogramBinWidthDegrees), 0);
  for (const double angle : anglesInDegrees)
  {
    // A degenerate tetrahedron has no defined angle; it is counted among the inverted ones instead.
    if (std::isfinite(angle))
    {
      ++histogram.counts.at(static_cast<std::size_t>(angle / histogram.binWidth));
    }
  }
  return histogram;
}

void
AddTetrahedronQuality(const TetrahedralMesh & mesh, QualityReport & report)
{
  const TetrahedronQuality quality = ComputeTetrahedronQuality(mesh);
  report.minimumDihedralAngle = quality.minimumDihedralAngle;
  report.maximumDihedralAngle = quality.maximumDihedralAngle;
  report.maximumRadiusEdgeRatio = quality.maximumRadiusEdgeRatio;
  report.invertedTetrahedra = quality.invertedTetrahedra + quality.malformedTetrahedra;
  report.minimumDihedralAngleHistogram = HistogramOf(quality.minimumDihedralAngles);
  for (std::size_t threshold = 0; threshold < SliverAngleThresholds.size(); ++threshold)
  {
    report.tetrahedraBelowDihedralAngle[threshold] = static_cast<std::size_t>(
      std::count_if(quality.minimumDihedralAngles.begin(), quality.minimumDihedralAngles.end(), [&](double angle) {
        return angle < SliverAngleThresholds[threshold];
      }));
  }
  report.flatTetrahedra = 0;
  for (const auto & tetrahedron : mesh.tetrahedra)
  {
    const std::array<Vector3, 4> corners{ { mesh.points[tetrahedron[0]],
                                            mesh.points[tetrahedron[1]],
                                            mesh.points[tetrahedron[2]],
                                            mesh.points[tetrahedron[3]] } };
    report.flatTetrahedra += !(VolumeOverShortestEdgeCubed(corners) > 1e-6) ? 1 : 0;
  }
}

void
AddLabelQualities(const TetrahedralMesh & mesh, const LabelVolume & segmentation, QualityReport & report)
{
  report.minimumBoundaryPlanarAngle = 180.0;
  for (const auto & labelAndQuality : MeasureLabels(mesh, segmentation))
  {
    const LabelQuality & quality = labelAndQuality.second;
    report.labels.push_back(quality);
    report.meshVolume += quality.meshVolume;
    report.segmentedVolume += quality.segmentedVolume;
    report.nonManifoldEdges += quality.boundary.nonManifoldEdges;
    report.nonManifoldVertices += quality.boundary.nonManifoldVertices;
    // Every boundary triangle bounds the label on its inner side, so the labels' minima cover all triangles.
    report.minimumBoundaryPlanarAngle =
      std::min(report.minimumBoundaryPlanarAngle, quality.boundary.minimumPlanarAngle);
  }
}

void
AddDistanceToMarchingCubes(const TetrahedralMesh & mesh, const LabelVolume & segmentation, QualityReport & report,
                           const DistanceProgress & progress)
{
  const TriangleSurface reference = ExtractLabelSurfaces(segmentation);
  report.distanceSampleSpacing = *std::min_element(segmentation.spacing.begin(), segmentation.spacing.end());
  report.distanceMeasured = true;
  report.distanceToMarchingCubes = ComputeTwoSidedDistance(mesh.points,
                                                           mesh.boundaryTriangles,
                                                           reference.points,
                                                           reference.triangles,
                                                           report.distanceSampleSpacing,
                                                           progress)
                                     .combined;
}

// ---------------------------------------------------------------------------------------------------------------
// JSON. ordered_json keeps the members in the order people read them; nlohmann-json writes non-finite numbers
// (JSON has none: a distance to an empty surface, say) as null.

using Json = nlohmann::ordered_json;

Json
ParametersJson(const MeshingRun & run)
{
  const TopologyRun & topology = run.topology;
  return { { "delta_mm", run.surfaceSamplingDistance },
           { "radius_edge_bound", run.radiusEdgeBound },
           { "min_dihedral_angle_deg", run.minimumDihedralAngle },
           { "labels", run.selectedLabels.empty() ? Json("all") : Json(run.selectedLabels) },
           { "merge_labels", run.mergeLabels },
           { "iso_value", run.isoValue ? Json(*run.isoValue) : Json() },
           { "max_vertices", run.maximumNumberOfVertices },
           { "regularization_scale", topology.regularizationScale },
           { "join_diagonal_voxels", topology.joinDiagonalVoxels },
           { "relabel_non_manifold_places", topology.relabelNonManifoldPlaces },
           { "topology_rounds", topology.regularizationRoundsAllowed },
           { "refine_thick_parts", topology.refineThickParts },
           { "manifold_refinement_levels", topology.manifoldRefinementLevels } };
}

/** What the topology options did (TopologyRun). */
Json
TopologyJson(const TopologyRun & topology)
{
  return { { "voxels_changed_at_pinches", topology.voxelsChangedAtPinches },
           { "relabelled_tetrahedra", topology.relabelledTetrahedra },
           { "regularization_rounds", topology.regularizationRoundsMade },
           { "locally_regularized_voxels", topology.locallyRegularizedVoxels },
           { "budget_reached", topology.budgetReached },
           { "thick_parts_refined", topology.thickPartsRefined },
           { "manifold_refinement_rounds", topology.manifoldRefinementRounds } };
}

/** {"5": count, "10": count, "15": count}: the thresholds are SliverAngleThresholds, written once. */
Json
BelowDihedralAngleJson(const QualityReport & report)
{
  Json counts = Json::object();
  for (std::size_t threshold = 0; threshold < SliverAngleThresholds.size(); ++threshold)
  {
    std::ostringstream key;
    key << SliverAngleThresholds[threshold];
    counts[key.str()] = report.tetrahedraBelowDihedralAngle[threshold];
  }
  return counts;
}

Json
QualityJson(const QualityReport & report)
{
  return { { "min_dihedral_angle_deg", report.minimumDihedralAngle },
           { "max_dihedral_angle_deg", report.maximumDihedralAngle },
           { "max_radius_edge_ratio", report.maximumRadiusEdgeRatio },
           { "min_boundary_planar_angle_deg", report.minimumBoundaryPlanarAngle },
           { "inverted_tetrahedra", report.invertedTetrahedra },
           { "flat_tetrahedra", report.flatTetrahedra },
           { "tetrahedra_below_dihedral_deg", BelowDihedralAngleJson(report) },
           { "manifold", report.IsManifold() },
           { "non_manifold_edges", report.nonManifoldEdges },
           { "non_manifold_vertices", report.nonManifoldVertices } };
}

/** null when the distance was not measured (DistanceMeasurement::Skip). */
Json
DistanceJson(const QualityReport & report)
{
  if (!report.distanceMeasured)
  {
    return nullptr;
  }
  const DistanceStatistics & distance = report.distanceToMarchingCubes;
  return { { "sample_spacing_mm", report.distanceSampleSpacing },
           { "samples", distance.count },
           { "mean_mm", distance.mean },
           { "percentile95_mm", distance.percentile95 },
           { "max_mm", distance.maximum } };
}

/** The genus of a surface that is not a closed manifold means nothing, and a lost label has neither genus nor
 * angle: they are written as null. */
Json
LabelJson(const LabelQuality & quality)
{
  const SurfaceTopology & boundary = quality.boundary;
  const bool              lost = quality.IsLost();
  const bool              closed = boundary.IsClosedManifold() && !lost;
  Json                    json{ { "label", quality.label },
             { "vertices", quality.vertices },
             { "tetrahedra", quality.tetrahedra },
             { "boundary_triangles", boundary.numberOfTriangles },
             { "mesh_volume_mm3", quality.meshVolume },
             { "segmented_volume_mm3", quality.segmentedVolume },
             { "boundary_components", boundary.numberOfComponents },
             { "boundary_genus", closed ? Json(boundary.totalGenus) : Json() },
             { "boundary_component_genera", closed ? Json(boundary.componentGenera) : Json() },
             { "non_manifold_edges", boundary.nonManifoldEdges },
             { "non_manifold_vertices", boundary.nonManifoldVertices },
             { "min_planar_angle_deg", lost ? Json() : Json(boundary.minimumPlanarAngle) },
             { "lost", lost },
             { "regularization",
                                  { { "components_removed", quality.regularizedComponentsRemoved },
                                    { "volume_removed_mm3", quality.regularizedVolumeRemoved },
                                    { "volume_added_mm3", quality.regularizedVolumeAdded } } },
             { "parts_without_tetrahedra", quality.partsWithoutTetrahedra },
             { "parts_without_tetrahedra_mm3", quality.partsWithoutTetrahedraVolume } };
  if (lost)
  {
    json["lost_components"] = quality.lostComponents;
    json["lost_volume_mm3"] = quality.segmentedVolume;
  }
  return json;
}

Json
ReportJson(const QualityReport & report)
{
  const MeshingRun & run = report.run;
  Json               labels = Json::array();
  for (const LabelQuality & quality : report.labels)
  {
    labels.push_back(LabelJson(quality));
  }
  Json phaseSeconds = Json::object();
  for (const auto & phaseAndSeconds : run.phaseSeconds)
  {
    phaseSeconds[phaseAndSeconds.first] = phaseAndSeconds.second;
  }
  const AngleHistogram & histogram = report.minimumDihedralAngleHistogram;
  return { { "input", run.inputFile },
           { "output", run.outputFile },
           { "parameters", ParametersJson(run) },
           { "topology", TopologyJson(run.topology) },
           { "vertices", report.vertices },
           { "tetrahedra", report.tetrahedra },
           { "boundary_triangles", report.boundaryTriangles },
           { "quality", QualityJson(report) },
           { "mesh_volume_mm3", report.meshVolume },
           { "segmented_volume_mm3", report.segmentedVolume },
           { "distance_to_marching_cubes", DistanceJson(report) },
           { "labels", labels },
           { "selected_labels_not_in_image", run.selectedLabelsNotInImage },
           { "min_dihedral_angle_histogram",
             { { "bin_width_deg", histogram.binWidth }, { "counts", histogram.counts } } },
           { "time_seconds", phaseSeconds },
           { "peak_memory_bytes", run.peakResidentMemoryBytes } };
}

// ---------------------------------------------------------------------------------------------------------------
// The table.

std::string
Fixed(double value, int decimals)
{
  std::ostringstream text;
  text.imbue(std::locale::classic());
  text << std::fixed << std::setprecision(decimals) << value;
  return text.str();
}

std::string
SignedPercent(double part, double whole)
{
  const double percent = 100.0 * (part - whole) / whole;
  return (percent >= 0.0 ? "+" : "") + Fixed(percent, 2) + "%";
}

void
PrintRow(std::ostream & out, const std::string & name, const std::string & value)
{
  out << "  " << std::left << std::setw(28) << name << value << '\n';
}

std::string
PhasesText(const MeshingRun & run)
{
  std::string text;
  for (const auto & phaseAndSeconds : run.phaseSeconds)
  {
    text += (text.empty() ? "" : ", ") + phaseAndSeconds.first + " " + Fixed(phaseAndSeconds.second, 2) + " s";
  }
  return text;
}

/** "2 components, 1.0 mm^3": what the segmentation had of a lost label. */
std::string
LostText(const LabelQuality & quality)
{
  return std::to_string(quality.lostComponents) + (quality.lostComponents == 1 ? " component, " : " components, ") +
         Fixed(quality.segmentedVolume, 1) + " mm^3";
}

/** "label 3 (1 component, 1.0 mm^3)" for each lost label; empty if none is lost. */
std::string
LostLabelsText(const std::vector<LabelQuality> & labels)
{
  std::string text;
  for (const LabelQuality & quality : labels)
  {
    if (quality.IsLost())
    {
      text += (text.empty() ? "label " : ", label ") + std::to_string(quality.label) + " (" + LostText(quality) + ")";
    }
  }
  return text;
}

void
PrintSummary(const QualityReport & report, std::ostream & out)
{
  const MeshingRun & run = report.run;
  PrintRow(out, "input", run.inputFile);
  PrintRow(out, "output", run.outputFile);
  PrintRow(out,
           "delta / rho / sigma",
           Fixed(run.surfaceSamplingDistance, 3) + " mm / " + Fixed(run.radiusEdgeBound, 2) + " / " +
             (run.minimumDihedralAngle > 0.0 ? Fixed(run.minimumDihedralAngle, 1) + " deg" : "off"));
  PrintRow(out, "vertices", std::to_string(report.vertices));
  PrintRow(out, "tetrahedra", std::to_string(report.tetrahedra));
  PrintRow(out, "boundary triangles", std::to_string(report.boundaryTriangles));
  PrintRow(out,
           "dihedral angle min / max",
           Fixed(report.minimumDihedralAngle, 3) + " / " + Fixed(report.maximumDihedralAngle, 3) + " deg");
  PrintRow(out,
           "dihedral < 5 / 10 / 15 deg",
           std::to_string(report.tetrahedraBelowDihedralAngle[0]) + " / " +
             std::to_string(report.tetrahedraBelowDihedralAngle[1]) + " / " +
             std::to_string(report.tetrahedraBelowDihedralAngle[2]));
  PrintRow(out, "flat (vol <= 1e-6 l^3)", std::to_string(report.flatTetrahedra));
  PrintRow(out, "max radius-edge ratio", Fixed(report.maximumRadiusEdgeRatio, 3));
  PrintRow(out, "min boundary planar angle", Fixed(report.minimumBoundaryPlanarAngle, 2) + " deg");
  PrintRow(out, "inverted tetrahedra", std::to_string(report.invertedTetrahedra));
  PrintRow(out,
           "manifold boundaries",
           std::string(report.IsManifold() ? "yes" : "NO") + " (" + std::to_string(report.nonManifoldEdges) +
             " non-manifold edges, " + std::to_string(report.nonManifoldVertices) + " non-manifold vertices)");
  PrintRow(out,
           "volume mesh / segmented",
           Fixed(report.meshVolume, 1) + " / " + Fixed(report.segmentedVolume, 1) + " mm^3 (" +
             SignedPercent(report.meshVolume, report.segmentedVolume) + ")");
  const std::string lostLabels = LostLabelsText(report.labels);
  if (!lostLabels.empty())
  {
    PrintRow(out, "LOST tissues", lostLabels);
  }
  if (!run.selectedLabelsNotInImage.empty())
  {
    std::string notInImage;
    for (const Label label : run.selectedLabelsNotInImage)
    {
      notInImage += (notInImage.empty() ? "label " : ", label ") + std::to_string(label);
    }
    PrintRow(out,
             "selected, NOT in image",
             notInImage +
               (run.selectedLabelsNotInImage.size() == 1 ? " (no voxel carries it)" : " (no voxel carries them)"));
  }
  std::size_t regularizedAway = 0;
  double      volumeRemoved = 0.0;
  double      volumeAdded = 0.0;
  std::size_t partsLeftOut = 0;
  double      volumeLeftOut = 0.0;
  for (const LabelQuality & quality : report.labels)
  {
    regularizedAway += quality.regularizedComponentsRemoved;
    volumeRemoved += quality.regularizedVolumeRemoved;
    volumeAdded += quality.regularizedVolumeAdded;
    partsLeftOut += quality.partsWithoutTetrahedra;
    volumeLeftOut += quality.partsWithoutTetrahedraVolume;
  }
  if (volumeRemoved > 0.0 || volumeAdded > 0.0)
  {
    PrintRow(out,
             "regularised at delta",
             std::to_string(regularizedAway) + (regularizedAway == 1 ? " component" : " components") + " removed; " +
               Fixed(volumeRemoved, 1) + " mm^3 taken from tissues, " + Fixed(volumeAdded, 1) + " mm^3 given to them");
  }
  if (partsLeftOut > 0)
  {
    PrintRow(out,
             "parts without tetrahedra",
             std::to_string(partsLeftOut) + " (" + Fixed(volumeLeftOut, 1) + " mm^3), per label in the JSON report");
  }
  const DistanceStatistics & distance = report.distanceToMarchingCubes;
  PrintRow(out,
           "distance to marching cubes",
           report.distanceMeasured ? "mean " + Fixed(distance.mean, 3) + ", p95 " + Fixed(distance.percentile95, 3) +
                                       ", max " + Fixed(distance.maximum, 3) + " mm"
                                   : std::string("not measured (--distance)"));
  PrintRow(out, "time", PhasesText(run));
  PrintRow(out, "peak memory", Fixed(static_cast<double>(run.peakResidentMemoryBytes) / (1024.0 * 1024.0), 1) + " MiB");
}

void
PrintLabelTable(const std::vector<LabelQuality> & labels, std::ostream & out)
{
  const std::vector<std::pair<std::string, int>> columns{
    { "label", 7 },       { "vertices", 10 },   { "tetrahedra", 12 }, { "triangles", 11 },      { "mesh mm^3", 12 },
    { "voxel mm^3", 12 }, { "components", 12 }, { "genus", 7 },       { "non-manif. e/v", 16 }, { "min angle", 11 }
  };
  out << "  ";
  for (const auto & column : columns)
  {
    out << std::right << std::setw(column.second) << column.first;
  }
  out << '\n';
  for (const LabelQuality & quality : labels)
  {
    const SurfaceTopology & boundary = quality.boundary;
    const bool              lost = quality.IsLost();
    // A lost label's boundary is empty: it has no components, genus or angle to show.
    const auto                     boundaryCell = [lost](const std::string & text) { return lost ? "-" : text; };
    const std::vector<std::string> cells{
      std::to_string(quality.label),
      std::to_string(quality.vertices),
      std::to_string(quality.tetrahedra),
      std::to_string(boundary.numberOfTriangles),
      Fixed(quality.meshVolume, 1),
      Fixed(quality.segmentedVolume, 1),
      boundaryCell(std::to_string(boundary.numberOfComponents)),
      boundaryCell(boundary.IsClosedManifold() ? std::to_string(boundary.totalGenus) : "-"),
      boundaryCell(std::to_string(boundary.nonManifoldEdges) + "/" + std::to_string(boundary.nonManifoldVertices)),
      boundaryCell(Fixed(boundary.minimumPlanarAngle, 2))
    };
    out << "  ";
    for (std::size_t i = 0; i < cells.size(); ++i)
    {
      out << std::right << std::setw(columns[i].second) << cells[i];
    }
    out << (lost ? "  lost: " + LostText(quality) : "") << '\n';
  }
}

} // namespace

QualityReport
ComputeQualityReport(const TetrahedralMesh & mesh, const LabelVolume & segmentation, DistanceMeasurement distance,
                     const DistanceProgress & distanceProgress)
{
  CheckInputs(mesh, segmentation);
  QualityReport report;
  report.vertices = mesh.points.size();
  report.tetrahedra = mesh.tetrahedra.size();
  report.boundaryTriangles = mesh.boundaryTriangles.size();
  AddTetrahedronQuality(mesh, report);
  AddLabelQualities(mesh, segmentation, report);
  if (distance == DistanceMeasurement::Measure)
  {
    AddDistanceToMarchingCubes(mesh, segmentation, report, distanceProgress);
  }
  return report;
}

void
AddWhatTheMeshLeftOut(QualityReport & report, const LabelRegularizationReport & regularization, double voxelVolume,
                      const std::vector<UnmeshedPart> & unmeshedParts)
{
  const auto entryOf = [&report](Label label) -> LabelQuality * {
    const auto found = std::find_if(report.labels.begin(), report.labels.end(), [label](const LabelQuality & quality) {
      return quality.label == label;
    });
    return found == report.labels.end() ? nullptr : &*found;
  };
  for (const LabelRegularizationChange & change : regularization.labels)
  {
    if (LabelQuality * const quality = entryOf(change.label))
    {
      quality->regularizedComponentsRemoved += change.componentsRemoved;
      quality->regularizedVolumeRemoved += static_cast<double>(change.voxelsRemoved) * voxelVolume;
      quality->regularizedVolumeAdded += static_cast<double>(change.voxelsAdded) * voxelVolume;
    }
  }
  for (const UnmeshedPart & part : unmeshedParts)
  {
    if (LabelQuality * const quality = entryOf(part.label))
    {
      ++quality->partsWithoutTetrahedra;
      quality->partsWithoutTetrahedraVolume += part.volume;
    }
  }
}

void
PrintQualityReport(const QualityReport & report, std::ostream & out)
{
  out << "Mesh quality report\n";
  PrintSummary(report, out);
  out << '\n';
  PrintLabelTable(report.labels, out);
}

void
WriteQualityReportJson(const QualityReport & report, std::ostream & out)
{
  // File names need not be UTF-8 (a Latin-1 directory, say): bytes JSON cannot hold become U+FFFD, not an error.
  out << ReportJson(report).dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
}

void
WriteQualityReportJsonFile(const QualityReport & report, const std::string & fileName)
{
  std::ofstream file(fileName);
  if (file)
  {
    WriteQualityReportJson(report, file);
    file.close();
  }
  if (!file)
  {
    throw std::runtime_error("cannot write the report file \"" + fileName + "\"");
  }
}

std::size_t
PeakResidentMemoryBytes()
{
#if defined(_WIN32)
  return 0;
#else
  struct rusage usage
  {};
  if (getrusage(RUSAGE_SELF, &usage) != 0)
  {
    return 0;
  }
#  if defined(__APPLE__)
  constexpr std::size_t bytesPerUnit = 1;
#  else
  // Linux reports kibibytes.
  constexpr std::size_t bytesPerUnit = 1024;
#  endif
  return static_cast<std::size_t>(usage.ru_maxrss) * bytesPerUnit;
#endif
}

} // namespace delaunay_refinement
