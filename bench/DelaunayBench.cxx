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

// delaunay-bench: itk::DelaunayImageToMeshFilter against CGAL's Mesh_3 on the same images, at matched surface
// fidelity, with every quality measure computed by the module's own code for both (issue #6, bench/README.md).

#include "DelaunayBenchChildProcess.h"
#include "DelaunayBenchFacetDistance.h"
#include "DelaunayBenchImages.h"
#include "DelaunayBenchMeshers.h"
#include "DelaunayImageToMeshQualityReport.h"
#include "DelaunayImageToMeshWriters.h"
#include "DelaunayRefinementMeshQuality.h"
#include "DelaunayRefinementMesher.h"

#include "itkImageFileWriter.h"
#include "itkMultiThreaderBase.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{

using namespace delaunay_bench;
namespace dr = delaunay_refinement;

const char * const DefaultDataDirectory = "/usr/share/doc/insighttoolkit5-examples/examples/Data";

struct Options
{
  bool quick{ false };
  bool oursOnly{ false };
  /** 0 = the default: 3, or 1 with --quick. */
  int                      runs{ 0 };
  std::vector<std::string> imageNames;
  /** Empty = each image's own list. */
  std::vector<double> deltas;
  std::string         dataDirectory{ DefaultDataDirectory };
  /** Empty = the meshes are not written. */
  std::string meshDirectory;
  /** Empty = the images are not written. */
  std::string imageDirectory;
  /** σ of the sliver-removal row (our filter with R4′, beside CGAL+perturb+exude); 0 leaves the row out. */
  double sliverRemovalAngle{ 15.0 };
};

/** Parses the command line into `options` (CLI11); nullopt when it was parsed, else the exit code after --help or
 * a mistake. */
std::optional<int>
ParseOptions(int argc, char * argv[], Options & options)
{
  CLI::App app("Our refinement against CGAL's Mesh_3 on the same images (bench/README.md).", "delaunay-bench");
  app.add_flag("--quick", options.quick, "a short run: the small and the 2-3 mm images, one delta each, one run");
  app.add_option("--runs", options.runs, "timed runs per mesher, the median is reported (default 3; 1 with --quick)")
    ->check(CLI::Range(1, std::numeric_limits<int>::max()));
  app
    .add_option("--images",
                options.imageNames,
                "only these images (sphere-64, torus-64, sphere-128, torus-128, brain-mask,\nkmeans-tissues, "
                "atlas-phantom, brain-mask-1mm, kmeans-tissues-1mm)")
    ->delimiter(',');
  app
    .add_option("--deltas",
                options.deltas,
                "these delta values (mm) for every selected image instead of each\n"
                "image's own")
    ->delimiter(',');
  app.add_flag("--ours-only", options.oursOnly, "run our filter only (for profiling)");
  app
    .add_option("--min-dihedral",
                options.sliverRemovalAngle,
                "sigma in degrees of the sliver-removal row (our filter with --min-dihedral,\nbeside "
                "CGAL+perturb+exude); 0 leaves the row out")
    ->check(CLI::Range(0.0, delaunay_refinement::ParameterLimits::LargestMinimumDihedralAngle))
    ->capture_default_str();
  app.add_option("--data-dir", options.dataDirectory, "where ITK's example images are")->capture_default_str();
  app
    .add_option("--write-meshes",
                options.meshDirectory,
                "write every mesh to this existing directory as IMAGE_DELTA_MESHER.vtu\n(for "
                "bench/downstream.py)")
    ->check(CLI::ExistingDirectory);
  app
    .add_option("--write-images",
                options.imageDirectory,
                "write every selected image to this existing directory as IMAGE.nrrd (to mesh\nit with "
                "delaunay-image-to-mesh, e.g. the generated atlas phantom)")
    ->check(CLI::ExistingDirectory);
  try
  {
    app.parse(argc, argv);
  }
  catch (const CLI::ParseError & error)
  {
    // CLI11 prints the help or the mistake; the exit codes stay 0 and EXIT_FAILURE, as before it.
    return app.exit(error) == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
  }
  if (options.runs == 0)
  {
    options.runs = options.quick ? 1 : 3;
  }
  // The refinement core's ranges, checked before minutes of other images.
  for (const double delta : options.deltas)
  {
    dr::RefinementParameters parameters;
    parameters.surfaceSamplingDistance = delta;
    dr::ValidateParameters(parameters);
  }
  return std::nullopt;
}

