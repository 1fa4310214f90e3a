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
#include "DelaunayImageToMeshWriters.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkErrorCode.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkTypeInt32Array.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <locale>
#include <map>
#include <stdexcept>
#include <system_error>
#include <utility>

namespace delaunay_refinement
{
namespace
{

using LabelPair = std::array<Label, 2>;

/** Indices of the tetrahedra of each label, labels in increasing order. */
using TetrahedraByLabel = std::map<Label, std::vector<std::size_t>>;

/** Indices of the boundary triangles of each label pair, pairs in lexicographic order. */
using TrianglesByLabelPair = std::map<LabelPair, std::vector<std::size_t>>;

using MeshFileWriter = void (*)(const TetrahedralMesh &, const std::string &);

std::string
LowerCaseExtension(const std::string & fileName)
{
  std::string extension = std::filesystem::path(fileName).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char character) {
    return static_cast<char>(std::tolower(character));
  });
  return extension;
}

template <std::size_t VNumberOfVertices>
void
CheckPointIndices(const std::vector<std::array<uint32_t, VNumberOfVertices>> & cells, std::size_t numberOfPoints,
                  const char * cellsName)
{
  for (std::size_t cellIndex = 0; cellIndex < cells.size(); ++cellIndex)
  {
    for (const uint32_t pointIndex : cells[cellIndex])
    {
      if (pointIndex >= numberOfPoints)
      {
        throw std::invalid_argument(std::string("WriteTetrahedralMesh: ") + cellsName + "[" +
                                    std::to_string(cellIndex) + "] uses point index " + std::to_string(pointIndex) +
                                    ", but the mesh has only " + std::to_string(numberOfPoints) + " points.");
      }
    }
  }
}

void
CheckArraySize(std::size_t labelsSize, const char * labelsName, std::size_t cellsSize, const char * cellsName)
{
  if (labelsSize != cellsSize)
  {
    throw std::invalid_argument(std::string("WriteTetrahedralMesh: ") + labelsName + " has " +
                                std::to_string(labelsSize) + " entries but " + cellsName + " has " +
                                std::to_string(cellsSize) + "; they must have one entry per cell.");
  }
}

/** The writers index the label arrays and the points by the cells' contents, so an inconsistent mesh would make
 * them read out of bounds. */
void
CheckMeshConsistency(const TetrahedralMesh & mesh)
{
  CheckArraySize(mesh.tetrahedronLabels.size(), "tetrahedronLabels", mesh.tetrahedra.size(), "tetrahedra");
  CheckArraySize(
    mesh.boundaryTriangleLabels.size(), "boundaryTriangleLabels", mesh.boundaryTriangles.size(), "boundaryTriangles");
  CheckPointIndices(mesh.tetrahedra, mesh.points.size(), "tetrahedra");
  CheckPointIndices(mesh.boundaryTriangles, mesh.points.size(), "boundaryTriangles");
}

TetrahedraByLabel
GroupTetrahedraByLabel(const TetrahedralMesh & mesh)
{
  TetrahedraByLabel groups;
  for (std::size_t tetrahedronIndex = 0; tetrahedronIndex < mesh.tetrahedra.size(); ++tetrahedronIndex)
  {
    groups[mesh.tetrahedronLabels[tetrahedronIndex]].push_back(tetrahedronIndex);
  }
  return groups;
}

TrianglesByLabelPair
GroupTrianglesByLabelPair(const TetrahedralMesh & mesh)
{
  TrianglesByLabelPair groups;
  for (std::size_t triangleIndex = 0; triangleIndex < mesh.boundaryTriangles.size(); ++triangleIndex)
  {
    groups[mesh.boundaryTriangleLabels[triangleIndex]].push_back(triangleIndex);
  }
  return groups;
}

/** One tag per label pair, numbered after the largest tetrahedron label so that an interface tag never equals a
 * tissue label: a reader that ignores the dimension of Gmsh physical groups, or that reads Medit references, can
 * then still tell tissues from interfaces. */
