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

// The quality report that delaunay-image-to-mesh prints, on the unit cube cut into the six Kuhn tetrahedra
// (0, e_a, e_a + e_b, (1, 1, 1)) for the orders (a, b, c) of the axes, against a 2 x 2 x 2-voxel segmentation
// of the same cube. Every expected value is derived in the comments.

#include "DelaunayImageToMeshQualityReport.h"
#include "DelaunayImageToMeshSurfaceExtraction.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace delaunay_refinement
{
namespace
{

constexpr double Tolerance = 1e-9;

using Face = std::array<uint32_t, 3>;

double
SignedVolume(const TetrahedralMesh & mesh, const std::array<uint32_t, 4> & t)
{
  const Vector3 & p = mesh.points[t[0]];
  return Dot(mesh.points[t[1]] - p, Cross(mesh.points[t[2]] - p, mesh.points[t[3]] - p)) / 6.0;
}

/** Cube corner (x, y, z) in {0, 1}^3 is point x + 2y + 4z. Tetrahedra whose x runs ahead of y get label 1,
 * the others `otherLabel`. */
TetrahedralMesh
KuhnCube(Label otherLabel)
{
  TetrahedralMesh mesh;
  for (uint32_t corner = 0; corner < 8; ++corner)
  {
    mesh.points.push_back({ { double(corner & 1u), double((corner >> 1) & 1u), double((corner >> 2) & 1u) } });
  }
  mesh.pointKinds.assign(8, VertexKind::BoxEdge);
  std::array<uint32_t, 3> axes{ { 0, 1, 2 } };
  do
  {
    const uint32_t          first = 1u << axes[0];
    std::array<uint32_t, 4> tetrahedron{ { 0, first, first | (1u << axes[1]), 7 } };
    if (SignedVolume(mesh, tetrahedron) < 0.0)
    {
      std::swap(tetrahedron[2], tetrahedron[3]);
    }
    mesh.tetrahedra.push_back(tetrahedron);
    const bool xBeforeY = std::find(axes.begin(), axes.end(), 0u) < std::find(axes.begin(), axes.end(), 1u);
    mesh.tetrahedronLabels.push_back(xBeforeY ? 1 : otherLabel);
  } while (std::next_permutation(axes.begin(), axes.end()));
  return mesh;
}

/** Adds the faces between different labels (the background outside), as the core makes them: outwards from
 * the tetrahedron's side, interfaces once, from the smaller label. */
void
AddBoundaryTriangles(TetrahedralMesh & mesh)
{
  std::map<Face, std::vector<std::pair<Face, Label>>> sidesOfFace;
  for (std::size_t i = 0; i < mesh.tetrahedra.size(); ++i)
  {
    const auto & t = mesh.tetrahedra[i];
    for (const Face & outwards : { Face{ { t[0], t[2], t[1] } },
                                   Face{ { t[0], t[1], t[3] } },
                                   Face{ { t[0], t[3], t[2] } },
                                   Face{ { t[1], t[2], t[3] } } })
    {
      Face key = outwards;
      std::sort(key.begin(), key.end());
      sidesOfFace[key].emplace_back(outwards, mesh.tetrahedronLabels[i]);
    }
  }
  for (const auto & faceAndSides : sidesOfFace)
  {
    const auto & sides = faceAndSides.second;
    const Label  other = sides.size() == 2 ? sides[1].second : BackgroundLabel;
    if (sides.size() == 1 || sides[0].second < other)
    {
      mesh.boundaryTriangles.push_back(sides[0].first);
      mesh.boundaryTriangleLabels.push_back({ { sides[0].second, other } });
    }
    else if (other < sides[0].second)
    {
      mesh.boundaryTriangles.push_back(sides[1].first);
      mesh.boundaryTriangleLabels.push_back({ { other, sides[0].second } });
    }
  }
}

/** 4 x 4 x 4 voxels of 0.5 mm centred at -0.25, 0.25, 0.75, 1.25 on each axis: the 2 x 2 x 2 voxels inside the
 * unit cube carry labels (volume 8 x 0.125 = 1 mm³), split at x = y like the mesh when `otherLabel` is not 1: a
 * voxel with i >= j is label 1 (6 voxels, 0.75 mm³), i < j is `otherLabel` (2 voxels, 0.25 mm³). */
LabelVolume
CubeSegmentation(Label otherLabel)
{
  LabelVolume volume;
  volume.size = { { 4, 4, 4 } };
  volume.spacing = { { 0.5, 0.5, 0.5 } };
  volume.origin = { { -0.25, -0.25, -0.25 } };
  volume.labels.assign(64, BackgroundLabel);
  for (std::size_t k = 1; k <= 2; ++k)
  {
    for (std::size_t j = 1; j <= 2; ++j)
    {
      for (std::size_t i = 1; i <= 2; ++i)
      {
        volume.labels[i + 4 * (j + 4 * k)] = i >= j ? 1 : otherLabel;
      }
    }
  }
  return volume;
}

QualityReport
CubeReport(Label otherLabel)
{
  TetrahedralMesh mesh = KuhnCube(otherLabel);
  AddBoundaryTriangles(mesh);
  return ComputeQualityReport(mesh, CubeSegmentation(otherLabel));
}

const LabelQuality &
EntryOf(const QualityReport & report, Label label)
{
  const auto entry = std::find_if(report.labels.begin(), report.labels.end(), [label](const LabelQuality & quality) {
    return quality.label == label;
  });
  if (entry == report.labels.end())
  {
    throw std::logic_error("no entry for label " + std::to_string(label));
  }
  return *entry;
}

/** The report as written, read back in its order. */
nlohmann::ordered_json
JsonOf(const QualityReport & report)
{
  std::ostringstream json;
  WriteQualityReportJson(report, json);
  return nlohmann::ordered_json::parse(json.str());
}

TEST(QualityReport, SingleLabelCubeCountsAndShape)
{
  const QualityReport report = CubeReport(1);
  EXPECT_EQ(report.vertices, 8u);
  EXPECT_EQ(report.tetrahedra, 6u);
  // Each of the 6 square faces is cut into 2 triangles.
  EXPECT_EQ(report.boundaryTriangles, 12u);
  // A Kuhn tetrahedron has dihedral angles 45, 45, 60, 90, 90, 90 degrees; its circumsphere is the cube's
  // (radius √3 / 2) and its shortest edge 1.
  EXPECT_NEAR(report.minimumDihedralAngle, 45.0, Tolerance);
  EXPECT_NEAR(report.maximumDihedralAngle, 90.0, Tolerance);
  EXPECT_NEAR(report.maximumRadiusEdgeRatio, std::sqrt(3.0) / 2.0, Tolerance);
  EXPECT_EQ(report.invertedTetrahedra, 0u);
  // The boundary triangles are right isosceles.
  EXPECT_NEAR(report.minimumBoundaryPlanarAngle, 45.0, Tolerance);
  EXPECT_EQ(report.tetrahedraBelowDihedralAngle, (std::array<std::size_t, 3>{ { 0, 0, 0 } }));
  EXPECT_EQ(report.flatTetrahedra, 0u);
}

// A tetrahedron of four points 1e-9 mm off a plane, beside the cube: flat to rounding, and below every threshold.
TEST(QualityReport, CountsFlatTetrahedraAndSlivers)
{
  TetrahedralMesh mesh = KuhnCube(1);
  const uint32_t  first = static_cast<uint32_t>(mesh.points.size());
  for (const Vector3 & point : { Vector3{ { 3.0, 0.0, 0.0 } },
                                 Vector3{ { 4.0, 0.0, 0.0 } },
                                 Vector3{ { 3.0, 1.0, 0.0 } },
                                 Vector3{ { 4.0, 1.0, 1e-9 } } })
  {
    mesh.points.push_back(point);
    mesh.pointKinds.push_back(VertexKind::Feature);
  }
  mesh.tetrahedra.push_back({ { first, first + 1, first + 2, first + 3 } });
  mesh.tetrahedronLabels.push_back(1);
  AddBoundaryTriangles(mesh);
  const QualityReport report = ComputeQualityReport(mesh, CubeSegmentation(1));
  EXPECT_EQ(report.flatTetrahedra, 1u);
  EXPECT_EQ(report.tetrahedraBelowDihedralAngle, (std::array<std::size_t, 3>{ { 1, 1, 1 } }));
  const nlohmann::ordered_json json = JsonOf(report);
  EXPECT_EQ(json["quality"]["flat_tetrahedra"], 1) << json;
  EXPECT_EQ(json["quality"]["tetrahedra_below_dihedral_deg"].dump(), R"({"5":1,"10":1,"15":1})") << json;
}

TEST(QualityReport, SingleLabelCubeTopologyAndVolume)
{
  const QualityReport report = CubeReport(1);
  ASSERT_EQ(report.labels.size(), 1u);
  const LabelQuality & cube = report.labels[0];
  EXPECT_EQ(cube.label, 1);
  EXPECT_EQ(cube.vertices, 8u);
  EXPECT_EQ(cube.tetrahedra, 6u);
  EXPECT_EQ(cube.boundary.numberOfTriangles, 12u);
  EXPECT_TRUE(report.IsManifold());
  EXPECT_EQ(cube.boundary.numberOfComponents, 1);
  EXPECT_EQ(cube.boundary.totalGenus, 0);
  EXPECT_NEAR(cube.meshVolume, 1.0, Tolerance);
  EXPECT_NEAR(cube.segmentedVolume, 1.0, Tolerance);
  EXPECT_NEAR(report.meshVolume, 1.0, Tolerance);
  EXPECT_NEAR(report.segmentedVolume, 1.0, Tolerance);
}

/** A voxel's volume is the product of its spacings whatever the grid's orientation: the two-label cube's voxels on
 * anisotropic grids turned about one axis and about an oblique one give 6 and 2 voxels of 0.375 mm³. A rotation
 * about z alone by a quarter turn would not tell a wrong determinant from the right one. */
TEST(QualityReport, SegmentedVolumeFollowsTheSpacingOnAnObliqueGrid)
{
  const TetrahedralMesh mesh = [] {
    TetrahedralMesh cube = KuhnCube(2);
    AddBoundaryTriangles(cube);
    return cube;
  }();
  using Matrix = std::array<std::array<double, 3>, 3>;
  const double c = std::cos(0.5);
  const double s = std::sin(0.5);
  // About z by 0.5 rad; about the axis (1, 2, 2) / 3 by 0.5 rad (Rodrigues' formula).
  const Matrix                aboutZ{ { { c, -s, 0.0 }, { s, c, 0.0 }, { 0.0, 0.0, 1.0 } } };
  const std::array<double, 3> axis{ { 1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0 } };
  Matrix                      oblique{};
  for (int row = 0; row < 3; ++row)
  {
    for (int column = 0; column < 3; ++column)
    {
      const double cross = row == column             ? 0.0
                           : (row + 1) % 3 == column ? -axis[3 - row - column]
                                                     : axis[3 - row - column];
      oblique[row][column] = (row == column ? c : 0.0) + (1.0 - c) * axis[row] * axis[column] + s * cross;
    }
  }
  for (const Matrix & direction : { aboutZ, oblique })
  {
    LabelVolume segmentation = CubeSegmentation(2);
    segmentation.spacing = { { 0.5, 0.75, 1.0 } };
    segmentation.direction = direction;
    const QualityReport report = ComputeQualityReport(mesh, segmentation);
    EXPECT_NEAR(EntryOf(report, 1).segmentedVolume, 6 * 0.375, Tolerance);
    EXPECT_NEAR(EntryOf(report, 2).segmentedVolume, 2 * 0.375, Tolerance);
    EXPECT_NEAR(report.segmentedVolume, 8 * 0.375, Tolerance);
  }
}

TEST(QualityReport, DistanceToMarchingCubes)
{
  const QualityReport report = CubeReport(1);
  // The voxel spacing.
  EXPECT_NEAR(report.distanceSampleSpacing, 0.5, Tolerance);
  // Marching cubes puts its vertices halfway between voxel centres: on the cube's faces, except that it cuts
  // each corner by the plane x + y + z = 2.5 (through the midpoints (1, 0.75, 0.75), ...). The cube's corner
  // (1, 1, 1), a sample, is (3 - 2.5) / √3 from it, and nothing is farther.
  const DistanceStatistics & distance = report.distanceToMarchingCubes;
  EXPECT_GT(distance.count, 0u);
  EXPECT_NEAR(distance.maximum, 0.5 / std::sqrt(3.0), Tolerance);
  EXPECT_GE(distance.percentile95, distance.mean);
  EXPECT_GE(distance.maximum, distance.percentile95);
  EXPECT_GT(distance.mean, 0.0);
  // The report gives both directions pooled, each sampled at the smallest voxel spacing: not one direction alone
  // (whose maximum is the same here, the corners being on the mesh's side), nor another sampling.
  TetrahedralMesh mesh = KuhnCube(1);
  AddBoundaryTriangles(mesh);
  const TriangleSurface  reference = ExtractLabelSurfaces(CubeSegmentation(1));
  const TwoSidedDistance both =
    ComputeTwoSidedDistance(mesh.points, mesh.boundaryTriangles, reference.points, reference.triangles, 0.5);
  ASSERT_GT(both.fromFirst.count, 0u);
  ASSERT_GT(both.fromSecond.count, 0u);
  EXPECT_EQ(distance.count, both.fromFirst.count + both.fromSecond.count);
  EXPECT_NE(both.fromFirst.mean, both.fromSecond.mean);
  EXPECT_EQ(distance.mean, both.combined.mean);
  EXPECT_EQ(distance.percentile95, both.combined.percentile95);
}

TEST(QualityReport, DistanceSkippedOnRequestAndNothingElse)
{
  TetrahedralMesh mesh = KuhnCube(1);
  AddBoundaryTriangles(mesh);
  const QualityReport measured = ComputeQualityReport(mesh, CubeSegmentation(1), DistanceMeasurement::Measure);
  const QualityReport skipped = ComputeQualityReport(mesh, CubeSegmentation(1), DistanceMeasurement::Skip);
  EXPECT_TRUE(measured.distanceMeasured);
  EXPECT_GT(measured.distanceToMarchingCubes.count, 0u);
  EXPECT_FALSE(skipped.distanceMeasured);
  EXPECT_EQ(skipped.distanceToMarchingCubes.count, 0u);
  const nlohmann::ordered_json measuredJson = JsonOf(measured);
  nlohmann::ordered_json       skippedJson = JsonOf(skipped);
  EXPECT_TRUE(skippedJson["distance_to_marching_cubes"].is_null()) << skippedJson;
  EXPECT_FALSE(measuredJson["distance_to_marching_cubes"].is_null()) << measuredJson;
  // Everything but the distance is the same report.
  skippedJson["distance_to_marching_cubes"] = measuredJson["distance_to_marching_cubes"];
  EXPECT_EQ(skippedJson.dump(), measuredJson.dump());
  std::ostringstream table;
  PrintQualityReport(skipped, table);
  EXPECT_NE(table.str().find("distance to marching cubes  not measured"), std::string::npos) << table.str();
}

TEST(QualityReport, MinimumDihedralAngleHistogram)
{
  const QualityReport    report = CubeReport(1);
  const AngleHistogram & histogram = report.minimumDihedralAngleHistogram;
  EXPECT_EQ(histogram.binWidth, 2.0);
  ASSERT_EQ(histogram.counts.size(), 45u);
  // All six tetrahedra have smallest dihedral angle 45°, in the bin [44°, 46°).
  for (std::size_t bin = 0; bin < histogram.counts.size(); ++bin)
  {
    EXPECT_EQ(histogram.counts[bin], bin == 22 ? 6u : 0u) << "bin " << bin;
  }
}

TEST(QualityReport, TwoLabelsMeetAtAnInterface)
{
  const QualityReport report = CubeReport(2);
  // The plane x = y holds the interface: triangles (0, 3, 7) and (0, 4, 7), written once.
  EXPECT_EQ(report.boundaryTriangles, 12u + 2u);
  ASSERT_EQ(report.labels.size(), 2u);
  for (const Label label : { 1, 2 })
  {
    const LabelQuality & half = EntryOf(report, label);
    // Each half is a triangular prism: 3 tetrahedra, 6 corners, 6 outer triangles + the 2 interface ones, a
    // closed surface of genus 0.
    EXPECT_EQ(half.tetrahedra, 3u) << label;
    EXPECT_EQ(half.vertices, 6u) << label;
    EXPECT_EQ(half.boundary.numberOfTriangles, 8u) << label;
    EXPECT_TRUE(half.boundary.IsClosedManifold()) << label;
    EXPECT_EQ(half.boundary.numberOfComponents, 1) << label;
    EXPECT_EQ(half.boundary.totalGenus, 0) << label;
    EXPECT_NEAR(half.meshVolume, 0.5, Tolerance) << label;
  }
  EXPECT_NEAR(EntryOf(report, 1).segmentedVolume, 0.75, Tolerance);
  EXPECT_NEAR(EntryOf(report, 2).segmentedVolume, 0.25, Tolerance);
  EXPECT_TRUE(report.IsManifold());
}

TEST(QualityReport, LabelOnlyInTheSegmentationIsLost)
{
  TetrahedralMesh mesh = KuhnCube(2);
  AddBoundaryTriangles(mesh);
  // Label 3, which the mesh lacks (too thin for δ, say), has two pieces outside the cube: voxels (0, 0, 0) and
  // (0, 0, 1), which share a face, and voxel (3, 3, 3); 3 voxels of 0.125 mm³. Label 2, next in value, must
  // not be counted with it.
  LabelVolume segmentation = CubeSegmentation(2);
  for (const std::size_t voxel : { 0, 16, 63 })
  {
    segmentation.labels[voxel] = 3;
  }
  const QualityReport report = ComputeQualityReport(mesh, segmentation);
  ASSERT_EQ(report.labels.size(), 3u);
  EXPECT_FALSE(EntryOf(report, 2).IsLost());
  EXPECT_EQ(EntryOf(report, 2).lostComponents, 0u);
  const LabelQuality & lost = EntryOf(report, 3);
  EXPECT_TRUE(lost.IsLost());
  EXPECT_EQ(lost.tetrahedra, 0u);
  EXPECT_EQ(lost.lostComponents, 2u);
  EXPECT_NEAR(lost.segmentedVolume, 0.375, Tolerance);
  EXPECT_NEAR(report.segmentedVolume, 1.375, Tolerance);

  const nlohmann::ordered_json   json = JsonOf(report);
  const nlohmann::ordered_json & meshed = json["labels"][1];
  EXPECT_EQ(meshed["lost"], false) << meshed;
  EXPECT_FALSE(meshed.contains("lost_components")) << meshed;
  const nlohmann::ordered_json & entry = json["labels"][2];
  EXPECT_EQ(entry["label"], 3) << entry;
  EXPECT_EQ(entry["lost"], true) << entry;
  EXPECT_EQ(entry["lost_components"], 2) << entry;
  EXPECT_NEAR(entry["lost_volume_mm3"].get<double>(), 0.375, Tolerance) << entry;
  // An empty boundary has no angle and no genus.
  EXPECT_TRUE(entry["min_planar_angle_deg"].is_null()) << entry;
  EXPECT_TRUE(entry["boundary_genus"].is_null()) << entry;
  EXPECT_TRUE(entry["boundary_component_genera"].is_null()) << entry;

  std::ostringstream table;
  PrintQualityReport(report, table);
  EXPECT_NE(table.str().find("LOST tissues                label 3 (2 components, 0.4 mm^3)\n"), std::string::npos)
    << table.str();
  // The row: no components, genus, non-manifold counts or angle, but what was lost.
  EXPECT_NE(table.str().find("\n        3         0           0          0         0.0         0.4           -      -"
                             "               -          -  lost: 2 components, 0.4 mm^3\n"),
            std::string::npos)
    << table.str();
  EXPECT_EQ(table.str().find("180.00"), std::string::npos) << table.str();
}

TEST(QualityReport, NothingLostNoLostRow)
{
  std::ostringstream table;
  PrintQualityReport(CubeReport(2), table);
  EXPECT_EQ(table.str().find("lost"), std::string::npos) << table.str();
  EXPECT_EQ(table.str().find("LOST"), std::string::npos) << table.str();
}

// A selected label no voxel carries is not in the segmentation, so it cannot read as lost: the run says it, in the
// summary and the JSON, which has the key (empty) on every report so that a script need not test for it.
TEST(QualityReport, SelectedLabelsNotInTheImageAreListed)
{
  QualityReport report = CubeReport(2);
  report.run.selectedLabels = { 2, 7, -40 };
  EXPECT_EQ(JsonOf(report)["selected_labels_not_in_image"], std::vector<int>{});
  std::ostringstream allThere;
  PrintQualityReport(report, allThere);
  EXPECT_EQ(allThere.str().find("NOT in image"), std::string::npos) << allThere.str();

  report.run.selectedLabelsNotInImage = { 7 };
  EXPECT_EQ(JsonOf(report)["selected_labels_not_in_image"], std::vector<int>{ 7 });
  std::ostringstream one;
  PrintQualityReport(report, one);
  EXPECT_NE(one.str().find("\n  selected, NOT in image      label 7 (no voxel carries it)\n"), std::string::npos)
    << one.str();

  report.run.selectedLabelsNotInImage = { -40, 7 };
  EXPECT_EQ(JsonOf(report)["selected_labels_not_in_image"], std::vector<int>({ -40, 7 }));
  std::ostringstream two;
  PrintQualityReport(report, two);
  EXPECT_NE(two.str().find("\n  selected, NOT in image      label -40, label 7 (no voxel carries them)\n"),
            std::string::npos)
    << two.str();
}

TEST(QualityReport, InconsistentMeshIsRejected)
{
  TetrahedralMesh mesh = KuhnCube(1);
  mesh.tetrahedronLabels.pop_back();
  EXPECT_THROW(ComputeQualityReport(mesh, CubeSegmentation(1)), std::invalid_argument);
  mesh = KuhnCube(1);
  mesh.tetrahedra[0][3] = 8;
  EXPECT_THROW(ComputeQualityReport(mesh, CubeSegmentation(1)), std::invalid_argument);
}

TEST(QualityReport, JsonHoldsTheNumbersAndTheRun)
{
  QualityReport report = CubeReport(1);
  report.run.inputFile = "cube.nii.gz";
  report.run.surfaceSamplingDistance = 0.5;
  report.run.phaseSeconds = { { "read", 0.25 }, { "mesh", 1.5 } };
  report.run.peakResidentMemoryBytes = 1048576;
  const nlohmann::ordered_json json = JsonOf(report);
  EXPECT_EQ(json["input"], "cube.nii.gz") << json;
  EXPECT_EQ(json["parameters"]["delta_mm"], 0.5) << json;
  EXPECT_EQ(json["tetrahedra"], 6) << json;
  EXPECT_EQ(json["quality"]["manifold"], true) << json;
  ASSERT_EQ(json["labels"].size(), 1u) << json;
  EXPECT_EQ(json["labels"][0]["boundary_genus"], 0) << json;
  // The phases keep the order in which they ran.
  EXPECT_EQ(json["time_seconds"].dump(), R"({"read":0.25,"mesh":1.5})") << json;
  EXPECT_EQ(json["peak_memory_bytes"], 1048576) << json;
  std::vector<std::size_t> counts(45, 0);
  counts[22] = 6;
  EXPECT_EQ(json["min_dihedral_angle_histogram"]["counts"], counts) << json;
}

TEST(QualityReport, JsonReadsBackEveryMeasure)
{
  QualityReport report = CubeReport(2);
  report.run = { "in.nrrd", "out.msh", 0.75, 1.5, 10.0, { { "mesh", 2.5 } }, 4096 };
  const nlohmann::ordered_json json = JsonOf(report);
  EXPECT_EQ(json["output"], "out.msh");
  EXPECT_EQ(json["parameters"]["radius_edge_bound"], 1.5);
  EXPECT_EQ(json["parameters"]["min_dihedral_angle_deg"], 10.0);
  EXPECT_EQ(json["vertices"], report.vertices);
  EXPECT_EQ(json["boundary_triangles"], report.boundaryTriangles);
  // Doubles are written to the last digit: they read back exactly.
  const nlohmann::ordered_json & quality = json["quality"];
  EXPECT_EQ(quality["min_dihedral_angle_deg"], report.minimumDihedralAngle);
  EXPECT_EQ(quality["max_dihedral_angle_deg"], report.maximumDihedralAngle);
  EXPECT_EQ(quality["max_radius_edge_ratio"], report.maximumRadiusEdgeRatio);
  EXPECT_EQ(quality["min_boundary_planar_angle_deg"], report.minimumBoundaryPlanarAngle);
  EXPECT_EQ(quality["inverted_tetrahedra"], 0);
  EXPECT_EQ(quality["non_manifold_edges"], 0);
  EXPECT_EQ(quality["non_manifold_vertices"], 0);
  EXPECT_EQ(json["mesh_volume_mm3"], report.meshVolume);
  EXPECT_EQ(json["segmented_volume_mm3"], report.segmentedVolume);
  const nlohmann::ordered_json & distance = json["distance_to_marching_cubes"];
  EXPECT_EQ(distance["sample_spacing_mm"], 0.5);
  EXPECT_EQ(distance["samples"], report.distanceToMarchingCubes.count);
  EXPECT_EQ(distance["mean_mm"], report.distanceToMarchingCubes.mean);
  EXPECT_EQ(distance["percentile95_mm"], report.distanceToMarchingCubes.percentile95);
  EXPECT_EQ(distance["max_mm"], report.distanceToMarchingCubes.maximum);
  EXPECT_EQ(json["min_dihedral_angle_histogram"]["bin_width_deg"], 2.0);
  ASSERT_EQ(json["labels"].size(), 2u);
  for (std::size_t i = 0; i < 2; ++i)
  {
    const nlohmann::ordered_json & entry = json["labels"][i];
    const LabelQuality &           half = report.labels[i];
    EXPECT_EQ(entry["label"], half.label);
    EXPECT_EQ(entry["vertices"], half.vertices);
    EXPECT_EQ(entry["tetrahedra"], half.tetrahedra);
    EXPECT_EQ(entry["boundary_triangles"], half.boundary.numberOfTriangles);
    EXPECT_EQ(entry["mesh_volume_mm3"], half.meshVolume);
    EXPECT_EQ(entry["segmented_volume_mm3"], half.segmentedVolume);
    EXPECT_EQ(entry["boundary_components"], 1);
    EXPECT_EQ(entry["boundary_genus"], 0);
    EXPECT_EQ(entry["boundary_component_genera"], std::vector<int>{ 0 });
    EXPECT_EQ(entry["non_manifold_edges"], 0);
    EXPECT_EQ(entry["non_manifold_vertices"], 0);
    EXPECT_EQ(entry["min_planar_angle_deg"], half.boundary.minimumPlanarAngle);
  }
  EXPECT_EQ(json["time_seconds"]["mesh"], 2.5);
  EXPECT_EQ(json["peak_memory_bytes"], 4096);
}

TEST(QualityReport, JsonRecordsEveryParameterAndWhatTheTopologyStepsDid)
{
  QualityReport report = CubeReport(2);
  report.run.selectedLabels = { 2, 7 };
  report.run.mergeLabels = true;
  report.run.maximumNumberOfVertices = 123456;
  TopologyRun & topology = report.run.topology;
  // Each number distinct, so that a key reading another member shows; the four flags, which two values cannot keep
  // apart, are set again below so that each one's pair of values differs from every other's.
  topology = { 0.25, true, 11, false, 12, 13, 14, 15, true, false, 16, 3, 17 };
  nlohmann::ordered_json         json = JsonOf(report);
  const nlohmann::ordered_json & parameters = json["parameters"];
  EXPECT_EQ(parameters["labels"], std::vector<int>({ 2, 7 })) << json;
  EXPECT_EQ(parameters["merge_labels"], true);
  EXPECT_TRUE(parameters["iso_value"].is_null());
  EXPECT_EQ(parameters["max_vertices"], 123456);
  EXPECT_EQ(parameters["regularization_scale"], 0.25);
  EXPECT_EQ(parameters["join_diagonal_voxels"], true);
  EXPECT_EQ(parameters["relabel_non_manifold_places"], false);
  EXPECT_EQ(parameters["topology_rounds"], 13);
  EXPECT_EQ(parameters["refine_thick_parts"], false);
  EXPECT_EQ(parameters["manifold_refinement_levels"], 3);
  const nlohmann::ordered_json & done = json["topology"];
  EXPECT_EQ(done["voxels_changed_at_pinches"], 11) << json;
  EXPECT_EQ(done["relabelled_tetrahedra"], 12);
  EXPECT_EQ(done["regularization_rounds"], 14);
  EXPECT_EQ(done["locally_regularized_voxels"], 15);
  EXPECT_EQ(done["budget_reached"], true);
  EXPECT_EQ(done["thick_parts_refined"], 16);
  EXPECT_EQ(done["manifold_refinement_rounds"], 17);
  // The flags again: join, relabel, budget and refine are (true, false, true, false) above and (true, true, false,
  // false) here.
  topology.relabelNonManifoldPlaces = true;
  topology.budgetReached = false;
  json = JsonOf(report);
  EXPECT_EQ(json["parameters"]["join_diagonal_voxels"], true);
  EXPECT_EQ(json["parameters"]["relabel_non_manifold_places"], true);
  EXPECT_EQ(json["topology"]["budget_reached"], false);
  EXPECT_EQ(json["parameters"]["refine_thick_parts"], false);

  // Every label (none selected), or an iso-value instead of labels.
  report.run.selectedLabels.clear();
  report.run.mergeLabels = false;
  report.run.isoValue = 92.5;
  json = JsonOf(report);
  EXPECT_EQ(json["parameters"]["labels"], "all") << json;
  EXPECT_EQ(json["parameters"]["iso_value"], 92.5);
}

TEST(QualityReport, JsonEscapesTextAndHasNoInfinity)
{
  QualityReport report = CubeReport(1);
  report.run.inputFile = "a \"quoted\" C:\\path\n";
  report.run.outputFile = "caf\xe9.vtu"; // Latin-1, not UTF-8
  report.maximumRadiusEdgeRatio = std::numeric_limits<double>::infinity();
  report.distanceToMarchingCubes.mean = std::numeric_limits<double>::quiet_NaN();
  const nlohmann::ordered_json json = JsonOf(report);
  EXPECT_EQ(json["input"], report.run.inputFile) << json;
  EXPECT_EQ(json["output"], "caf\xef\xbf\xbd.vtu") << json;
  EXPECT_TRUE(json["quality"]["max_radius_edge_ratio"].is_null()) << json;
  EXPECT_TRUE(json["distance_to_marching_cubes"]["mean_mm"].is_null()) << json;
}

TEST(QualityReport, GenusOfANonManifoldBoundaryIsNotReported)
{
  TetrahedralMesh mesh = KuhnCube(1);
  AddBoundaryTriangles(mesh);
  // Dropping a boundary triangle opens the surface: three of its edges now bound a single triangle.
  mesh.boundaryTriangles.pop_back();
  mesh.boundaryTriangleLabels.pop_back();
  const QualityReport report = ComputeQualityReport(mesh, CubeSegmentation(1));
  EXPECT_FALSE(report.IsManifold());
  EXPECT_EQ(report.nonManifoldEdges, 3u);
  const nlohmann::ordered_json json = JsonOf(report);
  EXPECT_TRUE(json["labels"][0]["boundary_genus"].is_null()) << json;
  EXPECT_TRUE(json["labels"][0]["boundary_component_genera"].is_null()) << json;
  EXPECT_EQ(json["quality"]["manifold"], false) << json;
}

TEST(QualityReport, TableNamesEveryMeasure)
{
  QualityReport report = CubeReport(2);
  report.run.phaseSeconds = { { "read", 0.0 }, { "mesh", 0.0 }, { "report", 0.0 }, { "write", 0.0 } };
  std::ostringstream table;
  PrintQualityReport(report, table);
  for (const char * row : { "vertices                    8\n",
                            "tetrahedra                  6\n",
                            "boundary triangles          14\n",
                            "dihedral angle min / max    45.000 / 90.000 deg\n",
                            "max radius-edge ratio       0.866\n",
                            // The interface triangle (0, 3, 7) has the angle asin(1 / √3) = 35.26° at 0.
                            "min boundary planar angle   35.26 deg\n",
                            "manifold boundaries         yes",
                            "volume mesh / segmented",
                            "distance to marching cubes  mean ",
                            "read 0.00 s, mesh 0.00 s, report 0.00 s, write 0.00 s",
                            "peak memory" })
  {
    EXPECT_NE(table.str().find(row), std::string::npos) << "missing '" << row << "' in\n" << table.str();
  }
  // One row per label, after the column headings.
  EXPECT_NE(table.str().find("\n        1         6           3          8         0.5"), std::string::npos)
    << table.str();
  EXPECT_NE(table.str().find("\n        2         6           3          8         0.5"), std::string::npos)
    << table.str();
}

/** The volume row's change is the mesh's volume relative to the segmentation's, with its sign: a mesh that lost
 * volume must not read as one that gained it. The cube's volumes are equal, so they are set here. */
TEST(QualityReport, VolumeChangeIsTheMeshRelativeToTheSegmentationWithItsSign)
{
  QualityReport report = CubeReport(1);
  for (const auto & [meshVolume, segmentedVolume, row] :
       { std::tuple<double, double, const char *>{ 0.9, 1.2, "0.9 / 1.2 mm^3 (-25.00%)\n" },
         std::tuple<double, double, const char *>{ 1.5, 1.2, "1.5 / 1.2 mm^3 (+25.00%)\n" } })
  {
    report.meshVolume = meshVolume;
    report.segmentedVolume = segmentedVolume;
    std::ostringstream table;
    PrintQualityReport(report, table);
    EXPECT_NE(table.str().find(std::string("volume mesh / segmented     ") + row), std::string::npos)
      << "missing '" << row << "' in\n"
      << table.str();
  }
}

/** What the regularisation took from the tissues and gave to them, summed over the labels in the table and per label
 * in the JSON, each under its own name: the two volumes differ here so that swapping them shows. */
TEST(QualityReport, RegularizationRowKeepsTakenAndGivenApart)
{
  QualityReport report = CubeReport(2);
  ASSERT_EQ(report.labels.size(), 2u);
  report.labels[0].regularizedComponentsRemoved = 1;
  report.labels[0].regularizedVolumeRemoved = 3.0;
  report.labels[0].regularizedVolumeAdded = 0.5;
  report.labels[1].regularizedVolumeRemoved = 1.0;
  report.labels[1].regularizedVolumeAdded = 2.0;
  std::ostringstream table;
  PrintQualityReport(report, table);
  EXPECT_NE(table.str().find("regularised at delta        1 component removed; 4.0 mm^3 taken from tissues, 2.5 mm^3 "
                             "given to them\n"),
            std::string::npos)
    << table.str();

  const nlohmann::ordered_json json = JsonOf(report);
  for (const std::size_t label : { 0u, 1u })
  {
    const nlohmann::ordered_json & regularization = json["labels"][label]["regularization"];
    EXPECT_EQ(regularization["components_removed"], report.labels[label].regularizedComponentsRemoved)
      << regularization;
    EXPECT_EQ(regularization["volume_removed_mm3"], report.labels[label].regularizedVolumeRemoved) << regularization;
    EXPECT_EQ(regularization["volume_added_mm3"], report.labels[label].regularizedVolumeAdded) << regularization;
  }
}

/** Two tetrahedra of one label touching at a corner: the label's boundary is pinched there, one non-manifold vertex
 * and no non-manifold edge, in the report and in each label's JSON entry. */
TEST(QualityReport, PinchedVertexIsCountedPerLabel)
{
  TetrahedralMesh mesh;
  mesh.points = { { { 0.0, 0.0, 0.0 } },  { { 1.0, 0.0, 0.0 } },  { { 0.0, 1.0, 0.0 } }, { { 0.0, 0.0, 1.0 } },
                  { { -1.0, 0.0, 0.0 } }, { { 0.0, -1.0, 0.0 } }, { { 0.0, 0.0, -1.0 } } };
  for (std::array<uint32_t, 4> tetrahedron :
       { std::array<uint32_t, 4>{ { 0, 1, 2, 3 } }, std::array<uint32_t, 4>{ { 0, 4, 5, 6 } } })
  {
    if (SignedVolume(mesh, tetrahedron) < 0.0)
    {
      std::swap(tetrahedron[2], tetrahedron[3]);
    }
    mesh.tetrahedra.push_back(tetrahedron);
    mesh.tetrahedronLabels.push_back(1);
  }
  AddBoundaryTriangles(mesh);
  const QualityReport report = ComputeQualityReport(mesh, CubeSegmentation(1));
  EXPECT_EQ(report.nonManifoldVertices, 1u);
  EXPECT_EQ(report.nonManifoldEdges, 0u);
  const nlohmann::ordered_json json = JsonOf(report);
  EXPECT_EQ(json["labels"][0]["non_manifold_vertices"], 1) << json;
  EXPECT_EQ(json["labels"][0]["non_manifold_edges"], 0) << json;
}

TEST(QualityReport, PeakMemoryIsMeasured)
{
  EXPECT_GT(PeakResidentMemoryBytes(), 1024u * 1024u);
}


/** The midpoint, in voxel indices, of every pair of face-neighbouring voxels of different labels, the volume
 * surrounded by one voxel of background: where the marching-cubes surfaces of the labels cross the lines between voxel
 * centres (VTK's discrete flying edges puts a vertex at each such midpoint, and every triangle of a cell whose lines it
 * crosses uses it). Found by a scan of the voxels, independently of VTK. */
std::vector<Vector3>
MidpointsBetweenDifferentLabels(const LabelVolume & volume)
{
  const auto labelAt = [&](long i, long j, long k) -> Label {
    if (i < 0 || j < 0 || k < 0 || i >= long(volume.size[0]) || j >= long(volume.size[1]) || k >= long(volume.size[2]))
    {
      return BackgroundLabel;
    }
    return volume.Labels()[std::size_t(i) + volume.size[0] * (std::size_t(j) + volume.size[1] * std::size_t(k))];
  };
  std::vector<Vector3> midpoints;
  for (long k = -1; k <= long(volume.size[2]); ++k)
  {
    for (long j = -1; j <= long(volume.size[1]); ++j)
    {
      for (long i = -1; i <= long(volume.size[0]); ++i)
      {
        for (int axis = 0; axis < 3; ++axis)
        {
          const long next[3] = { i + (axis == 0), j + (axis == 1), k + (axis == 2) };
          if (labelAt(i, j, k) != labelAt(next[0], next[1], next[2]))
          {
            Vector3 midpoint{ { double(i), double(j), double(k) } };
            midpoint[axis] += 0.5;
            midpoints.push_back(midpoint);
          }
        }
      }
    }
  }
  return midpoints;
}

/** The physical point of a continuous voxel index, written out here as the header defines it: origin + direction x
 * (spacing ⊙ index). */
Vector3
PhysicalPointOf(const LabelVolume & volume, const Vector3 & index)
{
  Vector3 point = volume.origin;
  for (int row = 0; row < 3; ++row)
  {
    for (int column = 0; column < 3; ++column)
    {
      point[row] += volume.direction[row][column] * (volume.spacing[column] * index[column]);
    }
  }
  return point;
}

/** How many of `points` lie within 1e-9 of `point`. */
std::size_t
CountNear(const std::vector<Vector3> & points, const Vector3 & point)
{
  return std::size_t(
    std::count_if(points.begin(), points.end(), [&](const Vector3 & other) { return Distance(other, point) < 1e-9; }));
}

/** The undirected edges of a surface's triangles, by their ends' positions, with how many triangles use each. */
std::map<std::pair<Vector3, Vector3>, int>
TrianglesPerEdge(const TriangleSurface & surface)
{
  std::map<std::pair<Vector3, Vector3>, int> count;
  for (const auto & triangle : surface.triangles)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      Vector3 a = surface.points[triangle[corner]];
      Vector3 b = surface.points[triangle[(corner + 1) % 3]];
      if (b < a)
      {
        std::swap(a, b);
      }
      ++count[{ a, b }];
    }
  }
  return count;
}