double
Median(std::vector<double> values)
{
  std::sort(values.begin(), values.end());
  const std::size_t middle = values.size() / 2;
  return values.size() % 2 == 1 ? values[middle] : 0.5 * (values[middle - 1] + values[middle]);
}

/** One mesher on one image and δ: medians over the runs, and the (deterministic) mesh's quality. */
struct MesherRow
{
  std::string       mesher;
  double            totalSeconds{ 0.0 };
  double            totalCpuSeconds{ 0.0 };
  double            refinementSeconds{ 0.0 };
  double            refinementCpuSeconds{ 0.0 };
  double            memoryBytes{ 0.0 };
  dr::QualityReport quality;
  /** Non-manifold edges of the union of the labels (the triangles with the background on one side), where the
   * quality report counts each label's own boundary. */
  std::size_t         unionNonManifoldEdges{ 0 };
  dr::TetrahedralMesh mesh;
  /** Each run's times, in run order: run i of every mesher belongs to the same round of alternation. */
  std::vector<double> totalSecondsPerRun;
  std::vector<double> refinementSecondsPerRun;
  std::vector<double> totalCpuSecondsPerRun;
  std::vector<double> refinementCpuSecondsPerRun;
};

/** The runs of one mesher, collected one at a time so that the meshers' runs can alternate. */
class MesherRuns
{
public:
  MesherRuns(std::string mesher, std::function<MesherOutput()> run)
    : m_Run(std::move(run))
  {
    m_Row.mesher = std::move(mesher);
  }

  void
  RunOnce()
  {
    MeasuredRun measured = RunInChildProcess(m_Run);
    m_Row.totalSecondsPerRun.push_back(measured.output.totalSeconds);
    m_Row.totalCpuSecondsPerRun.push_back(measured.output.totalCpuSeconds);
    m_Row.refinementSecondsPerRun.push_back(measured.output.refinementSeconds);
    m_Row.refinementCpuSecondsPerRun.push_back(measured.output.refinementCpuSeconds);
    m_MemoryBytes.push_back(static_cast<double>(measured.meshingMemoryBytes));
    m_Row.mesh = std::move(measured.output.mesh);
  }

  /** The quality of the mesh, which is the same in every run: computed once. */
  const dr::QualityReport &
  Quality(const dr::LabelVolume & volume)
  {
    if (!m_QualityComputed)
    {
      m_Row.quality = dr::ComputeQualityReport(m_Row.mesh, volume);
      // The background's boundary is the union's: the triangles with the background on one side.
      m_Row.unionNonManifoldEdges = dr::ComputeLabelBoundaryTopology(m_Row.mesh, dr::BackgroundLabel).nonManifoldEdges;
      m_QualityComputed = true;
    }
    return m_Row.quality;
  }

  MesherRow
  Finish(const dr::LabelVolume & volume)
  {
    m_Row.totalSeconds = Median(m_Row.totalSecondsPerRun);
    m_Row.totalCpuSeconds = Median(m_Row.totalCpuSecondsPerRun);
    m_Row.refinementSeconds = Median(m_Row.refinementSecondsPerRun);
    m_Row.refinementCpuSeconds = Median(m_Row.refinementCpuSecondsPerRun);
    m_Row.memoryBytes = Median(m_MemoryBytes);
    Quality(volume);
    std::cerr << "  " << m_Row.mesher << ": " << m_Row.totalSeconds << " s, " << m_Row.mesh.tetrahedra.size()
              << " tetrahedra\n";
    return std::move(m_Row);
  }

private:
  std::function<MesherOutput()> m_Run;
  MesherRow                     m_Row;
  std::vector<double>           m_MemoryBytes;
  bool                          m_QualityComputed{ false };
};

