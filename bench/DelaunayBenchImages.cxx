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
#include "DelaunayBenchImages.h"

#include "itkImageFileReader.h"
#include "itkImageRegionConstIterator.h"
#include "itkImageRegionIterator.h"
#include "itkImageRegionIteratorWithIndex.h"
#include "itkNearestNeighborInterpolateImageFunction.h"
#include "itkOrientImageFilter.h"
#include "itkResampleImageFilter.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <stdexcept>
#include <vector>

namespace delaunay_bench
{
namespace
{

using PointType = LabelImage::PointType;

/** A cube of `size`³ voxels of 1 mm, origin 0, labelled 1 where `isInside` holds at the voxel centre. */
LabelImage::Pointer
GenerateShape(unsigned int size, const std::function<bool(const PointType &)> & isInside)
{
  auto                 image = LabelImage::New();
  LabelImage::SizeType extent;
  extent.Fill(size);
  image->SetRegions(LabelImage::RegionType(extent));
  image->Allocate();
  for (itk::ImageRegionIteratorWithIndex<LabelImage> it(image, image->GetBufferedRegion()); !it.IsAtEnd(); ++it)
  {
    PointType center;
    image->TransformIndexToPhysicalPoint(it.GetIndex(), center);
    it.Set(isInside(center) ? 1 : 0);
  }
  return image;
}

LabelImage::Pointer
GenerateSphere(unsigned int size)
{
  const double middle = 0.5 * (size - 1);
  const double radius = 0.35 * size;
  return GenerateShape(size, [=](const PointType & p) {
    const double x = p[0] - middle;
    const double y = p[1] - middle;
    const double z = p[2] - middle;
    return x * x + y * y + z * z <= radius * radius;
  });
}

/** A torus around the z axis: genus 1, and a tube thin enough (about 4δ across at δ = 2 mm, 64³) to be a
 * harder case than the sphere. */
LabelImage::Pointer
GenerateTorus(unsigned int size)
{
  const double middle = 0.5 * (size - 1);
  const double ringRadius = 0.28 * size;
  const double tubeRadius = 0.12 * size;
  return GenerateShape(size, [=](const PointType & p) {
    const double x = p[0] - middle;
    const double y = p[1] - middle;
    const double z = p[2] - middle;
    const double fromRing = std::sqrt(x * x + y * y) - ringRadius;
    return fromRing * fromRing + z * z <= tubeRadius * tubeRadius;
  });
}

/** splitmix64: a fixed, portable stream of pseudo-random numbers (std::uniform_real_distribution differs between
 * standard libraries, and the phantom must be the same everywhere). */
class PortableRandom
{
public:
  explicit PortableRandom(uint64_t seed)
    : m_State(seed)
  {}

  /** Uniform in [0, 1). */
  double
  Next()
  {
    return static_cast<double>(Hash(m_State += 0x9E3779B97F4A7C15ull) >> 11) * 0x1.0p-53;
  }

