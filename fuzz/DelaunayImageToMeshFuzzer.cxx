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

// libFuzzer target for itk::DelaunayImageToMeshFilter (issue #5). The input bytes are a small label image
// (size, spacing, direction, origin, labels) and the filter's parameters, valid or not (see InputLayout
// below and fuzz/README.md). Every run must end in a mesh that meets every guarantee the randomized GoogleTest
// checks, or in the documented exception that the input calls for; anything else calls abort(), and
// AddressSanitizer, UndefinedBehaviorSanitizer and libFuzzer's timeout catch the rest.

#include "DelaunayImageToMeshRandomizedChecks.h"

#include "itkMultiThreaderBase.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace
{

using namespace itk::delaunay_image_to_mesh_randomized;

/** Byte offsets of the fixed-size header; the voxels follow it, one byte each, x fastest. */
enum InputLayout : std::size_t
{
  SizeX = 0,
  SizeY = 1,
  SizeZ = 2,
  SpacingX = 3, // 4, 5 for y, z
  AngleX = 6,   // 7, 8: Euler angles of the direction matrix, 360/256 degrees per step
  Flags = 9,
  OriginX = 10, // 11, 12: signed, 8 mm per step
  LabelCount = 13,
  DeltaLow = 14,
  DeltaHigh = 15,
  Rho = 16,
  Sigma = 17,
  VertexCapLow = 18,
  VertexCapHigh = 19,
  SelectedLabelMask = 20,
  IsoValue = 21,
  ShortLabelScale = 22,
  ManifoldLevels = 23,
  HeaderSize = 24
};

enum FlagBits : uint8_t
{
  Reflect = 1,
  PixelKindBits = 2 | 4, // 0, 1: unsigned char; 2: short; 3: float with an iso-value
  SelectLabels = 8,
  RepeatVoxelBytes = 16,
  ShiftRegionStart = 32,
  MergeLabels = 64
};

/** The largest image side: small images keep each run short enough for thousands of runs a minute. */
constexpr unsigned int LargestSide = 16;
/** The largest vertex cap the input can ask for, for the same reason. */
constexpr unsigned int LargestVertexCap = 2000;

double
SpacingFromCode(uint8_t code)
{
  switch (code)
  {
    case 250:
      return 1e-3;
    case 251:
      return 1e3;
    case 252:
      return 0.1;
    case 253:
      return 37.0;
    default:
      // 0.25 mm to 8 mm, geometrically.
      return 0.25 * std::pow(2.0, (code % 250) / 50.0);
  }
}

/** δ: the special codes are the invalid and the extreme values; the rest 0.05 to 50 voxels, geometrically. */
double
DeltaFromCode(unsigned int code, double largestSpacing)
{
  switch (code)
  {
    case 0:
      return 0.0;
    case 1:
      return -1.0;
    case 2:
      return std::numeric_limits<double>::quiet_NaN();
    case 3:
      return std::numeric_limits<double>::infinity();
    case 4:
      return 1e-300;
    case 5:
      return 1e300;
    case 6:
      return std::numeric_limits<double>::denorm_min();
    default:
      return 0.05 * std::pow(1000.0, code / 65535.0) * largestSpacing;
  }
}

double
RhoFromCode(uint8_t code)
{
  switch (code)
  {
    case 0:
      return 0.5;
    case 1:
      return std::numeric_limits<double>::quiet_NaN();
    case 2:
      return std::numeric_limits<double>::infinity();
    case 3:
      return 1.0;
    case 4:
      return 1e6;
    default:
      return code < 128 ? 2.0 : 1.0 + (code - 128) / 127.0 * 3.0;
  }
}

double
SigmaFromCode(uint8_t code)
{
  switch (code)
  {
    case 251:
      return -1.0;
    case 252:
      return delaunay_refinement::ParameterLimits::LargestMinimumDihedralAngle + 1.0;
    case 253:
      return std::numeric_limits<double>::quiet_NaN();
    case 254:
      return delaunay_refinement::ParameterLimits::LargestMinimumDihedralAngle;
    case 255:
      return 1e-9;
    default:
      return code < 192 ? 0.0 : (code - 192) / 58.0 * delaunay_refinement::ParameterLimits::LargestMinimumDihedralAngle;
  }
}

using Matrix3 = std::array<std::array<double, 3>, 3>;

Matrix3
DirectionFromAngles(const uint8_t * angles, bool reflect)
{
  constexpr double step = 2.0 * 3.14159265358979323846 / 256.0;
  const double     a = angles[0] * step, b = angles[1] * step, c = angles[2] * step;
  const double     ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b), cc = std::cos(c),
               sc = std::sin(c);
  // Rz(c) Ry(b) Rx(a)
  Matrix3 m{ { { { cc * cb, cc * sb * sa - sc * ca, cc * sb * ca + sc * sa } },
               { { sc * cb, sc * sb * sa + cc * ca, sc * sb * ca - cc * sa } },
               { { -sb, cb * sa, cb * ca } } } };
  if (reflect)
  {
    for (auto & row : m)
    {
      row[0] = -row[0];
    }
  }
  return m;
}