/** One run of CGAL with manifold(): what it gave, or the cap it reached. */
struct CappedCgalRun
{
  std::string overCap;
  double      totalSeconds{ 0.0 };
  std::size_t tetrahedra{ 0 };
  std::size_t nonManifoldEdges{ 0 };
  std::size_t unionNonManifoldEdges{ 0 };
};

/** CGAL Mesh_3 with manifold() and the case's criteria, once, within ResourceCap's defaults (5 minutes, 8 GB): on
 * the 1 mm brain mask it ran out of 24 GB after 13 minutes (issue #14). */
CappedCgalRun
RunCgalManifold(const LabelImage & image, CgalCriteria criteria, const dr::LabelVolume & volume)
{
  criteria.manifold = true;
  CappedCgalRun                    result;
  const std::optional<MeasuredRun> run =
    RunInChildProcessWithin([&] { return RunCgalMesh3(image, criteria); }, ResourceCap{}, result.overCap);
  if (run)
  {
    const dr::TetrahedralMesh & mesh = run->output.mesh;
    result.totalSeconds = run->output.totalSeconds;
    result.tetrahedra = mesh.tetrahedra.size();
    result.nonManifoldEdges = dr::ComputeQualityReport(mesh, volume, dr::DistanceMeasurement::Skip).nonManifoldEdges;
    result.unionNonManifoldEdges = dr::ComputeLabelBoundaryTopology(mesh, dr::BackgroundLabel).nonManifoldEdges;
  }
  return result;
}

/** Everything measured for one image and δ. */
struct BenchCase
{
  std::string image;
  double      delta{ 0.0 };
  MesherRow   ours;
  MesherRow   cgal;
  MesherRow   cgalOptimized;
  /** Our filter with sliver removal at σ = sliverRemovalAngle degrees, when that is not 0. */
  double                   sliverRemovalAngle{ 0.0 };
  std::optional<MesherRow> oursSliverRemoval;
  FacetDistanceMatch       match;
  double                   floorSeconds{ 0.0 };
  /** CGAL with manifold(), one capped run (ResourceCap); its non-manifold edges, or why it has none. */
  std::optional<CappedCgalRun> cgalManifold;
};

double
MedianBulkDelaunaySeconds(const std::vector<dr::Vector3> & points, int runs)
{
  std::vector<double> seconds;
  for (int i = 0; i < runs; ++i)
  {
    seconds.push_back(BulkDelaunaySeconds(points));
  }
  return Median(seconds);
}

BenchCase
RunCase(const BenchImage & benchImage, double delta, const Options & options, const dr::LabelVolume & volume,
        const dr::TriangleSurface & marchingCubes)
{
  std::cerr << benchImage.name << ", delta " << delta << " mm\n";
  const LabelImage & image = *benchImage.image;
  BenchCase          result;
  result.image = benchImage.name;
  result.delta = delta;
  // The filter's defaults (sliver removal at σ = 10° since issue #15), as a user gets them.
  MesherRuns ours("ours", [&] { return RunOurFilter(image, delta, dr::RefinementParameters{}.minimumDihedralAngle); });
  if (options.oursOnly)
  {
    for (int i = 0; i < options.runs; ++i)
    {
      ours.RunOnce();
    }
    result.ours = ours.Finish(volume);
    return result;
  }
  // Our mesh decides CGAL's facet_distance; our first run gives it and counts as a timed run.
  ours.RunOnce();
  const dr::QualityReport & ourQuality = ours.Quality(volume);
  result.match = MatchFacetDistance(
    image, delta, ourQuality.distanceToMarchingCubes, ourQuality.distanceSampleSpacing, marchingCubes);
  CgalCriteria criteria = CgalCriteriaForDelta(delta, result.match.facetDistance, false);
  CgalCriteria optimizedCriteria = criteria;
  optimizedCriteria.optimize = true;
  MesherRuns cgal("CGAL", [&] { return RunCgalMesh3(image, criteria); });
  MesherRuns cgalOptimized("CGAL+opt", [&] { return RunCgalMesh3(image, optimizedCriteria); });
  const bool removesSlivers = options.sliverRemovalAngle > 0.0;
  MesherRuns oursSliverRemoval("ours with sliver removal",
                               [&] { return RunOurFilter(image, delta, options.sliverRemovalAngle); });
  // The meshers take turns, run by run: this machine's speed drifts over seconds (a shared host), and a drift
  // must not fall on one mesher's runs only.
  for (int i = 0; i < options.runs; ++i)
  {
    if (i > 0)
    {
      ours.RunOnce();
    }
    cgal.RunOnce();
    cgalOptimized.RunOnce();
    if (removesSlivers)
    {
      oursSliverRemoval.RunOnce();
    }
  }
  result.ours = ours.Finish(volume);
  result.cgal = cgal.Finish(volume);
  result.cgalOptimized = cgalOptimized.Finish(volume);
  if (removesSlivers)
  {
    result.sliverRemovalAngle = options.sliverRemovalAngle;
    result.oursSliverRemoval = oursSliverRemoval.Finish(volume);
  }
  result.floorSeconds = MedianBulkDelaunaySeconds(result.ours.mesh.points, options.runs);
  std::cerr << "  CGAL with manifold(), capped\n";
  result.cgalManifold = RunCgalManifold(image, criteria, volume);
  return result;
}

