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
#ifndef DelaunayImageToMeshRandomizedChecks_h
#define DelaunayImageToMeshRandomizedChecks_h

// What the randomized GoogleTest and the libFuzzer target (fuzz/) share: running the filter on an arbitrary
// image with arbitrary parameters, sorting its outcome into "a mesh" or one of the documented exceptions, and
// every guarantee of docs/algorithm.md checked on the mesh the filter returned (with the measures of
// DelaunayRefinementMeshQuality.h, on the mesh converted as the filter's tests convert it). No GoogleTest here:
// the fuzzer aborts on a violation instead of failing a test.

#include "itkDelaunayImageToMeshFilter.h"
#include "itkDelaunayImageToMeshFilterTestHelpers.h"
#include "DelaunayImageToMeshRandomizedSegmentation.h"
#include "DelaunayRefinementGeometry.h"
#include "DelaunayRefinementBoundaryVertexChecks.h"
#include "DelaunayRefinementLocalSizingChecks.h"
#include "DelaunayRefinementManifoldChecks.h"
#include "DelaunayRefinementMeshQuality.h"
#include "DelaunayRefinementVoxelPinches.h"
#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkImageRegionIteratorWithIndex.h"

#include "itkLinearInterpolateImageFunction.h"
#include "itkNearestNeighborInterpolateImageFunction.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace itk
{
namespace delaunay_image_to_mesh_randomized
{

namespace dr = delaunay_refinement;
using dr::operator+;
using dr::operator-;
using dr::operator*;

/** The filter tests' double-precision output mesh: floats would blur the measured guarantees. */
using MeshType = delaunay_image_to_mesh_test::MeshType;

constexpr double Pi = 3.14159265358979323846;

/** A fixed, portable stream of random numbers: std::mt19937_64's output is standardized, the standard
 * distributions are not, so every draw is made here from its raw bits. */
class CaseRandom
{
public:
  explicit CaseRandom(uint64_t seed)
    : m_Engine(seed)
  {}

  /** Uniform in [low, high). */
  double
  Uniform(double low, double high)
  {
    return low + (high - low) * static_cast<double>(m_Engine() >> 11) * 0x1.0p-53;
  }

  double
  LogUniform(double low, double high)
  {
    return std::exp(Uniform(std::log(low), std::log(high)));
  }

  /** Uniform in [low, high], both included. */
  int
  Integer(int low, int high)
  {
    return low + static_cast<int>(m_Engine() % static_cast<uint64_t>(high - low + 1));
  }

  bool
  Chance(double probability)
  {
    return Uniform(0.0, 1.0) < probability;
  }

  template <typename T>
  const T &
  Pick(const std::vector<T> & values)
  {
    return values[static_cast<std::size_t>(Integer(0, static_cast<int>(values.size()) - 1))];
  }

  /** A uniformly distributed rotation, from a normalized Gaussian quaternion (Box-Muller on our own draws). */
  std::array<std::array<double, 3>, 3>
  Rotation()
  {
    std::array<double, 4> q{};
    double                norm = 0.0;
    for (double & component : q)
    {
      component = std::sqrt(-2.0 * std::log(1.0 - Uniform(0.0, 1.0))) * std::cos(2.0 * Pi * Uniform(0.0, 1.0));
      norm += component * component;
    }
    norm = std::sqrt(norm);
    const double w = q[0] / norm, x = q[1] / norm, y = q[2] / norm, z = q[3] / norm;
    return { { { { 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y) } },
               { { 2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x) } },
               { { 2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y) } } } };
  }

private:
  std::mt19937_64 m_Engine;
};

/** An image in the given physical space, voxel `i` (x fastest) set to pixelOf(i): the randomized cases and the
 * fuzzer's inputs describe their images the same way. */
template <typename TImage, typename TPixelOf>
typename TImage::Pointer
MakeImageInSpace(const std::array<SizeValueType, 3> & size, const std::array<IndexValueType, 3> & start,
                 const std::array<double, 3> & spacing, const std::array<double, 3> & origin,
                 const std::array<std::array<double, 3>, 3> & direction, TPixelOf && pixelOf)
{
  auto                           image = TImage::New();
  typename TImage::SizeType      itkSize;
  typename TImage::IndexType     itkStart;
  typename TImage::SpacingType   itkSpacing;
  typename TImage::PointType     itkOrigin;
  typename TImage::DirectionType itkDirection;
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    itkSize[axis] = size[axis];
    itkStart[axis] = start[axis];
    itkSpacing[axis] = spacing[axis];
    itkOrigin[axis] = origin[axis];
    for (unsigned int column = 0; column < 3; ++column)
    {
      itkDirection[axis][column] = direction[axis][column];
    }
  }
  image->SetRegions(typename TImage::RegionType(itkStart, itkSize));
  image->SetSpacing(itkSpacing);
  image->SetOrigin(itkOrigin);
  image->SetDirection(itkDirection);
  image->Allocate();
  std::size_t voxel = 0;
  for (ImageRegionIteratorWithIndex<TImage> it(image, image->GetBufferedRegion()); !it.IsAtEnd(); ++it)
  {
    it.Set(pixelOf(voxel++));
  }
  return image;
}

/** Only rounding may eat into a bound that the theory gives exactly. */
constexpr double RoundingSlack = 1e-9;

/** How one run of the filter ended. Every value but Unexpected is documented behaviour. */
enum class Outcome
{
  Mesh,
  NoObjectVoxel,
  RegularizedAway,
  NoTetrahedron,
  VertexLimit,
  SliverRemovalWithoutEnd,
  InvalidParameter,
  Aborted,
  Unexpected
};

inline const char *
OutcomeName(Outcome outcome)
{
  switch (outcome)
  {
    case Outcome::Mesh:
      return "mesh";
    case Outcome::NoObjectVoxel:
      return "exception: no voxel selected";
    case Outcome::RegularizedAway:
      return "exception: every part thinner than the regularisation scale";
    case Outcome::NoTetrahedron:
      return "exception: no tetrahedron (object too small for delta)";
    case Outcome::VertexLimit:
      return "exception: MaximumNumberOfVertices reached";
    case Outcome::SliverRemovalWithoutEnd:
      return "exception: sliver removal did not end";
    case Outcome::InvalidParameter:
      return "exception: invalid parameter";
    case Outcome::Aborted:
      return "aborted (ProcessAborted)";
    case Outcome::Unexpected:
      return "UNEXPECTED";
  }
  return "UNEXPECTED";
}

/** The documented exception messages of itk::DelaunayImageToMeshFilter, as the substrings every one of them
 * must contain. A description that matches none of them is an undocumented failure. */
inline Outcome
ClassifyExceptionDescription(const std::string & description)
{
  const auto contains = [&description](const char * text) { return description.find(text) != std::string::npos; };
  if (contains("No voxel of the input is part of the object"))
  {
    return Outcome::NoObjectVoxel;
  }
  if (contains("Every part of the object is thinner than the regularisation scale") &&
      contains("SurfaceSamplingDistance (delta)"))
  {
    return Outcome::RegularizedAway;
  }
  if (contains("The refinement produced no tetrahedron") && contains("too small for SurfaceSamplingDistance"))
  {
    return Outcome::NoTetrahedron;
  }
  // The core's message names its own parameter; the filter must add the name a user of the filter set.
  if (contains("reached maximumNumberOfVertices") && contains("MaximumNumberOfVertices = "))
  {
    return Outcome::VertexLimit;
  }
  if (contains("Sliver removal did not end") && contains("MinimumDihedralAngle = ") && contains("RadiusEdgeBound = "))
  {
    return Outcome::SliverRemovalWithoutEnd;
  }
  if (contains("Invalid SurfaceSamplingDistance") || contains("Invalid parameter "))
  {
    return Outcome::InvalidParameter;
  }
  return Outcome::Unexpected;
}

/** How long one run may take before the suite takes it for a hang: more than ten times the slowest case of the
 * default windows (4.4 s) in a release build. Instrumented builds (scripts/test-sanitizers.sh) run the filter 5 to 10
 * times slower, so they get five times as long: Blobs 1000030 at ρ = 1, σ = 0 (RandomizedRegression) takes 9 s in a
 * release build and ran past 60 s under AddressSanitizer. */
#if defined(__SANITIZE_ADDRESS__)
constexpr double RunTimeLimitSeconds = 300.0;
#else
constexpr double RunTimeLimitSeconds = 60.0;
#endif

