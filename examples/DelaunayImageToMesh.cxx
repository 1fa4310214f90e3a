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

// delaunay-image-to-mesh: meshes a segmented (or gray) 3-D image into labelled tetrahedra with
// itk::DelaunayImageToMeshFilter, writes the mesh for FEM codes and reports its quality. Run with --help.

#include "DelaunayImageToMeshInput.h"
#include "DelaunayImageToMeshQualityReport.h"
#include "DelaunayImageToMeshWriters.h"
#include "itkDelaunayImageToMeshFilter.h"

#include "itkLabelVolume.h"
#include "itkMesh.h"
#include "itkVersion.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>
#include <regex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

// Any standard header defines __GLIBC__ where the C library is glibc.
#if defined(__GLIBC__)
#  include <malloc.h>
#endif

#if defined(_WIN32)
#  include <io.h>
#  define DelaunayImageToMesh_isatty _isatty
#  define DelaunayImageToMesh_fileno _fileno
#else
#  include <unistd.h>
#  define DelaunayImageToMesh_isatty isatty
#  define DelaunayImageToMesh_fileno fileno
#endif

namespace
{

using namespace delaunay_image_to_mesh_program;
using delaunay_refinement::Label;
using delaunay_refinement::RefinementParameters;

constexpr int FailureExitCode = 2;

using LabelImageType = itk::Image<int32_t, 3>;
using GrayImageType = itk::Image<float, 3>;
using OutputMeshType = itk::Mesh<int32_t, 3>;
/** The filter's own defaults and limits (the same for every input pixel type). */
using FilterDefaults = itk::DelaunayImageToMeshFilter<itk::Image<int32_t, 3>, OutputMeshType>;


/** What the command line asks for. Defaults are the refinement core's. */
struct Options
{
  std::string inputPath;
  std::string outputPath;
  /** 0 = the filter's automatic δ, 4 × the largest voxel spacing. */
  double surfaceSamplingDistance{ 0.0 };
  double radiusEdgeBound{ RefinementParameters{}.radiusEdgeBound };
  double minimumDihedralAngle{ RefinementParameters{}.minimumDihedralAngle };
  /** As typed: "all" or labels. */
  std::vector<std::string> labels;
  bool                     mergeLabels{ false };
  bool                     keepDiagonalVoxels{ false };
  double                   regularizationScale{ FilterDefaults::DefaultRegularizationScale };
  unsigned int             topologyRegularizationRounds{ RefinementParameters{}.topologyRegularizationRounds };
  bool                     keepNonManifoldPlaces{ !RefinementParameters{}.relabelNonManifoldPlaces };
  bool                     keepThickPartsUnrefined{ !RefinementParameters{}.refineThickParts };
  unsigned int             manifoldRefinementLevels{ RefinementParameters{}.manifoldRefinementLevels };
  std::optional<double>    isoValue;
  std::size_t              maximumNumberOfVertices{ RefinementParameters{}.maximumNumberOfVertices };
  std::string              reportPath;
  bool                     measureDistance{ false };
  bool                     quiet{ false };
};

// ---------------------------------------------------------------------------------------------------------------
// Arguments: CLI11 parses and type-checks them; the core's ValidateParameters checks the refinement parameters.

/** A CLI11 check: "`need`, got 'text'" unless `valid(text)`. */
CLI::Validator
Requirement(std::function<bool(const std::string &)> valid, const std::string & need)
{
  return { [=](const std::string & text) { return valid(text) ? std::string() : need + ", got '" + text + "'"; }, "" };
}

/** Rejects an out-of-range value before the image is read, with the core's message after the option's name. */
template <typename TValue>
CLI::Validator
CoreRange(TValue RefinementParameters::*parameter)
{
  return { [parameter](const std::string & text) {
            RefinementParameters parameters;
            try
            {
              // Text that is no TValue at all is CLI11's to report, as a conversion error.
              if (CLI::detail::lexical_cast(text, parameters.*parameter))
              {
                delaunay_refinement::ValidateParameters(parameters);
              }
            }
            catch (const std::invalid_argument & error)
            {
              return std::string(error.what());
            }
            return std::string();
          },
           "" };
}

// CLI11 2.1 reads "-5" into an unsigned integer as 2^64 - 5.
const CLI::Validator WholeNumber = Requirement(
  [](const std::string & text) { return !text.empty() && text.find_first_not_of("0123456789") == std::string::npos; },
  "needs a whole number");
// CLI11 reads "nan" and "inf" as numbers; no gray value is either.
const CLI::Validator FiniteNumber = Requirement(
  [](const std::string & text) {
    double value = 0.0;
    return !CLI::detail::lexical_cast(text, value) || std::isfinite(value);
  },
  "needs a finite number");
const CLI::Validator LabelOrAll = Requirement(
  [](const std::string & text) {
    Label label = delaunay_refinement::BackgroundLabel;
    return text == "all" || (CLI::detail::lexical_cast(text, label) && label != delaunay_refinement::BackgroundLabel);
  },
  "needs 'all' or comma-separated integer labels such as 1,2 (0, the background, cannot be selected)");

// The output paths are checked before reading and meshing, which may take minutes, rather than when written.
const CLI::Validator InExistingDirectory(
  [](const std::string & path) {
    const std::filesystem::path directory = std::filesystem::path(path).parent_path();
    std::error_code             error;
    return directory.empty() || std::filesystem::is_directory(directory, error)
             ? std::string()
             : "directory '" + directory.string() + "' does not exist";
  },
  "");
const CLI::Validator MeshFileExtension(
  [](const std::string & path) {
    const std::vector<std::string> supported = delaunay_refinement::SupportedMeshFileExtensions();
    const std::string              extension = CLI::detail::to_lower(std::filesystem::path(path).extension().string());
    return std::find(supported.begin(), supported.end(), extension) != supported.end()
             ? std::string()
             : "unsupported output extension '" + extension + "' (supported: " + CLI::detail::join(supported, ", ") +
                 ")";
  },
  "");

/** The labels to mesh, from --labels checked by LabelOrAll; empty = every non-zero label. */
std::vector<Label>
SelectedLabels(const std::vector<std::string> & items)
{
  std::vector<Label> labels;
  for (const std::string & item : items)
  {
    if (item == "all")
    {
      return {};
    }
    labels.push_back(static_cast<Label>(std::stol(item)));
  }
  return labels;
}

void
AddOptions(CLI::App & app, Options & options)
{
  app.add_option("INPUT", options.inputPath)
    ->description("a 3-D image: NIfTI (.nii, .nii.gz), NRRD (.nrrd, .nhdr), MetaImage (.mha,\n.mhd), or a directory "
                  "holding a DICOM series (the first series found is read)")
    ->type_name("")
    ->required();
  app.add_option("OUTPUT", options.outputPath)
    ->description("the mesh, format by extension: .vtu (VTK XML), .vtk (VTK legacy), .msh\n(Gmsh 4.1), .mesh "
                  "(Medit); every tetrahedron carries its label")
    ->type_name("")
    ->required()
    ->check(MeshFileExtension)
    ->check(InExistingDirectory);

  app.option_defaults()->group("Meshing");
  app.add_option("-d,--delta", options.surfaceSamplingDistance)
    ->description("surface sampling distance delta in mm: smaller is finer and closer to the\nsurface (default: 4 x "
                  "the largest voxel spacing, the filter's automatic value)")
    ->type_name("MM")
    ->check(CoreRange(&RefinementParameters::surfaceSamplingDistance));
  app.add_option("--radius-edge", options.radiusEdgeBound)
    ->description("radius-edge bound rho, >= 1; the guarantees above hold with the default")
    ->type_name("R")
    ->capture_default_str()
    ->check(CoreRange(&RefinementParameters::radiusEdgeBound));
  app.add_option("--min-dihedral", options.minimumDihedralAngle)
    ->description("remove slivers: split or move tetrahedra with a dihedral angle below DEG, 0 to\n" +
                  std::to_string(static_cast<int>(delaunay_refinement::ParameterLimits::LargestMinimumDihedralAngle)) +
                  " (the R4' variant; 0 = off, the paper's method, whose bounds are proven)")
    ->type_name("DEG")
    ->capture_default_str()
    ->check(CoreRange(&RefinementParameters::minimumDihedralAngle));
  app.add_option("--max-vertices", options.maximumNumberOfVertices, "fail beyond N vertices")
    ->type_name("N")
    ->capture_default_str()
    ->check(WholeNumber)
    ->check(CoreRange(&RefinementParameters::maximumNumberOfVertices));

  app.option_defaults()->group("Tissues");
  CLI::Option * labels = app.add_option("--labels",
                                        options.labels,
                                        "the labels to mesh, each as a tissue (default: all = every "
                                        "non-zero label)");
  labels->type_name("all|L1,L2,...")->delimiter(',')->check(LabelOrAll);
  CLI::Option * merge = app.add_flag("--merge-labels",
                                     options.mergeLabels,
                                     "mesh the selected labels as one object, label 1 (e.g. a mask whose\nvalues "
                                     "are classes; default: each label is a tissue)");
  app.add_flag("--keep-diagonal-voxels",
               options.keepDiagonalVoxels,
               "keep voxels that touch only along an edge or at a corner as they are\n(default: one voxel "
               "there changes label, never a tissue's to the\nbackground, so that every boundary can be a manifold)");
  app.add_option("--regularization-scale", options.regularizationScale)
    ->description("delta is the resolution: parts of a tissue thinner than 2 x S x delta go to\ntheir neighbours and "
                  "slits that thin are filled, 0 to 0.5 (0 = the voxels as\nthey are)")
    ->type_name("S")
    ->capture_default_str()
    ->check(Requirement(
      [](const std::string & text) {
        double value = -1.0;
        return CLI::detail::lexical_cast(text, value) && value >= 0.0 &&
               value <= FilterDefaults::LargestRegularizationScale;
      },
      "a number in [0, 0.5]"));
  app.add_option("--topology-rounds", options.topologyRegularizationRounds)
    ->description("where a boundary is still not a manifold, regularise the labels around it\nand refine again, at "
                  "most N rounds (0 = never)")
    ->type_name("N")
    ->capture_default_str()
    ->check(WholeNumber)
    ->check(CoreRange(&RefinementParameters::topologyRegularizationRounds));
  app.add_flag("--no-topology-relabelling",
               options.keepNonManifoldPlaces,
               "do not give tetrahedra a neighbour's label where a boundary is not a\nmanifold (default: a cone "
               "there is cut off or a gap filled when that mends\nthe place and keeps the 30 degree bound)");
  app.add_flag("--no-thick-part-refinement",
               options.keepThickPartsUnrefined,
               "do not sample more finely the parts of a tissue that hold a ball of diameter\ndelta but would get no "
               "tetrahedron (default: each gets tetrahedra); the\nparts left without one are reported all the same");
  app.add_option("--manifold-levels", options.manifoldRefinementLevels)
    ->description("the old repair, opt-in: halve delta up to N times where a boundary is still\nnot a manifold "
                  "(meshes several times larger; default 0 = off)")
    ->type_name("N")
    ->capture_default_str()
    ->check(WholeNumber)
    ->check(CoreRange(&RefinementParameters::manifoldRefinementLevels));
  app.add_option("--iso", options.isoValue)
    ->description("treat INPUT as a gray image: mesh where the linearly interpolated value is\n>= VALUE, as label 1")
    ->type_name("VALUE")
    ->check(FiniteNumber)
    ->excludes(labels)
    ->excludes(merge);

  app.option_defaults()->group("Output");
  app.add_option("--report", options.reportPath, "also write the quality report as JSON")
    ->type_name("FILE.json")
    ->check(InExistingDirectory);
  app.add_flag("--distance",
               options.measureDistance,
               "also measure the two-sided distance between the mesh boundary and the\nmarching-cubes surface of the "
               "segmentation (mean, p95, max) for the report;\non a speckled segmentation it costs several times the "
               "meshing");
  app.add_flag("-q,--quiet", options.quiet, "print nothing but errors (no progress, no report table)");
}

/** Parses the command line into `options`; nullopt when it was parsed, else the exit code after --help or
 * --version. \throws UserError for any mistake. */
std::optional<int>
ParseArguments(int argc, char * argv[], Options & options)
{
  CLI::App app("Meshes the labelled regions of a 3-D image into tetrahedra by Delaunay refinement straight from the\n"
               "image. With the default radius-edge bound every tetrahedron has circumradius / shortest edge < 2 and\n"
               "every boundary triangle has all angles > 30 degrees; for a small enough --delta the boundary is a\n"
               "closed manifold close to the object's surface. Tissues (labels) are meshed conformingly.\n",
               ProgramName);
  // As before CLI11: a repeated option takes its last value, so that a pipeline can append overrides.
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast)->disable_flag_override();
  app.set_help_flag("-h,--help", "print this help and exit");
  app.set_version_flag("-V,--version",
                       std::string(ProgramName) + ' ' + DelaunayImageToMesh_PROGRAM_VERSION + " (ITK " +
                         itk::Version::GetITKVersion() + ")",
                       "print the version and exit");
  app
    .set_config("--config",
                "",
                "read options from FILE, TOML or INI, one per line: delta = 2,\nlabels = [1, 2], "
                "quiet = true; options on the command line win")
    ->type_name("FILE");
  // A misspelt key must not leave a parameter at its default unnoticed.
  app.allow_config_extras(CLI::config_extras_mode::error);
  AddOptions(app, options);
  app.footer(std::string("Progress goes to stderr, the quality report table to stdout. Exit status: 0 on success, 2 "
                         "on\nbad arguments, unreadable or unwritable files and meshing failures, with a one-line "
                         "error\non stderr.\n\nExample: ") +
             ProgramName + " brain.nii.gz brain.vtu -d 4 --report brain-report.json");
  try
  {
    app.parse(argc, argv);
  }
  catch (const CLI::Success & request)
  {
    return app.exit(request);
  }
  catch (const CLI::ParseError & error)
  {
    throw UserError(error.what());
  }
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------------------------------
// Meshing.

/** Shows a fraction done on stderr: a bar redrawn in place on a terminal, a line every 10% otherwise (logs and pipes
 * should not fill with carriage returns). `name` names the bar; `linePrefix` starts each line. */
class PercentDisplay
{
public:
  PercentDisplay(std::string name, std::string linePrefix, bool onTerminal)
    : m_Name(std::move(name))
    , m_LinePrefix(std::move(linePrefix))
    , m_OnTerminal(onTerminal)
  {}