std::map<LabelPair, Label>
NumberInterfaces(const TetrahedraByLabel & tetrahedraByLabel, const TrianglesByLabelPair & trianglesByLabelPair)
{
  const Label largestLabel = tetrahedraByLabel.empty() ? BackgroundLabel : tetrahedraByLabel.rbegin()->first;
  const auto  numberOfPairs = static_cast<int64_t>(trianglesByLabelPair.size());
  if (static_cast<int64_t>(largestLabel) + numberOfPairs > std::numeric_limits<Label>::max())
  {
    throw std::invalid_argument("WriteTetrahedralMesh: tetrahedron label " + std::to_string(largestLabel) +
                                " leaves no room for the " + std::to_string(numberOfPairs) +
                                " interface tags numbered after it.");
  }
  std::map<LabelPair, Label> interfaceTags;
  Label                      nextTag = std::max(largestLabel, BackgroundLabel) + 1;
  for (const auto & pairAndTriangles : trianglesByLabelPair)
  {
    interfaceTags[pairAndTriangles.first] = nextTag++;
  }
  return interfaceTags;
}

template <std::size_t VNumberOfVertices>
AxisAlignedBox
BoundingBoxOfCells(const std::vector<Vector3> &                                 points,
                   const std::vector<std::array<uint32_t, VNumberOfVertices>> & cells,
                   const std::vector<std::size_t> &                             cellIndices)
{
  constexpr double infinity = std::numeric_limits<double>::infinity();
  AxisAlignedBox   box{ { { infinity, infinity, infinity } }, { { -infinity, -infinity, -infinity } } };
  for (const std::size_t cellIndex : cellIndices)
  {
    for (const uint32_t pointIndex : cells[cellIndex])
    {
      for (std::size_t axis = 0; axis < 3; ++axis)
      {
        box.lower[axis] = std::min(box.lower[axis], points[pointIndex][axis]);
        box.upper[axis] = std::max(box.upper[axis], points[pointIndex][axis]);
      }
    }
  }
  return box;
}

std::ofstream
OpenForWriting(const std::string & fileName)
{
  std::ofstream file(fileName, std::ios::out | std::ios::trunc);
  if (!file)
  {
    throw std::runtime_error("WriteTetrahedralMesh: cannot open \"" + fileName +
                             "\" for writing (does its directory exist, and is it writable?).");
  }
  return file;
}

/** Once the file is opened, whatever goes wrong leaves a truncated file that a reader might take for a mesh. */
[[noreturn]] void
RemoveIncompleteFileAndThrow(const std::string & fileName, const std::string & reason)
{
  std::remove(fileName.c_str());
  throw std::runtime_error("WriteTetrahedralMesh: writing \"" + fileName + "\" failed (" + reason +
                           "); the incomplete file was removed.");
}

/** Opens the file, lets `writeContents` fill it, and makes sure every byte reached the disk: a full disk only
 * shows when the buffer is flushed, so the stream is checked after closing. */
void
WriteTextFile(const std::string & fileName, const std::function<void(std::ostream &)> & writeContents)
{
  std::ofstream file = OpenForWriting(fileName);
  // Mesh readers expect '.' as decimal separator whatever the global locale of the calling program.
  file.imbue(std::locale::classic());
  file.precision(std::numeric_limits<double>::max_digits10);
  writeContents(file);
  file.close();
  if (file.fail())
  {
    RemoveIncompleteFileAndThrow(fileName, "disk full or I/O error");
  }
}

template <std::size_t VNumberOfVertices>
void
WriteOneBasedIndices(std::ostream & stream, const std::array<uint32_t, VNumberOfVertices> & pointIndices)
{
  const char * separator = "";
  for (const uint32_t pointIndex : pointIndices)
  {
    stream << separator << static_cast<uint64_t>(pointIndex) + 1;
    separator = " ";
  }
}

void
WritePoint(std::ostream & stream, const Vector3 & point)
{
  stream << point[0] << ' ' << point[1] << ' ' << point[2];
}

// ---------------------------------------------------------------------------------------------------------------
// VTK formats