/** Everything a run sets on the filter. An empty `labels` means every non-zero label. */
struct FilterSettings
{
  double surfaceSamplingDistance{ 0.0 };
  double radiusEdgeBound{ 2.0 };
  double minimumDihedralAngle{ dr::RefinementParameters{}.minimumDihedralAngle };
  /** The safety cap: far above what any of the suite's images needs at its δ (its largest meshes have 30,000
   * vertices), so that reaching it is a runaway refinement (10,000 stopped five legitimate meshes). */
  SizeValueType          maximumNumberOfVertices{ 100000 };
  std::vector<dr::Label> labels;
  bool                   mergeLabels{ false };
  std::optional<double>  isoValue;
  /** Local halvings of δ where a boundary comes out non-manifold (the filter's default is 3). */
  unsigned int manifoldRefinementLevels{ dr::RefinementParameters{}.manifoldRefinementLevels };
  /** The filter's default unless a case turns it off. */
  double regularizationScale{ DelaunayImageToMeshFilter<Image<uint8_t, 3>, MeshType>::DefaultRegularizationScale };
  unsigned int topologyRegularizationRounds{ dr::RefinementParameters{}.topologyRegularizationRounds };
  bool         relabelNonManifoldPlaces{ dr::RefinementParameters{}.relabelNonManifoldPlaces };
  bool         refineThickParts{ dr::RefinementParameters{}.refineThickParts };
  /** The filter's default: voxels of a tissue touching only along an edge are joined (nearest-neighbour labels). */
  bool joinDiagonalVoxels{ true };
  /** Wall-clock budget of one run; the run is aborted through AbortGenerateData when it is exceeded. */
  double timeLimitSeconds{ RunTimeLimitSeconds };
};

/** Whether `settings` are where the sliver removal may be stopped by its budget (SliverRemovalWithoutEnd) as
 * documented: σ > 0 with ρ < 2, where the randomized suite found R4 and R4′ making work for each other without end.
 * With ρ >= 2 nothing proves that it ends either, but no run was seen not to: there the exception is a finding. */
inline bool
SliverRemovalMayNotEnd(const FilterSettings & settings)
{
  return settings.minimumDihedralAngle > 0.0 && settings.radiusEdgeBound < 2.0;
}

/** Whether a vertex-cap exception's `message` says that the sliver removal reached the cap: the refiner adds that
 * when the cap stops a pass after its first sliver, every vertex since being the sliver removal's. */
inline bool
IsReachedBySliverRemoval(const std::string & message)
{
  return message.find("the limit was reached by the sliver removal") != std::string::npos;
}

/** The vertex counts in an exception that stops the sliver removal ("it took the mesh from N0 vertices, where every
 * other rule was met, to N", as both the budget's and the vertex cap's messages say it): N0 and N, or nothing when
 * the message does not say it. */
inline std::optional<std::pair<unsigned long, unsigned long>>
SliverRemovalGrowthIn(const std::string & message)
{
  const std::string fromText = "it took the mesh from ";
  const std::string toText = " vertices, where every other rule was met, to ";
  const std::size_t from = message.find(fromText);
  const std::size_t to = message.find(toText, from);
  if (from == std::string::npos || to == std::string::npos)
  {
    return std::nullopt;
  }
  return std::make_pair(std::stoul(message.substr(from + fromText.size())),
                        std::stoul(message.substr(to + toText.size())));
}

/** Whether the case runs issue #14's topology defaults: the regularisation at its default scale, the relabelling,
 * the topology rounds, the joining of diagonal voxels, and no opt-in halving of δ, on a label image or an
 * iso-surface (whose voxels' sides are regularised too, and carried into the values it interpolates). */
inline bool
HasTheTopologyDefaults(const FilterSettings & settings)
{
  const FilterSettings defaults;
  return settings.regularizationScale == defaults.regularizationScale &&
         settings.relabelNonManifoldPlaces == defaults.relabelNonManifoldPlaces &&
         settings.refineThickParts == defaults.refineThickParts &&
         settings.topologyRegularizationRounds == defaults.topologyRegularizationRounds &&
         settings.manifoldRefinementLevels == defaults.manifoldRefinementLevels &&
         settings.joinDiagonalVoxels == defaults.joinDiagonalVoxels;
}

/** Whether every boundary of the mesh must be a closed manifold (issue #14's bar): the topology defaults, ρ's
 * default and σ's default or 0 (the paper's method), and δ at least the largest voxel spacing, where the bar starts.
 * Elsewhere the filter may leave places it could not mend (the randomized windows find them with δ below a voxel, or
 * with ρ = 1, or σ above its default), and must report them (CheckManifoldBoundaries). */
inline bool
IsPromisedManifold(const FilterSettings & settings, double delta, double largestSpacing)
{
  const FilterSettings defaults;
  return HasTheTopologyDefaults(settings) && settings.radiusEdgeBound == defaults.radiusEdgeBound &&
         (settings.minimumDihedralAngle == defaults.minimumDihedralAngle || settings.minimumDihedralAngle == 0.0) &&
         delta >= largestSpacing;
}

inline std::string
Describe(const FilterSettings & settings)
{
  std::ostringstream text;
  text.precision(17);
  text << "delta " << settings.surfaceSamplingDistance << ", rho " << settings.radiusEdgeBound << ", sigma "
       << settings.minimumDihedralAngle << ", MaximumNumberOfVertices " << settings.maximumNumberOfVertices;
  if (!settings.labels.empty())
  {
    text << ", labels";
    for (const dr::Label label : settings.labels)
    {
      text << ' ' << label;
    }
  }
  if (settings.mergeLabels)
  {
    text << ", merged";
  }
  if (settings.isoValue)
  {
    text << ", iso-value " << *settings.isoValue;
  }
  text << ", manifold refinement levels " << settings.manifoldRefinementLevels;
  if (!settings.joinDiagonalVoxels)
  {
    text << ", diagonal voxels kept";
  }
  return text.str();
}

/** The regularisation scale, and the other topology settings where they are not the filter's defaults, for a person
 * reproducing a case: not part of Describe(), whose text the recorded cases' fingerprints hash. */
inline std::string
DescribeTopologySettings(const FilterSettings & settings)
{
  std::ostringstream text;
  text << "regularisation scale " << settings.regularizationScale;
  if (settings.topologyRegularizationRounds != dr::RefinementParameters{}.topologyRegularizationRounds)
  {
    text << ", topology rounds " << settings.topologyRegularizationRounds;
  }
  if (!settings.relabelNonManifoldPlaces)
  {
    text << ", no relabelling";
  }
  if (!settings.refineThickParts)
  {
    text << ", no thick-part refinement";
  }
  return text.str();
}

/** What one run produced. */
struct RunResult
{
  Outcome                  outcome{ Outcome::Unexpected };
  std::string              message;
  std::vector<std::string> violations;
  std::size_t              tetrahedra{ 0 };
  std::size_t              points{ 0 };
  double                   seconds{ 0.0 };
  bool                     timedOut{ false };
  /** Of a mesh: the smallest volume in floating point (<= 0 for a sliver flat to rounding) and dihedral angle. */
  double smallestVolume{ 0.0 };
  /** Tetrahedra flat to rounding by issue #15's measure (CountFlatTetrahedra); any is a violation. */
  std::size_t flatTetrahedra{ 0 };
  double      smallestDihedralAngle{ 0.0 };
  /** What the refinement did, for a report. */
  std::string refinement;
  /** Components of the segmentation the filter meshed (GetObjectLabelImage(), the regularised labels) that hold a
   * ball of ThickComponentRadius() (diameter δ), counted from the voxels; the first of them described. Filled for
   * a mesh and for "no tetrahedron". */
  std::size_t thickComponents{ 0 };
  /** Components of any size without a tetrahedron, counted here from the voxels and the mesh (of a mesh only). */
  std::size_t unmeshedComponents{ 0 };
  std::string firstThickComponent;
  /** Of a mesh from nearest-neighbour labels: the largest distance, in units of δ, from the mesh's boundary to the
   * voxels' surface, and from the surface of the thick components to the mesh's boundary (-1: not measured). */
  double meshToSegmentation{ -1.0 };
  double segmentationToMesh{ -1.0 };
  /** Of a mesh with ρ >= 2: boundary triangle corners that are not feature vertices (Lemma 5 says none with σ = 0 and
   * a uniform δ), and R4′'s splits at a point failing its acceptance test. */
  std::size_t nonFeatureBoundaryCorners{ 0 };
  std::size_t sliverSplitsFailingAcceptance{ 0 };
  /** Of a mesh: the boundaries (each tissue's and the union's) that are not a closed manifold, counted from the mesh
   * (CountNonManifoldPlaces), and the non-manifold vertices the filter says it left. */
  std::size_t nonManifoldBoundaries{ 0 };
  std::size_t admittedNonManifoldVertices{ 0 };
  /** Whether every boundary had to be a closed manifold (IsPromisedManifold). */
  bool promisedManifold{ false };
  /** The topology regularisation's rounds, and whether they stopped at their budget of insertions. */
  std::size_t regularizationRounds{ 0 };
  bool        regularizationBudgetReached{ false };
};

inline std::string
DescribeRefinement(const dr::RefinementStatistics & statistics)
{
  std::ostringstream text;
  text << statistics.triangulationVertices << " triangulation vertices; R1 " << statistics.insertionsR1 << ", R2 "
       << statistics.insertionsR2 << ", R3 " << statistics.insertionsR3 << ", R4 " << statistics.insertionsR4
       << ", R4' " << statistics.insertionsR4Dihedral << " (" << statistics.sliverSplitsFailingAcceptance
       << " failing its acceptance test; " << statistics.sliverPerturbations << " moves), E1-E3 "
       << statistics.insertionsE1 + statistics.insertionsE2 + statistics.insertionsE3 << ", deleted "
       << statistics.deletedVertices << "; manifold refinement: " << statistics.manifoldRefinementRounds << " rounds, "
       << statistics.manifoldRefinementZones << " zones, " << statistics.remainingNonManifoldVertices
       << " non-manifold vertices left";
  return text.str();
}

