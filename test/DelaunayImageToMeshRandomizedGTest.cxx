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

// Randomized tests of itk::DelaunayImageToMeshFilter (issue #5): thousands of small label images built in
// memory from fixed seeds (blobs, noise, one-voxel sheets and lines, single voxels, many labels, objects on
// the border, thin images, and gray fields of bumps and noise cut at an iso-value), in random physical space
// (anisotropic spacing, oblique and reflected directions, far origins), meshed with δ from 0.3 to 20 voxels. Every run
// must end in a mesh that meets every guarantee, or in one of the filter's documented exceptions where the voxels say
// it applies; never in another exception, a crash or a hang. The rules are read from the voxels, not from the mesher
// (issue #17): "no tetrahedron" only when no component of the meshed segmentation is 2δ across, every component that
// thick holds a tetrahedron of its label, the boundary lies within δ of the voxels' surface and back within a bound,
// "vertex limit" only at a cap the case chose itself; and each family must end in a mesh in a minimum share of its
// cases.
//
// Reproducing one case: DELAUNAY_RANDOMIZED_SEED=<seed> ./DelaunayImageToMeshRandomizedGTests
//   --gtest_filter='*<Family>*' runs that seed alone and prints it. DELAUNAY_RANDOMIZED_CASES=<n> changes the
// number of cases per family (longer soak runs), and DELAUNAY_RANDOMIZED_FIRST_CASE=<k> skips the first k of each
// family's seeds, so that a wider search goes on where an earlier one stopped instead of running its cases again.

#include "DelaunayImageToMeshRandomizedChecks.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <map>
#include <random>
#include <tuple>

namespace
{

using namespace itk::delaunay_image_to_mesh_randomized;
using ShortImageType = itk::Image<short, 3>;
using UnsignedCharImageType = itk::Image<unsigned char, 3>;
using FloatImageType = itk::Image<float, 3>;

using Matrix3 = std::array<std::array<double, 3>, 3>;

dr::Vector3
Multiply(const Matrix3 & matrix, const dr::Vector3 & vector)
{
  dr::Vector3 result{ { 0.0, 0.0, 0.0 } };
  for (int row = 0; row < 3; ++row)
  {
    for (int column = 0; column < 3; ++column)
    {
      result[row] += matrix[row][column] * vector[column];
    }
  }
  return result;
}

// ---- Label canvases: the voxels of a case, painted in index space --------------------------------------

struct Canvas
{
  std::array<int, 3> size{ { 1, 1, 1 } };
  std::vector<int>   labels;

  explicit Canvas(const std::array<int, 3> & canvasSize)
    : size(canvasSize)
    , labels(static_cast<std::size_t>(canvasSize[0]) * canvasSize[1] * canvasSize[2], 0)
  {}

  bool
  IsInside(const std::array<int, 3> & index) const
  {
    return index[0] >= 0 && index[1] >= 0 && index[2] >= 0 && index[0] < size[0] && index[1] < size[1] &&
           index[2] < size[2];
  }

  int &
  At(const std::array<int, 3> & index)
  {
    return labels[static_cast<std::size_t>(index[0] + size[0] * (index[1] + size[1] * index[2]))];
  }

  int
  At(const std::array<int, 3> & index) const
  {
    return labels[static_cast<std::size_t>(index[0] + size[0] * (index[1] + size[1] * index[2]))];
  }

  template <typename TFunction>
  void
  ForEachVoxel(TFunction && function)
  {
    for (int z = 0; z < size[2]; ++z)
    {
      for (int y = 0; y < size[1]; ++y)
      {
        for (int x = 0; x < size[0]; ++x)
        {
          function(std::array<int, 3>{ { x, y, z } });
        }
      }
    }
  }

  dr::Vector3
  RandomPoint(CaseRandom & random, double outside) const
  {
    return { { random.Uniform(-outside, size[0] - 1 + outside),
               random.Uniform(-outside, size[1] - 1 + outside),
               random.Uniform(-outside, size[2] - 1 + outside) } };
  }

  int
  SmallestSide() const
  {
    return std::min({ size[0], size[1], size[2] });
  }
};

dr::Vector3
ToVector(const std::array<int, 3> & index)
{
  return { { static_cast<double>(index[0]), static_cast<double>(index[1]), static_cast<double>(index[2]) } };
}

/** A rotated ellipsoid, possibly reaching beyond the canvas. */
void
PaintEllipsoid(Canvas & canvas, CaseRandom & random, int label, double outside = 1.0)
{
  const dr::Vector3 center = canvas.RandomPoint(random, outside);
  const double      largest = std::max(0.8, 0.5 * std::max({ canvas.size[0], canvas.size[1], canvas.size[2] }));
  const dr::Vector3 radii{
    { random.Uniform(0.6, largest), random.Uniform(0.6, largest), random.Uniform(0.6, largest) }
  };
  const Matrix3 rotation = random.Rotation();
  canvas.ForEachVoxel([&](const std::array<int, 3> & index) {
    const dr::Vector3 local = Multiply(rotation, ToVector(index) - center);
    double            sum = 0.0;
    for (int axis = 0; axis < 3; ++axis)
    {
      sum += (local[axis] / radii[axis]) * (local[axis] / radii[axis]);
    }
    if (sum <= 1.0)
    {
      canvas.At(index) = label;
    }
  });
}

/** A one-voxel-thick digital plane (axis-aligned or oblique), whole or cut to a disc. */
void
PaintSheet(Canvas & canvas, CaseRandom & random, int label)
{
  dr::Vector3 normal{ { 0.0, 0.0, 0.0 } };
  if (random.Chance(0.5))
  {
    normal[random.Integer(0, 2)] = 1.0;
  }
  else
  {
    normal = Multiply(random.Rotation(), { { 1.0, 0.0, 0.0 } });
  }
  const double      thickness = std::max({ std::abs(normal[0]), std::abs(normal[1]), std::abs(normal[2]) });
  const dr::Vector3 center = canvas.RandomPoint(random, 0.0);
  const double      discRadius = random.Chance(0.5) ? random.Uniform(1.0, canvas.size[0]) : 1e9;
  canvas.ForEachVoxel([&](const std::array<int, 3> & index) {
    const dr::Vector3 offset = ToVector(index) - center;
    const double      height = dr::Dot(offset, normal);
    // The naive digital plane, |n . x| < max|n_i| / 2, is exactly one voxel thick along its dominant axis.
    if (std::abs(height) < 0.5 * thickness && dr::Norm(offset - height * normal) <= discRadius)
    {
      canvas.At(index) = label;
    }
  });
}

/** A one-voxel-thick digital segment. */
void
PaintLine(Canvas & canvas, CaseRandom & random, int label)
{
  const dr::Vector3 from = canvas.RandomPoint(random, 0.0);
  const dr::Vector3 to = canvas.RandomPoint(random, 0.0);
  const int         steps = 1 + static_cast<int>(4.0 * dr::Distance(from, to));
  for (int step = 0; step <= steps; ++step)
  {
    const dr::Vector3        point = from + (static_cast<double>(step) / steps) * (to - from);
    const std::array<int, 3> index{ { static_cast<int>(std::lround(point[0])),
                                      static_cast<int>(std::lround(point[1])),
                                      static_cast<int>(std::lround(point[2])) } };
    if (canvas.IsInside(index))
    {
      canvas.At(index) = label;
    }
  }
}

std::array<int, 3>
RandomVoxel(const Canvas & canvas, CaseRandom & random)
{
  return { { random.Integer(0, canvas.size[0] - 1),
             random.Integer(0, canvas.size[1] - 1),
             random.Integer(0, canvas.size[2] - 1) } };
}

/** Salt and pepper: each voxel, with probability `density`, becomes one of `labels` (0 = pepper). */
void
PaintNoise(Canvas & canvas, CaseRandom & random, double density, const std::vector<int> & labels)
{
  canvas.ForEachVoxel([&](const std::array<int, 3> & index) {
    if (random.Chance(density))
    {
      canvas.At(index) = random.Pick(labels);
    }
  });
}

/** Tissues that fill a region and touch each other: the nearest of a few random seeds gives the label. */
void
PaintVoronoiTissues(Canvas & canvas, CaseRandom & random, const std::vector<int> & labels, bool wholeCanvas)
{
  std::vector<std::pair<dr::Vector3, int>> seeds;
  const int                                numberOfSeeds = random.Integer(2, 10);
  for (int i = 0; i < numberOfSeeds; ++i)
  {
    seeds.emplace_back(canvas.RandomPoint(random, 0.0), random.Pick(labels));
  }
  const dr::Vector3 center = canvas.RandomPoint(random, 0.0);
  const double      radius = random.Uniform(2.0, canvas.size[0]);
  canvas.ForEachVoxel([&](const std::array<int, 3> & index) {
    const dr::Vector3 point = ToVector(index);
    if (!wholeCanvas && dr::Distance(point, center) > radius)
    {
      return;
    }
    const auto nearest = std::min_element(seeds.begin(), seeds.end(), [&point](const auto & a, const auto & b) {
      return dr::SquaredNorm(a.first - point) < dr::SquaredNorm(b.first - point);
    });
    canvas.At(index) = nearest->second;
  });
}

// ---- Cases ----------------------------------------------------------------------------------------------

enum class Family
{
  Blobs,
  SaltAndPepper,
  SheetsAndLines,
  SingleVoxels,
  ManyLabels,
  BorderTouching,
  ThinImages,
  Mixed,
  IsoSurfaces
};

const char *
FamilyName(Family family)
{
  switch (family)
  {
    case Family::Blobs:
      return "Blobs";
    case Family::SaltAndPepper:
      return "SaltAndPepper";
    case Family::SheetsAndLines:
      return "SheetsAndLines";
    case Family::SingleVoxels:
      return "SingleVoxels";
    case Family::ManyLabels:
      return "ManyLabels";
    case Family::BorderTouching:
      return "BorderTouching";
    case Family::ThinImages:
      return "ThinImages";
    case Family::Mixed:
      return "Mixed";
    case Family::IsoSurfaces:
      return "IsoSurfaces";
  }
  return "?";
}

enum class PixelKind
{
  UnsignedChar,
  Short,
  FloatIsoValue
};

struct Geometry
{
  std::array<double, 3> spacing{ { 1.0, 1.0, 1.0 } };
  dr::Vector3           origin{ { 0.0, 0.0, 0.0 } };
  Matrix3               direction{ { { { 1.0, 0.0, 0.0 } }, { { 0.0, 1.0, 0.0 } }, { { 0.0, 0.0, 1.0 } } } };
};

struct RandomCase
{
  uint64_t       seed{ 0 };
  Family         family{ Family::Blobs };
  Canvas         canvas{ { { 1, 1, 1 } } };
  Geometry       geometry;
  PixelKind      pixelKind{ PixelKind::UnsignedChar };
  FilterSettings settings;
  std::string    content;
};

std::string
Describe(const RandomCase & randomCase)
{
  std::ostringstream text;
  text.precision(6);
  const Geometry & g = randomCase.geometry;
  text << FamilyName(randomCase.family) << " seed " << randomCase.seed << " (" << randomCase.content << ", "
       << randomCase.canvas.size[0] << "x" << randomCase.canvas.size[1] << "x" << randomCase.canvas.size[2] << ", "
       << (randomCase.pixelKind == PixelKind::Short          ? "short"
           : randomCase.pixelKind == PixelKind::UnsignedChar ? "unsigned char"
                                                             : "float, iso-value")
       << ", spacing " << g.spacing[0] << " " << g.spacing[1] << " " << g.spacing[2] << ", origin " << g.origin[0]
       << " " << g.origin[1] << " " << g.origin[2] << ", direction rows";
  for (const auto & row : g.direction)
  {
    text << " [" << row[0] << " " << row[1] << " " << row[2] << "]";
  }
  text << ", " << Describe(randomCase.settings) << ")";
  return text.str();
}

/** Describe() and the topology settings, which the recorded cases' fingerprints leave out: what a person needs to
 * reproduce the case. */
std::string
DescribeToReproduce(const RandomCase & randomCase)
{
  return Describe(randomCase) + " (" + DescribeTopologySettings(randomCase.settings) + ")";
}

Geometry
RandomGeometry(CaseRandom & random)
{
  Geometry     geometry;
  const bool   isotropic = random.Chance(0.3);
  const double commonSpacing = random.LogUniform(0.5, 3.0);
  for (int axis = 0; axis < 3; ++axis)
  {
    geometry.spacing[axis] = isotropic ? commonSpacing : random.LogUniform(0.5, 3.0);
    geometry.origin[axis] = random.Chance(0.2) ? 0.0 : random.Uniform(-200.0, 200.0);
  }
  const double directionKind = random.Uniform(0.0, 1.0);
  if (directionKind < 0.6)
  {
    geometry.direction = random.Rotation();
  }
  else if (directionKind < 0.75)
  {
    // A reflection: a left-handed voxel frame, as some scanners write.
    geometry.direction = random.Rotation();
    const int flipped = random.Integer(0, 2);
    for (int row = 0; row < 3; ++row)
    {
      geometry.direction[row][flipped] = -geometry.direction[row][flipped];
    }
  }
  return geometry;
}

std::array<int, 3>
RandomSize(CaseRandom & random, int smallest, int largest)
{
  return {
    { random.Integer(smallest, largest), random.Integer(smallest, largest), random.Integer(smallest, largest) }
  };
}

/** Tissue labels a pixel type can hold: unsigned char 1..8 (and sometimes 255); short also negative and
 * extreme values. */
std::vector<int>
RandomLabelPool(CaseRandom & random, PixelKind pixelKind, int count)
{
  std::vector<int> pool;
  for (int i = 1; i <= count; ++i)
  {
    pool.push_back(i);
  }
  if (pixelKind == PixelKind::Short && random.Chance(0.3))
  {
    pool.back() = random.Pick(std::vector<int>{ -1, -7, 32767, -32768, 1000 });
  }
  else if (pixelKind == PixelKind::UnsignedChar && random.Chance(0.1))
  {
    pool.back() = 255;
  }
  return pool;
}

/** The gray levels of the IsoSurfaces family, 0 to IsoSurfaceLevels (the image holds level / IsoSurfaceLevels). */
constexpr int IsoSurfaceLevels = 1000;

/** A smooth random field with noise, as gray levels: an offset, a few Gaussian bumps and dips (some narrower than a
 * voxel, some crossing the canvas's border), and voxel noise of up to a quarter of the range; an iso-value in (0.1, 1)
 * then cuts blobs, necks, holes and speckle out of it. */
void
PaintGrayField(Canvas & canvas, CaseRandom & random)
{
  struct Bump
  {
    std::array<double, 3> center;
    double                width;
    double                height;
  };
  std::vector<Bump> bumps(static_cast<std::size_t>(random.Integer(2, 8)));
  for (Bump & bump : bumps)
  {
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      bump.center[axis] = random.Uniform(-0.1, 1.1) * canvas.size[axis];
    }
    bump.width = random.LogUniform(0.6, 8.0);
    bump.height = random.Chance(0.25) ? random.Uniform(-0.8, -0.2) : random.Uniform(0.4, 1.6);
  }
  const double offset = random.Uniform(0.0, 0.3);
  const double noise = random.Chance(0.3) ? 0.0 : random.Uniform(0.0, 0.25);
  for (int k = 0; k < canvas.size[2]; ++k)
  {
    for (int j = 0; j < canvas.size[1]; ++j)
    {
      for (int i = 0; i < canvas.size[0]; ++i)
      {
        double value = offset + random.Uniform(-noise, noise);
        for (const Bump & bump : bumps)
        {
          const double dx = i - bump.center[0];
          const double dy = j - bump.center[1];
          const double dz = k - bump.center[2];
          value += bump.height * std::exp(-(dx * dx + dy * dy + dz * dz) / (2.0 * bump.width * bump.width));
        }
        canvas.At({ { i, j, k } }) =
          static_cast<int>(std::lround(std::clamp(value, 0.0, 1.0) * static_cast<double>(IsoSurfaceLevels)));
      }
    }
  }
}