  static uint64_t
  Hash(uint64_t z)
  {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

private:
  uint64_t m_State;
};

/** An atlas-like phantom (issues #14 and #18): `labels` regions filling an ellipsoidal "brain" of 80 × 96 × 80 mm
 * in 96 × 112 × 96 voxels of 1 mm, each the Voronoi cell of a random seed, every region touching several others
 * along interfaces, triple curves and quadruple points, as an atlas's do. The distances to the seeds get a
 * per-voxel jitter of up to ±0.5 mm, so the interfaces are jagged at the voxel scale, with the odd voxel of one
 * label inside another, as a registered atlas's are. Background (0) outside the ellipsoid. */
LabelImage::Pointer
GenerateAtlasPhantom(unsigned int labels)
{
  const LabelImage::SizeType  extent{ { 96, 112, 96 } };
  const std::array<double, 3> middle{ { 47.5, 55.5, 47.5 } };
  const std::array<double, 3> semiAxes{ { 40.0, 48.0, 40.0 } };
  const auto                  insideEllipsoid = [&](const std::array<double, 3> & p) {
    double sum = 0.0;
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      const double t = (p[axis] - middle[axis]) / semiAxes[axis];
      sum += t * t;
    }
    return sum <= 1.0;
  };
  PortableRandom                     random(20261124);
  std::vector<std::array<double, 3>> seeds;
  while (seeds.size() < labels)
  {
    std::array<double, 3> seed{};
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      seed[axis] = middle[axis] + semiAxes[axis] * (2.0 * random.Next() - 1.0);
    }
    if (insideEllipsoid(seed))
    {
      seeds.push_back(seed);
    }
  }
  auto image = LabelImage::New();
  image->SetRegions(LabelImage::RegionType(extent));
  image->Allocate();
  uint64_t voxel = 0;
  for (itk::ImageRegionIteratorWithIndex<LabelImage> it(image, image->GetBufferedRegion()); !it.IsAtEnd(); ++it)
  {
    const std::array<double, 3> p{ { static_cast<double>(it.GetIndex()[0]),
                                     static_cast<double>(it.GetIndex()[1]),
                                     static_cast<double>(it.GetIndex()[2]) } };
    ++voxel;
    if (!insideEllipsoid(p))
    {
      it.Set(0);
      continue;
    }
    std::size_t nearest = 0;
    double      nearestDistance = std::numeric_limits<double>::infinity();
    for (std::size_t seed = 0; seed < seeds.size(); ++seed)
    {
      const double jitter =
        1.0 * (static_cast<double>(PortableRandom::Hash(voxel * 1024 + seed) >> 11) * 0x1.0p-53 - 0.5);
      const double distance = std::sqrt((p[0] - seeds[seed][0]) * (p[0] - seeds[seed][0]) +
                                        (p[1] - seeds[seed][1]) * (p[1] - seeds[seed][1]) +
                                        (p[2] - seeds[seed][2]) * (p[2] - seeds[seed][2])) +
                              jitter;
      if (distance < nearestDistance)
      {
        nearestDistance = distance;
        nearest = seed;
      }
    }
    it.Set(static_cast<uint8_t>(1 + nearest));
  }
  return image;
}

/** The same voxels in the same physical places, with the axes permuted and flipped so that the direction is
 * the identity (ITK's RAI): CGAL's Image_3 has no direction matrix. No interpolation is involved. */
LabelImage::Pointer
ReorientToIdentityDirection(const LabelImage::Pointer & image)
{
  auto orient = itk::OrientImageFilter<LabelImage, LabelImage>::New();
  orient->SetInput(image);
  orient->UseImageDirectionOn();
  orient->SetDesiredCoordinateOrientation(itk::SpatialOrientation::ITK_COORDINATE_ORIENTATION_RAI);
  orient->Update();
  return orient->GetOutput();
}

LabelImage::Pointer
ReadLabelImage(const std::string & fileName)
{
  auto reader = itk::ImageFileReader<LabelImage>::New();
  reader->SetFileName(fileName);
  reader->Update();
  return ReorientToIdentityDirection(reader->GetOutput());
}

void
MapLabels(LabelImage & image, const std::function<uint8_t(uint8_t)> & map)
{
  for (itk::ImageRegionIterator<LabelImage> it(&image, image.GetBufferedRegion()); !it.IsAtEnd(); ++it)
  {
    it.Set(map(it.Get()));
  }
}

/** The label that fills most of the image's border: the background class of a segmentation. */
uint8_t
MostFrequentBorderLabel(const LabelImage & image)
{
  const auto &                   region = image.GetBufferedRegion();
  std::map<uint8_t, std::size_t> counts;
  for (itk::ImageRegionConstIteratorWithIndex<LabelImage> it(&image, region); !it.IsAtEnd(); ++it)
  {
    bool onBorder = false;
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      const auto index = it.GetIndex()[axis];
      onBorder = onBorder || index == region.GetIndex()[axis] ||
                 index == region.GetIndex()[axis] + static_cast<long>(region.GetSize()[axis]) - 1;
    }
    counts[it.Get()] += onBorder;
  }
  return std::max_element(
           counts.begin(), counts.end(), [](const auto & a, const auto & b) { return a.second < b.second; })
    ->first;
}

/** The brain mask has labels 0/4/5/6; all of the brain is one object. */
LabelImage::Pointer
ReadBrainMask(const std::string & dataDirectory)
{
  LabelImage::Pointer image = ReadLabelImage(dataDirectory + "/KmeansTest_T1RawSkullStrip.nii.gz");
  MapLabels(*image, [](uint8_t label) { return label != 0 ? uint8_t{ 1 } : uint8_t{ 0 }; });
  return image;
}

/** The six k-means classes without the background class (found, not assumed: the class filling the border)
 * and without the few voxels of label 0. CGAL treats 0 as outside, so the background class becomes 0. */
LabelImage::Pointer
ReadKmeansTissues(const std::string & dataDirectory)
{
  LabelImage::Pointer image = ReadLabelImage(dataDirectory + "/KmeansTest_T1KmeansPrelimSegmentation.nii.gz");
  const uint8_t       backgroundClass = MostFrequentBorderLabel(*image);
  std::cerr << "k-means segmentation: class " << int{ backgroundClass } << " fills most of the border and is "
            << "taken as the background\n";
  MapLabels(*image, [=](uint8_t label) { return label == backgroundClass ? uint8_t{ 0 } : label; });
  return image;
}