/** The label the filter meshes a voxel of value `value` with (settings): 1 at or above the iso-value; else the
 * voxel's label when selected (every non-zero label when none is), 1 for every selected label when they are merged;
 * the background otherwise. */
inline dr::Label
ObjectLabelOf(double value, const FilterSettings & settings)
{
  if (settings.isoValue)
  {
    return value >= *settings.isoValue ? 1 : dr::BackgroundLabel;
  }
  const auto label = static_cast<dr::Label>(std::lround(value));
  const bool selected = settings.labels.empty() ||
                        std::find(settings.labels.begin(), settings.labels.end(), label) != settings.labels.end();
  if (label == dr::BackgroundLabel || !selected)
  {
    return dr::BackgroundLabel;
  }
  return settings.mergeLabels ? 1 : label;
}

/** The labels the filter may give a tetrahedron: the labels of the image's voxels as the oracle maps them
 * (rounded, kept when selected; 1 at or above the iso-value). */
template <typename TImage>
std::set<dr::Label>
TissueLabelsOf(const TImage & image, const FilterSettings & settings)
{
  std::set<dr::Label> labels;
  for (ImageRegionConstIteratorWithIndex<TImage> it(&image, image.GetBufferedRegion()); !it.IsAtEnd(); ++it)
  {
    const dr::Label label = ObjectLabelOf(static_cast<double>(it.Get()), settings);
    if (label != dr::BackgroundLabel)
    {
      labels.insert(label);
    }
  }
  return labels;
}

inline std::string
DescribeLabels(const std::set<dr::Label> & labels)
{
  std::ostringstream text;
  text << '{';
  for (const dr::Label label : labels)
  {
    text << ' ' << label;
  }
  text << " }";
  return text.str();
}

/** Collects violations as readable sentences, at most a few of each kind. */
class ViolationList
{
public:
  template <typename... TParts>
  void
  Add(const TParts &... parts)
  {
    std::ostringstream text;
    text.precision(17);
    (text << ... << parts);
    m_Violations.push_back(text.str());
  }

  std::vector<std::string>
  Take()
  {
    return std::move(m_Violations);
  }

private:
  std::vector<std::string> m_Violations;
};

inline double
CircumradiusOf(const std::array<dr::Vector3, 4> & corners, dr::Vector3 & center)
{
  // Solve 2 (p_i - p_0) . c' = |p_i - p_0|^2 for c' = center - p_0 by Cramer's rule.
  const dr::Vector3 a = corners[1] - corners[0];
  const dr::Vector3 b = corners[2] - corners[0];
  const dr::Vector3 c = corners[3] - corners[0];
  const double      denominator = 2.0 * dr::Dot(a, dr::Cross(b, c));
  const dr::Vector3 offset =
    (1.0 / denominator) * (dr::SquaredNorm(a) * dr::Cross(b, c) + dr::SquaredNorm(b) * dr::Cross(c, a) +
                           dr::SquaredNorm(c) * dr::Cross(a, b));
  center = corners[0] + offset;
  return dr::Norm(offset);
}

inline std::array<dr::Vector3, 4>
CornersOf(const dr::TetrahedralMesh & mesh, std::size_t tetrahedron)
{
  const auto & indices = mesh.tetrahedra[tetrahedron];
  return { mesh.points[indices[0]], mesh.points[indices[1]], mesh.points[indices[2]], mesh.points[indices[3]] };
}

/** A tetrahedron's corners (kinds and positions) and label, to reproduce a violation by hand. */
inline std::string
DescribeTetrahedron(const dr::TetrahedralMesh & mesh, std::size_t tetrahedron)
{
  std::ostringstream text;
  text.precision(17);
  text << "tetrahedron " << tetrahedron << " (label " << mesh.tetrahedronLabels[tetrahedron] << "):";
  for (const uint32_t corner : mesh.tetrahedra[tetrahedron])
  {
    const dr::Vector3 & point = mesh.points[corner];
    text << " " << dr::VertexKindName(mesh.pointKinds[corner]) << " (" << point[0] << ", " << point[1] << ", "
         << point[2] << ")";
  }
  return text.str();
}

/** The tetrahedron with the largest circumradius / shortest edge, recomputed here to name it. */
inline std::size_t
WorstRadiusEdgeTetrahedron(const dr::TetrahedralMesh & mesh)
{
  std::size_t worst = 0;
  double      worstRatio = -1.0;
  for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
  {
    const std::array<dr::Vector3, 4> corners = CornersOf(mesh, t);
    dr::Vector3                      center;
    double                           shortest = std::numeric_limits<double>::infinity();
    for (int first = 0; first < 4; ++first)
    {
      for (int second = first + 1; second < 4; ++second)
      {
        shortest = std::min(shortest, dr::Distance(corners[first], corners[second]));
      }
    }
    const double ratio = CircumradiusOf(corners, center) / shortest;
    if (!std::isfinite(ratio))
    {
      return t;
    }
    if (ratio > worstRatio)
    {
      worst = t;
      worstRatio = ratio;
    }
  }
  return worst;
}

/** The tetrahedron with the smallest signed volume. */
inline std::size_t
SmallestVolumeTetrahedron(const dr::TetrahedralMesh & mesh)
{
  std::size_t smallest = 0;
  double      smallestVolume = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
  {
    const std::array<dr::Vector3, 4> p = CornersOf(mesh, t);
    const double                     volume = dr::Dot(p[1] - p[0], dr::Cross(p[2] - p[0], p[3] - p[0])) / 6.0;
    if (volume < smallestVolume)
    {
      smallest = t;
      smallestVolume = volume;
    }
  }
  return smallest;
}

/** The interpolator the filter uses by default, to label points the way the filter does. */
template <typename TImage>
typename InterpolateImageFunction<TImage, double>::Pointer
DefaultInterpolatorFor(const TImage & image, const FilterSettings & settings)
{
  typename InterpolateImageFunction<TImage, double>::Pointer interpolator;
  if (settings.isoValue)
  {
    interpolator = LinearInterpolateImageFunction<TImage, double>::New();
  }
  else
  {
    interpolator = NearestNeighborInterpolateImageFunction<TImage, double>::New();
  }
  interpolator->SetInputImage(&image);
  return interpolator;
}

/** The label the filter's oracle gives the physical point `point`. */
template <typename TImage>
dr::Label
OracleLabelAt(const InterpolateImageFunction<TImage, double> & interpolator, const FilterSettings & settings,
              const std::set<dr::Label> & tissues, const dr::Vector3 & point)
{
  // ITK's IsInsideBuffer() admits points whose nearest voxel, as ITK rounds, is one past the buffer.
  const typename TImage::PointType physicalPoint(point.data());
  ContinuousIndex<double, 3>       continuousIndex;
  interpolator.GetInputImage()->TransformPhysicalPointToContinuousIndex(physicalPoint, continuousIndex);
  typename TImage::IndexType nearestIndex;
  nearestIndex.CopyWithRound(continuousIndex);
  if (!interpolator.IsInsideBuffer(continuousIndex) ||
      !interpolator.GetInputImage()->GetBufferedRegion().IsInside(nearestIndex))
  {
    return dr::BackgroundLabel;
  }
  const double value = interpolator.Evaluate(physicalPoint);
  if (settings.isoValue)
  {
    return value >= *settings.isoValue ? 1 : dr::BackgroundLabel;
  }
  const auto label = static_cast<dr::Label>(std::lround(value));
  if (settings.mergeLabels)
  {
    const std::set<dr::Label> selected(settings.labels.begin(), settings.labels.end());
    return label != dr::BackgroundLabel && (selected.empty() || selected.count(label)) ? 1 : dr::BackgroundLabel;
  }
  return tissues.count(label) ? label : dr::BackgroundLabel;
}

/** The image's labels as the oracle maps them, voxel by voxel, then with the voxel pinches removed by the core's
 * RemoveVoxelPinches (tested against brute force on its own): the labels the filter meshes with nearest-neighbour
 * labels and pinch removal on. The oracle works on a crop of the object with a background border; here the image
 * gets a border of one background voxel instead: the blocks that hold an object voxel are the same, in the same
 * order, so the changes are too. */