/** What the header says, decoded. */
struct DecodedInput
{
  std::array<unsigned int, 3> size{};
  std::array<double, 3>       spacing{};
  std::array<double, 3>       origin{};
  Matrix3                     direction{};
  uint8_t                     flags{ 0 };
  int                         labelCount{ 1 };
  int                         shortLabelScale{ 1 };
  FilterSettings              settings;
  const uint8_t *             voxels{ nullptr };
  std::size_t                 numberOfVoxelBytes{ 0 };
};

DecodedInput
Decode(const uint8_t * data)
{
  DecodedInput input;
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    input.size[axis] = 1 + data[SizeX + axis] % LargestSide;
    input.spacing[axis] = SpacingFromCode(data[SpacingX + axis]);
    input.origin[axis] = 8.0 * static_cast<int8_t>(data[OriginX + axis]);
  }
  input.flags = data[Flags];
  input.direction = DirectionFromAngles(data + AngleX, input.flags & Reflect);
  input.labelCount = 1 + data[LabelCount] % 8;
  const int scale = static_cast<int8_t>(data[ShortLabelScale]);
  input.shortLabelScale = scale == 0 ? 1 : scale;

  FilterSettings & settings = input.settings;
  const double     largestSpacing = *std::max_element(input.spacing.begin(), input.spacing.end());
  settings.surfaceSamplingDistance = DeltaFromCode(data[DeltaLow] | data[DeltaHigh] << 8, largestSpacing);
  settings.radiusEdgeBound = RhoFromCode(data[Rho]);
  settings.minimumDihedralAngle = SigmaFromCode(data[Sigma]);
  settings.maximumNumberOfVertices = (data[VertexCapLow] | data[VertexCapHigh] << 8) % (LargestVertexCap + 1);
  if ((input.flags & SelectLabels) != 0)
  {
    for (int label = 0; label < 8; ++label)
    {
      if ((data[SelectedLabelMask] >> label) & 1)
      {
        settings.labels.push_back(label + 1);
      }
    }
  }
  settings.mergeLabels = (input.flags & MergeLabels) != 0;
  // 0 gives the filter's default, 3; 8 gives 11, one more than the valid [0, 10].
  settings.manifoldRefinementLevels = (data[ManifoldLevels] + 3u) % 12u;
  if ((input.flags & PixelKindBits) == PixelKindBits)
  {
    settings.isoValue = data[IsoValue] / 255.0;
    settings.labels.clear();
    settings.mergeLabels = false;
  }
  // libFuzzer's -timeout catches a hang; this limit only turns a very slow run into a report of its own.
  settings.timeLimitSeconds = 20.0;
  return input;
}

/** The voxel's label, 0 to labelCount, from its byte (bytes past the input are 0, or repeat the input). */
int
VoxelLabel(const DecodedInput & input, std::size_t voxel)
{
  if (input.numberOfVoxelBytes == 0)
  {
    return 0;
  }
  if (voxel >= input.numberOfVoxelBytes && (input.flags & RepeatVoxelBytes) == 0)
  {
    return 0;
  }
  return input.voxels[voxel % input.numberOfVoxelBytes] % (input.labelCount + 1);
}

template <typename TImage>
typename TImage::Pointer
MakeImage(const DecodedInput & input, const std::function<typename TImage::PixelType(std::size_t)> & pixelOf)
{
  std::array<itk::SizeValueType, 3>  size{};
  std::array<itk::IndexValueType, 3> start{};
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    size[axis] = input.size[axis];
    start[axis] = (input.flags & ShiftRegionStart) != 0 ? -3 + static_cast<int>(axis) : 0;
  }
  return MakeImageInSpace<TImage>(size, start, input.spacing, input.origin, input.direction, pixelOf);
}

bool
IsValid(const FilterSettings & settings)
{
  const double delta = settings.surfaceSamplingDistance;
  const double rho = settings.radiusEdgeBound;
  const double sigma = settings.minimumDihedralAngle;
  // δ beyond 1e30 mm overflows the geometry: the proposed fix of the fuzzer's first finding refuses it.
  return delta >= 0.0 && delta <= 1e30 && std::isfinite(rho) && rho >= 1.0 && sigma >= 0.0 &&
         sigma <= delaunay_refinement::ParameterLimits::LargestMinimumDihedralAngle &&
         settings.maximumNumberOfVertices >= 8 && settings.manifoldRefinementLevels <= 10;
}