  ~PercentDisplay()
  {
    if (m_OnTerminal && m_ShownPercent >= 0)
    {
      std::cerr << std::endl;
    }
  }

  PercentDisplay(const PercentDisplay &) = delete;
  PercentDisplay &
  operator=(const PercentDisplay &) = delete;

  void
  Show(double fraction)
  {
    const int percent = static_cast<int>(std::floor(100.0 * std::clamp(fraction, 0.0, 1.0)));
    const int step = m_OnTerminal ? 1 : 10;
    if (m_ShownPercent >= 0 && percent / step <= m_ShownPercent / step)
    {
      return;
    }
    m_ShownPercent = percent;
    if (m_OnTerminal)
    {
      constexpr int width = 40;
      const int     filled = percent * width / 100;
      std::cerr << '\r' << m_Name << " [" << std::string(filled, '#') << std::string(width - filled, ' ') << "] "
                << percent << '%' << std::flush;
    }
    else
    {
      std::cerr << m_LinePrefix << ": " << percent << '%' << std::endl;
    }
  }

private:
  std::string m_Name;
  std::string m_LinePrefix;
  bool        m_OnTerminal;
  int         m_ShownPercent{ -1 };
};

/** Shows a process's progress on stderr while it lives (PercentDisplay; lines "progress: N%"). */
class ProgressDisplay
{
public:
  ProgressDisplay(itk::ProcessObject * process, bool onTerminal)
    : m_Process(process)
    , m_Display("meshing", "progress", onTerminal)
  {
    m_Observer = process->AddObserver(itk::ProgressEvent(),
                                      [this](const itk::EventObject &) { m_Display.Show(m_Process->GetProgress()); });
  }

