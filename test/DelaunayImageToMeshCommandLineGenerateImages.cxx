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

// Writes the small images the command-line tests mesh, into the directory given as the only argument:
// - labels.nii.gz, labels.nrrd, labels.mha: two overlapping balls, label 1 (radius 7 mm, centred 3 mm to the
//   left of the image centre) and label 2 (radius 5 mm, 5 mm to the right, winning where they overlap), on an
//   anisotropic, rotated, shifted grid, so that the files only agree if spacing, origin and direction are read;
// - labels-uint8.nrrd, labels-uint16.nrrd, labels-int32.nrrd, labels-float.nrrd: the same image in other pixel
//   types (the program reads 8- and 16-bit label files as they are, floating-point ones as floats, others as 32-bit
//   integers); labels-float-rounding.nrrd holds each label less 1e-4, which must round to the same labels;
// - labels-dicom/: the same balls as a DICOM series (one file per slice), on an unrotated grid;
// - gray.mha: 100 minus the distance to the image centre (mm), so that --iso 92 is a ball of radius 8 mm.
// - speck.nii.gz: the balls and a third tissue, label 3, of two face-adjacent voxels (3.75 mm³) away from them:
//   a tissue far thinner than the default δ (6 mm), which the mesh loses.

#include "itkCastImageFilter.h"
#include "itkGDCMImageIO.h"
#include "itkImage.h"
#include "itkImageFileWriter.h"
#include "itkImageRegionConstIterator.h"
#include "itkImageRegionIterator.h"
#include "itkImageRegionIteratorWithIndex.h"
#include "itkImageSeriesWriter.h"
#include "itkMetaDataObject.h"
#include "itkVector.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace
{

using LabelImageType = itk::Image<short, 3>;
using GrayImageType = itk::Image<float, 3>;
using SliceType = itk::Image<short, 2>;

template <typename TImage>
typename TImage::Pointer
MakeGrid(bool rotated)
{
  auto                        image = TImage::New();
  typename TImage::SizeType   size{ { 30, 26, 20 } };
  typename TImage::RegionType region(size);
  image->SetRegions(region);
  const double spacing[3] = { 1.0, 1.25, 1.5 };
  const double origin[3] = { -12.0, 4.0, 2.5 };
  image->SetSpacing(spacing);
  image->SetOrigin(origin);
  if (rotated)
  {
    // A quarter turn about z: voxel axis i runs along physical y, j along -x.
    typename TImage::DirectionType direction;
    direction.Fill(0.0);
    direction(0, 1) = -1.0;
    direction(1, 0) = 1.0;
    direction(2, 2) = 1.0;
    image->SetDirection(direction);
  }
  image->Allocate();
  return image;
}

template <typename TImage>
itk::Point<double, 3>
CentreOf(const TImage * image)
{
  itk::ContinuousIndex<double, 3> centreIndex;
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    centreIndex[axis] = 0.5 * (image->GetLargestPossibleRegion().GetSize(axis) - 1.0);
  }
  itk::Point<double, 3> centre;
  image->TransformContinuousIndexToPhysicalPoint(centreIndex, centre);
  return centre;
}

LabelImageType::Pointer
MakeLabelImage(bool rotated)
{
  auto                        image = MakeGrid<LabelImageType>(rotated);
  const itk::Point<double, 3> centre = CentreOf(image.GetPointer());
  itk::Point<double, 3>       leftCentre = centre;
  itk::Point<double, 3>       rightCentre = centre;
  leftCentre[0] -= 3.0;
  rightCentre[0] += 5.0;
  for (itk::ImageRegionIteratorWithIndex<LabelImageType> it(image, image->GetLargestPossibleRegion()); !it.IsAtEnd();
       ++it)
  {
    itk::Point<double, 3> point;
    image->TransformIndexToPhysicalPoint(it.GetIndex(), point);
    it.Set(point.EuclideanDistanceTo(rightCentre) <= 5.0 ? 2 : point.EuclideanDistanceTo(leftCentre) <= 7.0 ? 1 : 0);
  }
  return image;
}