[[noreturn]] void
Fail(const std::string & problem, const RunResult & result, const FilterSettings & settings)
{
  std::fprintf(stderr,
               "\n*** DelaunayImageToMeshFuzzer: %s\n    outcome: %s\n    message: %s\n    settings: %s\n"
               "    refinement: %s\n",
               problem.c_str(),
               OutcomeName(result.outcome),
               result.message.c_str(),
               Describe(settings).c_str(),
               result.refinement.c_str());
  for (const std::string & violation : result.violations)
  {
    std::fprintf(stderr, "    - %s\n", violation.c_str());
  }
  std::abort();
}

/** The outcome the input calls for where it can be told in advance, else that of a mesh that meets every
 * guarantee or a documented refusal. */
template <typename TImage>
void
RunAndVerify(const typename TImage::Pointer & image, const FilterSettings & settings)
{
  const RunResult result = RunAndCheck<TImage>(image, settings);
  if (!IsValid(settings))
  {
    if (result.outcome != Outcome::InvalidParameter)
    {
      Fail("invalid parameters were not refused", result, settings);
    }
    return;
  }
  const bool hasObject = !TissueLabelsOf(*image, settings).empty();
  switch (result.outcome)
  {
    case Outcome::Mesh:
      if (!result.violations.empty())
      {
        Fail("the mesh violates a guarantee", result, settings);
      }
      if (!hasObject)
      {
        Fail("a mesh although no voxel is selected", result, settings);
      }
      return;
    case Outcome::NoObjectVoxel:
      if (hasObject)
      {
        Fail("'no voxel selected' although voxels are", result, settings);
      }
      return;
    case Outcome::RegularizedAway: {
      // Not handled before issue #17 (the switch let it pass unchecked): the randomized suite's rule.
      const std::string contradiction = ContradictsRegularizedAway(*image, settings);
      if (!hasObject || !contradiction.empty())
      {
        Fail(hasObject ? contradiction : "'regularised away' although no voxel is selected", result, settings);
      }
      return;
    }
    case Outcome::NoTetrahedron:
      // The randomized suite's rule: only a segmentation with no part 2δ across may give no tetrahedron.
      if (result.thickComponents != 0)
      {
        Fail("'no tetrahedron' although " + result.firstThickComponent, result, settings);
      }
      [[fallthrough]];
    case Outcome::VertexLimit:
      if (!hasObject)
      {
        Fail("no voxel is selected, yet the filter did not say so", result, settings);
      }
      return;
    case Outcome::SliverRemovalWithoutEnd:
      if (!SliverRemovalMayNotEnd(settings))
      {
        Fail("sliver removal stopped by its budget with rho >= 2", result, settings);
      }
      return;
    case Outcome::InvalidParameter:
      Fail("valid parameters were refused", result, settings);
    case Outcome::Aborted:
      Fail(result.timedOut ? "no result within the time limit" : "aborted", result, settings);
    case Outcome::Unexpected:
      Fail("an undocumented exception", result, settings);
  }
}

} // namespace

extern "C" int
LLVMFuzzerInitialize(int *, char ***)
{
  // One thread: the runs are small, and a fuzzer's findings must reproduce exactly.
  itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(1);
  return 0;
}

extern "C" int
LLVMFuzzerTestOneInput(const uint8_t * data, std::size_t size)
{
  if (size < HeaderSize)
  {
    return 0;
  }
  DecodedInput input = Decode(data);
  input.voxels = data + HeaderSize;
  input.numberOfVoxelBytes = size - HeaderSize;
  switch ((input.flags & PixelKindBits) >> 1)
  {
    case 0:
    case 1:
      RunAndVerify<itk::Image<unsigned char, 3>>(
        MakeImage<itk::Image<unsigned char, 3>>(
          input, [&](std::size_t voxel) { return static_cast<unsigned char>(VoxelLabel(input, voxel)); }),
        input.settings);
      break;
    case 2:
      RunAndVerify<itk::Image<short, 3>>(
        MakeImage<itk::Image<short, 3>>(
          input,
          [&](std::size_t voxel) { return static_cast<short>(VoxelLabel(input, voxel) * input.shortLabelScale); }),
        input.settings);
      break;
    default:
      // Gray values: the voxel byte itself, scaled to [0, 1], against the iso-value.
      RunAndVerify<itk::Image<float, 3>>(
        MakeImage<itk::Image<float, 3>>(input,
                                        [&](std::size_t voxel) {
                                          return input.numberOfVoxelBytes == 0 ? 0.0f
                                                 : (voxel < input.numberOfVoxelBytes ||
                                                    (input.flags & RepeatVoxelBytes) != 0)
                                                   ? input.voxels[voxel % input.numberOfVoxelBytes] / 255.0f
                                                   : 0.0f;
                                        }),
        input.settings);
      break;
  }
  return 0;
}