template <typename TImage>
typename Image<dr::Label, 3>::Pointer
JoinedLabelImage(const TImage & image, const FilterSettings & settings, const std::set<dr::Label> & tissues)
{
  auto joined = Image<dr::Label, 3>::New();
  joined->CopyInformation(&image);
  joined->SetRegions(image.GetBufferedRegion());
  joined->Allocate();
  const auto                                        interpolator = DefaultInterpolatorFor(image, settings);
  ImageRegionIteratorWithIndex<Image<dr::Label, 3>> it(joined, joined->GetBufferedRegion());
  for (; !it.IsAtEnd(); ++it)
  {
    typename TImage::PointType point;
    image.TransformIndexToPhysicalPoint(it.GetIndex(), point);
    it.Set(OracleLabelAt(*interpolator, settings, tissues, { { point[0], point[1], point[2] } }));
  }
  const auto &                     size = joined->GetBufferedRegion().GetSize();
  const std::array<std::size_t, 3> padded{ { size[0] + 2, size[1] + 2, size[2] + 2 } };
  std::vector<dr::Label>           labels(padded[0] * padded[1] * padded[2], dr::BackgroundLabel);
  const auto                       paddedOffset = [&padded](std::size_t i, std::size_t j, std::size_t k) {
    return (i + 1) + padded[0] * ((j + 1) + padded[1] * (k + 1));
  };
  const dr::Label * const buffer = joined->GetBufferPointer();
  for (std::size_t k = 0, offset = 0; k < size[2]; ++k)
  {
    for (std::size_t j = 0; j < size[1]; ++j)
    {
      for (std::size_t i = 0; i < size[0]; ++i, ++offset)
      {
        labels[paddedOffset(i, j, k)] = buffer[offset];
      }
    }
  }
  dr::RemoveVoxelPinches(labels.data(), padded);
  for (std::size_t k = 0, offset = 0; k < size[2]; ++k)
  {
    for (std::size_t j = 0; j < size[1]; ++j)
    {
      for (std::size_t i = 0; i < size[0]; ++i, ++offset)
      {
        joined->GetBufferPointer()[offset] = labels[paddedOffset(i, j, k)];
      }
    }
  }
  return joined;
}

/** An iso-surface's values as the filter interpolates them once its voxels' sides of the iso-value were regularised
 * (docs/algorithm.md, "Topology"), written here from that rule, not from the library's code: on the filter's label
 * image's voxels inside the image, each voxel whose regularised label is on the other side than its value gets its
 * value mirrored in the iso-value (2 iso - v), or the type's nearest value on its side where that is not. */
template <typename TImage, typename TFilter>
typename TImage::Pointer
CarriedIsoValues(const TImage & image, const TFilter & filter, double iso)
{
  using ValueType = typename TImage::PixelType;
  static_assert(std::is_floating_point_v<ValueType>, "the randomized iso-value images are floating point");
  const auto * labels = filter.GetObjectLabelImage();
  auto         region = labels->GetBufferedRegion();
  region.Crop(image.GetBufferedRegion());
  auto values = TImage::New();
  values->CopyInformation(&image);
  values->SetRegions(region);
  values->Allocate();
  for (ImageRegionIteratorWithIndex<TImage> it(values, region); !it.IsAtEnd(); ++it)
  {
    const ValueType value = image.GetPixel(it.GetIndex());
    const bool      object = labels->GetPixel(it.GetIndex()) != dr::BackgroundLabel;
    if ((static_cast<double>(value) >= iso) == object)
    {
      it.Set(value);
      continue;
    }
    auto            mirrored = static_cast<ValueType>(2.0 * iso - static_cast<double>(value));
    const ValueType toward = object ? std::numeric_limits<ValueType>::max() : std::numeric_limits<ValueType>::lowest();
    while ((static_cast<double>(mirrored) >= iso) != object)
    {
      mirrored = std::nextafter(mirrored, toward);
    }
    it.Set(mirrored);
  }
  return values;
}

/** The label the filter meshes at a physical point: OracleLabelAt on the image (with an iso-value: on its values
 * carried to the regularised voxels' sides, CarriedIsoValues()), or on JoinedLabelImage, or on the filter's
 * regularised label image. */
template <typename TImage, typename TFilter>
std::function<dr::Label(const dr::Vector3 &)>
MeshedLabelFunction(const TImage & image, const TFilter & filter, const FilterSettings & settings,
                    const std::set<dr::Label> & tissues)
{
  const bool regularised = filter.GetRegularizationReport().changedVoxels > 0 ||
                           filter.GetNumberOfLocallyRegularizedVoxels() > 0 || filter.GetNumberOfJoiningVoxels() > 0;
  if constexpr (std::is_floating_point_v<typename TImage::PixelType>)
  {
    if (settings.isoValue && regularised)
    {
      const auto values = CarriedIsoValues(image, filter, *settings.isoValue);
      const auto interpolator = DefaultInterpolatorFor(*values, settings);
      return [=](const dr::Vector3 & point) { return OracleLabelAt(*interpolator, settings, tissues, point); };
    }
  }
  if (filter.GetRegularizationReport().changedVoxels > 0 || filter.GetNumberOfLocallyRegularizedVoxels() > 0)
  {
    // The regularised labels are the ones the mesh must carry (docs/algorithm.md, "Topology"): the image the
    // filter says it meshed, which holds mapped labels (outside its region, background).
    const auto labels = Image<dr::Label, 3>::ConstPointer(filter.GetObjectLabelImage());
    const auto interpolator = DefaultInterpolatorFor(*labels, FilterSettings{});
    return [=](const dr::Vector3 & point) { return OracleLabelAt(*interpolator, FilterSettings{}, tissues, point); };
  }
  if (settings.isoValue || !settings.joinDiagonalVoxels)
  {
    const auto interpolator = DefaultInterpolatorFor(image, settings);
    return [=](const dr::Vector3 & point) { return OracleLabelAt(*interpolator, settings, tissues, point); };
  }
  const auto joined = JoinedLabelImage(image, settings, tissues);
  const auto interpolator = DefaultInterpolatorFor(*joined, FilterSettings{});
  // The joined image holds mapped labels already: the default settings keep every tissue as it is.
  return [=](const dr::Vector3 & point) { return OracleLabelAt(*interpolator, FilterSettings{}, tissues, point); };
}

/** The output is every tetrahedron whose circumcentre is inside the object, labelled with the label there.
 * Voxel-derived circumcentres often lie exactly on a voxel face, edge or corner, where a rounding difference
 * between the core's circumcentre and ours flips the nearest voxel: a label seen within a hair of the
 * circumcentre is accepted.
 * Tetrahedra flatter than 1e-6 relative volume are skipped: their recomputed circumcentre is not trustworthy.
 * The tetrahedra the mesh says it relabelled at non-manifold places (docs/algorithm.md, "Topology") carry a
 * neighbour's label instead: one of their face neighbours in the mesh must carry it too. */
/** The facet of a tetrahedron opposite corner `skipped`, its indices sorted. */
inline std::array<uint32_t, 3>
SortedFacet(const std::array<uint32_t, 4> & tetrahedron, int skipped)
{
  std::array<uint32_t, 3> facet{};
  int                     count = 0;
  for (int corner = 0; corner < 4; ++corner)
  {
    if (corner != skipped)
    {
      facet[count++] = tetrahedron[corner];
    }
  }
  std::sort(facet.begin(), facet.end());
  return facet;
}

template <typename TImage, typename TFilter>
void
CheckCircumcenterLabels(const TImage & image, const TFilter & filter, const FilterSettings & settings,
                        const std::set<dr::Label> & tissues, const dr::TetrahedralMesh & mesh,
                        ViolationList & violations)
{
  const auto   labelAt = MeshedLabelFunction(image, filter, settings, tissues);
  const auto & spacing = image.GetSpacing();
  const double hair = 1e-6 * *std::max_element(spacing.Begin(), spacing.End());
  std::size_t  wrong = 0;
  // The outputs hold the refined mesh's tetrahedra in its order (CheckOutputsAgree), not its relabelling list.
  const std::vector<uint32_t> & relabelledList = filter.GetRefinedMesh().topologyRelabelledTetrahedra;
  const std::set<uint32_t>      relabelled(relabelledList.begin(), relabelledList.end());
  std::map<std::array<uint32_t, 3>, std::vector<std::size_t>> tetrahedraOfFacet;
  if (!relabelled.empty())
  {
    for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
    {
      for (int skipped = 0; skipped < 4; ++skipped)
      {
        tetrahedraOfFacet[SortedFacet(mesh.tetrahedra[t], skipped)].push_back(t);
      }
    }
  }
  std::size_t carriesItsCircumcenterLabel = 0;
  for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
  {
    const bool isRelabelled = relabelled.count(static_cast<uint32_t>(t)) != 0;
    if (isRelabelled)
    {
      bool sharedWithANeighbour = false;
      for (int skipped = 0; skipped < 4; ++skipped)
      {
        for (const std::size_t other : tetrahedraOfFacet.at(SortedFacet(mesh.tetrahedra[t], skipped)))
        {
          sharedWithANeighbour =
            sharedWithANeighbour || (other != t && mesh.tetrahedronLabels[other] == mesh.tetrahedronLabels[t]);
        }
      }
      if (!sharedWithANeighbour)
      {
        violations.Add("tetrahedron ", t, " was relabelled at a non-manifold place but no neighbour has its label");
      }
    }
    const std::array<dr::Vector3, 4> corners = CornersOf(mesh, t);
    dr::Vector3                      center;
    const double                     radius = CircumradiusOf(corners, center);
    const double                     volume =
      std::abs(dr::Dot(corners[1] - corners[0], dr::Cross(corners[2] - corners[0], corners[3] - corners[0]))) / 6.0;
    // A flat tetrahedron's circumcentre is arbitrary; on a boundary it may carry the label beyond (docs/algorithm.md,
    // "Flat caps").
    if (!(volume > 1e-6 * radius * radius * radius) || dr::IsFlatToRounding(corners))
    {
      continue;
    }
    // The centre itself first, then the 26 points a hair away (a centre can sit on a voxel edge or corner).
    int matches = 0;
    for (int probe = 0; probe < 27 && (isRelabelled || matches == 0); ++probe)
    {
      const int         code = (probe + 13) % 27;
      const dr::Vector3 offset{ { hair * (code % 3 - 1), hair * (code / 3 % 3 - 1), hair * (code / 9 - 1) } };
      matches += labelAt(center + offset) == mesh.tetrahedronLabels[t];
    }
    const bool seen = matches > 0;
    if (isRelabelled)
    {
      // The list exempts its tetrahedra from the check below: one whose circumcentre is well inside its own label
      // was not relabelled, and a list that held it could hide a wrong label behind it.
      carriesItsCircumcenterLabel += matches == 27;
      continue;
    }
    if (!seen && wrong++ < 3)
    {
      violations.Add("tetrahedron ",
                     t,
                     " is labelled ",
                     mesh.tetrahedronLabels[t],
                     " but the image says ",
                     labelAt(center),
                     " at its circumcentre (",
                     center[0],
                     ", ",
                     center[1],
                     ", ",
                     center[2],
                     ")");
    }
  }
  if (carriesItsCircumcenterLabel != 0)
  {
    violations.Add(carriesItsCircumcenterLabel,
                   " of the ",
                   relabelled.size(),
                   " tetrahedra listed as relabelled at "
                   "non-manifold places carry the label at their circumcentre");
  }
}