void
PaintContent(RandomCase & randomCase, CaseRandom & random)
{
  Canvas &               canvas = randomCase.canvas;
  const std::vector<int> labels = RandomLabelPool(random, randomCase.pixelKind, random.Integer(1, 3));
  std::vector<int>       noiseLabels = labels;
  noiseLabels.push_back(0);
  switch (randomCase.family)
  {
    case Family::Blobs: {
      const int blobs = random.Integer(1, 4);
      for (int i = 0; i < blobs; ++i)
      {
        PaintEllipsoid(canvas, random, random.Pick(labels));
      }
      randomCase.content = std::to_string(blobs) + " ellipsoids";
      break;
    }
    case Family::SaltAndPepper: {
      const double density = random.LogUniform(0.01, 0.6);
      if (random.Chance(0.5))
      {
        PaintEllipsoid(canvas, random, labels.front());
        randomCase.content = "ellipsoid + ";
      }
      PaintNoise(canvas, random, density, noiseLabels);
      randomCase.content += "salt and pepper, density " + std::to_string(density);
      break;
    }
    case Family::SheetsAndLines: {
      const int sheets = random.Integer(0, 2);
      const int lines = random.Integer(sheets == 0 ? 1 : 0, 3);
      for (int i = 0; i < sheets; ++i)
      {
        PaintSheet(canvas, random, random.Pick(labels));
      }
      for (int i = 0; i < lines; ++i)
      {
        PaintLine(canvas, random, random.Pick(labels));
      }
      randomCase.content = std::to_string(sheets) + " sheets, " + std::to_string(lines) + " lines";
      break;
    }
    case Family::SingleVoxels: {
      const int voxels = random.Chance(0.5) ? 1 : random.Integer(2, 6);
      for (int i = 0; i < voxels; ++i)
      {
        canvas.At(RandomVoxel(canvas, random)) = random.Pick(labels);
      }
      randomCase.content = std::to_string(voxels) + " single voxels";
      break;
    }
    case Family::ManyLabels: {
      const std::vector<int> many = RandomLabelPool(random, randomCase.pixelKind, random.Integer(4, 8));
      PaintVoronoiTissues(canvas, random, many, random.Chance(0.3));
      const int blobs = random.Integer(0, 3);
      for (int i = 0; i < blobs; ++i)
      {
        PaintEllipsoid(canvas, random, random.Pick(many));
      }
      randomCase.content =
        std::to_string(many.size()) + " labels, Voronoi tissues + " + std::to_string(blobs) + " ellipsoids";
      break;
    }
    case Family::BorderTouching: {
      const double kind = random.Uniform(0.0, 1.0);
      if (kind < 0.15)
      {
        canvas.ForEachVoxel([&](const std::array<int, 3> & index) { canvas.At(index) = labels.front(); });
        randomCase.content = "whole image one label";
      }
      else if (kind < 0.4)
      {
        const int  axis = random.Integer(0, 2);
        const int  depth = random.Integer(1, std::max(1, canvas.size[axis] / 2));
        const bool atEnd = random.Chance(0.5);
        canvas.ForEachVoxel([&](const std::array<int, 3> & index) {
          if (atEnd ? index[axis] >= canvas.size[axis] - depth : index[axis] < depth)
          {
            canvas.At(index) = labels.front();
          }
        });
        randomCase.content = "slab on a face, " + std::to_string(depth) + " voxels deep";
      }
      else
      {
        const int blobs = random.Integer(1, 3);
        for (int i = 0; i < blobs; ++i)
        {
          PaintEllipsoid(canvas, random, random.Pick(labels), 4.0);
        }
        randomCase.content = std::to_string(blobs) + " ellipsoids centred near or beyond the border";
      }
      break;
    }
    case Family::ThinImages: {
      PaintEllipsoid(canvas, random, labels.front());
      if (random.Chance(0.5))
      {
        PaintNoise(canvas, random, random.Uniform(0.05, 0.5), noiseLabels);
      }
      randomCase.content = "thin image, ellipsoid and maybe noise";
      break;
    }
    case Family::Mixed: {
      const std::vector<int> many = RandomLabelPool(random, randomCase.pixelKind, random.Integer(1, 8));
      std::vector<int>       manyWithBackground = many;
      manyWithBackground.push_back(0);
      const int blobs = random.Integer(0, 3);
      for (int i = 0; i < blobs; ++i)
      {
        PaintEllipsoid(canvas, random, random.Pick(many), 3.0);
      }
      if (random.Chance(0.5))
      {
        PaintSheet(canvas, random, random.Pick(many));
      }
      if (random.Chance(0.5))
      {
        PaintLine(canvas, random, random.Pick(many));
      }
      if (random.Chance(0.3))
      {
        PaintNoise(canvas, random, random.LogUniform(0.005, 0.3), manyWithBackground);
      }
      randomCase.content = "mixed: " + std::to_string(blobs) + " ellipsoids, sheet/line/noise";
      break;
    }
    case Family::IsoSurfaces:
      PaintGrayField(canvas, random);
      randomCase.content = "gray field: Gaussian bumps and noise";
      break;
  }
}

std::vector<int>
PresentLabels(const Canvas & canvas)
{
  std::set<int> present(canvas.labels.begin(), canvas.labels.end());
  present.erase(0);
  return { present.begin(), present.end() };
}

/** Sometimes mesh only some labels (maybe none that is present, maybe one that is absent). */
void
MaybeSelectLabels(RandomCase & randomCase, CaseRandom & random)
{
  const std::vector<int> present = PresentLabels(randomCase.canvas);
  if (randomCase.pixelKind == PixelKind::FloatIsoValue || !random.Chance(0.2))
  {
    return;
  }
  for (const int label : present)
  {
    if (random.Chance(0.5))
    {
      randomCase.settings.labels.push_back(label);
    }
  }
  if (random.Chance(0.3))
  {
    randomCase.settings.labels.push_back(random.Chance(0.5) ? 77 : 0);
  }
}

/** Whether σ is the filter's default: a case that drew no σ of its own (a drawn one is never exactly the default). */
bool
IsTheDefaultMinimumDihedralAngle(double sigma)
{
  return sigma == dr::RefinementParameters{}.minimumDihedralAngle;
}

void
ChooseParameters(RandomCase & randomCase, CaseRandom & random)
{
  FilterSettings & settings = randomCase.settings;
  const auto &     spacing = randomCase.geometry.spacing;
  const double     largestSpacing = *std::max_element(spacing.begin(), spacing.end());
  // Mostly δ of a few voxels, where meshes are made; a quarter large, where "too small for delta" is expected.
  // No finer than 1/40 of the image's largest side: finer meshes only cost time (the vertex cap stops them).
  const int largestSide = std::max({ randomCase.canvas.size[0], randomCase.canvas.size[1], randomCase.canvas.size[2] });
  const double finest = std::max(0.3, largestSide / 40.0);
  const double deltaInVoxels = random.Chance(0.75) ? random.LogUniform(finest, 3.0) : random.LogUniform(3.0, 20.0);
  settings.surfaceSamplingDistance = random.Chance(0.05) ? 0.0 : deltaInVoxels * largestSpacing;
  if (random.Chance(0.3))
  {
    settings.radiusEdgeBound = random.Chance(0.15) ? 1.0 : random.Uniform(1.0, 4.0);
  }
  if (randomCase.family == Family::Mixed && random.Chance(0.15))
  {
    settings.minimumDihedralAngle = random.Uniform(1.0, 20.0);
  }
  if (randomCase.family == Family::Mixed && random.Chance(0.1))
  {
    settings.maximumNumberOfVertices = static_cast<itk::SizeValueType>(random.Integer(8, 300));
  }
  if (randomCase.family == Family::Mixed && random.Chance(0.2))
  {
    settings.manifoldRefinementLevels = static_cast<unsigned int>(random.Integer(0, 5));
  }
  if (randomCase.pixelKind == PixelKind::FloatIsoValue)
  {
    settings.isoValue = random.Uniform(0.1, 1.0);
  }
  MaybeSelectLabels(randomCase, random);
  settings.mergeLabels = randomCase.family == Family::Mixed && !settings.isoValue && random.Chance(0.1);
  // Drawn last, so that the other settings of each seed stay what they were before the option existed.
  settings.joinDiagonalVoxels = !random.Chance(0.2);
  settings.regularizationScale = random.Chance(0.2) ? 0.0 : settings.regularizationScale;
  // The defaults remove slivers (σ = 10°); a quarter of the cases that did not draw σ run the paper's method, whose
  // bounds are proven and checked in full (Lemma 2's edges among them).
  if (random.Chance(0.25) && IsTheDefaultMinimumDihedralAngle(settings.minimumDihedralAngle))
  {
    settings.minimumDihedralAngle = 0.0;
  }
}