// ---- The table ----------------------------------------------------------------------------------------------

std::string
Format(double value, int decimals)
{
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", decimals, value);
  return text;
}

std::string
Megabytes(double bytes)
{
  return Format(bytes / (1024.0 * 1024.0), 1);
}

std::string
QualityColumns(const MesherRow & row)
{
  const dr::QualityReport & q = row.quality;
  const auto &              d = q.distanceToMarchingCubes;
  return std::to_string(q.vertices) + " | " + std::to_string(q.tetrahedra) + " | " + Megabytes(row.memoryBytes) +
         " | " + Format(q.maximumRadiusEdgeRatio, 3) + " | " + Format(q.minimumDihedralAngle, 2) + " | " +
         Format(q.minimumBoundaryPlanarAngle, 2) + " | " + std::to_string(q.nonManifoldEdges) + " | " +
         Format(d.mean, 3) + " / " + Format(d.percentile95, 3) + " / " + Format(d.maximum, 3);
}

void
PrintTableHeader()
{
  std::cout << "| image | δ mm | mesher | wall s | refine wall s | cpu s | refine cpu s | vertices | tets | peak MB | "
               "max R/E | min dihedral ° | min bdry angle ° | NM edges | dist mean / p95 / max mm | ours/CGAL time: "
               "refine wall; total wall; refine cpu; total cpu | ours/CGAL mem |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
}

std::string
Ratio(double numerator, double denominator)
{
  return Format(numerator / denominator, 2);
}

std::string
TimeColumns(const MesherRow & row, bool hasRefinementSplit)
{
  return Format(row.totalSeconds, 3) + " | " + (hasRefinementSplit ? Format(row.refinementSeconds, 3) : "") + " | " +
         Format(row.totalCpuSeconds, 3) + " | " + (hasRefinementSplit ? Format(row.refinementCpuSeconds, 3) : "");
}