/** Well-formed tetrahedra, every point used and finite. */
inline void
CheckWellFormed(const dr::TetrahedralMesh & mesh, const dr::TetrahedronQuality & quality, ViolationList & violations)
{
  if (mesh.tetrahedra.empty() || mesh.boundaryTriangles.empty())
  {
    violations.Add("a mesh with ",
                   mesh.tetrahedra.size(),
                   " tetrahedra and ",
                   mesh.boundaryTriangles.size(),
                   " boundary triangles: a bounded object has both");
  }
  for (const dr::Vector3 & point : mesh.points)
  {
    if (!std::isfinite(point[0]) || !std::isfinite(point[1]) || !std::isfinite(point[2]))
    {
      violations.Add("a non-finite point");
      break;
    }
  }
  if (quality.malformedTetrahedra != 0 || quality.duplicateTetrahedra != 0 || quality.unusedPoints != 0 ||
      quality.invertedTetrahedra != 0)
  {
    violations.Add("malformed ",
                   quality.malformedTetrahedra,
                   ", duplicate ",
                   quality.duplicateTetrahedra,
                   ", inverted ",
                   quality.invertedTetrahedra,
                   " tetrahedra (smallest volume ",
                   quality.minimumVolume,
                   "), unused points ",
                   quality.unusedPoints,
                   "; smallest ",
                   DescribeTetrahedron(mesh, SmallestVolumeTetrahedron(mesh)));
  }
}

/** Theorem 2 (proven for σ = 0, any ρ >= 1; measured with σ > 0): boundary triangles inside their surface balls
 * (circumradius < δ), hence boundary planar angles > 30°; with ρ >= 2 only feature vertices on the boundary (Lemma 5),
 * unless `lemma5MayFail`. Returns how many boundary triangle corners are not feature vertices (counted with ρ >= 2).
 * Lemma 2's edges are checked against the exported local sizing (CheckEdgesAgainstLocalSizing).
 * Lemma 5 rests on Lemma 2, and may fail where either does not hold: where the refinement halved δ locally for
 * manifoldness (a cell across the edge of a refined zone has edges shorter than the δ at its circumcentre, so an
 * intersecting cell can reach radius-edge ratio ρ and its split, R4 on intersecting cells, leaves a free vertex near
 * the surface), and with σ > 0, whose R4′ points come closer than δ to other vertices: the same R4 split follows
 * (found: ManyLabels 5022738), and R4′ itself splits a sliver at a point failing its acceptance test where no
 * other point passes (docs/algorithm.md, "R4′ picks its point"). Such a vertex is still a corner of triangles inside
 * their surface balls, so within δ of the surface, which CheckAgainstSegmentation asserts of the whole boundary. */
inline std::size_t
CheckBoundaryGuarantees(const dr::TetrahedralMesh & mesh, double delta, bool lemma5MayFail, double rho,
                        ViolationList & violations)
{
  const dr::SurfaceTopology boundary = dr::ComputeBoundaryTopology(mesh);
  if (!(boundary.minimumPlanarAngle > 30.0))
  {
    violations.Add("smallest boundary planar angle ", boundary.minimumPlanarAngle, " deg <= 30 deg");
  }
  // R3's surface balls, so the triangles' circumradii, stay below δ with its lattice tie margin.
  const double largestCircumradius = dr::LargestBoundaryCircumradius(mesh);
  const double circumradiusBound = delta * (1.0 + dr::LatticeTieMargin);
  if (!(largestCircumradius < circumradiusBound))
  {
    violations.Add("largest boundary triangle circumradius ",
                   largestCircumradius,
                   " >= delta (1 + LatticeTieMargin) ",
                   circumradiusBound);
  }
  if (rho < 2.0)
  {
    return 0;
  }
  const std::vector<uint32_t> nonFeatureCorners = dr::NonFeatureBoundaryCorners(mesh);
  if (!nonFeatureCorners.empty() && !lemma5MayFail)
  {
    const uint32_t     vertex = nonFeatureCorners.front();
    std::ostringstream first;
    first.precision(17);
    first << dr::VertexKindName(mesh.pointKinds[vertex]) << " vertex " << vertex << " (" << mesh.points[vertex][0]
          << ", " << mesh.points[vertex][1] << ", " << mesh.points[vertex][2] << ")";
    violations.Add(nonFeatureCorners.size(),
                   " boundary triangle corners are not feature vertices (rho >= 2), the first a ",
                   first.str());
  }
  return nonFeatureCorners.size();
}

/** Every tetrahedron carries a tissue label of the image; every boundary triangle has a tissue first and a
 * different tissue or the background second. */
inline void
CheckLabels(const dr::TetrahedralMesh & mesh, const std::set<dr::Label> & tissues, ViolationList & violations)
{
  for (std::size_t t = 0; t < mesh.tetrahedronLabels.size(); ++t)
  {
    if (!tissues.count(mesh.tetrahedronLabels[t]))
    {
      violations.Add("tetrahedron ",
                     t,
                     " has label ",
                     mesh.tetrahedronLabels[t],
                     ", not one of the image's labels ",
                     DescribeLabels(tissues));
      break;
    }
  }
  for (std::size_t i = 0; i < mesh.boundaryTriangleLabels.size(); ++i)
  {
    const auto & labels = mesh.boundaryTriangleLabels[i];
    if (!tissues.count(labels[0]) || !(tissues.count(labels[1]) || labels[1] == dr::BackgroundLabel) ||
        labels[0] == labels[1])
    {
      violations.Add("boundary triangle ", i, " has labels {", labels[0], ", ", labels[1], "}");
      break;
    }
  }
  const dr::BoundaryConsistency consistency = dr::CheckBoundaryAgainstTetrahedra(mesh);
  if (!consistency.IsConsistent())
  {
    violations.Add("boundary triangles disagree with the tetrahedra: missing ",
                   consistency.missingTriangles,
                   ", extra ",
                   consistency.extraTriangles,
                   ", wrong labels ",
                   consistency.wrongLabels,
                   ", wrong orientation ",
                   consistency.wrongOrientation,
                   ", over-shared facets ",
                   consistency.overSharedFacets,
                   "; ",
                   consistency.firstWronglyOriented);
  }
}

/** The two ITK outputs and GetRefinedMesh() describe the same mesh. */
template <typename TFilter>
void
CheckOutputsAgree(TFilter & filter, const dr::TetrahedralMesh & fromOutputs, ViolationList & violations)
{
  const dr::TetrahedralMesh & refined = filter.GetRefinedMesh();
  if (fromOutputs.points != refined.points || fromOutputs.tetrahedra != refined.tetrahedra ||
      fromOutputs.tetrahedronLabels != refined.tetrahedronLabels ||
      fromOutputs.boundaryTriangles != refined.boundaryTriangles ||
      fromOutputs.boundaryTriangleLabels != refined.boundaryTriangleLabels)
  {
    violations.Add("the ITK outputs differ from GetRefinedMesh()");
  }
  if (filter.GetInterfaceMesh()->GetNumberOfPoints() != fromOutputs.points.size())
  {
    violations.Add("the interface mesh has ",
                   filter.GetInterfaceMesh()->GetNumberOfPoints(),
                   " points, not ",
                   fromOutputs.points.size());
  }
}