vtkSmartPointer<vtkUnstructuredGrid>
ToVtkUnstructuredGrid(const TetrahedralMesh & mesh)
{
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(mesh.points.size()));
  for (std::size_t pointIndex = 0; pointIndex < mesh.points.size(); ++pointIndex)
  {
    points->SetPoint(static_cast<vtkIdType>(pointIndex), mesh.points[pointIndex].data());
  }

  auto cells = vtkSmartPointer<vtkCellArray>::New();
  cells->AllocateExact(static_cast<vtkIdType>(mesh.tetrahedra.size()),
                       4 * static_cast<vtkIdType>(mesh.tetrahedra.size()));
  for (const auto & tetrahedron : mesh.tetrahedra)
  {
    const vtkIdType pointIds[4] = { tetrahedron[0], tetrahedron[1], tetrahedron[2], tetrahedron[3] };
    cells->InsertNextCell(4, pointIds);
  }

  auto labels = vtkSmartPointer<vtkTypeInt32Array>::New();
  labels->SetName("label");
  labels->SetNumberOfValues(static_cast<vtkIdType>(mesh.tetrahedronLabels.size()));
  for (std::size_t tetrahedronIndex = 0; tetrahedronIndex < mesh.tetrahedronLabels.size(); ++tetrahedronIndex)
  {
    labels->SetValue(static_cast<vtkIdType>(tetrahedronIndex), mesh.tetrahedronLabels[tetrahedronIndex]);
  }

  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(points);
  grid->SetCells(VTK_TETRA, cells);
  // Active scalars, so that viewers colour the tissues without being told which array to use.
  grid->GetCellData()->SetScalars(labels);
  return grid;
}

/** vtkErrorCode::GetStringFromErrorCode() lives in VTK::CommonMisc, which this library does not link. */
std::string
DescribeVtkError(unsigned long errorCode)
{
  if (errorCode == vtkErrorCode::NoError)
  {
    return "Write() failed without an error code";
  }
  // Below FirstVTKErrorCode, VTK stores the errno of the failed system call (the XML writers do).
  if (errorCode < vtkErrorCode::FirstVTKErrorCode)
  {
    return std::generic_category().message(static_cast<int>(errorCode));
  }
  if (errorCode == vtkErrorCode::OutOfDiskSpaceError)
  {
    return "out of disk space";
  }
  return "VTK error code " + std::to_string(errorCode);
}

/** VTK writers report failure through their return value and error code, not by throwing, and use errno values
 * both for a file they cannot open and for a failed write; so the file is first opened here, which tells the two
 * apart and makes sure that only a file this call created is removed. (The XML and legacy writers share no base
 * class declaring Write().) */
template <typename TVtkWriter>
void
RunVtkWriter(TVtkWriter & writer, const std::string & fileName)
{
  OpenForWriting(fileName).close();
  writer.SetFileName(fileName.c_str());
  const int           succeeded = writer.Write();
  const unsigned long errorCode = writer.GetErrorCode();
  if (!succeeded || errorCode != vtkErrorCode::NoError)
  {
    RemoveIncompleteFileAndThrow(fileName, "VTK: " + DescribeVtkError(errorCode));
  }
}

void
WriteVtkXmlFile(const TetrahedralMesh & mesh, const std::string & fileName)
{
  auto writer = vtkSmartPointer<vtkXMLUnstructuredGridWriter>::New();
  writer->SetInputData(ToVtkUnstructuredGrid(mesh));
  writer->SetDataModeToBinary();
  // 32-bit block headers cap each array at 4 GiB, which a large brain mesh can exceed.
  writer->SetHeaderTypeToUInt64();
  // zlib's fastest level: a quarter of the default level's time (0.07 against 0.25 s for the k-means tissues' 159 k
  // tetrahedra) for a file 8 % larger. Still zlib, which every VTU reader (VTK, ParaView, meshio) decompresses.
  writer->SetCompressionLevel(1);
  RunVtkWriter(*writer, fileName);
}