/** Nearest-neighbour resampling onto `spacing` mm voxels covering the same physical extent (voxel faces, not
 * centres, kept in place). */
LabelImage::Pointer
ResampleIsotropic(const LabelImage & image, double spacing)
{
  const auto &         inputSpacing = image.GetSpacing();
  const auto &         inputSize = image.GetBufferedRegion().GetSize();
  LabelImage::SizeType size;
  PointType            origin;
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    const double extent = inputSpacing[axis] * static_cast<double>(inputSize[axis]);
    size[axis] = static_cast<itk::SizeValueType>(std::lround(extent / spacing));
    origin[axis] = image.GetOrigin()[axis] - 0.5 * inputSpacing[axis] + 0.5 * spacing;
  }
  auto resample = itk::ResampleImageFilter<LabelImage, LabelImage>::New();
  resample->SetInput(&image);
  resample->SetInterpolator(itk::NearestNeighborInterpolateImageFunction<LabelImage, double>::New());
  resample->SetSize(size);
  resample->SetOutputOrigin(origin);
  resample->SetOutputSpacing(LabelImage::SpacingType(spacing));
  resample->SetOutputDirection(image.GetDirection());
  resample->SetDefaultPixelValue(0);
  resample->Update();
  return resample->GetOutput();
}

} // namespace

std::vector<BenchImage>
MakeBenchImages(bool quick, const std::string & dataDirectory)
{
  using Deltas = std::vector<double>;
  const LabelImage::Pointer brainMask = ReadBrainMask(dataDirectory);
  const LabelImage::Pointer kmeansTissues = ReadKmeansTissues(dataDirectory);
  std::vector<BenchImage>   images;
  images.push_back({ "sphere-64", "generated ball", GenerateSphere(64), quick ? Deltas{ 4 } : Deltas{ 2, 4 } });
  images.push_back({ "torus-64", "generated torus", GenerateTorus(64), quick ? Deltas{ 4 } : Deltas{ 2, 4 } });
  if (!quick)
  {
    images.push_back({ "sphere-128", "generated ball", GenerateSphere(128), { 2, 4 } });
    images.push_back({ "torus-128", "generated torus", GenerateTorus(128), { 2, 4 } });
  }
  images.push_back(
    { "brain-mask", "KmeansTest_T1RawSkullStrip, non-zero = brain", brainMask, quick ? Deltas{ 4 } : Deltas{ 2, 4 } });
  images.push_back(
    { "kmeans-tissues", "KmeansTest_T1KmeansPrelimSegmentation, the 5 tissue classes", kmeansTissues, { 4 } });
  if (!quick)
  {
    images.push_back({ "atlas-phantom",
                       "generated atlas-like phantom: 120 touching labels, 96 x 112 x 96 voxels of 1 mm",
                       GenerateAtlasPhantom(120),
                       { 2, 4 } });
    images.push_back({ "brain-mask-1mm",
                       "the brain mask resampled (nearest neighbour) to 1 mm isotropic",
                       ResampleIsotropic(*brainMask, 1.0),
                       { 2 } });
    images.push_back({ "kmeans-tissues-1mm",
                       "the k-means tissues resampled (nearest neighbour) to 1 mm isotropic",
                       ResampleIsotropic(*kmeansTissues, 1.0),
                       { 4 } });
  }
  for (const BenchImage & benchImage : images)
  {
    RequireIdentityDirection(*benchImage.image, benchImage.name);
  }
  return images;
}

delaunay_refinement::LabelVolume
ToLabelVolume(const LabelImage & image)
{
  delaunay_refinement::LabelVolume volume;
  const auto &                     region = image.GetBufferedRegion();
  PointType                        origin;
  image.TransformIndexToPhysicalPoint(region.GetIndex(), origin);
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    volume.size[axis] = region.GetSize()[axis];
    volume.origin[axis] = origin[axis];
    volume.spacing[axis] = image.GetSpacing()[axis];
    for (unsigned int column = 0; column < 3; ++column)
    {
      volume.direction[axis][column] = image.GetDirection()[axis][column];
    }
  }
  // The iterator runs x fastest, then y, then z: LabelVolume's order.
  for (itk::ImageRegionConstIterator<LabelImage> it(&image, region); !it.IsAtEnd(); ++it)
  {
    volume.labels.push_back(it.Get());
  }
  return volume;
}

void
RequireIdentityDirection(const LabelImage & image, const std::string & name)
{
  LabelImage::DirectionType identity;
  identity.SetIdentity();
  if (image.GetDirection() != identity)
  {
    throw std::invalid_argument("image " + name +
                                " has a non-identity direction matrix, which CGAL's Image_3 cannot represent");
  }
}

} // namespace delaunay_bench