RandomCase
MakeCase(Family family, uint64_t seed)
{
  CaseRandom random(seed);
  RandomCase randomCase;
  randomCase.seed = seed;
  randomCase.family = family;
  const double pixelDraw = random.Uniform(0.0, 1.0);
  randomCase.pixelKind = pixelDraw < 0.5 ? PixelKind::UnsignedChar : PixelKind::Short;
  if ((family == Family::Mixed && pixelDraw > 0.9) || family == Family::IsoSurfaces)
  {
    randomCase.pixelKind = PixelKind::FloatIsoValue;
  }
  std::array<int, 3> size = RandomSize(random, 6, 24);
  if (family == Family::ThinImages)
  {
    size = RandomSize(random, 1, 12);
    size[random.Integer(0, 2)] = random.Integer(1, 3);
  }
  randomCase.canvas = Canvas(size);
  randomCase.geometry = RandomGeometry(random);
  PaintContent(randomCase, random);
  ChooseParameters(randomCase, random);
  return randomCase;
}

/** The case of `seed` as the regression tests recorded it, before sliver removal became the default (issue #15): a
 * case that drew no σ of its own ran without it. */
RandomCase
MakeRecordedCase(Family family, uint64_t seed)
{
  RandomCase randomCase = MakeCase(family, seed);
  if (IsTheDefaultMinimumDihedralAngle(randomCase.settings.minimumDihedralAngle))
  {
    randomCase.settings.minimumDihedralAngle = 0.0;
  }
  return randomCase;
}

// ---- Running a case -------------------------------------------------------------------------------------

template <typename TImage>
typename TImage::Pointer
MakeImage(const RandomCase & randomCase, const std::function<typename TImage::PixelType(int)> & toPixel)
{
  std::array<itk::SizeValueType, 3>  size{};
  std::array<itk::IndexValueType, 3> start{};
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    size[axis] = static_cast<itk::SizeValueType>(randomCase.canvas.size[axis]);
    // A non-zero region start: the index must not be assumed to begin at 0.
    start[axis] = static_cast<itk::IndexValueType>(randomCase.seed % 3) - 1;
  }
  const Geometry & geometry = randomCase.geometry;
  return MakeImageInSpace<TImage>(
    size, start, geometry.spacing, geometry.origin, geometry.direction, [&](std::size_t voxel) {
      return toPixel(randomCase.canvas.labels[voxel]);
    });
}

/** The δ the filter uses for the case: its own, or the filter's automatic 4 x the largest spacing. */
double
EffectiveDelta(const RandomCase & randomCase)
{
  return randomCase.settings.surfaceSamplingDistance > 0.0
           ? randomCase.settings.surfaceSamplingDistance
           : 4.0 * *std::max_element(randomCase.geometry.spacing.begin(), randomCase.geometry.spacing.end());
}

struct CaseReport
{
  RunResult                result;
  std::vector<std::string> problems;
};

/** Runs a case and lists what is wrong with its outcome: a guarantee violated, an undocumented exception, or
 * a documented one where the image says it cannot apply. */
template <typename TImage>
CaseReport
RunCase(const RandomCase & randomCase, const typename TImage::Pointer & image)
{
  CaseReport report;
  report.result = RunAndCheck<TImage>(image, randomCase.settings);
  const RunResult &         result = report.result;
  const std::set<dr::Label> tissues = TissueLabelsOf(*image, randomCase.settings);
  report.problems = result.violations;
  const auto problem = [&report](const std::string & text) { report.problems.push_back(text); };
  switch (result.outcome)
  {
    case Outcome::Mesh:
      if (tissues.empty())
      {
        problem("no voxel is selected, yet the filter did not say so");
      }
      break;
    case Outcome::VertexLimit:
      // The suite's cap (FilterSettings) is far above what any of its images needs at its δ: reaching it is a
      // runaway refinement. Only a cap the case chose itself may stop a run, and the sliver removal where it is
      // documented not to end (as for SliverRemovalWithoutEnd below), when the filter says that it reached the cap.
      if (randomCase.settings.maximumNumberOfVertices >= FilterSettings{}.maximumNumberOfVertices &&
          !(SliverRemovalMayNotEnd(randomCase.settings) && IsReachedBySliverRemoval(result.message)))
      {
        problem("the vertex cap " + std::to_string(randomCase.settings.maximumNumberOfVertices) +
                " was reached: " + result.message);
      }
      break;
    case Outcome::SliverRemovalWithoutEnd:
      if (!SliverRemovalMayNotEnd(randomCase.settings))
      {
        problem("exception: " + result.message);
      }
      break;
    case Outcome::NoObjectVoxel:
      if (!tissues.empty())
      {
        problem("'no voxel selected' although the image holds the labels " + DescribeLabels(tissues));
      }
      break;
    case Outcome::NoTetrahedron:
      // Only a segmentation with no part a δ across may give no tetrahedron (counted from the voxels the filter
      // meshed, after its regularisation; ThickComponentRadius()).
      if (result.thickComponents != 0)
      {
        problem("'no tetrahedron' although " + result.firstThickComponent);
      }
      break;
    case Outcome::RegularizedAway: {
      const std::string contradiction = ContradictsRegularizedAway(*image, randomCase.settings);
      if (!contradiction.empty())
      {
        problem(contradiction);
      }
      break;
    }
    case Outcome::InvalidParameter:
    case Outcome::Unexpected:
      problem("exception: " + result.message);
      break;
    case Outcome::Aborted:
      problem(result.timedOut ? "no result within " + std::to_string(randomCase.settings.timeLimitSeconds) + " s"
                              : "aborted: " + result.message);
      break;
  }
  return report;
}

CaseReport
RunCase(const RandomCase & randomCase)
{
  switch (randomCase.pixelKind)
  {
    case PixelKind::UnsignedChar:
      return RunCase<UnsignedCharImageType>(randomCase, MakeImage<UnsignedCharImageType>(randomCase, [](int label) {
                                              return static_cast<unsigned char>(label);
                                            }));
    case PixelKind::Short:
      return RunCase<ShortImageType>(
        randomCase, MakeImage<ShortImageType>(randomCase, [](int label) { return static_cast<short>(label); }));
    case PixelKind::FloatIsoValue:
      break;
  }
  // Gray values: the IsoSurfaces family's levels; elsewhere 1 inside every object, 0 outside. The iso-value decides
  // where the surface lies in between.
  if (randomCase.family == Family::IsoSurfaces)
  {
    return RunCase<FloatImageType>(randomCase, MakeImage<FloatImageType>(randomCase, [](int level) {
                                     return static_cast<float>(level) / static_cast<float>(IsoSurfaceLevels);
                                   }));
  }
  return RunCase<FloatImageType>(
    randomCase, MakeImage<FloatImageType>(randomCase, [](int label) { return label != 0 ? 1.0f : 0.0f; }));
}

/** Runs a case that must mesh and pass every check of the suite (a regression case); its report, for more checks. */
CaseReport
ExpectMeshPassingEveryCheck(const RandomCase & randomCase)
{
  CaseReport report = RunCase(randomCase);
  EXPECT_EQ(report.result.outcome, Outcome::Mesh) << report.result.message;
  EXPECT_TRUE(report.problems.empty()) << report.problems.front();
  return report;
}

// ---- The suite ------------------------------------------------------------------------------------------

struct FamilySummary
{
  std::size_t                    cases{ 0 };
  std::map<Outcome, std::size_t> outcomes;
  std::size_t                    failures{ 0 };
  double                         seconds{ 0.0 };
  double                         slowestSeconds{ 0.0 };
  uint64_t                       slowestSeed{ 0 };
  std::size_t                    largestMesh{ 0 };
  /** Meshes holding a tetrahedron flat to rounding (volume <= 1e-6 × shortest edge cubed), unusable in FEM: issue
   * #15's bar. Each such mesh also fails its case (a violation); counted here to show the bar at a glance. */
  std::size_t meshesWithFlatTetrahedra{ 0 };
  double      smallestDihedralAngle{ 180.0 };
  /** Of the meshes with nearest-neighbour labels: the largest distances, in δ, between boundary and voxels. */
  std::vector<double> meshToSegmentation;
  std::vector<double> segmentationToMesh;
  /** Components of the regularised labels without a tetrahedron (thinner than ThickComponentRadius(): the others
   * fail their case), each listed by the filter. */
  std::size_t unmeshedComponents{ 0 };
  /** Meshes with σ > 0 and ρ >= 2 whose boundary has a vertex that is not a feature vertex (Lemma 5 is not promised
   * there, CheckBoundaryGuarantees), and how many of them had a forced R4′ split. */
  std::size_t meshesWithFreeBoundaryVertices{ 0 };
  std::size_t meshesWithFreeBoundaryVerticesAndForcedSplits{ 0 };
  /** Meshes whose every boundary must be a closed manifold (IsPromisedManifold); meshes with a boundary that is not
   * (CheckManifoldBoundaries: never a promised one, and each admitted by the filter, else the case fails), and of
   * them those with the topology defaults. */
  std::size_t meshesPromisedManifold{ 0 };
  std::size_t meshesNotManifold{ 0 };
  std::size_t meshesNotManifoldWithTopologyDefaults{ 0 };
};

/** "median / 95th percentile / 99th percentile / maximum" of some values. */
std::string
DescribeDistribution(std::vector<double> values)
{
  if (values.empty())
  {
    return "none";
  }
  std::sort(values.begin(), values.end());
  const auto at = [&values](double fraction) {
    return values[static_cast<std::size_t>(fraction * static_cast<double>(values.size() - 1))];
  };
  std::ostringstream text;
  text << std::setprecision(3) << at(0.5) << " / " << at(0.95) << " / " << at(0.99) << " / " << values.back();
  return text.str();
}

std::map<Family, FamilySummary> &
SummaryOfTheRun()
{
  static std::map<Family, FamilySummary> summaries;
  return summaries;
}

void
PrintSummary(std::ostream & stream, const std::string & title, const FamilySummary & summary)
{
  stream << title << ": " << summary.cases << " cases in " << std::fixed << std::setprecision(1) << summary.seconds
         << " s (slowest " << std::setprecision(2) << summary.slowestSeconds << " s, seed " << summary.slowestSeed
         << "; largest mesh " << summary.largestMesh << " tetrahedra), " << summary.failures << " failing\n"
         << "    meshes with a tetrahedron flat to rounding (volume <= 1e-6 x shortest edge cubed): "
         << summary.meshesWithFlatTetrahedra << "; smallest dihedral angle " << std::setprecision(3)
         << summary.smallestDihedralAngle << " deg\n"
         << "    largest distance in delta (median / p95 / p99 / max), boundary to voxels: "
         << DescribeDistribution(summary.meshToSegmentation)
         << "; thick parts' surface to boundary: " << DescribeDistribution(summary.segmentationToMesh) << "\n"
         << "    components thinner than the thick ones without a tetrahedron, listed by the filter "
         << summary.unmeshedComponents << "\n"
         << "    sigma > 0: meshes with a free vertex on a boundary (Lemma 5 not promised) "
         << summary.meshesWithFreeBoundaryVertices << ", of them with a forced R4' split "
         << summary.meshesWithFreeBoundaryVerticesAndForcedSplits << "\n"
         << "    meshes promised a closed manifold boundary " << summary.meshesPromisedManifold
         << "; meshes with a boundary not a closed manifold (admitted by the filter) " << summary.meshesNotManifold
         << ", of them with the topology defaults " << summary.meshesNotManifoldWithTopologyDefaults << "\n";
  for (const auto & entry : summary.outcomes)
  {
    stream << "    " << std::setw(6) << entry.second << "  " << OutcomeName(entry.first) << "\n";
  }
}