void
WriteVtkLegacyFile(const TetrahedralMesh & mesh, const std::string & fileName)
{
  auto writer = vtkSmartPointer<vtkUnstructuredGridWriter>::New();
  writer->SetInputData(ToVtkUnstructuredGrid(mesh));
  writer->SetFileTypeToBinary();
  // The legacy format is chosen for older tools, and many of them read version 4.2 only, not VTK 9's 5.1.
  writer->SetFileVersion(vtkUnstructuredGridWriter::VTK_LEGACY_READER_VERSION_4_2);
  RunVtkWriter(*writer, fileName);
}

// ---------------------------------------------------------------------------------------------------------------
// Gmsh 4.1 ASCII

/** What the Gmsh sections share: entity tags are the 1-based ranks of the labels and label pairs. */
struct GmshGroups
{
  TetrahedraByLabel          tetrahedraByLabel;
  TrianglesByLabelPair       trianglesByLabelPair;
  std::map<LabelPair, Label> interfaceTags;
};

/** Gmsh reads a non-positive physical tag as "no physical group" or as a request to flip the orientation. */
void
CheckGmshPhysicalTags(const TetrahedraByLabel & tetrahedraByLabel)
{
  if (!tetrahedraByLabel.empty() && tetrahedraByLabel.begin()->first <= 0)
  {
    throw std::invalid_argument("WriteTetrahedralMesh: tetrahedron label " +
                                std::to_string(tetrahedraByLabel.begin()->first) +
                                " cannot be a Gmsh physical tag; .msh files need labels >= 1.");
  }
}

std::string
InterfaceName(const LabelPair & labelPair)
{
  return "interface_" + std::to_string(labelPair[0]) + "_" + std::to_string(labelPair[1]);
}

void
WriteGmshPhysicalNames(std::ostream & stream, const GmshGroups & groups)
{
  stream << "$PhysicalNames\n" << groups.tetrahedraByLabel.size() + groups.interfaceTags.size() << '\n';
  for (const auto & labelAndTetrahedra : groups.tetrahedraByLabel)
  {
    stream << "3 " << labelAndTetrahedra.first << " \"label_" << labelAndTetrahedra.first << "\"\n";
  }
  for (const auto & pairAndTag : groups.interfaceTags)
  {
    stream << "2 " << pairAndTag.second << " \"" << InterfaceName(pairAndTag.first) << "\"\n";
  }
  stream << "$EndPhysicalNames\n";
}

void
WriteGmshEntity(std::ostream & stream, std::size_t entityTag, const AxisAlignedBox & box, Label physicalTag)
{
  stream << entityTag << ' ';
  WritePoint(stream, box.lower);
  stream << ' ';
  WritePoint(stream, box.upper);
  // One physical tag, no bounding entities: the mesh is discrete and carries no CAD topology.
  stream << " 1 " << physicalTag << " 0\n";
}

void
WriteGmshEntities(std::ostream & stream, const TetrahedralMesh & mesh, const GmshGroups & groups)
{
  stream << "$Entities\n0 0 " << groups.trianglesByLabelPair.size() << ' ' << groups.tetrahedraByLabel.size() << '\n';
  std::size_t surfaceTag = 1;
  for (const auto & pairAndTriangles : groups.trianglesByLabelPair)
  {
    WriteGmshEntity(stream,
                    surfaceTag++,
                    BoundingBoxOfCells(mesh.points, mesh.boundaryTriangles, pairAndTriangles.second),
                    groups.interfaceTags.at(pairAndTriangles.first));
  }
  std::size_t volumeTag = 1;
  for (const auto & labelAndTetrahedra : groups.tetrahedraByLabel)
  {
    WriteGmshEntity(stream,
                    volumeTag++,
                    BoundingBoxOfCells(mesh.points, mesh.tetrahedra, labelAndTetrahedra.second),
                    labelAndTetrahedra.first);
  }
  stream << "$EndEntities\n";
}

/** All nodes go in one block on the first volume entity: Gmsh stores each node once, and its elements may use
 * nodes of any entity, so splitting nodes per entity would only add bookkeeping. */