  ~ProgressDisplay() { m_Process->RemoveObserver(m_Observer); }

  ProgressDisplay(const ProgressDisplay &) = delete;
  ProgressDisplay &
  operator=(const ProgressDisplay &) = delete;

private:
  itk::ProcessObject * m_Process;
  PercentDisplay       m_Display;
  unsigned long        m_Observer{ 0 };
};

class Stopwatch
{
public:
  double
  Seconds() const
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_Start).count();
  }

private:
  std::chrono::steady_clock::time_point m_Start{ std::chrono::steady_clock::now() };
};

template <typename TImage>
auto
MakeFilter(const TImage * image, const Options & options)
{
  auto filter = itk::DelaunayImageToMeshFilter<TImage, OutputMeshType>::New();
  filter->SetInput(image);
  filter->SetSurfaceSamplingDistance(options.surfaceSamplingDistance);
  filter->SetRadiusEdgeBound(options.radiusEdgeBound);
  filter->SetMinimumDihedralAngle(options.minimumDihedralAngle);
  filter->SetMaximumNumberOfVertices(options.maximumNumberOfVertices);
  filter->SetJoinDiagonalVoxels(!options.keepDiagonalVoxels);
  filter->SetRegularizationScale(options.regularizationScale);
  filter->SetTopologyRegularizationRounds(options.topologyRegularizationRounds);
  filter->SetRelabelNonManifoldPlaces(!options.keepNonManifoldPlaces);
  filter->SetRefineThickParts(!options.keepThickPartsUnrefined);
  filter->SetManifoldRefinementLevels(options.manifoldRefinementLevels);
  if (options.isoValue)
  {
    filter->SetIsoValue(*options.isoValue);
  }
  else
  {
    filter->SetLabels(SelectedLabels(options.labels));
    filter->SetMergeLabels(options.mergeLabels);
  }
  return filter;
}