LabelImageType::Pointer
MakeSpeckImage()
{
  auto image = MakeLabelImage(true);
  image->SetPixel({ { 3, 3, 3 } }, 3);
  image->SetPixel({ { 4, 3, 3 } }, 3);
  return image;
}

GrayImageType::Pointer
MakeGrayImage()
{
  auto                        image = MakeGrid<GrayImageType>(true);
  const itk::Point<double, 3> centre = CentreOf(image.GetPointer());
  for (itk::ImageRegionIteratorWithIndex<GrayImageType> it(image, image->GetLargestPossibleRegion()); !it.IsAtEnd();
       ++it)
  {
    itk::Point<double, 3> point;
    image->TransformIndexToPhysicalPoint(it.GetIndex(), point);
    it.Set(static_cast<float>(100.0 - point.EuclideanDistanceTo(centre)));
  }
  return image;
}

template <typename TImage>
void
WriteImage(const TImage * image, const std::string & path)
{
  auto writer = itk::ImageFileWriter<TImage>::New();
  writer->SetInput(image);
  writer->SetFileName(path);
  writer->UseCompressionOn();
  writer->Update();
}

/** The labels, each voxel's mapped by `map`, as an image of `TPixel` on the same grid. */
template <typename TPixel, typename TMap>
typename itk::Image<TPixel, 3>::Pointer
MappedLabels(const LabelImageType * labels, TMap map)
{
  using OutputImageType = itk::Image<TPixel, 3>;
  auto image = OutputImageType::New();
  image->CopyInformation(labels);
  image->SetRegions(labels->GetBufferedRegion());
  image->Allocate();
  itk::ImageRegionConstIterator<LabelImageType> input(labels, labels->GetBufferedRegion());
  itk::ImageRegionIterator<OutputImageType>     output(image, image->GetBufferedRegion());
  for (; !input.IsAtEnd(); ++input, ++output)
  {
    output.Set(map(input.Get()));
  }
  return image;
}

/** The labels as floats, each non-zero one less 1e-4: a label image resampled or saved in floating point. */
GrayImageType::Pointer
LabelsLessATenThousandth(const LabelImageType * labels)
{
  return MappedLabels<float>(labels, [](short label) { return label == 0 ? 0.0f : static_cast<float>(label) - 1e-4f; });
}

template <typename TPixel>
void
WriteLabelsAs(const LabelImageType * labels, const std::string & path)
{
  using OutputImageType = itk::Image<TPixel, 3>;
  auto cast = itk::CastImageFilter<LabelImageType, OutputImageType>::New();
  cast->SetInput(labels);
  cast->Update();
  WriteImage(cast->GetOutput(), path);
}

/** The labels with 1 and 2 mapped to `first` and `second`, as an image of `TPixel`: label values a 32-bit signed
 * integer cannot hold, or that a float cannot tell apart. */
template <typename TPixel>
void
WriteLabelsRenamed(const LabelImageType * labels, TPixel first, TPixel second, const std::string & path)
{
  WriteImage(MappedLabels<TPixel>(labels,
                                  [first, second](short label) -> TPixel {
                                    return label == 0 ? TPixel{ 0 } : label == 1 ? first : second;
                                  })
               .GetPointer(),
             path);
}

/** The labels as three components a voxel (label, label + 1, label + 2): a colour or vector image, not labels. */
void
WriteLabelsAsVectors(const LabelImageType * labels, const std::string & path)
{
  using VectorType = itk::Vector<uint8_t, 3>;
  WriteImage(MappedLabels<VectorType>(labels,
                                      [](short label) {
                                        VectorType vector;
                                        for (unsigned int component = 0; component < 3; ++component)
                                        {
                                          vector[component] = static_cast<uint8_t>(label == 0 ? 0 : label + component);
                                        }
                                        return vector;
                                      })
               .GetPointer(),
             path);
}