/** The radius of a ball that makes a component of the segmentation thick enough that the mesh must hold it.
 *
 * With nearest-neighbour labels, δ / 2 (a ball of diameter δ, issue #14's "at least δ thick"): the filter finds the
 * parts of its labels that hold no tetrahedron and samples those that thick more finely until they do
 * (RefinementStatistics::unmeshedParts; docs/algorithm.md, "Topology"). Before it did, the randomized suite's 3,000
 * cases lost about 140 components of radius 0.50-0.70 δ, and 3,132 in the SaltAndPepper family alone of seeds
 * 47,000-48,599.
 *
 * With an iso-value there is no voxel census, and the bound is the proven one, 2δ: take the tetrahedron of the final
 * triangulation that holds the centre c of a ball of radius 2δ inside a component. If its circumsphere misses the
 * surface, that sphere (which holds c) lies inside the component, and so does its centre; if it meets the surface,
 * R2 no longer applying means its radius is < 2δ, so its centre is within 2δ of c, inside the ball. Either way its
 * circumcentre carries the component's label: the tetrahedron is output. The measured one, δ, is used; the surface
 * is the linear interpolation's, which lies up to a voxel diagonal inside the voxels that reach the iso-value (the
 * ones the segmentation holds): the ball is that much larger. */
inline double
ThickComponentRadius(double delta, const FilterSettings & settings, const Vector<double, 3> & spacing)
{
  const double diagonal = std::sqrt(spacing[0] * spacing[0] + spacing[1] * spacing[1] + spacing[2] * spacing[2]);
  return settings.isoValue ? delta + diagonal : 0.5 * delta;
}

/** The radius of the ball whose opening of the labels is the part of the segmentation the mesh's boundary follows
 * (the distance check, LargestDistance's callers): δ, and with an iso-value a voxel diagonal more (see
 * ThickComponentRadius()). Thinner parts attached to thicker ones (rims, lines, sheets, cavities) are meshed, but
 * their surface is not resolved. */
inline double
ResolvedPartRadius(double delta, const FilterSettings & settings, const Vector<double, 3> & spacing)
{
  const double diagonal = std::sqrt(spacing[0] * spacing[0] + spacing[1] * spacing[1] + spacing[2] * spacing[2]);
  return delta + (settings.isoValue ? diagonal : 0.0);
}

/** Which components of the segmentation the filter meshed hold a ball of ThickComponentRadius() (into `result`). */
template <typename TFilter>
std::vector<bool>
FindThickComponents(const TFilter & filter, const FilterSettings & settings, const SegmentationComponents & components,
                    RunResult & result)
{
  const double      delta = filter.GetEffectiveSurfaceSamplingDistance();
  const auto &      spacing = filter.GetObjectLabelImage()->GetSpacing();
  const double      radius = ThickComponentRadius(delta, settings, spacing);
  std::vector<bool> thick(components.NumberOfComponents(), false);
  for (std::size_t component = 0; component < thick.size(); ++component)
  {
    thick[component] = components.LargestBallRadius(component, radius) >= radius;
    if (thick[component] && result.thickComponents++ == 0)
    {
      result.firstThickComponent = "a component of label " + std::to_string(components.LabelOf(component)) + " (" +
                                   std::to_string(components.NumberOfVoxels(component)) +
                                   " voxels) holds a ball of radius " + std::to_string(radius / delta) + " delta";
    }
  }
  return thick;
}

/** Largest distance from the points to the surface, or 0 for no point. */
inline double
LargestDistance(const std::vector<dr::Vector3> & samples, const dr::TriangleSurfaceDistance & surface)
{
  double largest = 0.0;
  for (const dr::Vector3 & sample : samples)
  {
    largest = std::max(largest, surface.Distance(sample));
  }
  return largest;
}

/** Largest distances between the mesh's boundary and the voxels' surface, in units of δ.
 *
 * Boundary to voxels: every boundary triangle lies in its surface ball, centred on the surface with a radius R3 keeps
 * below δ (1 + LatticeTieMargin), so within that of the surface (R3's tie margin: a surface ball the voxel lattice
 * makes exactly δ wide is kept whatever δ's last bits; SheetsAndLines 3315603 reaches 1.0000019 δ with the margin,
 * 0.929 δ without it). Measured over the 1,300 meshes of the suite (nearest-neighbour labels): median 0.43, 99th
 * percentile 0.91, largest 0.98. A mesh made at 2δ reaches about 2δ.
 *
 * The thick parts' surface to the boundary: the faces between the thick parts of two labels (ThickParts(), with the
 * ball of ResolvedPartRadius(): the labels opened at that scale, which is what the mesh's boundary follows). Measured
 * over the suite's 3,000 cases: 95th percentile 0.83, 99th 0.91, largest 1.48 (ManyLabels). Before, the whole surface
 * of the thick components was measured, and its tail (99th percentile 2.6, largest 4.46; then 5.1, 8.3 and 18.3 in a
 * search of 12,000 more cases) was parts thinner than the ball attached to thick ones (rims, lines, sheets and
 * cavities that survived the regularisation), which the refinement does not resolve, as it does not resolve
 * components that thin, at any distance from a boundary. The bound keeps a margin over the largest: it catches a lost
 * or dropped thick part, whose faces lie about the ball's radius or more from any boundary. */
constexpr double MeshToSegmentationBound = 1.0 + dr::LatticeTieMargin;
constexpr double SegmentationToMeshBound = 2.0;

/** The mesh against the segmentation it stands for (the filter's regularised labels), from the voxels alone:
 * every component thick enough at δ holds the circumcentre or the centroid of a tetrahedron of its label; with
 * nearest-neighbour labels, the boundary's feature vertices lie on the voxels' surface within the oracle's
 * tolerance, and the boundary and that surface (of the thick components) are within a fraction of δ both ways. */
template <typename TFilter>
void
CheckAgainstSegmentation(const TFilter & filter, const FilterSettings & settings, const dr::TetrahedralMesh & mesh,
                         ViolationList & violations, RunResult & result)
{
  const double                 delta = filter.GetEffectiveSurfaceSamplingDistance();
  const SegmentationComponents components(*filter.GetObjectLabelImage());
  const std::vector<bool>      thick = FindThickComponents(filter, settings, components, result);
  std::vector<bool>            meshed(components.NumberOfComponents(), false);
  for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
  {
    const std::array<dr::Vector3, 4> corners = CornersOf(mesh, t);
    dr::Vector3                      center;
    CircumradiusOf(corners, center);
    const dr::Vector3 centroid = 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
    for (const dr::Vector3 & point : { center, centroid })
    {
      const std::size_t component = components.ComponentAt(point);
      if (component != SegmentationComponents::None && components.LabelOf(component) == mesh.tetrahedronLabels[t])
      {
        meshed[component] = true;
      }
    }
  }
  std::size_t lost = 0;
  for (std::size_t component = 0; component < thick.size(); ++component)
  {
    result.unmeshedComponents += !meshed[component];
    if (thick[component] && !meshed[component] && lost++ < 3)
    {
      violations.Add("a component of label ",
                     components.LabelOf(component),
                     " (",
                     components.NumberOfVoxels(component),
                     " voxels) holds a ball of radius ",
                     components.LargestBallRadius(component, 4.0 * delta) / delta,
                     " delta but no tetrahedron");
    }
  }
  // Nothing is lost silently: the parts the filter lists without a tetrahedron are the components counted here (it
  // has no census of an iso-value's interpolated labels).
  const std::size_t listed = filter.GetRefinementStatistics().unmeshedParts.size();
  if (!settings.isoValue && listed != result.unmeshedComponents)
  {
    violations.Add("the filter lists ",
                   listed,
                   " parts of its labels without a tetrahedron; the voxels and the mesh show ",
                   result.unmeshedComponents);
  }
  if (settings.isoValue || mesh.boundaryTriangles.empty())
  {
    return;
  }
  const auto & spacing = filter.GetObjectLabelImage()->GetSpacing();
  const double smallestSpacing = std::min({ spacing[0], spacing[1], spacing[2] });
  // Samples about half a δ apart on the boundary (whose triangles are about δ across) and half a voxel apart on
  // the voxels' faces: the distances are judged at a tenth of δ, and denser samples only cost time.
  const double                         boundarySampleSpacing = delta / 2.0;
  const double                         faceSampleSpacing = smallestSpacing;
  std::vector<dr::Vector3>             surfacePoints;
  std::vector<std::array<uint32_t, 3>> surfaceTriangles;
  components.Surface(surfacePoints, surfaceTriangles, [](std::size_t, std::size_t) { return true; });
  const dr::TriangleSurfaceDistance surface(surfacePoints, surfaceTriangles);
  // The oracle's surface points are bisected to 1e-4 of the smallest spacing (ImageLabelOracle::SurfaceTolerance).
  const double       tolerance = 1e-4 * smallestSpacing * (1.0 + 1e-6);
  std::size_t        offSurface = 0;
  std::set<uint32_t> boundaryVertices;
  for (const auto & triangle : mesh.boundaryTriangles)
  {
    boundaryVertices.insert(triangle.begin(), triangle.end());
  }
  // Every boundary feature vertex is on the surface of the labels the filter meshed, where the local topology
  // regularisation changed them too (it once left some off: the voxel pinches it mended after its balls fell
  // outside them; RegressionLocalRegularization replays the case).
  for (const uint32_t vertex : boundaryVertices)
  {
    const double distance = surface.Distance(mesh.points[vertex]);
    if (mesh.pointKinds[vertex] != dr::VertexKind::Feature || !(distance > tolerance))
    {
      continue;
    }
    if (offSurface++ < 3)
    {
      violations.Add("boundary feature vertex ",
                     vertex,
                     " (",
                     mesh.points[vertex][0],
                     ", ",
                     mesh.points[vertex][1],
                     ", ",
                     mesh.points[vertex][2],
                     ") lies ",
                     distance,
                     " mm off the voxels' surface");
    }
  }
  result.meshToSegmentation =
    LargestDistance(dr::SampleTriangles(mesh.points, mesh.boundaryTriangles, boundarySampleSpacing), surface) / delta;
  // The surface of the thick components as the labels opened by the ball stand it: a face between the thick parts of
  // two labels (the background's included; beyond the image is background). The rims, lines, sheets and cavities
  // thinner than the ball are left out, as the thin components are: the refinement does not resolve them at δ, and
  // they can lie far from any boundary (SheetsAndLines 3003993, regularisation scale 0: a line 18 δ long hanging off
  // a thick sheet; SaltAndPepper 2004185: a one-voxel cavity 0.93 δ thick inside an ellipsoid, 5 δ from its surface).
  const std::vector<bool> thickPart = components.ThickParts(ResolvedPartRadius(delta, settings, spacing));
  const auto              isThickPart = [&thickPart](std::size_t voxel) {
    return voxel == SegmentationComponents::None || thickPart[voxel];
  };
  std::vector<dr::Vector3>             thickPoints;
  std::vector<std::array<uint32_t, 3>> thickTriangles;
  components.Surface(thickPoints, thickTriangles, [&](std::size_t a, std::size_t b) {
    const bool tissueA = a != SegmentationComponents::None && components.ComponentOf(a) != SegmentationComponents::None;
    const bool tissueB = b != SegmentationComponents::None && components.ComponentOf(b) != SegmentationComponents::None;
    return (tissueA || tissueB) && isThickPart(a) && isThickPart(b);
  });
  const dr::TriangleSurfaceDistance boundary(mesh.points, mesh.boundaryTriangles);
  result.segmentationToMesh =
    LargestDistance(dr::SampleTriangles(thickPoints, thickTriangles, faceSampleSpacing), boundary) / delta;
  if (!(result.meshToSegmentation <= MeshToSegmentationBound))
  {
    violations.Add("the boundary lies ",
                   result.meshToSegmentation,
                   " delta from the voxels' surface, beyond ",
                   MeshToSegmentationBound,
                   " delta");
  }
  if (!(result.segmentationToMesh <= SegmentationToMeshBound))
  {
    violations.Add("the surface of a thick part lies ",
                   result.segmentationToMesh,
                   " delta from the boundary, beyond ",
                   SegmentationToMeshBound,
                   " delta");
  }
}