void
RunFilter(itk::ProcessObject * filter, bool quiet)
{
  std::optional<ProgressDisplay> display;
  if (!quiet)
  {
    display.emplace(filter, DelaunayImageToMesh_isatty(DelaunayImageToMesh_fileno(stderr)) != 0);
  }
  try
  {
    filter->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    throw UserError("meshing failed: " + OneLine(error.GetDescription()));
  }
}

void
WriteMesh(const delaunay_refinement::TetrahedralMesh & mesh, const std::string & path)
{
  try
  {
    delaunay_refinement::WriteTetrahedralMesh(mesh, path);
  }
  catch (const std::exception & error)
  {
    throw UserError("cannot write '" + path + "': " + OneLine(error.what()));
  }
}

/** The run as the report records it: every parameter read back from the filter, so that the report says what the
 * mesh was made with, and what the topology options did. */
template <typename TFilter>
delaunay_refinement::MeshingRun
DescribeRun(const TFilter & filter, const Options & options,
            const std::vector<std::pair<std::string, double>> & phaseSeconds)
{
  delaunay_refinement::MeshingRun run;
  run.inputFile = options.inputPath;
  run.outputFile = options.outputPath;
  run.surfaceSamplingDistance = filter.GetEffectiveSurfaceSamplingDistance();
  run.radiusEdgeBound = filter.GetRadiusEdgeBound();
  run.minimumDihedralAngle = filter.GetMinimumDihedralAngle();
  run.phaseSeconds = phaseSeconds;
  run.peakResidentMemoryBytes = delaunay_refinement::PeakResidentMemoryBytes();
  if (filter.GetUseIsoValue())
  {
    run.isoValue = filter.GetIsoValue();
  }
  else
  {
    run.selectedLabels.assign(filter.GetLabels().begin(), filter.GetLabels().end());
    run.selectedLabelsNotInImage.assign(filter.GetSelectedLabelsNotInImage().begin(),
                                        filter.GetSelectedLabelsNotInImage().end());
    run.mergeLabels = filter.GetMergeLabels();
  }
  run.maximumNumberOfVertices = filter.GetMaximumNumberOfVertices();
  const delaunay_refinement::RefinementStatistics & statistics = filter.GetRefinementStatistics();
  delaunay_refinement::TopologyRun &                topology = run.topology;
  topology.regularizationScale = filter.GetRegularizationScale();
  topology.joinDiagonalVoxels = filter.GetJoinDiagonalVoxels();
  topology.voxelsChangedAtPinches = filter.GetNumberOfJoiningVoxels();
  topology.relabelNonManifoldPlaces = filter.GetRelabelNonManifoldPlaces();
  topology.relabelledTetrahedra = filter.GetNumberOfTopologyRelabelledTetrahedra();
  topology.regularizationRoundsAllowed = filter.GetTopologyRegularizationRounds();
  topology.regularizationRoundsMade = statistics.topologyRegularizationRounds;
  topology.locallyRegularizedVoxels = filter.GetNumberOfLocallyRegularizedVoxels();
  topology.budgetReached = filter.GetTopologyRegularizationBudgetReached();
  topology.refineThickParts = filter.GetRefineThickParts();
  topology.thickPartsRefined = statistics.thickPartsRefined;
  topology.manifoldRefinementLevels = filter.GetManifoldRefinementLevels();
  topology.manifoldRefinementRounds = statistics.manifoldRefinementRounds;
  return run;
}

