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

#include "DelaunayImageToMeshQualityReport.h"
#include "DelaunayImageToMeshWriters.h"
#include "itkDelaunayImageToMeshFilter.h"

#include "itkGDCMImageIO.h"
#include "itkGDCMSeriesFileNames.h"
#include "itkImageFileReader.h"
#include "itkImageIOFactory.h"
#include "itkImageRegionConstIterator.h"
#include "itkImageSeriesReader.h"
#include "itkLabelVolume.h"
#include "itkMesh.h"
#include "itkVersion.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

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

using delaunay_refinement::Label;

constexpr const char * ProgramName = "delaunay-image-to-mesh";
constexpr int          FailureExitCode = 2;

using LabelImageType = itk::Image<int32_t, 3>;
using GrayImageType = itk::Image<float, 3>;
using OutputMeshType = itk::Mesh<int32_t, 3>;

/** A problem the user can fix (an argument, a file): reported as one line, without a stack. */
class UserError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/** What the command line asks for. Defaults are the refinement core's. */
struct Options
{
  enum class Action
  {
    Mesh,
    PrintHelp,
    PrintVersion
  };
  Action      action{ Action::Mesh };
  std::string inputPath;
  std::string outputPath;
  /** 0 = the filter's automatic δ, 4 × the largest voxel spacing. */
  double surfaceSamplingDistance{ 0.0 };
  double radiusEdgeBound{ delaunay_refinement::RefinementParameters{}.radiusEdgeBound };
  double minimumDihedralAngle{ 0.0 };
  /** Empty = every non-zero label. */
  std::vector<Label>    labels;
  bool                  mergeLabels{ false };
  bool                  joinDiagonalVoxels{ true };
  std::optional<double> isoValue;
  std::size_t           maximumNumberOfVertices{ delaunay_refinement::RefinementParameters{}.maximumNumberOfVertices };
  std::string           reportPath;
  bool                  quiet{ false };
};

void
PrintHelp(std::ostream & out)
{
  out << "Usage: " << ProgramName << " INPUT OUTPUT [options]\n"
      << "\n"
      << "Meshes the labelled regions of a 3-D image into tetrahedra by Delaunay refinement straight from the\n"
      << "image. With the default radius-edge bound every tetrahedron has circumradius / shortest edge < 2 and\n"
      << "every boundary triangle has all angles > 30 degrees; for a small enough --delta the boundary is a\n"
      << "closed manifold close to the object's surface. Tissues (labels) are meshed conformingly.\n"
      << "\n"
      << "  INPUT    a 3-D image: NIfTI (.nii, .nii.gz), NRRD (.nrrd, .nhdr), MetaImage (.mha, .mhd), or a\n"
      << "           directory holding a DICOM series (the first series found is read)\n"
      << "  OUTPUT   the mesh, format by extension: .vtu (VTK XML), .vtk (VTK legacy), .msh (Gmsh 4.1),\n"
      << "           .mesh (Medit); every tetrahedron carries its label\n"
      << "\n"
      << "Options:\n"
      << "  --delta MM               surface sampling distance delta in mm: smaller is finer and closer to the\n"
      << "                           surface (default: 4 x the largest voxel spacing, the filter's automatic value)\n"
      << "  --radius-edge R          radius-edge bound rho, >= 1 (default: "
      << delaunay_refinement::RefinementParameters{}.radiusEdgeBound << "; the guarantees above hold with it)\n"
      << "  --min-dihedral DEG       also split tetrahedra with a dihedral angle below DEG, 0 to 30 (the R4'\n"
      << "                           variant; default: off). Nothing is proven with it.\n"
      << "  --labels all|L1,L2,...   the labels to mesh, each as a tissue (default: all = every non-zero label)\n"
      << "  --merge-labels           mesh the selected labels as one object, label 1 (e.g. a mask whose values\n"
      << "                           are classes; default: each label is a tissue)\n"
      << "  --keep-diagonal-voxels   do not join voxels of a tissue that touch only along an edge (default: one of\n"
      << "                           the two background voxels at that edge joins them, so that the boundary can\n"
      << "                           be a manifold there)\n"
      << "  --iso VALUE              treat INPUT as a gray image: mesh where the linearly interpolated value is\n"
      << "                           >= VALUE, as label 1 (cannot be combined with --labels or --merge-labels)\n"
      << "  --max-vertices N         fail beyond N vertices (default: "
      << delaunay_refinement::RefinementParameters{}.maximumNumberOfVertices << ")\n"
      << "  --report FILE.json       also write the quality report as JSON\n"
      << "  --quiet                  print nothing but errors (no progress, no report table)\n"
      << "  --version                print the version and exit\n"
      << "  --help                   print this help and exit\n"
      << "\n"
      << "Progress goes to stderr, the quality report table to stdout. Exit status: 0 on success, 2 on bad\n"
      << "arguments, unreadable or unwritable files and meshing failures, with a one-line error on stderr.\n"
      << "\n"
      << "Example: " << ProgramName << " brain.nii.gz brain.vtu --delta 4 --report brain-report.json\n";
}