/** The labels as a 4-D image of one time point (a fourth axis of size 1, spacing 1), as some tools save volumes. */
void
WriteLabelsAsOneTimePoint(const LabelImageType * labels, const std::string & path)
{
  using OutputImageType = itk::Image<short, 4>;
  auto                         image = OutputImageType::New();
  OutputImageType::SizeType    size{};
  OutputImageType::SpacingType spacing;
  OutputImageType::PointType   origin;
  spacing.Fill(1.0);
  origin.Fill(0.0);
  OutputImageType::DirectionType direction;
  direction.SetIdentity();
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    size[axis] = labels->GetBufferedRegion().GetSize(axis);
    spacing[axis] = labels->GetSpacing()[axis];
    origin[axis] = labels->GetOrigin()[axis];
    for (unsigned int other = 0; other < 3; ++other)
    {
      direction(axis, other) = labels->GetDirection()(axis, other);
    }
  }
  size[3] = 1;
  image->SetRegions(OutputImageType::RegionType(size));
  image->SetSpacing(spacing);
  image->SetOrigin(origin);
  image->SetDirection(direction);
  image->Allocate();
  std::copy_n(labels->GetBufferPointer(), labels->GetBufferedRegion().GetNumberOfPixels(), image->GetBufferPointer());
  WriteImage(image.GetPointer(), path);
}

std::string
DicomNumbers(const std::vector<double> & values)
{
  std::ostringstream text;
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    text << (i == 0 ? "" : "\\") << values[i];
  }
  return text.str();
}

/** The tags a reader needs to stack the slices: fixed study and series UIDs (GDCM would otherwise give every
 * file a series of its own), each slice's position, the orientation and the spacing; and the photometric
 * interpretation, without which GDCM warns. */
itk::MetaDataDictionary
SliceDictionary(const LabelImageType * image, unsigned int slice)
{
  const std::string       uidRoot = "1.2.826.0.1.3680043.10.543.";
  const auto &            spacing = image->GetSpacing();
  itk::Point<double, 3>   position;
  itk::MetaDataDictionary dictionary;
  image->TransformIndexToPhysicalPoint({ { 0, 0, static_cast<itk::IndexValueType>(slice) } }, position);
  itk::EncapsulateMetaData<std::string>(dictionary, "0008|0060", "MR");
  itk::EncapsulateMetaData<std::string>(dictionary, "0028|0004", "MONOCHROME2");
  itk::EncapsulateMetaData<std::string>(dictionary, "0008|0016", "1.2.840.10008.5.1.4.1.1.4");
  itk::EncapsulateMetaData<std::string>(dictionary, "0020|000d", uidRoot + "1");
  itk::EncapsulateMetaData<std::string>(dictionary, "0020|000e", uidRoot + "2");
  itk::EncapsulateMetaData<std::string>(dictionary, "0008|0018", uidRoot + "3." + std::to_string(slice + 1));
  itk::EncapsulateMetaData<std::string>(dictionary, "0020|0013", std::to_string(slice + 1));
  itk::EncapsulateMetaData<std::string>(
    dictionary, "0020|0032", DicomNumbers({ position[0], position[1], position[2] }));
  itk::EncapsulateMetaData<std::string>(dictionary, "0020|0037", DicomNumbers({ 1, 0, 0, 0, 1, 0 }));
  itk::EncapsulateMetaData<std::string>(dictionary, "0028|0030", DicomNumbers({ spacing[1], spacing[0] }));
  itk::EncapsulateMetaData<std::string>(dictionary, "0018|0050", DicomNumbers({ spacing[2] }));
  itk::EncapsulateMetaData<std::string>(dictionary, "0018|0088", DicomNumbers({ spacing[2] }));
  return dictionary;
}