/** Prints the totals of every family that ran, when the whole program ends. */
class SummaryPrinter : public testing::Environment
{
public:
  void
  TearDown() override
  {
    FamilySummary total;
    for (const auto & entry : SummaryOfTheRun())
    {
      const FamilySummary & summary = entry.second;
      total.cases += summary.cases;
      total.failures += summary.failures;
      total.seconds += summary.seconds;
      total.largestMesh = std::max(total.largestMesh, summary.largestMesh);
      total.meshesWithFlatTetrahedra += summary.meshesWithFlatTetrahedra;
      total.smallestDihedralAngle = std::min(total.smallestDihedralAngle, summary.smallestDihedralAngle);
      if (summary.slowestSeconds > total.slowestSeconds)
      {
        total.slowestSeconds = summary.slowestSeconds;
        total.slowestSeed = summary.slowestSeed;
      }
      for (const auto & outcome : summary.outcomes)
      {
        total.outcomes[outcome.first] += outcome.second;
      }
      total.unmeshedComponents += summary.unmeshedComponents;
      total.meshesWithFreeBoundaryVertices += summary.meshesWithFreeBoundaryVertices;
      total.meshesWithFreeBoundaryVerticesAndForcedSplits += summary.meshesWithFreeBoundaryVerticesAndForcedSplits;
      total.meshesPromisedManifold += summary.meshesPromisedManifold;
      total.meshesNotManifold += summary.meshesNotManifold;
      total.meshesNotManifoldWithTopologyDefaults += summary.meshesNotManifoldWithTopologyDefaults;
      total.meshToSegmentation.insert(
        total.meshToSegmentation.end(), summary.meshToSegmentation.begin(), summary.meshToSegmentation.end());
      total.segmentationToMesh.insert(
        total.segmentationToMesh.end(), summary.segmentationToMesh.begin(), summary.segmentationToMesh.end());
    }
    if (SummaryOfTheRun().size() > 1)
    {
      PrintSummary(std::cout, "All randomized families", total);
    }
  }
};

const testing::Environment * const summaryPrinter = testing::AddGlobalTestEnvironment(new SummaryPrinter);

std::size_t
CasesPerFamily(std::size_t defaultCount)
{
  const char * text = std::getenv("DELAUNAY_RANDOMIZED_CASES");
  return text ? static_cast<std::size_t>(std::strtoull(text, nullptr, 10)) : defaultCount;
}

std::size_t
FirstCase()
{
  const char * text = std::getenv("DELAUNAY_RANDOMIZED_FIRST_CASE");
  return text ? static_cast<std::size_t>(std::strtoull(text, nullptr, 10)) : 0;
}

std::optional<uint64_t>
OnlySeed()
{
  const char * text = std::getenv("DELAUNAY_RANDOMIZED_SEED");
  if (!text)
  {
    return std::nullopt;
  }
  return static_cast<uint64_t>(std::strtoull(text, nullptr, 10));
}

/** With σ > 0 Lemma 5 is not promised (CheckBoundaryGuarantees): R4′ splits a sliver at a point that fails its
 * acceptance test when no candidate passes (a forced split), and that point may be a free vertex on a boundary. A free
 * boundary vertex without any forced split in its mesh is rare, because R4′'s acceptance test rejects every point
 * that puts a free vertex on a boundary (SliverSplit::NewBoundaryTrianglesAreGood). Measured over the searches of
 * 14,400 to 16,000 cases per family: at most 1.1 % of the cases (Mixed 159 of 14,400, SaltAndPepper 99 of 16,000, the
 * others 0.02 to 0.15 %). With that test accepting every point (the mutation check's split-accepts-any-boundary), 18
 * of the first 100 Mixed cases, and every mesh the suite checks still met its other checks: besides the pinned meshes
 * (fingerprints, baselines), this bound is the only test that sees it. */
constexpr double MaximumShareOfFreeBoundaryVerticesWithoutForcedSplits = 0.05;

struct FamilyRun
{
  Family      family;
  std::size_t cases;
  /** Meshes asserted among the family's cases, as a fraction of them: about 0.85 of the measured fraction (of the
   * 3,000 cases: Blobs 272 of 400, SaltAndPepper 139 of 350, SheetsAndLines 101 of 350, SingleVoxels 26 of 400,
   * ManyLabels 221 of 300, BorderTouching 235 of 400, ThinImages 125 of 400, Mixed 181 of 400), so that a mesher
   * that gives up on what it could mesh fails even where every single refusal looks documented. */
  double minimumMeshFraction;
};

std::ostream &
operator<<(std::ostream & stream, const FamilyRun & run)
{
  return stream << FamilyName(run.family);
}

class RandomizedImages : public testing::TestWithParam<FamilyRun>
{};

TEST_P(RandomizedImages, MeshMeetsEveryGuaranteeOrFailsAsDocumented)
{
  const FamilyRun &     run = GetParam();
  const uint64_t        firstSeed = 1000003u * (static_cast<uint64_t>(run.family) + 1);
  std::vector<uint64_t> seeds;
  if (const std::optional<uint64_t> only = OnlySeed())
  {
    seeds.push_back(*only);
  }
  else
  {
    for (std::size_t i = 0; i < CasesPerFamily(run.cases); ++i)
    {
      seeds.push_back(firstSeed + FirstCase() + i);
    }
  }
  FamilySummary & summary = SummaryOfTheRun()[run.family];
  for (const uint64_t seed : seeds)
  {
    const RandomCase randomCase = MakeCase(run.family, seed);
    if (OnlySeed())
    {
      std::cout << DescribeToReproduce(randomCase) << std::endl;
    }
    const CaseReport report = RunCase(randomCase);
    ++summary.cases;
    ++summary.outcomes[report.result.outcome];
    summary.seconds += report.result.seconds;
    summary.largestMesh = std::max(summary.largestMesh, report.result.tetrahedra);
    summary.unmeshedComponents += report.result.unmeshedComponents;
    if (randomCase.settings.minimumDihedralAngle > 0.0 && report.result.nonFeatureBoundaryCorners > 0)
    {
      ++summary.meshesWithFreeBoundaryVertices;
      summary.meshesWithFreeBoundaryVerticesAndForcedSplits += report.result.sliverSplitsFailingAcceptance > 0;
    }
    if (report.result.outcome == Outcome::Mesh)
    {
      if (report.result.meshToSegmentation >= 0.0)
      {
        summary.meshToSegmentation.push_back(report.result.meshToSegmentation);
        summary.segmentationToMesh.push_back(report.result.segmentationToMesh);
      }
      summary.meshesWithFlatTetrahedra += report.result.flatTetrahedra > 0;
      summary.meshesPromisedManifold += report.result.promisedManifold;
      if (report.result.nonManifoldBoundaries > 0)
      {
        ++summary.meshesNotManifold;
        summary.meshesNotManifoldWithTopologyDefaults += HasTheTopologyDefaults(randomCase.settings);
      }
      summary.smallestDihedralAngle = std::min(summary.smallestDihedralAngle, report.result.smallestDihedralAngle);
    }
    if (report.result.seconds > summary.slowestSeconds)
    {
      summary.slowestSeconds = report.result.seconds;
      summary.slowestSeed = seed;
    }
    if (!report.problems.empty())
    {
      ++summary.failures;
      std::ostringstream problems;
      for (const std::string & text : report.problems)
      {
        problems << "\n  - " << text;
      }
      ADD_FAILURE() << DescribeToReproduce(randomCase) << ": " << OutcomeName(report.result.outcome)
                    << (report.result.refinement.empty() ? "" : " (" + report.result.refinement + ")")
                    << problems.str();
    }
  }
  PrintSummary(std::cout, FamilyName(run.family), summary);
  if (!OnlySeed())
  {
    const std::size_t meshes = summary.outcomes[Outcome::Mesh];
    EXPECT_GE(static_cast<double>(meshes), run.minimumMeshFraction * static_cast<double>(seeds.size()))
      << meshes << " meshes of " << seeds.size() << " cases";
    const std::size_t unforced =
      summary.meshesWithFreeBoundaryVertices - summary.meshesWithFreeBoundaryVerticesAndForcedSplits;
    EXPECT_LE(static_cast<double>(unforced),
              MaximumShareOfFreeBoundaryVerticesWithoutForcedSplits * static_cast<double>(seeds.size()))
      << unforced << " meshes of " << seeds.size() << " cases have a free vertex on a boundary (sigma > 0) without a "
      << "forced R4' split: R4' accepts points that put free vertices on boundaries";
  }
}

INSTANTIATE_TEST_SUITE_P(
  Family, RandomizedImages,
  testing::Values(FamilyRun{ Family::Blobs, 400, 0.58 }, FamilyRun{ Family::SaltAndPepper, 350, 0.33 },
                  FamilyRun{ Family::SheetsAndLines, 350, 0.24 }, FamilyRun{ Family::SingleVoxels, 400, 0.04 },
                  FamilyRun{ Family::ManyLabels, 300, 0.63 }, FamilyRun{ Family::BorderTouching, 400, 0.50 },
                  FamilyRun{ Family::ThinImages, 400, 0.26 }, FamilyRun{ Family::Mixed, 400, 0.38 },
                  FamilyRun{ Family::IsoSurfaces, 300, 0.55 }),
  [](const testing::TestParamInfo<FamilyRun> & info) { return FamilyName(info.param.family); });

// ---- Regressions: cases this suite found, replayed --------------------------------------------------------

/** FNV-1a of everything a case is made of: if the generator changes, a replayed seed is another case, and the
 * regression it stood for must be found again. */
uint64_t
Fingerprint(const RandomCase & randomCase)
{
  uint64_t   hash = 14695981039346656037ull;
  const auto mix = [&hash](uint64_t value) {
    hash ^= value;
    hash *= 1099511628211ull;
  };
  for (const char character : Describe(randomCase))
  {
    mix(static_cast<unsigned char>(character));
  }
  for (const int label : randomCase.canvas.labels)
  {
    mix(static_cast<uint32_t>(label));
  }
  return hash;
}

/** A replayed case. Its fingerprint was recomputed once, on purpose, when the suite's vertex cap (part of the
 * description) went from 10,000 to 100,000 (issue #17): the images and the other settings are the recorded ones. */
struct RecordedCase
{
  Family   family;
  uint64_t seed;
  uint64_t fingerprint;
};

void
ExpectReplayPasses(const RecordedCase & recorded)
{
  RandomCase randomCase = MakeRecordedCase(recorded.family, recorded.seed);
  // Replayed as they were recorded, before the topology regularisation of issue #14 became the default: the
  // regressions they stand for were in the refinement's numerics, on these labels as they are.
  randomCase.settings.manifoldRefinementLevels = 3;
  randomCase.settings.regularizationScale = 0.0;
  randomCase.settings.topologyRegularizationRounds = 0;
  randomCase.settings.relabelNonManifoldPlaces = false;
  ASSERT_EQ(Fingerprint(randomCase), recorded.fingerprint)
    << "the generator changed: " << Describe(randomCase) << " is no longer the recorded case";
  const CaseReport report = RunCase(randomCase);
  EXPECT_EQ(report.result.outcome, Outcome::Mesh) << Describe(randomCase) << ": " << report.result.message;
  EXPECT_TRUE(report.problems.empty()) << Describe(randomCase) << ": " << OutcomeName(report.result.outcome) << ": "
                                       << (report.problems.empty() ? "" : report.problems.front());
}

/** CGAL's filtered circumcentre of a nearly flat tetrahedron (four nearly co-spherical voxel-derived points) can
 * be far from the true centre; Voronoi edges and surface balls built on it put feature vertices closer than δ
 * (Lemma 2) and, in 6000044, a boundary triangle with a planar angle of 29.65° (< 30°, Theorem 2); in 6000274 a
 * boundary triangle of circumradius 1.04 > δ = 1.01 (R3's surface ball). */
TEST(RandomizedRegression, FloatingPointCircumcentresOfNearlyFlatTetrahedra)
{
  for (const RecordedCase & recorded : { RecordedCase{ Family::BorderTouching, 6000044, 3629006560914750677u },
                                         RecordedCase{ Family::BorderTouching, 6000067, 7159928999815081109u },
                                         RecordedCase{ Family::ThinImages, 7000059, 2815026025713388522u },
                                         RecordedCase{ Family::BorderTouching, 6000274, 15747545407499901381u } })
  {
    ExpectReplayPasses(recorded);
  }
}