template <typename TImage>
int
MeshImage(const Options & options)
{
  std::vector<std::pair<std::string, double>> phaseSeconds;
  const Stopwatch                             readTime;
  const auto image = ReadImage<TImage>(options.inputPath, options.quiet ? nullptr : &std::cerr);
  phaseSeconds.emplace_back("read", readTime.Seconds());

  const Stopwatch meshTime;
  const auto      filter = MakeFilter(image.GetPointer(), options);
  RunFilter(filter.GetPointer(), options.quiet);
  if (!options.quiet && filter->GetNumberOfJoiningVoxels() > 0)
  {
    std::cout << "removed voxel pinches (labels touching only along a voxel edge or at a corner): "
              << filter->GetNumberOfJoiningVoxels()
              << " voxels changed label (--keep-diagonal-voxels keeps them as they are)\n";
  }
  if (!options.quiet && filter->GetNumberOfTopologyRelabelledTetrahedra() > 0)
  {
    std::cout << "relabelled at non-manifold places: " << filter->GetNumberOfTopologyRelabelledTetrahedra()
              << " tetrahedra took a neighbour's label (--no-topology-relabelling keeps them)\n";
  }
  const delaunay_refinement::RefinementStatistics & statistics = filter->GetRefinementStatistics();
  if (!options.quiet && statistics.topologyRegularizationBudgetReached)
  {
    std::cout << "topology regularisation: stopped after " << statistics.topologyRegularizationRounds
              << " rounds, at its budget of inserted vertices (docs/algorithm.md, \"Topology\"); "
              << statistics.remainingNonManifoldVertices
              << " non-manifold vertices left (a larger delta or radius-edge bound gives fewer)\n";
  }
  if (!options.quiet && statistics.manifoldRefinementRounds > 0)
  {
    std::cout << "halved delta around non-manifold places: " << statistics.manifoldRefinementRounds << " rounds, "
              << statistics.manifoldRefinementZones << " zones (--manifold-levels)\n";
  }
  // An iso-surface is regularised through its voxels' values (docs/algorithm.md, "Topology"); places are left where
  // the topology options were turned off or the rounds ran out, and the opt-in halving is what reaches them then.
  if (!options.quiet && options.isoValue && statistics.remainingNonManifoldVertices > 0 &&
      options.manifoldRefinementLevels == 0)
  {
    std::cout << "non-manifold places left (a vertex and a label each): " << statistics.remainingNonManifoldVertices
              << "; --manifold-levels 2 refines around them\n";
  }
  const std::size_t forcedSliverSplits = statistics.sliverSplitsFailingAcceptance;
  if (!options.quiet && forcedSliverSplits > 0)
  {
    std::cout << "sliver removal: " << forcedSliverSplits
              << " slivers, in layers about delta thick, could be split only where a boundary loses a bound (a free "
                 "vertex on it, within delta of the surface)\n";
  }
  const delaunay_refinement::TetrahedralMesh & mesh = filter->GetRefinedMesh();
  phaseSeconds.emplace_back("mesh", meshTime.Seconds());

  // Nothing is measured when nobody will see the report.
  const bool                         wantReport = !options.quiet || !options.reportPath.empty();
  delaunay_refinement::QualityReport report;
  if (wantReport)
  {
    const Stopwatch reportTime;
    // The reference is the segmentation: the voxels after label selection, merging or the iso-value, before the
    // regularisation at the scale of delta, so that fidelity is measured against the input and a tissue the
    // regularisation removed reads as lost.
    // The distance can take minutes on a speckled segmentation: its progress is shown as the meshing's is
    // (lines "distance: N%").
    std::optional<PercentDisplay>         distanceDisplay;
    delaunay_refinement::DistanceProgress distanceProgress;
    if (options.measureDistance && !options.quiet)
    {
      distanceDisplay.emplace(
        "distance", "distance", DelaunayImageToMesh_isatty(DelaunayImageToMesh_fileno(stderr)) != 0);
      distanceProgress = [&distanceDisplay](double fraction) { distanceDisplay->Show(fraction); };
    }
    report = delaunay_refinement::ComputeQualityReport(mesh,
                                                       itk::ViewLabelVolume(filter->GetSelectedLabelImage()),
                                                       options.measureDistance
                                                         ? delaunay_refinement::DistanceMeasurement::Measure
                                                         : delaunay_refinement::DistanceMeasurement::Skip,
                                                       distanceProgress);
    const auto & spacing = filter->GetSelectedLabelImage()->GetSpacing();
    delaunay_refinement::AddWhatTheMeshLeftOut(report,
                                               filter->GetRegularizationReport(),
                                               spacing[0] * spacing[1] * spacing[2],
                                               filter->GetRefinementStatistics().unmeshedParts);
    distanceDisplay.reset();
    phaseSeconds.emplace_back("report", reportTime.Seconds());
  }

  const Stopwatch writeTime;
  WriteMesh(mesh, options.outputPath);
  phaseSeconds.emplace_back("write", writeTime.Seconds());
  if (!wantReport)
  {
    return EXIT_SUCCESS;
  }

  report.run = DescribeRun(*filter, options, phaseSeconds);
  if (!options.reportPath.empty())
  {
    delaunay_refinement::WriteQualityReportJsonFile(report, options.reportPath);
  }
  if (!options.quiet)
  {
    delaunay_refinement::PrintQualityReport(report, std::cout);
  }
  return EXIT_SUCCESS;
}

