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

// delaunay-bench-cgal-mesh: CGAL Mesh_3's mesh of a label image, with the benchmark's criteria, written to a file
// (.vtu, .vtk, .msh, .mesh), so that what is done downstream with our meshes can be done with CGAL's
// (test/DelaunayImageToMeshDownstreamLameShell.py, issue #19). Fidelity can be matched to ours as the benchmark does:
// --match-mean-distance takes our mesh's mean two-sided distance to the marching-cubes surface (the "mean_mm" of
// delaunay-image-to-mesh --report) and searches facet_distance for it.

#include "DelaunayBenchFacetDistance.h"
#include "DelaunayBenchImages.h"
#include "DelaunayBenchMeshers.h"
#include "DelaunayImageToMeshWriters.h"

#include "itkImageFileReader.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

namespace
{

using namespace delaunay_bench;

struct Options
{
  std::string input;
  std::string output;
  double      delta{ 0.0 };
  double      facetDistance{ 0.0 };
  double      matchMeanDistance{ 0.0 };
  double      matchPercentile95Distance{ 0.0 };
  bool        optimize{ false };
};

int
Run(const Options & options)
{
  const LabelImage::Pointer image = itk::ReadImage<LabelImage>(options.input);
  RequireIdentityDirection(*image, options.input);
  FacetDistanceMatch match;
  match.facetDistance = options.facetDistance;
  if (options.matchMeanDistance > 0.0)
  {
    const delaunay_refinement::LabelVolume     volume = ToLabelVolume(*image);
    const delaunay_refinement::TriangleSurface marchingCubes = delaunay_refinement::ExtractLabelSurfaces(volume);
    const double sampleSpacing = *std::min_element(volume.spacing.begin(), volume.spacing.end());
    delaunay_refinement::DistanceStatistics ours;
    ours.mean = options.matchMeanDistance;
    ours.percentile95 = options.matchPercentile95Distance;
    match = MatchFacetDistance(*image, options.delta, ours, sampleSpacing, marchingCubes);
  }
  const MesherOutput cgal =
    RunCgalMesh3(*image, CgalCriteriaForDelta(options.delta, match.facetDistance, options.optimize));
  delaunay_refinement::WriteTetrahedralMesh(cgal.mesh, options.output);
  // One JSON object on stdout: what was run and what it gave.
  std::printf("{\"delta_mm\": %.17g, \"facet_size_mm\": %.17g, \"facet_distance_mm\": %.17g, \"cell_size_mm\": %.17g, "
              "\"optimize\": %s, \"target_mean_distance_mm\": %.17g, \"target_percentile95_distance_mm\": %.17g, "
              "\"matched_mean_distance_mm\": %.17g, \"matched_percentile95_distance_mm\": %.17g, "
              "\"matched\": %s, \"trials\": %d, \"vertices\": %zu, \"tetrahedra\": %zu, \"seconds\": %.6g}\n",
              options.delta,
              FacetSizePerDelta * options.delta,
              match.facetDistance,
              CellSizePerDelta * options.delta,
              options.optimize ? "true" : "false",
              options.matchMeanDistance,
              options.matchPercentile95Distance,
              match.cgalDistance.mean,
              match.cgalDistance.percentile95,
              match.matched ? "true" : "false",
              match.trials,
              cgal.mesh.points.size(),
              cgal.mesh.tetrahedra.size(),
              cgal.totalSeconds);
  return EXIT_SUCCESS;
}

} // namespace

int
main(int argc, char * argv[])
{
  Options  options;
  CLI::App app("CGAL Mesh_3's mesh of a label image with delaunay-bench's criteria (bench/README.md): facet_angle "
               "30, facet_size = delta, cell_radius_edge_ratio 2, cell_size = 8 delta.",
               "delaunay-bench-cgal-mesh");
  app.add_option("INPUT", options.input, "label image (labels 0-255, identity direction)")->required();
  app.add_option("OUTPUT", options.output, "mesh file: .vtu, .vtk, .msh or .mesh")->required();
  app.add_option("-d,--delta", options.delta, "surface sampling distance, mm: CGAL's facet_size")
    ->required()
    ->check(CLI::PositiveNumber);
  auto * facetDistance =
    app.add_option("--facet-distance", options.facetDistance, "CGAL's facet_distance, mm (default: off)")
      ->check(CLI::PositiveNumber);
  auto * matchMean =
    app
      .add_option("--match-mean-distance",
                  options.matchMeanDistance,
                  "search the tightest facet_distance at which this mean two-sided distance to\nthe marching-cubes "
                  "surface (ours, mm) is not worse than CGAL's by more than 10 %")
      ->check(CLI::PositiveNumber)
      ->excludes(facetDistance);
  app
    .add_option("--match-p95-distance",
                options.matchPercentile95Distance,
                "with --match-mean-distance: our 95th percentile distance (mm), matched the\nsame way")
    ->check(CLI::PositiveNumber)
    ->needs(matchMean);
  app.add_flag("--optimize", options.optimize, "CGAL's perturbation and exudation after the refinement");
  try
  {
    app.parse(argc, argv);
  }
  catch (const CLI::ParseError & error)
  {
    return app.exit(error) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
  }
  try
  {
    return Run(options);
  }
  catch (const std::exception & error)
  {
    std::cerr << "delaunay-bench-cgal-mesh: " << error.what() << "\n";
    return EXIT_FAILURE;
  }
}