void
PrintVersion(std::ostream & out)
{
  out << ProgramName << ' ' << DelaunayImageToMesh_PROGRAM_VERSION << " (ITK " << itk::Version::GetITKVersion()
      << ")\n";
}

// ---------------------------------------------------------------------------------------------------------------
// Arguments.

double
ParseNumber(const std::string & option, const std::string & text)
{
  char *       end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(value))
  {
    throw UserError(option + " needs a number, got '" + text + "'");
  }
  return value;
}

/** A number for `option` for which `isValid` holds; `validity` says which numbers those are. */
template <typename TPredicate>
double
ParseNumberWhere(const std::string & option, const std::string & text, TPredicate isValid, const std::string & validity)
{
  const double value = ParseNumber(option, text);
  if (!isValid(value))
  {
    throw UserError(option + " must be " + validity + ", got '" + text + "'");
  }
  return value;
}

std::size_t
ParseVertexLimit(const std::string & option, const std::string & text)
{
  // The core needs room for the 8 corners of its bounding box.
  constexpr std::size_t smallest = 8;
  const std::regex      digits("[0-9]{1,18}");
  if (!std::regex_match(text, digits) || std::stoull(text) < smallest)
  {
    throw UserError(option + " must be a whole number >= " + std::to_string(smallest) + ", got '" + text + "'");
  }
  return static_cast<std::size_t>(std::stoull(text));
}

std::vector<Label>
ParseLabels(const std::string & option, const std::string & text)
{
  if (text == "all")
  {
    return {};
  }
  const std::regex labelList("-?[0-9]{1,9}(,-?[0-9]{1,9})*");
  if (!std::regex_match(text, labelList))
  {
    throw UserError(option + " needs 'all' or comma-separated integer labels such as 1,2, got '" + text + "'");
  }
  std::vector<Label> labels;
  std::istringstream list(text);
  for (std::string item; std::getline(list, item, ',');)
  {
    labels.push_back(static_cast<Label>(std::stol(item)));
  }
  if (std::count(labels.begin(), labels.end(), delaunay_refinement::BackgroundLabel) > 0)
  {
    throw UserError(option + " cannot select label 0, the background, got '" + text + "'");
  }
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  return labels;
}

/** The value of the option at `arguments[index]`: after '=' in the same argument, or the next argument. */
class OptionValue
{
public:
  OptionValue(const std::vector<std::string> & arguments, std::size_t & index, std::optional<std::string> inlineValue)
    : m_Arguments(arguments)
    , m_Index(index)
    , m_InlineValue(std::move(inlineValue))
  {}

  std::string
  Take(const std::string & option, const std::string & placeholder)
  {
    if (m_InlineValue)
    {
      return *m_InlineValue;
    }
    if (m_Index + 1 >= m_Arguments.size())
    {
      throw UserError("option " + option + " needs a value (" + option + " " + placeholder + ")");
    }
    return m_Arguments[++m_Index];
  }

  void
  RequireNone(const std::string & option) const
  {
    if (m_InlineValue)
    {
      throw UserError("option " + option + " takes no value, got '" + *m_InlineValue + "'");
    }
  }

private:
  const std::vector<std::string> & m_Arguments;
  std::size_t &                    m_Index;
  std::optional<std::string>       m_InlineValue;
};