void
WriteGmshNodes(std::ostream & stream, const TetrahedralMesh & mesh)
{
  const std::size_t numberOfPoints = mesh.points.size();
  stream << "$Nodes\n";
  if (numberOfPoints == 0)
  {
    stream << "0 0 0 0\n$EndNodes\n";
    return;
  }
  stream << "1 " << numberOfPoints << " 1 " << numberOfPoints << '\n';
  stream << "3 1 0 " << numberOfPoints << '\n';
  for (std::size_t pointIndex = 0; pointIndex < numberOfPoints; ++pointIndex)
  {
    stream << pointIndex + 1 << '\n';
  }
  for (const Vector3 & point : mesh.points)
  {
    WritePoint(stream, point);
    stream << '\n';
  }
  stream << "$EndNodes\n";
}

/** Element tags are the 1-based indices in the mesh (tetrahedra, then boundary triangles), so that elements can
 * be matched with the cells of a .vtu written from the same mesh although Gmsh groups them by entity. */
template <std::size_t VNumberOfVertices>
void
WriteGmshElementBlock(std::ostream & stream, int entityDimension, std::size_t entityTag, int gmshElementType,
                      const std::vector<std::array<uint32_t, VNumberOfVertices>> & cells,
                      const std::vector<std::size_t> & cellIndices, std::size_t firstElementTag)
{
  stream << entityDimension << ' ' << entityTag << ' ' << gmshElementType << ' ' << cellIndices.size() << '\n';
  for (const std::size_t cellIndex : cellIndices)
  {
    stream << firstElementTag + cellIndex << ' ';
    WriteOneBasedIndices(stream, cells[cellIndex]);
    stream << '\n';
  }
}

void
WriteGmshElements(std::ostream & stream, const TetrahedralMesh & mesh, const GmshGroups & groups)
{
  constexpr int     gmshTriangle = 2;
  constexpr int     gmshTetrahedron = 4;
  const std::size_t numberOfElements = mesh.tetrahedra.size() + mesh.boundaryTriangles.size();
  const std::size_t numberOfBlocks = groups.tetrahedraByLabel.size() + groups.trianglesByLabelPair.size();
  stream << "$Elements\n"
         << numberOfBlocks << ' ' << numberOfElements << ' ' << (numberOfElements > 0 ? 1 : 0) << ' '
         << numberOfElements << '\n';
  std::size_t volumeTag = 1;
  for (const auto & labelAndTetrahedra : groups.tetrahedraByLabel)
  {
    WriteGmshElementBlock(stream, 3, volumeTag++, gmshTetrahedron, mesh.tetrahedra, labelAndTetrahedra.second, 1);
  }
  std::size_t surfaceTag = 1;
  for (const auto & pairAndTriangles : groups.trianglesByLabelPair)
  {
    WriteGmshElementBlock(stream,
                          2,
                          surfaceTag++,
                          gmshTriangle,
                          mesh.boundaryTriangles,
                          pairAndTriangles.second,
                          mesh.tetrahedra.size() + 1);
  }
  stream << "$EndElements\n";
}

void
WriteGmshFile(const TetrahedralMesh & mesh, const std::string & fileName)
{
  GmshGroups groups;
  groups.tetrahedraByLabel = GroupTetrahedraByLabel(mesh);
  groups.trianglesByLabelPair = GroupTrianglesByLabelPair(mesh);
  CheckGmshPhysicalTags(groups.tetrahedraByLabel);
  groups.interfaceTags = NumberInterfaces(groups.tetrahedraByLabel, groups.trianglesByLabelPair);
  WriteTextFile(fileName, [&mesh, &groups](std::ostream & stream) {
    stream << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
    WriteGmshPhysicalNames(stream, groups);
    WriteGmshEntities(stream, mesh, groups);
    WriteGmshNodes(stream, mesh);
    WriteGmshElements(stream, mesh, groups);
  });
}

// ---------------------------------------------------------------------------------------------------------------
// Medit ASCII

void
WriteMeditVertices(std::ostream & stream, const TetrahedralMesh & mesh)
{
  stream << "Vertices\n" << mesh.points.size() << '\n';
  for (const Vector3 & point : mesh.points)
  {
    WritePoint(stream, point);
    stream << " 0\n";
  }
}