/** Three labels and background in 3 x 2 x 2 voxels touching every face of the volume, on an anisotropic grid turned
 * a quarter about z and moved away from the origin: the vertices of the label surfaces are exactly the midpoints
 * between neighbouring voxels of different labels (the border ones too, against the background put around the
 * volume), placed in physical space by the volume's origin, spacing and direction. */
TEST(LabelSurfaces, VerticesAreTheMidpointsBetweenDifferentLabelsInPhysicalSpace)
{
  LabelVolume volume;
  volume.size = { { 3, 2, 2 } };
  volume.spacing = { { 0.5, 1.0, 2.0 } };
  volume.origin = { { 10.0, 20.0, 30.0 } };
  volume.direction = { { { { 0.0, -1.0, 0.0 } }, { { 1.0, 0.0, 0.0 } }, { { 0.0, 0.0, 1.0 } } } };
  // x = 0: label 1; x = 1: label 2; x = 2: label 3, but background at (2, 0, 0) and label 1 at (2, 1, 1).
  volume.labels = { 1, 2, 0, 1, 2, 3, 1, 2, 3, 1, 2, 1 };
  const TriangleSurface surface = ExtractLabelSurfaces(volume);
  ASSERT_FALSE(surface.triangles.empty());
  std::vector<Vector3> expected;
  for (const Vector3 & index : MidpointsBetweenDifferentLabels(volume))
  {
    expected.push_back(PhysicalPointOf(volume, index));
  }
  std::vector<Vector3> used;
  for (const auto & triangle : surface.triangles)
  {
    for (const uint32_t vertex : triangle)
    {
      ASSERT_LT(vertex, surface.points.size());
      used.push_back(surface.points[vertex]);
    }
  }
  for (const Vector3 & point : used)
  {
    EXPECT_EQ(CountNear(expected, point), 1u) << "a vertex at " << point[0] << " " << point[1] << " " << point[2];
  }
  for (const Vector3 & point : expected)
  {
    EXPECT_GT(CountNear(used, point), 0u) << "no vertex at " << point[0] << " " << point[1] << " " << point[2];
  }
}