/** Applies --quiet, --help or --version; false if `option` is none of them. */
bool
ApplyFlag(const std::string & option, const OptionValue & value, Options & options)
{
  if (option == "--quiet")
  {
    options.quiet = true;
  }
  else if (option == "--merge-labels")
  {
    options.mergeLabels = true;
  }
  else if (option == "--keep-diagonal-voxels")
  {
    options.joinDiagonalVoxels = false;
  }
  else if (option == "--help")
  {
    options.action = Options::Action::PrintHelp;
  }
  else if (option == "--version")
  {
    options.action = Options::Action::PrintVersion;
  }
  else
  {
    return false;
  }
  value.RequireNone(option);
  return true;
}

/** The valid ranges are the refinement core's (ValidateParameters); they are checked here as well so that the
 * message names the option, and before the image is read. */
void
ApplyOption(const std::string & option, OptionValue & value, Options & options)
{
  if (ApplyFlag(option, value, options))
  {
    return;
  }
  if (option == "--delta")
  {
    options.surfaceSamplingDistance = ParseNumberWhere(
      option, value.Take(option, "MM"), [](double delta) { return delta > 0.0; }, "a distance > 0 in mm");
  }
  else if (option == "--radius-edge")
  {
    options.radiusEdgeBound = ParseNumberWhere(
      option, value.Take(option, "R"), [](double rho) { return rho >= 1.0; }, ">= 1");
  }
  else if (option == "--min-dihedral")
  {
    options.minimumDihedralAngle = ParseNumberWhere(
      option,
      value.Take(option, "DEG"),
      [](double sigma) { return sigma >= 0.0 && sigma <= 30.0; },
      "in [0, 30] degrees");
  }
  else if (option == "--labels")
  {
    options.labels = ParseLabels(option, value.Take(option, "all|L1,L2,..."));
  }
  else if (option == "--iso")
  {
    options.isoValue = ParseNumber(option, value.Take(option, "VALUE"));
  }
  else if (option == "--max-vertices")
  {
    options.maximumNumberOfVertices = ParseVertexLimit(option, value.Take(option, "N"));
  }
  else if (option == "--report")
  {
    options.reportPath = value.Take(option, "FILE.json");
  }
  else
  {
    throw UserError("unknown option '" + option + "' (see --help)");
  }
}

void
CheckPositionalArguments(const std::vector<std::string> & positional, Options & options)
{
  if (positional.size() > 2)
  {
    throw UserError("unexpected argument '" + positional[2] + "': give exactly INPUT and OUTPUT (see --help)");
  }
  if (positional.size() < 2)
  {
    throw UserError(std::string(positional.empty() ? "missing INPUT and OUTPUT" : "missing OUTPUT") +
                    " (usage: " + ProgramName + " INPUT OUTPUT [options])");
  }
  options.inputPath = positional[0];
  options.outputPath = positional[1];
}

Options
ParseArguments(const std::vector<std::string> & arguments)
{
  Options                  options;
  std::vector<std::string> positional;
  bool                     labelsGiven = false;
  for (std::size_t index = 0; index < arguments.size(); ++index)
  {
    const std::string & argument = arguments[index];
    if (argument.size() < 2 || argument[0] != '-')
    {
      positional.push_back(argument);
      continue;
    }
    const std::size_t          equals = argument.find('=');
    const std::string          option = argument.substr(0, equals);
    std::optional<std::string> inlineValue;
    if (equals != std::string::npos)
    {
      inlineValue = argument.substr(equals + 1);
    }
    OptionValue value(arguments, index, inlineValue);
    ApplyOption(option, value, options);
    labelsGiven = labelsGiven || option == "--labels" || option == "--merge-labels";
  }
  if (options.action != Options::Action::Mesh)
  {
    return options;
  }
  if (labelsGiven && options.isoValue)
  {
    throw UserError("--iso cannot be combined with --labels or --merge-labels: --iso meshes a gray image as the "
                    "single label 1");
  }
  CheckPositionalArguments(positional, options);
  return options;
}

// ---------------------------------------------------------------------------------------------------------------
// Files.

std::string
LowerCaseExtension(const std::string & path)
{
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char character) {
    return static_cast<char>(std::tolower(character));
  });
  return extension;
}

void
CheckDirectoryOf(const std::string & path, const std::string & what)
{
  const std::filesystem::path directory = std::filesystem::path(path).parent_path();
  std::error_code             error;
  if (!directory.empty() && !std::filesystem::is_directory(directory, error))
  {
    throw UserError("cannot write " + what + " '" + path + "': directory '" + directory.string() + "' does not exist");
  }
}