int
Run(int argc, char * argv[])
{
  Options options;
  if (const std::optional<int> exitCode = ParseArguments(argc, argv, options))
  {
    return *exitCode;
  }
  if (options.isoValue)
  {
    return MeshImage<GrayImageType>(options);
  }
  // A label file of 8- or 16-bit integers is read as they are: as 32-bit integers it took two to four times the
  // file's voxels in memory, as much as the whole refinement (49 MB for the 12 MB of the 1 mm brain mask). A file of
  // floats is read as floats, so that the filter rounds each value to the nearest label: reading it as integers
  // truncated 1.9999999 to label 1. Doubles and integers that a 32-bit signed integer cannot hold (unsigned 32-bit,
  // 64-bit) are read as doubles, exact to 2^53: read as 32-bit integers they wrapped (4,000,000,000 became
  // -294,967,296, 2^33 + 1 became label 1, another tissue), and the filter now refuses a value beyond its labels.
  switch (ScalarComponentTypeOf(options.inputPath))
  {
    case itk::IOComponentEnum::FLOAT:
      return MeshImage<GrayImageType>(options);
    case itk::IOComponentEnum::DOUBLE:
    case itk::IOComponentEnum::UINT:
    case itk::IOComponentEnum::LONG:
    case itk::IOComponentEnum::ULONG:
    case itk::IOComponentEnum::LONGLONG:
    case itk::IOComponentEnum::ULONGLONG:
      return MeshImage<itk::Image<double, 3>>(options);
    case itk::IOComponentEnum::UCHAR:
      return MeshImage<itk::Image<uint8_t, 3>>(options);
    case itk::IOComponentEnum::SHORT:
      return MeshImage<itk::Image<int16_t, 3>>(options);
    case itk::IOComponentEnum::USHORT:
      return MeshImage<itk::Image<uint16_t, 3>>(options);
    default:
      return MeshImage<LabelImageType>(options);
  }
}