/** The surface of one label touching every face of the volume is closed there, the volume being surrounded by
 * background first: every edge of its triangles is on exactly two of them, and it reaches half a voxel beyond the
 * outermost voxel centres on every side. */
TEST(LabelSurfaces, OneLabelFillingTheVolumeGivesOneClosedSurface)
{
  LabelVolume volume;
  volume.size = { { 2, 3, 2 } };
  volume.labels.assign(12, 5);
  const TriangleSurface surface = ExtractLabelSurfaces(volume);
  ASSERT_FALSE(surface.triangles.empty());
  for (const auto & [edge, triangles] : TrianglesPerEdge(surface))
  {
    EXPECT_EQ(triangles, 2) << "edge from " << edge.first[0] << " " << edge.first[1] << " " << edge.first[2] << " to "
                            << edge.second[0] << " " << edge.second[1] << " " << edge.second[2];
  }
  // The surface spans the volume and the half voxel around it, on every side.
  for (int axis = 0; axis < 3; ++axis)
  {
    const auto [lowest, highest] =
      std::minmax_element(surface.points.begin(), surface.points.end(), [axis](const Vector3 & a, const Vector3 & b) {
        return a[axis] < b[axis];
      });
    EXPECT_EQ((*lowest)[axis], -0.5);
    EXPECT_EQ((*highest)[axis], double(volume.size[axis]) - 0.5);
  }
}

} // namespace
} // namespace delaunay_refinement