/** Each case must mesh and pass every check of the suite (σ's among them when the case has σ > 0); returns the
 * reports. */
std::vector<CaseReport>
ExpectMeshedPassingEveryCheck(const std::vector<std::pair<Family, uint64_t>> & cases)
{
  std::vector<CaseReport> reports;
  for (const auto & [family, seed] : cases)
  {
    const RandomCase randomCase = MakeRecordedCase(family, seed);
    reports.push_back(RunCase(randomCase));
    const CaseReport & report = reports.back();
    EXPECT_EQ(report.result.outcome, Outcome::Mesh) << Describe(randomCase) << ": " << report.result.message;
    EXPECT_TRUE(report.problems.empty()) << Describe(randomCase) << ": " << report.problems.front();
  }
  return reports;
}

/** Each case must mesh, pass every check of the suite, and have no tetrahedron flat to rounding. */
void
ExpectMeshedWithoutFlatTetrahedra(const std::vector<std::pair<Family, uint64_t>> & cases)
{
  const std::vector<CaseReport> reports = ExpectMeshedPassingEveryCheck(cases);
  for (std::size_t index = 0; index < cases.size(); ++index)
  {
    EXPECT_EQ(reports[index].result.flatTetrahedra, 0u)
      << Describe(MakeRecordedCase(cases[index].first, cases[index].second));
  }
}

/** Tetrahedra flat to rounding (issue #15's bar): before R4′ moved a corner of each, these default-parameter cases had
 * them: four co-circular voxel-face centres on a plane of the surface (Blobs 1000005, 7 flat tetrahedra), the four
 * lateral face centres of a single voxel, whose plane crosses the surface (SingleVoxels 4000370), and a thin sheet
 * (SheetsAndLines 3000104). Each must mesh, pass every check of the suite, and have none. */
TEST(RandomizedRegression, FlatTetrahedraAreMovedAway)
{
  ExpectMeshedWithoutFlatTetrahedra(
    { { Family::Blobs, 1000005 }, { Family::SingleVoxels, 4000370 }, { Family::SheetsAndLines, 3000104 } });
}

/** Tetrahedra flat to rounding whose every move failed the strict acceptance (no rule applies to what the move
 * creates, no new non-manifold vertex): where ρ is near 1 almost every new tetrahedron reaches ρ (Blobs 1000030,
 * Mixed 8000162 at ρ = 1, SaltAndPepper 2000322), and in sheets thinner than δ every move changes a link
 * (SheetsAndLines 3000180, an isolated flat tetrahedron, and 3000227). After the refinement they are moved with
 * the later acceptance levels and the refinement resumed (docs/algorithm.md, "R4′ moves a vertex"). */
TEST(RandomizedRegression, FlatTetrahedraLeftAfterTheRefinementAreMovedAway)
{
  ExpectMeshedWithoutFlatTetrahedra({ { Family::Blobs, 1000030 },
                                      { Family::SaltAndPepper, 2000322 },
                                      { Family::SheetsAndLines, 3000180 },
                                      { Family::SheetsAndLines, 3000227 },
                                      { Family::Mixed, 8000162 } });
}

/** Tetrahedra flat to rounding inside a tissue that no move of a corner removes: δ = 1.055683 is a hair below
 * h/√2 = 1.055701 for voxels of 1.49299 mm, so the surface samples on the faces of one-voxel lines are that hair
 * more than δ apart, and every move breaks Lemma 2's spacing to one of them (SheetsAndLines 3006723, found by a
 * search of seeds 6,000-12,999: 6 flat tetrahedra). They are removed from the output by an edge removal
 * (docs/algorithm.md, "Flat tetrahedra inside a tissue"); the case must mesh and pass every check, Lemma 2's among
 * them, and have none. */
TEST(RandomizedRegression, FlatTetrahedraNoMoveRemovesAreRemovedWithAnEdge)
{
  ExpectMeshedWithoutFlatTetrahedra({ { Family::SheetsAndLines, 3006723 } });
}

/** With labels merged, the check of "every part thinner than the regularisation scale" measured the voxels whose value
 * is the merged label's id (1) instead of the selected labels' (found by a search of seeds 16,000-17,499: Mixed
 * 8017397 selects label 2 alone, 23 voxels none farther than 1.6 mm from another label, beside 184 voxels of label 1
 * up to 4.45 mm deep), and called the filter's right outcome a contradiction. The case must end so, with no problem
 * found. */
TEST(RandomizedRegression, RegularisedAwayIsJudgedOnTheSelectedLabels)
{
  const RandomCase randomCase = MakeRecordedCase(Family::Mixed, 8017397);
  const CaseReport report = RunCase(randomCase);
  EXPECT_EQ(report.result.outcome, Outcome::RegularizedAway) << Describe(randomCase) << ": " << report.result.message;
  EXPECT_TRUE(report.problems.empty()) << Describe(randomCase) << ": " << report.problems.front();
}

/** The check of "every part thinner than the regularisation scale" takes the opening's tie margin (LatticeTieMargin):
 * a voxel exactly one spacing from another label, where the reach is that spacing to rounding, is within the opening's
 * reach, and the check had called the filter's right outcome a contradiction (found by the search of seeds 237,600-
 * 239,199: SheetsAndLines 3239090, a voxel 2.319032 mm from another label against a reach of 2.319010 mm without the
 * margin; 3239091, 1.262593 against 1.262588). Each case must end so, with no problem found. */
TEST(RandomizedRegression, RegularisedAwayTakesTheOpeningsTieMargin)
{
  for (const uint64_t seed : { 3239090, 3239091 })
  {
    const RandomCase randomCase = MakeCase(Family::SheetsAndLines, seed);
    const CaseReport report = RunCase(randomCase);
    EXPECT_EQ(report.result.outcome, Outcome::RegularizedAway) << Describe(randomCase) << ": " << report.result.message;
    EXPECT_TRUE(report.problems.empty()) << Describe(randomCase) << ": " << report.problems.front();
  }
}

/** A tetrahedron flat to rounding on the background must not become a tissue's when the relabelling at non-manifold
 * places moves it: its corners are nearly co-circular, so its radius-edge ratio is small, and only a flatness test
 * keeps it out. A search over 1,500 cases per family (σ = 0 in all three) found SaltAndPepper 2001483 with three,
 * Mixed 8000776 and 8001351 with one each. */
TEST(RandomizedRegression, TheRelabellingGivesNoTissueAFlatTetrahedron)
{
  ExpectMeshedWithoutFlatTetrahedra(
    { { Family::SaltAndPepper, 2001483 }, { Family::Mixed, 8000776 }, { Family::Mixed, 8001351 } });
}

/** Slivers that R4′ leaves to the flat-cap step, as caps on the background, must end peeled or split: once the slivers
 * waited for every other rule, Mixed 8000216 (σ = 17.6°) kept one of 14.6°, because a relabelling move at a
 * non-manifold place gave a background neighbour a tissue's label and nothing peeled or split it after that
 * (docs/algorithm.md, "Topology", step 3). It must mesh and pass every check of the suite, σ's among them. */
TEST(RandomizedRegression, SliversLeftAsCapsAreNotStrandedByTheRelabelling)
{
  ASSERT_GT(MakeRecordedCase(Family::Mixed, 8000216).settings.minimumDihedralAngle, 15.0)
    << "the case is no longer the one";
  ExpectMeshedPassingEveryCheck({ { Family::Mixed, 8000216 } });
}

/** A relabelling move at a non-manifold place must make no tetrahedron alone with its label. It compared the numbers
 * of such tetrahedra around the move before and after, so a move that gave an isolated tetrahedron a neighbour of its
 * label while isolating a relabelled one passed: SaltAndPepper 2002799 (σ = 0, from a search of the 1,500 cases per
 * family after the suite's own) ended with a relabelled tetrahedron that no neighbour shares its label with. It must
 * mesh and pass every check of the suite, that one among them. */
TEST(RandomizedRegression, TheRelabellingLeavesNoRelabelledTetrahedronAlone)
{
  ExpectMeshedPassingEveryCheck({ { Family::SaltAndPepper, 2002799 } });
}

/** R3 compared a facet's surface ball with its shortest edge without the margin the checks of the 30° bound use, so a
 * triangle of exactly 30° (a circumradius equal to its shortest edge, which the voxel lattice makes) stayed or went
 * by rounding. Found by a search of seeds 45,400-46,999: ManyLabels 5045684 (σ = 10°, δ just below the voxel) kept
 * a boundary triangle of three feature vertices whose smallest angle was 29.99999999999974°. It must mesh and pass
 * every check of the suite, the 30° bound among them. */
TEST(RandomizedRegression, RThreeSplitsATriangleOfExactlyThirtyDegrees)
{
  // The case as the search drew it, with the default σ (MakeRecordedCase would run it with σ = 0).
  const RandomCase randomCase = MakeCase(Family::ManyLabels, 5045684);
  ASSERT_GT(randomCase.settings.minimumDihedralAngle, 0.0) << "the case is no longer the one";
  const CaseReport report = RunCase(randomCase);
  ASSERT_EQ(report.result.outcome, Outcome::Mesh) << Describe(randomCase) << ": " << report.result.message;
  EXPECT_TRUE(report.problems.empty()) << Describe(randomCase) << ": " << report.problems.front();
}

/** Issue #14's manifold promise: found by the first search after the families checked manifoldness (seeds 29,400 on),
 * outside the windows the suite runs. The defaults but σ = 0, δ = 1.13 voxels: 2 non-manifold places, 3 after the
 * first round's δ balls (cutting the pinch left a smaller one beside it), none after the second round's 2δ balls. The
 * rounds stopped after the first, whose count had grown, and the filter reported 3 places left. Now they stop only
 * after the places have risen twice above the count the repair began with (FewPlacesThatFluctuateDoNotStopTheRounds).
 * It must mesh, promise a closed manifold and pass every check of the suite, that one among them. */
TEST(RandomizedRegression, ARegularizationRoundThatLeavesMorePlacesIsFollowedByAnother)
{
  const std::vector<CaseReport> reports = ExpectMeshedPassingEveryCheck({ { Family::SheetsAndLines, 3029473 } });
  EXPECT_TRUE(reports.front().result.promisedManifold) << "the case is no longer the one";
}

/** A component that holds a ball of diameter δ, but not 2δ, had no tetrahedron although the regularisation kept it:
 * here three single voxels of 0.665 mm at δ = 0.587 mm (a ball of radius 0.57 δ each), with the relabelling at
 * non-manifold places off (with it this case happened to keep them). Now the filter finds the parts of its labels
 * without a tetrahedron and samples those a δ across more finely; the case must mesh and pass every check, every
 * component a δ across meshed among them. */
TEST(RandomizedRegression, ComponentsADeltaAcrossAreMeshed)
{
  RandomCase randomCase = MakeRecordedCase(Family::Mixed, 8000038);
  randomCase.settings.relabelNonManifoldPlaces = false;
  const CaseReport report = RunCase(randomCase);
  ASSERT_EQ(report.result.outcome, Outcome::Mesh);
  EXPECT_TRUE(report.problems.empty()) << report.problems.front();
  EXPECT_GT(report.result.thickComponents, 0u) << "the case is no longer the one";
}

/** The same case with RefineThickParts off, the opt-out of that sampling: the thick parts are lost again, and listed.
 * Every problem the checks find must be such a part without a tetrahedron (the suite's own count from the voxels and
 * the mesh), and none the list of the parts without one, which must equal that count. */
TEST(RandomizedRegression, ThickPartsLostWithTheirRefinementOffAreListed)
{
  RandomCase randomCase = MakeRecordedCase(Family::Mixed, 8000038);
  randomCase.settings.relabelNonManifoldPlaces = false;
  randomCase.settings.refineThickParts = false;
  const CaseReport report = RunCase(randomCase);
  ASSERT_EQ(report.result.outcome, Outcome::Mesh);
  ASSERT_FALSE(report.problems.empty()) << "no thick part lost: the option turned nothing off";
  for (const std::string & problem : report.problems)
  {
    EXPECT_NE(problem.find("delta but no tetrahedron"), std::string::npos) << problem;
  }
  EXPECT_GT(report.result.unmeshedComponents, 0u);
}