void
PrintCase(const BenchCase & c, bool oursOnly)
{
  const std::string prefix = "| " + c.image + " | " + Format(c.delta, 1) + " | ";
  std::string       ratios = " | | |";
  if (!oursOnly)
  {
    ratios = " | " + Ratio(c.ours.refinementSeconds, c.cgal.totalSeconds) + "; " +
             Ratio(c.ours.totalSeconds, c.cgal.totalSeconds) + "; " +
             Ratio(c.ours.refinementCpuSeconds, c.cgal.totalCpuSeconds) + "; " +
             Ratio(c.ours.totalCpuSeconds, c.cgal.totalCpuSeconds) + " | " +
             Ratio(c.ours.memoryBytes, c.cgal.memoryBytes) + " |";
  }
  std::cout << prefix << "ours | " << TimeColumns(c.ours, true) << " | " << QualityColumns(c.ours) << ratios << "\n";
  if (oursOnly)
  {
    return;
  }
  const std::string facetDistance =
    c.match.facetDistance > 0.0 ? "fd " + Format(c.match.facetDistance, 3) : std::string("fd off");
  std::cout << prefix << "CGAL (" << facetDistance << ") | " << TimeColumns(c.cgal, false) << " | "
            << QualityColumns(c.cgal) << " | | |\n";
  std::cout << prefix << "CGAL+perturb+exude | " << TimeColumns(c.cgalOptimized, false) << " | "
            << QualityColumns(c.cgalOptimized) << " | | |\n";
  if (c.oursSliverRemoval)
  {
    const MesherRow & row = *c.oursSliverRemoval;
    std::cout << prefix << "ours, σ = " << Format(c.sliverRemovalAngle, 0) << "° | " << TimeColumns(row, true) << " | "
              << QualityColumns(row)
              << " | vs CGAL+perturb+exude: " << Ratio(row.refinementSeconds, c.cgalOptimized.totalSeconds) << "; "
              << Ratio(row.totalSeconds, c.cgalOptimized.totalSeconds) << "; "
              << Ratio(row.refinementCpuSeconds, c.cgalOptimized.totalCpuSeconds) << "; "
              << Ratio(row.totalCpuSeconds, c.cgalOptimized.totalCpuSeconds) << " | "
              << Ratio(row.memoryBytes, c.cgalOptimized.memoryBytes) << " |\n";
  }
  std::cout << prefix << "floor: bulk DT of our vertices | " << Format(c.floorSeconds, 3) << " | | | | "
            << c.ours.quality.vertices << " | | | | | | | | refine wall/floor "
            << Ratio(c.ours.refinementSeconds, c.floorSeconds) << "; refine cpu/floor "
            << Ratio(c.ours.refinementCpuSeconds, c.floorSeconds) << " | |\n";
}

/** Ours / CGAL round by round (both meshers' run i ran back to back), as "median (min-max)": a drift of the host's
 * speed between rounds cancels in each ratio, where it does not in a ratio of two medians. */
std::string
PairedRatios(const std::vector<double> & ours, const std::vector<double> & cgal)
{
  std::vector<double> ratios;
  for (std::size_t round = 0; round < std::min(ours.size(), cgal.size()); ++round)
  {
    ratios.push_back(ours[round] / cgal[round]);
  }
  if (ratios.empty())
  {
    return "";
  }
  return Format(Median(ratios), 2) + " (" + Format(*std::min_element(ratios.begin(), ratios.end()), 2) + "-" +
         Format(*std::max_element(ratios.begin(), ratios.end()), 2) + ")";
}

void
PrintPairedRatios(const std::vector<BenchCase> & cases, int runs)
{
  std::cout << "\nours / CGAL (no optimisers) round by round, median (min-max) over the " << runs
            << " rounds; CGAL's time is its whole run (image copy, domain, make_mesh_3):\n\n"
            << "| image | δ mm | refine wall | refine cpu | total wall | total cpu |\n"
            << "|---|---|---|---|---|---|\n";
  for (const BenchCase & c : cases)
  {
    std::cout << "| " << c.image << " | " << Format(c.delta, 1) << " | "
              << PairedRatios(c.ours.refinementSecondsPerRun, c.cgal.totalSecondsPerRun) << " | "
              << PairedRatios(c.ours.refinementCpuSecondsPerRun, c.cgal.totalCpuSecondsPerRun) << " | "
              << PairedRatios(c.ours.totalSecondsPerRun, c.cgal.totalSecondsPerRun) << " | "
              << PairedRatios(c.ours.totalCpuSecondsPerRun, c.cgal.totalCpuSecondsPerRun) << " |\n";
  }
  if (std::none_of(cases.begin(), cases.end(), [](const BenchCase & c) { return c.oursSliverRemoval.has_value(); }))
  {
    return;
  }
  std::cout << "\nours with sliver removal / CGAL+perturb+exude, the same way:\n\n"
            << "| image | δ mm | σ ° | total wall | total cpu |\n"
            << "|---|---|---|---|---|\n";
  for (const BenchCase & c : cases)
  {
    if (c.oursSliverRemoval)
    {
      std::cout << "| " << c.image << " | " << Format(c.delta, 1) << " | " << Format(c.sliverRemovalAngle, 0) << " | "
                << PairedRatios(c.oursSliverRemoval->totalSecondsPerRun, c.cgalOptimized.totalSecondsPerRun) << " | "
                << PairedRatios(c.oursSliverRemoval->totalCpuSecondsPerRun, c.cgalOptimized.totalCpuSecondsPerRun)
                << " |\n";
    }
  }
}