/** Checked before reading and meshing, which may take minutes, rather than when writing. */
void
CheckOutputPaths(const Options & options)
{
  const std::vector<std::string> supported = delaunay_refinement::SupportedMeshFileExtensions();
  const std::string              extension = LowerCaseExtension(options.outputPath);
  if (std::find(supported.begin(), supported.end(), extension) == supported.end())
  {
    std::string list;
    for (const std::string & candidate : supported)
    {
      list += (list.empty() ? "" : ", ") + candidate;
    }
    throw UserError("cannot write '" + options.outputPath + "': unsupported output extension '" + extension +
                    "' (supported: " + list + ")");
  }
  CheckDirectoryOf(options.outputPath, "the mesh");
  if (!options.reportPath.empty())
  {
    CheckDirectoryOf(options.reportPath, "the report");
  }
}

/** ITK's descriptions may span lines and start with "ITK ERROR: ClassName(0x...): "; the user needs one line,
 * the message. */
std::string
OneLine(const std::string & description)
{
  static const std::regex objectPrefix("^\\s*(ITK ERROR:|itk::ERROR:)?\\s*[A-Za-z_:]+\\(0x[0-9a-fA-F]+\\):\\s*");
  static const std::regex whitespace("\\s+");
  const std::string message = std::regex_replace(std::regex_replace(description, objectPrefix, ""), whitespace, " ");
  const std::size_t end = message.find_last_not_of(' ');
  return end == std::string::npos ? message : message.substr(0, end + 1);
}

void
CheckThreeDimensional(const std::string & path, const itk::ImageIOBase & io)
{
  unsigned int dimensions = io.GetNumberOfDimensions();
  // A 4-D file with a single time point (common for NIfTI) is still a 3-D image.
  while (dimensions > 3 && io.GetDimensions(dimensions - 1) == 1)
  {
    --dimensions;
  }
  if (dimensions != 3)
  {
    throw UserError("cannot mesh input '" + path + "': it is a " + std::to_string(io.GetNumberOfDimensions()) +
                    "-D image, a 3-D image is needed");
  }
}

void
CheckReadableFile(const std::string & path)
{
  std::FILE * file = std::fopen(path.c_str(), "rb");
  if (file == nullptr)
  {
    throw UserError("cannot read input '" + path + "': " + std::strerror(errno));
  }
  std::fclose(file);
}

template <typename TImage>
typename TImage::Pointer
ReadImageFile(const std::string & path)
{
  CheckReadableFile(path);
  const itk::ImageIOBase::Pointer io = itk::ImageIOFactory::CreateImageIO(path.c_str(), itk::IOFileModeEnum::ReadMode);
  if (io.IsNull())
  {
    throw UserError("cannot read input '" + path +
                    "': not an image format ITK can read here (NIfTI, NRRD, MetaImage, DICOM)");
  }
  auto reader = itk::ImageFileReader<TImage>::New();
  reader->SetFileName(path);
  reader->SetImageIO(io);
  try
  {
    io->SetFileName(path);
    io->ReadImageInformation();
    CheckThreeDimensional(path, *io);
    reader->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    throw UserError("cannot read input '" + path + "': " + OneLine(error.GetDescription()));
  }
  return reader->GetOutput();
}

template <typename TImage>
typename TImage::Pointer
ReadDicomSeries(const std::string & directory, std::ostream * notes)
{
  auto seriesFiles = itk::GDCMSeriesFileNames::New();
  seriesFiles->SetUseSeriesDetails(true);
  // It warns in several lines when it finds no series; this program says so in one.
  const bool showWarnings = itk::Object::GetGlobalWarningDisplay();
  itk::Object::GlobalWarningDisplayOff();
  seriesFiles->SetDirectory(directory);
  const std::vector<std::string> seriesIdentifiers = seriesFiles->GetSeriesUIDs();
  itk::Object::SetGlobalWarningDisplay(showWarnings);
  if (seriesIdentifiers.empty())
  {
    throw UserError("cannot read input '" + directory + "': the directory holds no DICOM series");
  }
  if (seriesIdentifiers.size() > 1 && notes != nullptr)
  {
    *notes << ProgramName << ": note: '" << directory << "' holds " << seriesIdentifiers.size()
           << " DICOM series; reading the first, " << seriesIdentifiers.front() << '\n';
  }
  auto reader = itk::ImageSeriesReader<TImage>::New();
  reader->SetImageIO(itk::GDCMImageIO::New());
  reader->SetFileNames(seriesFiles->GetFileNames(seriesIdentifiers.front()));
  try
  {
    reader->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    throw UserError("cannot read the DICOM series in '" + directory + "': " + OneLine(error.GetDescription()));
  }
  return reader->GetOutput();
}