/** Found by the search of seeds 99,800-101,399: a centroid exactly on the face between the grid's first voxel (a
 * one-voxel part of label 1) and the layer of background before it, at continuous index -0.5. The filter, like ITK's
 * nearest-neighbour interpolator, puts such a point in the upper voxel and so found the part meshed; the suite's own
 * count rounded it into the padding and counted one part more without a tetrahedron than the filter listed. Both
 * now round the same way, and the counts must agree. */
TEST(RandomizedRegression, APointOnAFaceAtANegativeHalfIndexIsInTheUpperVoxel)
{
  const CaseReport report = RunCase(MakeCase(Family::SaltAndPepper, 2100177));
  ASSERT_EQ(report.result.outcome, Outcome::Mesh);
  EXPECT_TRUE(report.problems.empty()) << report.problems.front();
  EXPECT_GT(report.result.unmeshedComponents, 600u) << "the case is no longer the one";
}

// ---- Known defects, pinned: when one is fixed its test fails, and the check it is excused from gets strict -----

/** With ρ = 1 and σ > 0 the sliver removal may not end: R4 splits every tissue tetrahedron whose radius-edge ratio
 * reaches 1 and R4′ every one with a dihedral angle below σ, and near the boundary the two can keep making work for
 * each other (nothing is proven below ρ = 2, nor with σ > 0). Found by searches of the suite's Mixed family, all at
 * ρ = 1: 8004179 (σ = 18.9°), 8007944 (σ = 14.1°, δ = 1.34 mm), 8011618, 8019154, 8020056, 8021071, 8021246,
 * 8023578 and 8024542 (σ = 14° to 19.3°), and with the default σ = 10° Blobs 1000030 at δ (1 + 1e-9); each ran to the
 * suite's cap of 100,000 vertices (8024542 in 25 s) where the runs that end have a few hundred. The first search with
 * the budget (seeds 25,800-26,199) found Mixed 8025878 (ρ = 1, σ = 19.9°, δ = 2.24 mm): stopped after 1.0 s, and at
 * the cap in 16.8 s with the budget switched off. It is chaotic: of six values of δ within 0.3 % of 8004179's, three
 * ended and three ran away. Now a pass of the sliver removal may leave at most 10 times the vertices it started from
 * plus 1,000 (docs/algorithm.md, "When sliver removal does not end"): both cases must stop there with the exception
 * that names σ and ρ, far below the cap. Since the opening leaves no fin at the root of a removed part (issue #14,
 * 2026-11-29), 8025878's labels differ and its sliver removal ends, as do 8011618's and 8019154's: 8004179, which
 * still ran away (as 8020056, 8021071, 8021246, 8023578 and 8024542 do), took its place. Since a topology round's
 * ball that the pinch removal undid takes the other choice (2026-11-30), 8004179's sliver removal ends too: 8020056
 * (σ = 16.97°) takes its place. */
TEST(RandomizedRegression, SliverRemovalThatDoesNotEndStopsAtItsBudget)
{
  for (const auto & [seed, sigma] : { std::pair<uint64_t, const char *>{ 8007944, "sigma = 14." },
                                      std::pair<uint64_t, const char *>{ 8020056, "sigma = 16.9" } })
  {
    SCOPED_TRACE("Mixed " + std::to_string(seed));
    const RandomCase randomCase = MakeRecordedCase(Family::Mixed, seed);
    ASSERT_EQ(randomCase.settings.radiusEdgeBound, 1.0) << "the case is no longer the one";
    ASSERT_EQ(randomCase.settings.maximumNumberOfVertices, FilterSettings{}.maximumNumberOfVertices);
    const CaseReport report = RunCase(randomCase);
    ASSERT_EQ(report.result.outcome, Outcome::SliverRemovalWithoutEnd)
      << OutcomeName(report.result.outcome) << ": " << report.result.message;
    EXPECT_TRUE(report.problems.empty()) << report.problems.front();
    const std::string & message = report.result.message;
    EXPECT_NE(message.find(sigma), std::string::npos) << message;
    EXPECT_NE(message.find("rho = 1,"), std::string::npos) << message;
    // "... from N0 vertices, where every other rule was met, to N, more than 10 times as many plus 1000": the check
    // follows every insertion, so it stops within a few vertices of the budget, and far below the cap it ran to.
    const auto growth = SliverRemovalGrowthIn(message);
    ASSERT_TRUE(growth.has_value()) << message;
    const auto [startedAt, stoppedAt] = *growth;
    EXPECT_GT(stoppedAt, 10 * startedAt + 1000) << message;
    EXPECT_LE(stoppedAt, 10 * startedAt + 1000 + 8) << message;
    EXPECT_LT(stoppedAt, FilterSettings{}.maximumNumberOfVertices / 4) << message;
  }
}

/** The budget above is relative, so a pass that starts large can reach the vertex cap first. Found by a search of
 * 12,800 more cases (seeds 66,200-67,799): Mixed 8067665 (ρ = 1, σ = 16.6°, δ = 0.45 mm) took its first sliver at
 * 18,244 vertices and ran to the suite's cap of 100,000 in 27 s, under its budget of 183,440; the cap's exception
 * did not say why, and the suite read it as a runaway of unknown cause. Now the refiner adds that the sliver
 * removal reached the cap, from how many vertices (the suite accepts that where it accepts the budget's exception).
 * With a cap of 30,000 the case stops there in seconds; with 10,000 the cap comes before any sliver is taken, and
 * the message must not blame the sliver removal. */
TEST(RandomizedRegression, VertexCapReachedBySliverRemovalSaysSo)
{
  RandomCase randomCase = MakeRecordedCase(Family::Mixed, 8067665);
  ASSERT_EQ(randomCase.settings.radiusEdgeBound, 1.0) << "the case is no longer the one";
  ASSERT_GT(randomCase.settings.minimumDihedralAngle, 16.0) << "the case is no longer the one";
  constexpr std::size_t cap = 30000;
  randomCase.settings.maximumNumberOfVertices = cap;
  const CaseReport    report = RunCase(randomCase);
  const std::string & message = report.result.message;
  ASSERT_EQ(report.result.outcome, Outcome::VertexLimit) << OutcomeName(report.result.outcome) << ": " << message;
  EXPECT_TRUE(IsReachedBySliverRemoval(message)) << message;
  const auto growth = SliverRemovalGrowthIn(message);
  ASSERT_TRUE(growth.has_value()) << message;
  const unsigned long startedAt = growth->first;
  EXPECT_GT(startedAt, 10000u) << message;
  EXPECT_LT(startedAt, cap) << message;

  randomCase.settings.maximumNumberOfVertices = 10000;
  const CaseReport early = RunCase(randomCase);
  ASSERT_EQ(early.result.outcome, Outcome::VertexLimit) << early.result.message;
  EXPECT_FALSE(IsReachedBySliverRemoval(early.result.message)) << early.result.message;
}

/** A part that holds a ball of diameter δ ended without a tetrahedron. Found by a search of 12,800 more cases (seeds
 * 56,600-58,199): Blobs 1056639 (ρ = 1, σ = 0, δ = 1.48 mm on voxels of 1.68 mm, diagonal voxels kept), whose
 * one-voxel parts hold balls of radius 0.57 δ. Each of the census's four rounds found one or two such parts without a
 * tetrahedron and sampled them more finely, but they were other parts each round (seven in all): the refinement and
 * the topology steps after a round left another one without a tetrahedron, and the rounds, four in all, ran out with
 * one left (listed, so not lost silently). Now each part gets at most four rounds and the rounds go on while a part
 * has some left (Refiner::WithEveryThickPart): the case ends after five rounds with every part meshed. It was meshed
 * before too with the relabelling at non-manifold places off, which must stay so. */
TEST(RandomizedRegression, ThickPartFoundInALateRoundIsSampledToo)
{
  RandomCase randomCase = MakeRecordedCase(Family::Blobs, 1056639);
  ASSERT_EQ(randomCase.settings.radiusEdgeBound, 1.0) << "the case is no longer the one";
  ASSERT_EQ(randomCase.settings.minimumDihedralAngle, 0.0) << "the case is no longer the one";
  for (const bool relabel : { true, false })
  {
    SCOPED_TRACE(relabel ? "relabelling on" : "relabelling off");
    randomCase.settings.relabelNonManifoldPlaces = relabel;
    const CaseReport report = RunCase(randomCase);
    ASSERT_EQ(report.result.outcome, Outcome::Mesh) << report.result.message;
    EXPECT_TRUE(report.problems.empty()) << report.problems.front();
    EXPECT_EQ(report.result.unmeshedComponents, 0u);
  }
}

/** The suite's sizing check did not know the census's tie margin. Found by a search of 12,800 more cases (seeds
 * 61,400-62,999): ManyLabels 5062585 (ρ = 2, σ = 10°, the default δ) has a part whose largest ball is 1e-4 below
 * δ / 2 or less, which the census counts as a diameter of δ and samples at its radius (docs/algorithm.md,
 * "Topology", step 4); the check wanted every sampling distance at least δ / 2 after one round, and read 0.99997
 * δ / 2 as a violation. It now allows the documented margin below δ / 2^rounds, and no more. */
TEST(RandomizedRegression, ThickPartZoneAtTheTieMarginPassesTheSizingCheck)
{
  const RandomCase randomCase = MakeCase(Family::ManyLabels, 5062585);
  ASSERT_EQ(randomCase.settings.radiusEdgeBound, 2.0) << "the case is no longer the one";
  ExpectMeshPassingEveryCheck(randomCase);
}

/** A sliver that R4′ leaves to the flat-cap step as a cap on the background, where peeling it off would make a
 * vertex non-manifold: the step gave it its label back and nothing split it after that. Found by a search of 12,000
 * more cases (seeds 4,500-5,999): Mixed 8005805 (σ = 5.2°) kept a tetrahedron of 0.0087° with four surface corners
 * and two facets on the background. Now such a sliver is split after all and the repairs run again
 * (Refiner::PeelFlatCaps); the case must mesh and pass every check, σ among them. */
TEST(RegressionSliverCaps, SliverThatCannotBePeeledIsSplit)
{
  const RandomCase randomCase = MakeRecordedCase(Family::Mixed, 8005805);
  ASSERT_GT(randomCase.settings.minimumDihedralAngle, 5.0) << "the case is no longer the one";
  const CaseReport report = RunCase(randomCase);
  ASSERT_EQ(report.result.outcome, Outcome::Mesh);
  EXPECT_TRUE(report.problems.empty()) << report.problems.front();
  EXPECT_GT(report.result.smallestDihedralAngle, randomCase.settings.minimumDihedralAngle);
}

/** The case where boundary feature vertices stayed off the voxel surface after the local topology regularisation
 * (issue #14): the voxel pinches mended after the balls were regularised changed voxels outside the balls, and the
 * refinement looked again only inside them. Now each such voxel has a ball of its own; the case must mesh and pass
 * every check, the feature vertices' place on the surface among them. */
TEST(RegressionLocalRegularization, FeatureVerticesStayOnTheRegularizedSurface)
{
  const CaseReport report = RunCase(MakeRecordedCase(Family::Blobs, 1000004));
  ASSERT_EQ(report.result.outcome, Outcome::Mesh);
  EXPECT_TRUE(report.problems.empty()) << report.problems.front();
}

/** A topology round whose ball the pinch removal undid. Found by a search of 12,800 more cases (seeds 122,400-123,999):
 * SaltAndPepper 2123048 (δ = 1.1 voxels, σ = 10°) kept one non-manifold vertex of label 2 through all 20 rounds. Each
 * round's ball (2δ) cut the place's seven voxels of label 2 to the background, and the pinch removal, which never cuts
 * a tissue by the background, joined all seven again: the labels ended as they were, the round refined the same mesh,
 * and the place was left (reported, but promised a manifold at δ above the voxel). Now a ball whose changes were all
 * undone takes the other choice (here label 2 fills it), and a call that changes nothing returns no ball; the case
 * must mesh (one round mends it now) and pass every check, its boundaries' manifoldness among them. */