void
WriteMeditTetrahedra(std::ostream & stream, const TetrahedralMesh & mesh)
{
  stream << "Tetrahedra\n" << mesh.tetrahedra.size() << '\n';
  for (std::size_t tetrahedronIndex = 0; tetrahedronIndex < mesh.tetrahedra.size(); ++tetrahedronIndex)
  {
    WriteOneBasedIndices(stream, mesh.tetrahedra[tetrahedronIndex]);
    stream << ' ' << mesh.tetrahedronLabels[tetrahedronIndex] << '\n';
  }
}

/** Medit references are bare integers, so comments record which label pair each triangle reference stands for. */
void
WriteMeditTriangles(std::ostream & stream, const TetrahedralMesh & mesh,
                    const std::map<LabelPair, Label> & interfaceTags)
{
  for (const auto & pairAndTag : interfaceTags)
  {
    stream << "# Triangle reference " << pairAndTag.second << ": " << InterfaceName(pairAndTag.first)
           << " (normal from label " << pairAndTag.first[0] << " towards label " << pairAndTag.first[1] << ")\n";
  }
  stream << "Triangles\n" << mesh.boundaryTriangles.size() << '\n';
  for (std::size_t triangleIndex = 0; triangleIndex < mesh.boundaryTriangles.size(); ++triangleIndex)
  {
    WriteOneBasedIndices(stream, mesh.boundaryTriangles[triangleIndex]);
    stream << ' ' << interfaceTags.at(mesh.boundaryTriangleLabels[triangleIndex]) << '\n';
  }
}

void
WriteMeditFile(const TetrahedralMesh & mesh, const std::string & fileName)
{
  const std::map<LabelPair, Label> interfaceTags =
    NumberInterfaces(GroupTetrahedraByLabel(mesh), GroupTrianglesByLabelPair(mesh));
  WriteTextFile(fileName, [&mesh, &interfaceTags](std::ostream & stream) {
    stream << "MeshVersionFormatted 2\nDimension 3\n";
    WriteMeditVertices(stream, mesh);
    WriteMeditTetrahedra(stream, mesh);
    WriteMeditTriangles(stream, mesh, interfaceTags);
    stream << "End\n";
  });
}

// ---------------------------------------------------------------------------------------------------------------

const std::vector<std::pair<std::string, MeshFileWriter>> &
MeshFileWriters()
{
  static const std::vector<std::pair<std::string, MeshFileWriter>> writers{
    { ".vtu", WriteVtkXmlFile }, { ".vtk", WriteVtkLegacyFile }, { ".msh", WriteGmshFile }, { ".mesh", WriteMeditFile }
  };
  return writers;
}

std::string
SupportedExtensionsList()
{
  std::string list;
  for (const std::string & extension : SupportedMeshFileExtensions())
  {
    list += (list.empty() ? "" : ", ") + extension;
  }
  return list;
}

MeshFileWriter
WriterForFile(const std::string & fileName)
{
  const std::string extension = LowerCaseExtension(fileName);
  for (const auto & extensionAndWriter : MeshFileWriters())
  {
    if (extensionAndWriter.first == extension)
    {
      return extensionAndWriter.second;
    }
  }
  throw std::invalid_argument("WriteTetrahedralMesh: cannot write \"" + fileName + "\": its extension \"" + extension +
                              "\" is not one of the supported mesh file extensions (" + SupportedExtensionsList() +
                              ").");
}

} // namespace

void
WriteTetrahedralMesh(const TetrahedralMesh & mesh, const std::string & fileName)
{
  const MeshFileWriter writeFile = WriterForFile(fileName);
  CheckMeshConsistency(mesh);
  writeFile(mesh, fileName);
}

std::vector<std::string>
SupportedMeshFileExtensions()
{
  std::vector<std::string> extensions;
  for (const auto & extensionAndWriter : MeshFileWriters())
  {
    extensions.push_back(extensionAndWriter.first);
  }
  return extensions;
}

} // namespace delaunay_refinement