template <typename TImage>
typename TImage::Pointer
ReadImage(const std::string & path, std::ostream * notes)
{
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
  {
    return ReadDicomSeries<TImage>(path, notes);
  }
  return ReadImageFile<TImage>(path);
}

// ---------------------------------------------------------------------------------------------------------------
// Meshing.

/** Shows a process's progress on stderr while it lives: a bar redrawn in place on a terminal, a line every 10%
 * otherwise (logs and pipes should not fill with carriage returns). */
class ProgressDisplay
{
public:
  ProgressDisplay(itk::ProcessObject * process, bool onTerminal)
    : m_Process(process)
    , m_OnTerminal(onTerminal)
  {
    m_Observer =
      process->AddObserver(itk::ProgressEvent(), [this](const itk::EventObject &) { Show(m_Process->GetProgress()); });
  }

  ~ProgressDisplay()
  {
    m_Process->RemoveObserver(m_Observer);
    if (m_OnTerminal && m_ShownPercent >= 0)
    {
      std::cerr << std::endl;
    }
  }

  ProgressDisplay(const ProgressDisplay &) = delete;
  ProgressDisplay &
  operator=(const ProgressDisplay &) = delete;

private:
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
      std::cerr << "\rmeshing [" << std::string(filled, '#') << std::string(width - filled, ' ') << "] " << percent
                << '%' << std::flush;
    }
    else
    {
      std::cerr << "progress: " << percent << '%' << std::endl;
    }
  }

  itk::ProcessObject * m_Process;
  bool                 m_OnTerminal;
  unsigned long        m_Observer{ 0 };
  int                  m_ShownPercent{ -1 };
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
  filter->SetJoinDiagonalVoxels(options.joinDiagonalVoxels);
  if (options.isoValue)
  {
    filter->SetIsoValue(*options.isoValue);
  }
  else
  {
    filter->SetLabels(options.labels);
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
    std::cerr << "joined voxels that touched only along an edge: " << filter->GetNumberOfJoiningVoxels()
              << " background voxels took a tissue's label (--keep-diagonal-voxels keeps them apart)\n";
  }
  const delaunay_refinement::TetrahedralMesh & mesh = filter->GetRefinedMesh();
  phaseSeconds.emplace_back("mesh", meshTime.Seconds());

  // The report's distances cost about as much as writing; skip them when nobody will see the report.
  const bool                         wantReport = !options.quiet || !options.reportPath.empty();
  delaunay_refinement::QualityReport report;
  if (wantReport)
  {
    const Stopwatch reportTime;
    // The reference is what the filter meshed: the voxels after label selection, merging or the iso-value, with
    // the joining voxels.
    report = delaunay_refinement::ComputeQualityReport(mesh, itk::MakeLabelVolume(filter->GetObjectLabelImage()));
    phaseSeconds.emplace_back("report", reportTime.Seconds());
  }

  const Stopwatch writeTime;
  WriteMesh(mesh, options.outputPath);
  phaseSeconds.emplace_back("write", writeTime.Seconds());
  if (!wantReport)
  {
    return EXIT_SUCCESS;
  }

  report.run = { options.inputPath,
                 options.outputPath,
                 filter->GetEffectiveSurfaceSamplingDistance(),
                 options.radiusEdgeBound,
                 options.minimumDihedralAngle,
                 phaseSeconds,
                 delaunay_refinement::PeakResidentMemoryBytes() };
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
Run(const std::vector<std::string> & arguments)
{
  const Options options = ParseArguments(arguments);
  switch (options.action)
  {
    case Options::Action::PrintHelp:
      PrintHelp(std::cout);
      return EXIT_SUCCESS;
    case Options::Action::PrintVersion:
      PrintVersion(std::cout);
      return EXIT_SUCCESS;
    case Options::Action::Mesh:
      break;
  }
  CheckOutputPaths(options);
  return options.isoValue ? MeshImage<GrayImageType>(options) : MeshImage<LabelImageType>(options);
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
  try
  {
    return Run(std::vector<std::string>(argv + 1, argv + argc));
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