/** Issue #14: every tissue's boundary and the union's is a closed manifold, counted from the mesh without the
 * library's topology code. Where it is promised (`promised`, IsPromisedManifold) a place is a violation; elsewhere the
 * filter may leave places it could not mend, but it must say so (RefinementStatistics::remainingNonManifoldVertices),
 * never leave them silently, and its count of the vertices it left is at least the non-manifold vertices of any one
 * boundary. */
inline void
CheckManifoldBoundaries(const dr::TetrahedralMesh & mesh, const dr::RefinementStatistics & statistics, bool promised,
                        ViolationList & violations, RunResult & result)
{
  std::set<dr::Label> boundaries(mesh.tetrahedronLabels.begin(), mesh.tetrahedronLabels.end());
  boundaries.insert(dr::BackgroundLabel);
  std::ostringstream found;
  // The most non-manifold vertices on one boundary: the filter's count of the vertices it left (each a vertex where
  // some boundary is not a manifold) cannot be smaller.
  std::size_t mostVertices = 0;
  for (const dr::Label label : boundaries)
  {
    const dr::NonManifoldCount places =
      dr::CountNonManifoldPlaces(mesh.boundaryTriangles, mesh.boundaryTriangleLabels, label);
    if (!places.None())
    {
      ++result.nonManifoldBoundaries;
      found << (label == dr::BackgroundLabel ? std::string(" the union's") : " label " + std::to_string(label) + "'s")
            << " (" << places.edges << " edges, " << places.vertices << " vertices)";
    }
    mostVertices = std::max(mostVertices, places.vertices);
  }
  result.admittedNonManifoldVertices = statistics.remainingNonManifoldVertices;
  result.promisedManifold = promised;
  result.regularizationRounds = statistics.topologyRegularizationRounds;
  result.regularizationBudgetReached = statistics.topologyRegularizationBudgetReached;
  if (result.nonManifoldBoundaries > 0 && promised)
  {
    violations.Add("boundaries not a closed manifold with the topology defaults and delta >= the largest spacing:",
                   found.str());
  }
  else if (result.nonManifoldBoundaries > 0 && result.admittedNonManifoldVertices == 0)
  {
    violations.Add("boundaries not a closed manifold although the filter says it left none:", found.str());
  }
  else if (mostVertices > result.admittedNonManifoldVertices)
  {
    violations.Add("the filter says it left ",
                   result.admittedNonManifoldVertices,
                   " non-manifold vertices, fewer than one boundary has:",
                   found.str());
  }
}

/** How far from a voxel of another label a voxel must be to survive the opening of its label (docs/algorithm.md,
 * "Topology", step 1): the scale times δ (the one set, or the automatic 4 × the largest spacing) plus half the
 * smallest spacing, lengthened by the lattice tie margin. */
template <typename TImage>
double
OpeningReach(const TImage & image, const FilterSettings & settings)
{
  const auto & spacing = image.GetSpacing();
  const double delta = settings.surfaceSamplingDistance > 0.0 ? settings.surfaceSamplingDistance
                                                              : 4.0 * std::max({ spacing[0], spacing[1], spacing[2] });
  return (settings.regularizationScale * delta + 0.5 * std::min({ spacing[0], spacing[1], spacing[2] })) *
         (1.0 + dr::LatticeTieMargin);
}

/** Calls visit(index, label) for every voxel of `image` whose voxels within the opening's reach (OpeningReach, up
 * to rounding) all carry its label (ObjectLabelOf; outside the image, the background): the voxels the opening keeps,
 * whatever else it removes. Distances between voxel centres from the index offsets and the spacing (the direction is
 * a rotation); the offsets within the reach are listed once. */
template <typename TImage, typename TVisit>
void
ForEachVoxelBeyondTheOpeningsReach(const TImage & image, const FilterSettings & settings, TVisit && visit)
{
  const auto & spacing = image.GetSpacing();
  const double reach = OpeningReach(image, settings) * (1.0 + 1e-9);
  const auto   region = image.GetBufferedRegion();
  const auto   labelOf = [&](const typename TImage::IndexType & index) {
    return region.IsInside(index) ? ObjectLabelOf(static_cast<double>(image.GetPixel(index)), settings)
                                    : dr::BackgroundLabel;
  };
  std::array<long, 3> box{};
  for (int axis = 0; axis < 3; ++axis)
  {
    box[axis] = static_cast<long>(std::ceil(reach / spacing[axis]));
  }
  std::vector<typename TImage::OffsetType> withinReach;
  for (long dz = -box[2]; dz <= box[2]; ++dz)
  {
    for (long dy = -box[1]; dy <= box[1]; ++dy)
    {
      for (long dx = -box[0]; dx <= box[0]; ++dx)
      {
        const double x = static_cast<double>(dx) * spacing[0];
        const double y = static_cast<double>(dy) * spacing[1];
        const double z = static_cast<double>(dz) * spacing[2];
        if (!(std::sqrt(x * x + y * y + z * z) > reach))
        {
          withinReach.push_back({ { dx, dy, dz } });
        }
      }
    }
  }
  for (ImageRegionConstIteratorWithIndex<TImage> it(&image, region); !it.IsAtEnd(); ++it)
  {
    const auto      index = it.GetIndex();
    const dr::Label label = labelOf(index);
    if (std::all_of(withinReach.begin(), withinReach.end(), [&](const typename TImage::OffsetType & offset) {
          return labelOf(index + offset) == label;
        }))
    {
      visit(index, label);
    }
  }
}

/** The labels the filter says it meshed (GetObjectLabelImage(), which the checks of the mesh read where the labels
 * were regularised) against the input's, where the opening alone changed them (no pinch joined, no local round): the
 * opening keeps every voxel beyond its reach from every voxel of another label (ContradictsRegularizedAway rests on
 * the same rule), so each such voxel must keep its label, the background's included. */
template <typename TFilter, typename TImage>
void
CheckVoxelsBeyondTheOpeningsReachKeepTheirLabels(const TFilter & filter, const TImage & image,
                                                 const FilterSettings & settings, ViolationList & violations)
{
  if (filter.GetRegularizationReport().changedVoxels == 0 || filter.GetNumberOfJoiningVoxels() > 0 ||
      filter.GetNumberOfLocallyRegularizedVoxels() > 0)
  {
    return;
  }
  const auto  meshed = Image<dr::Label, 3>::ConstPointer(filter.GetObjectLabelImage());
  std::size_t changed = 0;
  std::string first;
  ForEachVoxelBeyondTheOpeningsReach(image, settings, [&](const typename TImage::IndexType & index, dr::Label label) {
    typename TImage::PointType point;
    image.TransformIndexToPhysicalPoint(index, point);
    Image<dr::Label, 3>::IndexType meshedIndex;
    const dr::Label                meshedLabel =
      meshed->TransformPhysicalPointToIndex(point, meshedIndex) ? meshed->GetPixel(meshedIndex) : dr::BackgroundLabel;
    if (meshedLabel != label && changed++ == 0)
    {
      std::ostringstream text;
      text << "voxel " << index << " of label " << label << ", beyond the opening's reach "
           << OpeningReach(image, settings) << " mm from every other label, has label " << meshedLabel
           << " in the labels the filter meshed";
      first = text.str();
    }
  });
  if (changed > 0)
  {
    violations.Add(changed, " voxels beyond the opening's reach changed label; the first: ", first);
  }
}