void
WriteDicomSeries(const LabelImageType * image, const std::filesystem::path & directory)
{
  std::filesystem::create_directories(directory);
  const unsigned int                   slices = image->GetLargestPossibleRegion().GetSize(2);
  std::vector<itk::MetaDataDictionary> dictionaries;
  std::vector<std::string>             fileNames;
  for (unsigned int slice = 0; slice < slices; ++slice)
  {
    dictionaries.push_back(SliceDictionary(image, slice));
    fileNames.push_back((directory / ("slice" + std::to_string(100 + slice) + ".dcm")).string());
  }
  std::vector<itk::MetaDataDictionary *> dictionaryPointers;
  for (itk::MetaDataDictionary & dictionary : dictionaries)
  {
    dictionaryPointers.push_back(&dictionary);
  }
  auto io = itk::GDCMImageIO::New();
  io->KeepOriginalUIDOn();
  auto writer = itk::ImageSeriesWriter<LabelImageType, SliceType>::New();
  writer->SetInput(image);
  writer->SetImageIO(io);
  writer->SetFileNames(fileNames);
  writer->SetMetaDataDictionaryArray(&dictionaryPointers);
  writer->Update();
}

} // namespace

int
main(int argc, char * argv[])
{
  if (argc != 2)
  {
    std::cerr << "Usage: " << argv[0] << " OUTPUT_DIRECTORY" << std::endl;
    return EXIT_FAILURE;
  }
  try
  {
    const std::filesystem::path directory(argv[1]);
    std::filesystem::create_directories(directory);
    const LabelImageType::Pointer labels = MakeLabelImage(true);
    for (const char * name : { "labels.nii.gz", "labels.nrrd", "labels.mha" })
    {
      WriteImage(labels.GetPointer(), (directory / name).string());
    }
    WriteLabelsAs<uint8_t>(labels, (directory / "labels-uint8.nrrd").string());
    WriteLabelsAs<uint16_t>(labels, (directory / "labels-uint16.nrrd").string());
    // Values a signed 16-bit reading would make negative.
    WriteLabelsRenamed<uint16_t>(labels, 40000, 65535, (directory / "labels-uint16-high.nrrd").string());
    WriteLabelsAsOneTimePoint(labels, (directory / "labels-one-time-point.mha").string());
    WriteLabelsAsOneTimePoint(labels, (directory / "labels-one-time-point.nii.gz").string());
    WriteLabelsAsOneTimePoint(labels, (directory / "labels-one-time-point.nrrd").string());
    WriteLabelsAs<int32_t>(labels, (directory / "labels-int32.nrrd").string());
    WriteLabelsAs<float>(labels, (directory / "labels-float.nrrd").string());
    // The largest label, and integers beyond a 32-bit signed integer or a float (read as doubles).
    WriteLabelsRenamed<uint32_t>(labels, 100000, 2147483647, (directory / "labels-uint32-largest.nrrd").string());
    WriteLabelsRenamed<double>(
      labels, 16777216.0, 16777217.0, (directory / "labels-double-beyond-float.nrrd").string());
    WriteLabelsRenamed<uint32_t>(labels, 1, 4000000000u, (directory / "labels-uint32-beyond.nrrd").string());
    WriteLabelsRenamed<int64_t>(labels, 1, (int64_t{ 1 } << 33) + 1, (directory / "labels-int64-beyond.nrrd").string());
    WriteLabelsAsVectors(labels, (directory / "labels-vector.nrrd").string());
    WriteImage(LabelsLessATenThousandth(labels).GetPointer(), (directory / "labels-float-rounding.nrrd").string());
    WriteDicomSeries(MakeLabelImage(false), directory / "labels-dicom");
    WriteImage(MakeGrayImage().GetPointer(), (directory / "gray.mha").string());
    WriteImage(MakeSpeckImage().GetPointer(), (directory / "speck.nii.gz").string());
  }
  catch (const std::exception & error)
  {
    std::cerr << "Cannot write the test images: " << error.what() << std::endl;
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}