/** Lets the process reuse the memory it frees instead of handing it back to the system: with glibc's defaults a
 * block of 128 KiB or more is mapped fresh and unmapped when freed, and the top of the heap is trimmed, so each of
 * the set-up's short-lived buffers (a label's sets of bits, the label components' runs) and the label image, which
 * could reuse what the image reader freed, costs a page fault per 4 KiB page on its first write. On a virtual machine
 * a fault costs microseconds (14 µs measured here), and the faults were a sixth of a coarse run on a 1 M-voxel image.
 * Blocks below 32 MiB (glibc's largest automatic threshold) now come from the heap, which is never trimmed: the
 * program ends after one mesh, and its peak grows only by what the heap keeps (a few megabytes; bench/README.md, "At
 * 12c3d99"). Larger buffers are still mapped (the per-voxel buffers, on huge pages; DelaunayRefinementLargeBuffers.h).
 * A setting of this program, not of the filter: a library must not change how its host process allocates. */
void
KeepFreedMemoryInTheProcess()
{
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
#endif
}

int
ReportError(const std::string & message)
{
  std::cerr << ProgramName << ": error: " << OneLine(message) << std::endl;
  return FailureExitCode;
}

} // namespace

int
main(int argc, char * argv[])
{
  KeepFreedMemoryInTheProcess();
  try
  {
    return Run(argc, argv);
  }
  catch (const itk::ExceptionObject & error)
  {
    return ReportError(error.GetDescription());
  }
  catch (const std::exception & error)
  {
    return ReportError(error.what());
  }
}