TEST(RegressionLocalRegularization, BallUndoneByThePinchRemovalTakesTheOtherChoice)
{
  const RandomCase randomCase = MakeCase(Family::SaltAndPepper, 2123048);
  ASSERT_EQ(randomCase.settings.topologyRegularizationRounds, dr::RefinementParameters{}.topologyRegularizationRounds)
    << "the case is no longer the one";
  const CaseReport report = ExpectMeshPassingEveryCheck(randomCase);
  EXPECT_EQ(report.result.nonManifoldBoundaries, 0u);
}

/** A tetrahedron flat to rounding next to relabelled ones (issue #15's bar: none, whatever the parameters). Found by a
 * search of 12,800 more cases (seeds 124,000-125,599): SaltAndPepper 2125029 (ρ = 2.87, σ = 0, δ = 0.92 voxel) kept
 * one tetrahedron of label 2 whose volume was 6e-15 times its shortest edge cubed: four surface samples at the corners
 * of a parallelogram of voxel-face centres on the interface with label 1. Every move of a corner failed, the last
 * resort's too, and of its edges only two had a ring all of label 2, whose other tetrahedra the topology relabelling
 * had given label 2: the edge removal left such rings alone, since their tetrahedra need not carry the label at their
 * circumcentres. Now it replaces them by tetrahedra that are listed as relabelled in turn (FlatTetrahedronRemoval::
 * RemoveEdge); the case must mesh with no flat tetrahedron and pass every check. */
TEST(RegressionFlatTetrahedra, FlatTetrahedronWhoseRingsWereRelabelledIsRemoved)
{
  const RandomCase randomCase = MakeCase(Family::SaltAndPepper, 2125029);
  ASSERT_EQ(randomCase.settings.minimumDihedralAngle, 0.0) << "the case is no longer the one";
  const CaseReport report = ExpectMeshPassingEveryCheck(randomCase);
  EXPECT_EQ(report.result.flatTetrahedra, 0u);
}

/** A tetrahedron flat to rounding between three labels. Found by a search of 16,000 more cases (seeds
 * 157,600-173,599): SaltAndPepper 2164606 (ρ = 2.85, σ = 0, δ = 0.88 voxel) kept one tetrahedron of label 3 with two
 * facets on the background, one on label 1 and one inside label 3. No move of a corner passed, no edge had a ring in
 * one tissue (one edge's ring is that tetrahedron alone), and the flat-cap step asked that the two facets not on the
 * background be inside the tetrahedron's tissue. A tetrahedron flat to rounding has no inside, so it now takes the
 * label beyond two of its facets whatever its other two face (FlatCaps::LabelAsFlatCap); the case must mesh with no
 * flat tetrahedron and pass every check, the boundary's angles and manifoldness among them. */
TEST(RegressionFlatTetrahedra, FlatTetrahedronBetweenThreeLabelsTakesTheLabelBeyondTwoFacets)
{
  const RandomCase randomCase = MakeCase(Family::SaltAndPepper, 2164606);
  ASSERT_EQ(randomCase.settings.minimumDihedralAngle, 0.0) << "the case is no longer the one";
  const CaseReport report = ExpectMeshPassingEveryCheck(randomCase);
  EXPECT_EQ(report.result.flatTetrahedra, 0u);
}

/** The opt-in manifold refinement (ManifoldRefinementLevels > 0) repairs a mesh only when at most a fixed fraction of
 * its boundary vertices are non-manifold (ManifoldRepair::IsRepairable), all of them or none: ManyLabels seed 5000157
 * sat at that threshold, so δ and δ (1 + 1e-12) gave 4 rounds, 190 zones and 9,275 vertices, or no round and 857
 * vertices. Since R2 splits from 3δ it no longer does; this case gives 3,398 vertices or 284, and 24 of ManyLabels'
 * first 300 seeds change by more than 3 × either way. This was the instability of issue #17; the default mechanism
 * (the regularisation) does not have it (RandomizedStability). */
TEST(RandomizedKnownDefect, OptInManifoldRefinementJumpsWithTheLastBitsOfDelta)
{
  RandomCase randomCase = MakeRecordedCase(Family::ManyLabels, 5000040);
  randomCase.settings.manifoldRefinementLevels = 3;
  randomCase.settings.regularizationScale = 0.0;
  randomCase.settings.topologyRegularizationRounds = 0;
  randomCase.settings.relabelNonManifoldPlaces = false;
  const double delta = EffectiveDelta(randomCase);
  randomCase.settings.surfaceSamplingDistance = delta;
  const CaseReport atDelta = RunCase(randomCase);
  randomCase.settings.surfaceSamplingDistance = delta * (1.0 + 1e-12);
  const CaseReport perturbed = RunCase(randomCase);
  ASSERT_EQ(atDelta.result.outcome, Outcome::Mesh);
  ASSERT_EQ(perturbed.result.outcome, Outcome::Mesh);
  EXPECT_GT(atDelta.result.points, 5 * perturbed.result.points)
    << "fixed? add the opt-in manifold refinement to RandomizedStability and remove this test";
}

/** A part just over δ across stayed without a tetrahedron through every round of finer sampling. Found by a search
 * of 12,800 more cases (seeds 59,800-61,399): SaltAndPepper 2060717 (ρ = 1, σ = 10°, δ = 0.61 mm, an oblique
 * direction, diagonal voxels kept), whose two-voxel part holds a ball of radius 0.510 δ. The part lay inside a
 * background tetrahedron of circumradius 1.18 δ whose circumcentre was 1.06 δ from the part's ball, outside the zone
 * of finer sampling, and no rule looked at the zone: R2 read the local δ at the circumcentre, R1 at the surface point
 * closest to it (on another part). Four rounds, down to δ' = 0.064 δ, inserted nothing. Now R2 reads the finest δ its
 * circumball meets in a zone made for such a part (LocalSampling::DeltaForCircumball); the part gets its tetrahedra in
 * the next round and the case must mesh and pass every check. */
TEST(RandomizedRegression, PartInsideAnotherLabelsTetrahedronIsRefined)
{
  const RandomCase randomCase = MakeCase(Family::SaltAndPepper, 2060717);
  ASSERT_EQ(randomCase.settings.radiusEdgeBound, 1.0) << "the case is no longer the one";
  const CaseReport report = ExpectMeshPassingEveryCheck(randomCase);
  EXPECT_EQ(report.result.unmeshedComponents, 0u);
}

/** The regularisation's rounds made the mesh again each time where the non-manifold places covered the image. Found by
 * a search of 12,800 more cases (seeds 59,800-61,399): SaltAndPepper 2061491 (ρ = 1, σ = 10°, δ = 0.6 of the largest
 * spacing, 23 x 21 x 19 voxels) began the repair with 1,921 places on 43,203 vertices; each round inserted about 1.5
 * times the mesh, and the suite stopped the run at a minute, in the ninth of its 20 rounds. The rounds now have a
 * budget of insertions (4 times the mesh they began with, plus 1,000): that case ends after 3 rounds in 30 s with
 * 844 places, reported. This one is the only case of seeds 0-399 of every family that reaches the budget (5.6 times
 * its mesh in 13 rounds before; δ below the largest spacing, so its boundary is not promised a manifold): it must
 * stop early, say so, admit the places it leaves and pass every other check. */
TEST(RandomizedRegression, RegularizationRoundsStopAtTheirBudgetAndSaySo)
{
  const RandomCase randomCase = MakeCase(Family::SaltAndPepper, 2000322);
  const CaseReport report = ExpectMeshPassingEveryCheck(randomCase);
  EXPECT_FALSE(report.result.promisedManifold) << "the case is no longer the one";
  EXPECT_TRUE(report.result.regularizationBudgetReached);
  EXPECT_LT(report.result.regularizationRounds, 13u);
}

/** R3 measured a surface ball's radius from one corner of its facet, and the ball's centre, on a Voronoi edge whose
 * ends are floating-point constructions, could be nearer to another corner. Found by a search of 12,800 more cases
 * (seeds 72,600-74,199): SaltAndPepper 2073625 (ρ = 2, σ = 0, diagonal voxels kept) inserted a feature vertex 1.3e-8
 * of the local δ (0.57 δ, a thin part's zone) closer than that to another, and the suite's sizing check failed (it
 * allows 1e-9). Measuring the radius to the nearest corner broke the planar angle bound on SaltAndPepper 2076891 (the
 * test below). A ball's centre that far off is now put on the exact Voronoi line of the facet
 * (NearestPointOnCircumcenterAxis); both cases must mesh and pass every check. */
TEST(RandomizedRegression, SurfaceBallCentreIsOnItsFacetsVoronoiLine)
{
  const RandomCase randomCase = MakeCase(Family::SaltAndPepper, 2073625);
  ASSERT_EQ(randomCase.settings.radiusEdgeBound, 2.0) << "the case is no longer the one";
  ExpectMeshPassingEveryCheck(randomCase);
}

/** The other side of the test above: with R3's radius measured to the nearest corner of the facet from a ball's
 * centre off the facet's Voronoi line, a facet whose true circumradius reached its threshold by 1e-9 stayed, and
 * SaltAndPepper 2076891 (ρ = 1.997, σ = 10°, found by a search of seeds 75,800-77,399) kept a boundary triangle with
 * a smallest angle of 29.999999998717°. On the line the nearest corner is as far as the others, to rounding; the case
 * must mesh and pass every check. */
TEST(RandomizedRegression, SurfaceBallRadiusKeepsThePlanarAngleBound)
{
  ExpectMeshPassingEveryCheck(MakeCase(Family::SaltAndPepper, 2076891));
}

/** Vertices inserted for a zone of finer δ outside it honour a finer spacing than the δ at their points, and the
 * sizing exported with the mesh must say so, or a check of every edge against it fails where the refinement kept its
 * own bound. Each case must mesh and pass every check.
 * - R2's free vertices for a rescue zone: a search of 12,800 more cases (seeds 75,800-77,399) found SaltAndPepper
 *   2077343 (ρ = 2.42, σ = 0, no regularisation, diagonal voxels kept), with edges of 1.87-2.48 between a feature and
 *   a free vertex whose exported δ was 2.35, against the 2.51 the suite allowed (twice the finest sampling distance
 *   exported). The free vertices were circumcentres of tetrahedra whose circumballs met a zone of δ' below 0.94, made
 *   for a part the refinement left without a tetrahedron, with no output point inside it. The mesh now exports the δ
 *   each such vertex was inserted with (LocalSampling::SamplingDistanceOf).
 * - R3's feature vertices beside a zone, where a facet's shortest edge is R3's threshold: the search of seeds
 *   239,200-240,799 found SaltAndPepper 2240051 (ρ = 2, σ = 0, 2 × 0.51 × 0.59 mm voxels, δ = 1.39 mm), which
 *   sampled a thick part at 0.77 mm, whose points all ended outside the mesh, and put an R3 point 0.90 δ from two
 *   others beside it, exported at δ. The mesh now exports the ball's radius for such a vertex. */
TEST(RandomizedRegression, VerticesInsertedForAZoneExportTheDeltaTheyHonoured)
{
  for (const uint64_t seed : { 2077343, 2240051 })
  {
    const RandomCase randomCase = MakeCase(Family::SaltAndPepper, seed);
    ASSERT_EQ(randomCase.settings.minimumDihedralAngle, 0.0) << "the case is no longer the one";
    ExpectMeshPassingEveryCheck(randomCase);
  }
}

