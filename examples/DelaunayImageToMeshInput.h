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
#ifndef DelaunayImageToMeshInput_h
#define DelaunayImageToMeshInput_h

// The command-line program's input (examples/DelaunayImageToMesh.cxx): an image file ITK can read, or a directory
// holding a DICOM series, read as a 3-D image, every failure turned into one line the user can act on.

#include "itkImageFileReader.h"
#include "itkImageIOFactory.h"
#include "itkImageSeriesReader.h"
#include "vnl/algo/vnl_determinant.h"
#if DelaunayImageToMesh_READS_DICOM
#  include "itkGDCMImageIO.h"
#  include "itkGDCMSeriesFileNames.h"
#endif

#include <cmath>
#include <filesystem>
#include <ostream>
#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

namespace delaunay_image_to_mesh_program
{

inline constexpr const char * ProgramName = "delaunay-image-to-mesh";

/** A problem the user can fix (an argument, a file): reported as one line, without a stack. */
class UserError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};


/** ITK's descriptions may span lines and start with "ITK ERROR: ClassName(0x...): "; the user needs one line,
 * the message. */
inline std::string
OneLine(const std::string & description)
{
  static const std::regex objectPrefix("^\\s*(ITK ERROR:|itk::ERROR:)?\\s*[A-Za-z_:]+\\(0x[0-9a-fA-F]+\\):\\s*");
  static const std::regex whitespace("\\s+");
  const std::string message = std::regex_replace(std::regex_replace(description, objectPrefix, ""), whitespace, " ");
  const std::size_t end = message.find_last_not_of(' ');
  return end == std::string::npos ? message : message.substr(0, end + 1);
}

inline void
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

/** A label or gray value per voxel: ITK's reader would turn a colour or vector voxel into one number (a colour's
 * luminance: the components 1, 2, 3 became label 1), meshing labels the file does not hold. */
inline void
CheckOneComponent(const std::string & path, const itk::ImageIOBase & io)
{
  if (io.GetNumberOfComponents() != 1)
  {
    throw UserError("cannot mesh input '" + path + "': its voxels have " + std::to_string(io.GetNumberOfComponents()) +
                    " components (" + itk::ImageIOBase::GetPixelTypeAsString(io.GetPixelType()) +
                    "); a label image, or a gray image with --iso, has one value per voxel");
  }
}

/** The direction of a file's first three axes, as the IO read it (direction cosines are the matrix's columns).
 * ITK 5.2's ImageFileReader gives a file of more dimensions than the image the identity instead (it takes the IO's
 * default direction), which would move and turn a 4-D MetaImage or NRRD file of one time point in physical space. */
template <typename TImage>
typename TImage::DirectionType
DirectionOfTheFirstThreeAxes(const std::string & path, const itk::ImageIOBase & io)
{
  typename TImage::DirectionType direction;
  for (unsigned int column = 0; column < 3; ++column)
  {
    const std::vector<double> axis = io.GetDirection(column);
    for (unsigned int row = 0; row < 3; ++row)
    {
      direction[row][column] = row < axis.size() ? axis[row] : 0.0;
    }
    // As the reader does for the axes it keeps: a negative spacing turns the axis around.
    if (io.GetSpacing(column) < 0.0)
    {
      for (unsigned int row = 0; row < 3; ++row)
      {
        direction[row][column] = -direction[row][column];
      }
    }
  }
  if (!(std::abs(vnl_determinant(direction.GetVnlMatrix())) > 1e-6))
  {
    throw UserError("cannot mesh input '" + path + "': the direction of its first three axes is singular (the " +
                    std::to_string(io.GetNumberOfDimensions()) + "-D direction mixes them with the others)");
  }
  return direction;
}

inline void
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
    CheckOneComponent(path, *io);
    reader->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    throw UserError("cannot read input '" + path + "': " + OneLine(error.GetDescription()));
  }
  typename TImage::Pointer image = reader->GetOutput();
  if (io->GetNumberOfDimensions() > 3)
  {
    image->DisconnectPipeline();
    image->SetDirection(DirectionOfTheFirstThreeAxes<TImage>(path, *io));
  }
  return image;
}

template <typename TImage>
typename TImage::Pointer
ReadDicomSeries(const std::string & directory, std::ostream * notes)
{
#if !DelaunayImageToMesh_READS_DICOM
  (void)notes;
  throw UserError("cannot read input '" + directory + "': this build has no DICOM reader (ITK without ITKIOGDCM)");
#else
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
  CheckOneComponent(directory, *reader->GetImageIO());
  return reader->GetOutput();
#endif
}

/** The pixel component type of a one-component image file; unknown for a directory (a DICOM series), a
 * many-component file or a file ITK cannot read (ReadImage() then says why). */
inline itk::IOComponentEnum
ScalarComponentTypeOf(const std::string & path)
{
  std::error_code error;
  if (std::filesystem::is_directory(path, error))
  {
    return itk::IOComponentEnum::UNKNOWNCOMPONENTTYPE;
  }
  const itk::ImageIOBase::Pointer io = itk::ImageIOFactory::CreateImageIO(path.c_str(), itk::IOFileModeEnum::ReadMode);
  if (io.IsNull())
  {
    return itk::IOComponentEnum::UNKNOWNCOMPONENTTYPE;
  }
  try
  {
    io->SetFileName(path);
    io->ReadImageInformation();
  }
  catch (const itk::ExceptionObject &)
  {
    return itk::IOComponentEnum::UNKNOWNCOMPONENTTYPE;
  }
  return io->GetNumberOfComponents() == 1 ? io->GetComponentType() : itk::IOComponentEnum::UNKNOWNCOMPONENTTYPE;
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

} // namespace delaunay_image_to_mesh_program

#endif