void
PrintNonManifoldEdges(const std::vector<BenchCase> & cases)
{
  const ResourceCap cap;
  std::cout << "\nnon-manifold edges, ours / CGAL: summed over the label boundaries (the main table's column) and of "
               "the union of the labels against the background; CGAL with manifold() (same criteria, one run capped at "
            << cap.cpuSeconds << " s and " << (cap.addressSpaceBytes >> 30) << " GB):\n\n"
            << "| image | δ mm | label boundaries | union of the labels | CGAL manifold(): label boundaries / union | "
               "CGAL manifold(): tets | CGAL manifold(): wall s |\n"
            << "|---|---|---|---|---|---|---|\n";
  for (const BenchCase & c : cases)
  {
    std::cout << "| " << c.image << " | " << Format(c.delta, 1) << " | " << c.ours.quality.nonManifoldEdges << " / "
              << c.cgal.quality.nonManifoldEdges << " | " << c.ours.unionNonManifoldEdges << " / "
              << c.cgal.unionNonManifoldEdges << " | ";
    if (!c.cgalManifold)
    {
      std::cout << "not run | | |\n";
    }
    else if (!c.cgalManifold->overCap.empty())
    {
      std::cout << c.cgalManifold->overCap << " | | |\n";
    }
    else
    {
      std::cout << c.cgalManifold->nonManifoldEdges << " / " << c.cgalManifold->unionNonManifoldEdges << " | "
                << c.cgalManifold->tetrahedra << " | " << Format(c.cgalManifold->totalSeconds, 3) << " |\n";
    }
  }
}

std::string
MatchDescription(const FacetDistanceMatch & match)
{
  if (match.matched)
  {
    return "yes";
  }
  return match.oursIsNotWorse ? "no: CGAL coarser at the tightest bound tried"
                              : "no: CGAL is closer even with the bound off";
}

void
PrintFidelityMatches(const std::vector<BenchCase> & cases)
{
  std::cout << "\nfacet_distance per image and δ (the tightest bound at which neither our mean nor our p95 two-sided "
               "distance is worse than CGAL's by more than "
            << 100.0 * FidelityTolerance << " %):\n\n"
            << "| image | δ mm | facet_distance mm | ours: mean / p95 mm | CGAL: mean / p95 mm | matched | trials |\n"
            << "|---|---|---|---|---|---|---|\n";
  for (const BenchCase & c : cases)
  {
    const dr::DistanceStatistics & ours = c.ours.quality.distanceToMarchingCubes;
    std::cout << "| " << c.image << " | " << Format(c.delta, 1) << " | "
              << (c.match.facetDistance > 0.0 ? Format(c.match.facetDistance, 4) : std::string("off")) << " | "
              << Format(ours.mean, 3) << " / " << Format(ours.percentile95, 3) << " | "
              << Format(c.match.cgalDistance.mean, 3) << " / " << Format(c.match.cgalDistance.percentile95, 3) << " | "
              << MatchDescription(c.match) << " | " << c.match.trials << " |\n";
  }
}

bool
IsSelected(const BenchImage & image, const Options & options)
{
  return options.imageNames.empty() ||
         std::find(options.imageNames.begin(), options.imageNames.end(), image.name) != options.imageNames.end();
}