/** Every guarantee that holds for the settings, checked on what the filter returned, into `result`. */
template <typename TFilter, typename TImage>
void
CheckGuarantees(TFilter & filter, const TImage & image, const FilterSettings & settings, RunResult & result)
{
  ViolationList                violations;
  const dr::TetrahedralMesh    mesh = delaunay_image_to_mesh_test::TetrahedralMeshFromOutputs(filter);
  const double                 delta = filter.GetEffectiveSurfaceSamplingDistance();
  const double                 rho = filter.GetRadiusEdgeBound();
  const double                 sigma = filter.GetMinimumDihedralAngle();
  const std::set<dr::Label>    tissues = TissueLabelsOf(image, settings);
  const dr::TetrahedronQuality quality = dr::ComputeTetrahedronQuality(mesh);

  CheckWellFormed(mesh, quality, violations);
  CheckOutputsAgree(filter, mesh, violations);
  CheckVoxelsBeyondTheOpeningsReachKeepTheirLabels(filter, image, settings, violations);
  if (!(quality.maximumRadiusEdgeRatio < rho))
  {
    violations.Add("largest radius-edge ratio ",
                   quality.maximumRadiusEdgeRatio,
                   " >= rho ",
                   rho,
                   ": ",
                   DescribeTetrahedron(mesh, WorstRadiusEdgeTetrahedron(mesh)));
  }
  if (sigma > 0.0)
  {
    // R4' promises the dihedral bound; nothing of Theorem 2 is proven then. Checked with the angles computed here
    // from the face normals, and with the library's metric, which must agree.
    const double smallest = delaunay_image_to_mesh_test::SmallestDihedralAngleFromNormals(mesh);
    if (!(smallest >= sigma * (1.0 - RoundingSlack)))
    {
      violations.Add("smallest dihedral angle ", smallest, " deg < sigma ", sigma, " deg");
    }
    if (!(std::abs(smallest - quality.minimumDihedralAngle) <= 1e-6))
    {
      violations.Add("the library's smallest dihedral angle ",
                     quality.minimumDihedralAngle,
                     " deg differs from the face normals' ",
                     smallest,
                     " deg");
    }
  }
  // Lemma 2 edge by edge, with the sizing the refinement exported (GetRefinedMesh() has the outputs' points).
  const dr::LocalSizingReport sizing =
    dr::CheckEdgesAgainstTheRefinementsSizing(filter.GetRefinedMesh(),
                                              delta,
                                              rho,
                                              sigma,
                                              filter.GetManifoldRefinementLevels(),
                                              filter.GetRefinementStatistics().thickPartRounds,
                                              RoundingSlack);
  for (const std::string & problem : sizing.problems)
  {
    violations.Add(problem);
  }
  // With σ > 0 the boundary keeps its bounds as well (measured, not proven); Lemma 5 may fail (see
  // CheckBoundaryGuarantees), and the meshes where it does are counted.
  result.nonFeatureBoundaryCorners =
    CheckBoundaryGuarantees(mesh, delta, sizing.refinedLocally || sigma > 0.0, rho, violations);
  result.sliverSplitsFailingAcceptance = filter.GetRefinementStatistics().sliverSplitsFailingAcceptance;
  CheckLabels(mesh, tissues, violations);
  CheckCircumcenterLabels(image, filter, settings, tissues, mesh, violations);
  CheckAgainstSegmentation(filter, settings, mesh, violations, result);
  const auto & spacing = image.GetSpacing();
  CheckManifoldBoundaries(mesh,
                          filter.GetRefinementStatistics(),
                          IsPromisedManifold(settings, delta, std::max({ spacing[0], spacing[1], spacing[2] })),
                          violations,
                          result);
  // Issue #15: a tetrahedron flat to rounding is singular for every solver, whatever σ.
  result.flatTetrahedra = delaunay_image_to_mesh_test::CountFlatTetrahedra(mesh);
  if (result.flatTetrahedra > 0)
  {
    violations.Add(result.flatTetrahedra, " tetrahedra flat to rounding (volume <= 1e-6 x shortest edge cubed)");
  }
  result.violations = violations.Take();
  result.smallestVolume = quality.minimumVolume;
  result.smallestDihedralAngle = quality.minimumDihedralAngle;
}

/** Whether "every part thinner than the regularisation scale" may be the outcome: the opening keeps every voxel whose
 * nearest voxel of another label is farther than its reach (RegularizationScale x δ + half the smallest spacing,
 * lengthened by LatticeTieMargin, as the opening's own: a voxel at a lattice distance equal to the reach is within it
 * whatever δ's last bits), so it cannot remove them all when one such voxel exists. Returns an empty string, or what
 * contradicts the outcome. */
template <typename TImage>
std::string
ContradictsRegularizedAway(const TImage & image, const FilterSettings & settings)
{
  std::string contradiction;
  ForEachVoxelBeyondTheOpeningsReach(image, settings, [&](const typename TImage::IndexType & index, dr::Label label) {
    if (label != dr::BackgroundLabel && contradiction.empty())
    {
      std::ostringstream text;
      text << "'regularised away' although voxel " << index << " of label " << label << " lies beyond its reach "
           << OpeningReach(image, settings) << " mm from every other label";
      contradiction = text.str();
    }
  });
  return contradiction;
}

/** Runs `filter` on `image` with `settings`, and sorts the result. A ProcessAborted caused by the time limit
 * is reported as timedOut. */
template <typename TImage>
RunResult
RunAndCheck(const TImage * image, const FilterSettings & settings)
{
  using FilterType = DelaunayImageToMeshFilter<TImage, MeshType>;
  using Clock = std::chrono::steady_clock;
  auto filter = FilterType::New();
  filter->SetInput(image);
  filter->SetSurfaceSamplingDistance(settings.surfaceSamplingDistance);
  filter->SetRadiusEdgeBound(settings.radiusEdgeBound);
  filter->SetMinimumDihedralAngle(settings.minimumDihedralAngle);
  filter->SetMaximumNumberOfVertices(settings.maximumNumberOfVertices);
  filter->SetLabels(settings.labels);
  filter->SetMergeLabels(settings.mergeLabels);
  filter->SetManifoldRefinementLevels(settings.manifoldRefinementLevels);
  filter->SetJoinDiagonalVoxels(settings.joinDiagonalVoxels);
  filter->SetRegularizationScale(settings.regularizationScale);
  filter->SetTopologyRegularizationRounds(settings.topologyRegularizationRounds);
  filter->SetRelabelNonManifoldPlaces(settings.relabelNonManifoldPlaces);
  filter->SetRefineThickParts(settings.refineThickParts);
  if (settings.isoValue)
  {
    filter->SetIsoValue(*settings.isoValue);
  }
  RunResult  result;
  const auto start = Clock::now();
  const auto elapsed = [start] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  filter->AddObserver(ProgressEvent(), [&](const EventObject &) {
    if (elapsed() > settings.timeLimitSeconds)
    {
      result.timedOut = true;
      filter->AbortGenerateDataOn();
    }
  });
  try
  {
    filter->Update();
    result.seconds = elapsed();
    result.outcome = Outcome::Mesh;
    result.tetrahedra = filter->GetOutput()->GetNumberOfCells();
    result.points = filter->GetOutput()->GetNumberOfPoints();
    result.refinement = DescribeRefinement(filter->GetRefinementStatistics());
    CheckGuarantees(*filter, *image, settings, result);
  }
  catch (const ProcessAborted & aborted)
  {
    result.seconds = elapsed();
    result.outcome = Outcome::Aborted;
    result.message = aborted.GetDescription();
  }
  catch (const ExceptionObject & error)
  {
    result.seconds = elapsed();
    result.message = error.GetDescription();
    result.outcome = ClassifyExceptionDescription(result.message);
    if (result.outcome == Outcome::NoTetrahedron && filter->GetObjectLabelImage())
    {
      FindThickComponents(*filter, settings, SegmentationComponents(*filter->GetObjectLabelImage()), result);
    }
  }
  catch (const std::exception & error)
  {
    result.seconds = elapsed();
    result.message = std::string("std::exception, not itk::ExceptionObject: ") + error.what();
    result.outcome = Outcome::Unexpected;
  }
  catch (...)
  {
    result.seconds = elapsed();
    result.message = "an exception of unknown type";
    result.outcome = Outcome::Unexpected;
  }
  return result;
}

} // namespace delaunay_image_to_mesh_randomized
} // namespace itk

#endif