/** The regularisation rounds stopped after two rounds that left 7 non-manifold places where the repair began with 6,
 * on a boundary promised a manifold. Found by a search of 12,800 more cases (seeds 74,200-75,799): SaltAndPepper
 * 2075775 (ρ = 2, σ = 10°, δ = 1.23 of the spacing, 8 x 23 x 8 voxels). The rounds took "more places than at the
 * start" as making things worse; a count of a few fluctuates by one or two as the balls cut pinches, and the rounds
 * that followed would have left 6, 2 and 0. "More" is now beyond the square root of the count at the start. A search
 * of seeds 157,600-165,599 found SaltAndPepper 2164423 (ρ = 2, σ = 10°, δ = 1.22 of the spacing, 7 x 12 x 7 voxels):
 * 3 places, then 5 and 5, beyond the square root (1.7) and within the one or two a ball may leave; the round after
 * would have left 0. "More" is now beyond two at least. A search of seeds 282,400-312,799 found SaltAndPepper 2297698
 * (ρ = 2, σ = 10°, δ = 1.29 of the spacing, 10 x 13 x 20 voxels, labels -32768 and 1): 4 places, then 10 and 7, both
 * beyond two, and the rounds stopped with 6 non-manifold vertices; 7, 1 and 0 came next. A count that falls is being
 * settled; the rounds now stop only after the places rose twice above the start's level. Each case must mesh and pass
 * every check, the manifold one among them. */
TEST(RandomizedRegression, FewPlacesThatFluctuateDoNotStopTheRounds)
{
  for (const uint64_t seed : { 2075775, 2164423, 2297698 })
  {
    const RandomCase randomCase = MakeCase(Family::SaltAndPepper, seed);
    ASSERT_EQ(randomCase.settings.radiusEdgeBound, 2.0) << "the case is no longer the one";
    const CaseReport report = ExpectMeshPassingEveryCheck(randomCase);
    EXPECT_TRUE(report.result.promisedManifold) << "the case is no longer the one";
    EXPECT_EQ(report.result.nonManifoldBoundaries, 0u) << "seed " << seed;
  }
}

/** R3 keeps a boundary triangle whose surface ball is up to δ (1 + LatticeTieMargin) wide (docs/algorithm.md, "Rules"),
 * so the boundary lies within that of the voxels' surface, not within δ. Found by a search of seeds 314,400-315,999:
 * SheetsAndLines 3315603 (one line, δ = half the spacing, ρ = 1, σ = 10°, an oblique direction) reached 1.0000019 δ,
 * and the suite's bound was δ; R3 without its margin gives 0.929 δ. The case must pass every check, the distance bound
 * of the documented guarantee among them, and still reach past δ. */
TEST(RandomizedRegression, BoundaryWithinTheSurfaceBallsTieMargin)
{
  const RandomCase randomCase = MakeCase(Family::SheetsAndLines, 3315603);
  ASSERT_EQ(randomCase.settings.radiusEdgeBound, 1.0) << "the case is no longer the one";
  const CaseReport report = ExpectMeshPassingEveryCheck(randomCase);
  EXPECT_GT(report.result.meshToSegmentation, 1.0) << "the case is no longer the one";
}

/** With ρ < 2, R4's point is only ρ × its tetrahedron's shortest edge from its neighbours, so beside a zone's short
 * edges it comes closer than the δ at its point, and the mesh exports that (docs/algorithm.md, "Local sampling
 * distance"). Found by a search of seeds 330,400-331,999: SheetsAndLines 3330698 (ρ = 1, σ = 0, an oblique
 * direction) sampled a thick part at δ / 2, whose points all went later, and kept an R4 vertex 0.98 δ from a feature
 * vertex and from a free one while every output point was exported at δ. The case must pass every check, Lemma 2's
 * edges against the exported sizing among them. */
TEST(RandomizedRegression, AnR4PointBesideAZoneExportsItsSpacing)
{
  const RandomCase randomCase = MakeCase(Family::SheetsAndLines, 3330698);
  ASSERT_EQ(randomCase.settings.radiusEdgeBound, 1.0) << "the case is no longer the one";
  ASSERT_EQ(randomCase.settings.minimumDihedralAngle, 0.0) << "the case is no longer the one";
  ExpectMeshPassingEveryCheck(randomCase);
}

// ---- Stability under the last bits of δ ---------------------------------------------------------------------

/** What a run made: its outcome and, for a mesh, its counts. */
struct MeshSize
{
  Outcome     outcome{ Outcome::Unexpected };
  std::size_t points{ 0 };
  std::size_t tetrahedra{ 0 };
};

MeshSize
MeshSizeOf(const RandomCase & randomCase)
{
  const CaseReport report = RunCase(randomCase);
  return { report.result.outcome, report.result.points, report.result.tetrahedra };
}

/** Relative perturbations of δ: from the last bits of a double to a millionth. */
const std::vector<double> &
DeltaPerturbations()
{
  static const std::vector<double> perturbations{ 1e-12, -1e-12, 1e-10, 1e-9, -1e-9, 1e-8, 1e-6, -1e-6 };
  return perturbations;
}

/** A change of δ in its last bits may move which way a tie falls (a circumcentre on a voxel face, cospherical voxel
 * points), and so the cascade of the refinement, but the mesh's size must follow δ, not its rounding. Found by this
 * suite: ManyLabels seed 5000157 (24x19x10 voxels) gave 844 vertices at δ (1 + 1e-12) and 8,415 at δ (1 + 1e-9) when
 * the manifold refinement was the default (issue #17); with the regularisation that replaced it, 4.1 % at most.
 * Measured on the meshes below (1,000 to 12,000 tetrahedra, perturbations 1e-12 to 1e-6) since the voxel pinches
 * of every label are removed and non-manifold places are relabelled (issue #14): 1.0-3.8 % for the blobs, salt and
 * pepper, sheets and lines, thin images and mixed images, 2.3-6.4 % for many labels and border-touching images
 * (6.4 % is 72 of 1,126 tetrahedra). Before those, salt and pepper (whose every voxel is a tie) moved by up to
 * 11.8 % and the bound was 15 %. The bound keeps a margin over what is measured. */
constexpr double LargestRelativeSizeChange = 0.08;

/** The largest relative change of the mesh's points and tetrahedra over DeltaPerturbations(), with a failure for
 * each one beyond LargestRelativeSizeChange when `expectWithinTheBound` (else the changes are only measured). */
double
LargestChangeUnderDeltaPerturbations(RandomCase randomCase, bool expectWithinTheBound)
{
  const double delta = EffectiveDelta(randomCase);
  randomCase.settings.surfaceSamplingDistance = delta;
  const MeshSize reference = MeshSizeOf(randomCase);
  EXPECT_EQ(reference.outcome, Outcome::Mesh) << Describe(randomCase);
  double largestChange = 0.0;
  for (const double perturbation : DeltaPerturbations())
  {
    randomCase.settings.surfaceSamplingDistance = delta * (1.0 + perturbation);
    const MeshSize perturbed = MeshSizeOf(randomCase);
    EXPECT_EQ(perturbed.outcome, Outcome::Mesh) << Describe(randomCase);
    for (const auto & [name, before, after] :
         { std::make_tuple("points", reference.points, perturbed.points),
           std::make_tuple("tetrahedra", reference.tetrahedra, perturbed.tetrahedra) })
    {
      const double change = std::abs(static_cast<double>(after) - static_cast<double>(before)) / before;
      largestChange = std::max(largestChange, change);
      if (expectWithinTheBound)
      {
        EXPECT_LE(change, LargestRelativeSizeChange) << Describe(randomCase) << ": delta x (1 + " << perturbation
                                                     << ") gives " << after << " " << name << " instead of " << before;
      }
    }
  }
  std::cout << FamilyName(randomCase.family) << " seed " << randomCase.seed << " (sigma "
            << randomCase.settings.minimumDihedralAngle << "): " << reference.tetrahedra
            << " tetrahedra, largest relative change of the counts under the perturbations of delta " << largestChange
            << "\n";
  return largestChange;
}

void
ExpectStableUnderDeltaPerturbations(const RandomCase & randomCase)
{
  LargestChangeUnderDeltaPerturbations(randomCase, true);
}

TEST(RandomizedStability, RecordedCaseChangesByAFewPerCentAtMost)
{
  ExpectStableUnderDeltaPerturbations(MakeRecordedCase(Family::ManyLabels, 5000157));
}

/** The first meshes of every family's seeds that hold at least a thousand tetrahedra at their δ (on a smaller mesh a
 * few per cent is a few elements, which any change of the cascade moves; the single voxels make none that large),
 * as recorded: with the paper's method (σ = 0) unless the case drew a σ, where the bound was measured. Sliver
 * removal, the default since issue #15, moves such small random meshes more (the known defect below); the defaults
 * are held to a bound on the real images (itkDelaunayImageToMeshFilterGTest, "TheDefaultsFollowDeltaNotItsLastBits").
 */
TEST(RandomizedStability, FirstMeshesOfEveryFamilyChangeByAFewPerCentAtMost)
{
  // Runs with fewer cases per family (the sanitizers' 100) take one mesh per family.
  const std::size_t     meshesPerFamily = CasesPerFamily(300) < 300 ? 1 : 2;
  constexpr std::size_t smallestMesh = 1000;
  for (const Family family : { Family::Blobs,
                               Family::SaltAndPepper,
                               Family::SheetsAndLines,

                               Family::ManyLabels,
                               Family::BorderTouching,
                               Family::ThinImages,
                               Family::Mixed })
  {
    const uint64_t firstSeed = 1000003u * (static_cast<uint64_t>(family) + 1);
    std::size_t    found = 0;
    for (uint64_t seed = firstSeed; found < meshesPerFamily && seed < firstSeed + 100; ++seed)
    {
      const RandomCase randomCase = MakeRecordedCase(family, seed);
      if (randomCase.settings.maximumNumberOfVertices < FilterSettings{}.maximumNumberOfVertices)
      {
        continue;
      }
      const MeshSize size = MeshSizeOf(randomCase);
      if (size.outcome != Outcome::Mesh || size.tetrahedra < smallestMesh)
      {
        continue;
      }
      ++found;
      ExpectStableUnderDeltaPerturbations(randomCase);
    }
    EXPECT_EQ(found, meshesPerFamily) << FamilyName(family);
  }
}

/** Sliver removal (σ = 10°, the default) makes more choices that a tie decides (which candidate point, which corner
 * moves), and on small random meshes the last bits of δ move more than the bound above. Measured on the first two
 * meshes of every family over a thousand tetrahedra when σ = 10° became the default: 1.5-4.7 %, but for this case,
 * ManyLabels 5000016, 16.8 % (1,176 tetrahedra), and BorderTouching 6000018, 8.8 % (1,512 tetrahedra); 6.5 % and
 * 5.2 % with σ = 0. Once R4′ tried a corner move first where R3 would split its point again: 7.7 % and 8.8 %. The
 * amount follows the construction's last bits: computing every circumcentre from sorted corners (tried, not kept) gave
 * 8.7 % and 8.1 %, and 12.8 % and 11.8 % (this case and Blobs 1000004) once the sorted corners were oriented. Since R2
 * splits from 3δ instead of 2δ, this case moves by 13.8 % (1,225 tetrahedra) and BorderTouching 6000018, pinned here
 * before, by 4.6 %; of the 27 meshes over a thousand tetrahedra with the default σ among each family's first 40 seeds,
 * 22 move by 1.2-7.9 %, SaltAndPepper 2000025 by 8.0 %, SheetsAndLines 3000019 by 9.2 %, Mixed 8000052 by 16.7 % and
 * Blobs 1000030 (ρ = 1, 74,429 tetrahedra) by 31 % (at least 27 % with 2δ). That one is the radius-edge bound of 1
 * with sliver removal: σ = 0 gives 33,971 tetrahedra there, which move by 2.8 %, and ρ = 1.2 with σ = 10° gives 24,528,
 * which move by 2.6 %. On the real images the defaults move by under 2 % (brain mask at 2 mm 1.0 %, atlas phantom at
 * 1 mm 1.7 %, k-means tissues at 4 mm 0.4 %). */
TEST(RandomizedKnownDefect, SliverRemovalMovesSmallRandomMeshesMoreWithTheLastBitsOfDelta)
{
  const RandomCase randomCase = MakeCase(Family::ManyLabels, 5000016);
  ASSERT_EQ(randomCase.settings.minimumDihedralAngle, dr::RefinementParameters{}.minimumDihedralAngle)
    << "the case is no longer the one";
  EXPECT_GT(LargestChangeUnderDeltaPerturbations(randomCase, false), LargestRelativeSizeChange)
    << "fixed? then hold the first meshes of every family to the bound with the defaults, and remove this test";
}

} // namespace