/** \throws std::invalid_argument for an --images name that is not in this run's list. */
void
RequireKnownImageNames(const std::vector<BenchImage> & images, const Options & options)
{
  for (const std::string & name : options.imageNames)
  {
    if (std::none_of(images.begin(), images.end(), [&](const BenchImage & image) { return image.name == name; }))
    {
      throw std::invalid_argument("--images: no image \"" + name + "\" in this run's list" +
                                  (options.quick ? " (--quick leaves out the 128^3 shapes and the 1 mm grids)" : ""));
    }
  }
}

/** The case's meshes as `directory`/IMAGE_DELTA_MESHER.vtu, MESHER one of ours, cgal, cgal-optimized: what
 * bench/downstream.py solves on. */
void
WriteCaseMeshes(const BenchCase & c, bool oursOnly, const std::string & directory)
{
  const std::string prefix = directory + "/" + c.image + "_" + Format(c.delta, 1) + "_";
  dr::WriteTetrahedralMesh(c.ours.mesh, prefix + "ours.vtu");
  if (!oursOnly)
  {
    dr::WriteTetrahedralMesh(c.cgal.mesh, prefix + "cgal.vtu");
    dr::WriteTetrahedralMesh(c.cgalOptimized.mesh, prefix + "cgal-optimized.vtu");
    if (c.oursSliverRemoval)
    {
      dr::WriteTetrahedralMesh(c.oursSliverRemoval->mesh, prefix + "ours-sliver-removal.vtu");
    }
  }
}

int
RunBenchmark(const Options & options)
{
  // Both meshers run on one thread: CGAL's sequential Mesh_3 against our filter with ITK's set-up unthreaded.
  // The Platform threader keeps ITK from starting a thread pool, which a forked child would inherit dead.
  itk::MultiThreaderBase::SetGlobalDefaultThreader(itk::MultiThreaderBase::ThreaderEnum::Platform);
  itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(1);

  const std::vector<BenchImage> images = MakeBenchImages(options.quick, options.dataDirectory);
  RequireKnownImageNames(images, options);
  std::vector<BenchCase> cases;
  for (const BenchImage & benchImage : images)
  {
    if (!IsSelected(benchImage, options))
    {
      continue;
    }
    std::cerr << benchImage.name << ": " << benchImage.description << ", "
              << benchImage.image->GetBufferedRegion().GetSize() << " voxels of " << benchImage.image->GetSpacing()
              << " mm\n";
    if (!options.imageDirectory.empty())
    {
      itk::WriteImage(benchImage.image, options.imageDirectory + "/" + benchImage.name + ".nrrd", true);
    }
    const dr::LabelVolume     volume = ToLabelVolume(*benchImage.image);
    const dr::TriangleSurface marchingCubes = dr::ExtractLabelSurfaces(volume);
    for (const double delta : options.deltas.empty() ? benchImage.deltas : options.deltas)
    {
      cases.push_back(RunCase(benchImage, delta, options, volume, marchingCubes));
      if (!options.meshDirectory.empty())
      {
        WriteCaseMeshes(cases.back(), options.oursOnly, options.meshDirectory);
      }
    }
  }
  std::cout << "\nrho = 2, nearest-neighbour oracle; CGAL: facet_angle 30, facet_size " << FacetSizePerDelta
            << " delta, cell_radius_edge_ratio 2, cell_size " << CellSizePerDelta << " delta, sequential; medians of "
            << options.runs << " runs\n\n";
  PrintTableHeader();
  for (const BenchCase & c : cases)
  {
    PrintCase(c, options.oursOnly);
  }
  if (!options.oursOnly)
  {
    PrintPairedRatios(cases, options.runs);
    PrintNonManifoldEdges(cases);
    PrintFidelityMatches(cases);
  }
  return EXIT_SUCCESS;
}

} // namespace

int
main(int argc, char * argv[])
{
  try
  {
    Options options;
    if (const std::optional<int> exitCode = ParseOptions(argc, argv, options))
    {
      return *exitCode;
    }
    return RunBenchmark(options);
  }
  catch (const std::exception & error)
  {
    std::cerr << "delaunay-bench: " << error.what() << "\n";
    return EXIT_FAILURE;
  }
}
