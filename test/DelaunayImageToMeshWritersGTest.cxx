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

#include <gtest/gtest.h>

#include <vtkCallbackCommand.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace
{
using namespace delaunay_refinement;

using Tetrahedron = std::array<uint32_t, 4>;
using Triangle = std::array<uint32_t, 3>;
using LabelPair = std::array<Label, 2>;

double
SignedVolumeTimesSix(const TetrahedralMesh & mesh, const Tetrahedron & tetrahedron)
{
  const Vector3 & origin = mesh.points[tetrahedron[0]];
  return Dot(mesh.points[tetrahedron[1]] - origin,
             Cross(mesh.points[tetrahedron[2]] - origin, mesh.points[tetrahedron[3]] - origin));
}

/** The four faces of a positively oriented tetrahedron, each with its normal pointing out of the tetrahedron. */
std::array<Triangle, 4>
OutwardFaces(const Tetrahedron & corner)
{
  return { { { corner[1], corner[2], corner[3] },
             { corner[0], corner[3], corner[2] },
             { corner[0], corner[1], corner[3] },
             { corner[0], corner[2], corner[1] } } };
}

/** Every facet with different labels on its two sides, oriented out of the tetrahedron with the smaller label, as
 * the mesher produces them. */
void
AddBoundaryTriangles(TetrahedralMesh & mesh)
{
  std::map<Triangle, std::vector<std::pair<Label, Triangle>>> sidesOfFacet;
  for (std::size_t tetrahedronIndex = 0; tetrahedronIndex < mesh.tetrahedra.size(); ++tetrahedronIndex)
  {
    for (const Triangle & face : OutwardFaces(mesh.tetrahedra[tetrahedronIndex]))
    {
      Triangle facetKey = face;
      std::sort(facetKey.begin(), facetKey.end());
      sidesOfFacet[facetKey].emplace_back(mesh.tetrahedronLabels[tetrahedronIndex], face);
    }
  }
  for (auto & facetAndSides : sidesOfFacet)
  {
    auto & sides = facetAndSides.second;
    std::sort(sides.begin(), sides.end());
    const Label outsideLabel = sides.size() == 1 ? BackgroundLabel : sides[1].first;
    if (sides[0].first != outsideLabel)
    {
      mesh.boundaryTriangles.push_back(sides[0].second);
      mesh.boundaryTriangleLabels.push_back({ sides[0].first, outsideLabel });
    }
  }
}

/** A box split into the six tetrahedra around its main diagonal, three labelled 1 and three labelled 2. The
 * coordinates have no short decimal form, so that a writer printing too few digits is caught. */
TetrahedralMesh
MakeTwoLabelBox()
{
  const Vector3   origin{ { 0.1, -1.0 / 3.0, 12345.678901234567 } };
  const Vector3   edge{ { 1.0 / 3.0, 0.7, 2.0 / 7.0 } };
  TetrahedralMesh mesh;
  for (uint32_t corner = 0; corner < 8; ++corner)
  {
    mesh.points.push_back({ { origin[0] + (corner & 1U) * edge[0],
                              origin[1] + ((corner >> 1U) & 1U) * edge[1],
                              origin[2] + ((corner >> 2U) & 1U) * edge[2] } });
    mesh.pointKinds.push_back(VertexKind::BoxEdge);
  }
  // Each permutation of the axes gives the path 0 -> one axis -> two axes -> opposite corner 7.
  std::array<uint32_t, 3> axes{ { 0, 1, 2 } };
  do
  {
    Tetrahedron tetrahedron{ { 0, 1U << axes[0], (1U << axes[0]) | (1U << axes[1]), 7 } };
    if (SignedVolumeTimesSix(mesh, tetrahedron) < 0.0)
    {
      std::swap(tetrahedron[1], tetrahedron[2]);
    }
    mesh.tetrahedronLabels.push_back(mesh.tetrahedra.size() < 3 ? 1 : 2);
    mesh.tetrahedra.push_back(tetrahedron);
  } while (std::next_permutation(axes.begin(), axes.end()));
  AddBoundaryTriangles(mesh);
  return mesh;
}

template <typename TReader>
vtkSmartPointer<vtkUnstructuredGrid>
ReadWithVtk(const std::string & fileName)
{
  vtkNew<TReader> reader;
  reader->SetFileName(fileName.c_str());
  reader->Update();
  return reader->GetOutput();
}

void
ExpectSameAsVtkGrid(const TetrahedralMesh & mesh, vtkUnstructuredGrid * grid)
{
  ASSERT_NE(grid, nullptr);
  ASSERT_EQ(grid->GetNumberOfPoints(), static_cast<vtkIdType>(mesh.points.size()));
  ASSERT_EQ(grid->GetNumberOfCells(), static_cast<vtkIdType>(mesh.tetrahedra.size()));
  EXPECT_EQ(grid->GetPoints()->GetDataType(), VTK_DOUBLE);
  for (vtkIdType pointId = 0; pointId < grid->GetNumberOfPoints(); ++pointId)
  {
    Vector3 point;
    grid->GetPoint(pointId, point.data());
    EXPECT_EQ(point, mesh.points[pointId]) << "point " << pointId;
  }
  vtkDataArray * labels = grid->GetCellData()->GetArray("label");
  ASSERT_NE(labels, nullptr);
  EXPECT_EQ(labels->GetDataType(), VTK_INT);
  vtkNew<vtkIdList> pointIds;
  for (vtkIdType cellId = 0; cellId < grid->GetNumberOfCells(); ++cellId)
  {
    EXPECT_EQ(grid->GetCellType(cellId), VTK_TETRA) << "cell " << cellId;
    grid->GetCellPoints(cellId, pointIds);
    ASSERT_EQ(pointIds->GetNumberOfIds(), 4);
    for (vtkIdType corner = 0; corner < 4; ++corner)
    {
      EXPECT_EQ(pointIds->GetId(corner), mesh.tetrahedra[cellId][corner]) << "cell " << cellId;
    }
    EXPECT_EQ(labels->GetTuple1(cellId), mesh.tetrahedronLabels[cellId]) << "cell " << cellId;
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Reading back with meshio, an independent reader that FEM users rely on.

/** Prints "point x y z" per point (repr round-trips doubles exactly), "<cell type> <0-based point ids> <value of
 * the given cell-data array>" per cell, and "group <name> <tag> <dimension>" per Gmsh physical name. Written
 * without single quotes so that the shell can take it in single quotes. */
constexpr const char * meshioDumpScript = R"(import sys, meshio
mesh = meshio.read(sys.argv[1], file_format=sys.argv[2])
for p in mesh.points: print("point", *[repr(float(c)) for c in p])
for block, values in zip(mesh.cells, mesh.cell_data[sys.argv[3]]):
    for cell, value in zip(block.data, values.reshape(-1)): print(block.type, *cell, value)
for name, (tag, dim) in mesh.field_data.items(): print("group", name, tag, dim)
)";

/** How meshio is told to read one of the written files. The format is named because meshio would otherwise try
 * a .msh file as ANSYS first (printing that failure on stdout). */
struct MeshioFormat
{
  std::string fileName;
  std::string formatName;
  std::string labelArrayName;
  bool        hasBoundaryTriangles;
};

/** Debian's python3-meshio lives in the system interpreter, which a user's PATH may shadow (pyenv, venv). */
std::string
PythonWithMeshio()
{
  for (const std::string candidate : { "python3", "/usr/bin/python3" })
  {
    if (std::system((candidate + " -c 'import meshio' > /dev/null 2>&1").c_str()) == 0)
    {
      return candidate;
    }
  }
  return {};
}

std::string
RunMeshioDump(const std::string & python, const std::string & path, const MeshioFormat & format)
{
  const std::string command = python + " -c '" + meshioDumpScript + "' '" + path + "' '" + format.formatName + "' '" +
                              format.labelArrayName + "'";
  FILE * pipe = popen(command.c_str(), "r");
  if (pipe == nullptr)
  {
    ADD_FAILURE() << "cannot run " << command;
    return {};
  }
  std::string output;
  char        buffer[4096];
  while (const std::size_t count = std::fread(buffer, 1, sizeof(buffer), pipe))
  {
    output.append(buffer, count);
  }
  EXPECT_EQ(pclose(pipe), 0) << "meshio failed on " << path << "; it printed:\n" << output;
  return output;
}

/** What meshio reports about a mesh file. */
struct MeshioView
{
  std::vector<Vector3>                         points;
  std::vector<std::pair<Tetrahedron, Label>>   tetrahedra;
  std::vector<std::pair<Triangle, Label>>      triangles;
  std::map<std::string, std::pair<Label, int>> groups;
};

template <std::size_t VNumberOfVertices>
std::pair<std::array<uint32_t, VNumberOfVertices>, Label>
ParseCell(std::istringstream & line)
{
  std::pair<std::array<uint32_t, VNumberOfVertices>, Label> cell;
  for (uint32_t & pointIndex : cell.first)
  {
    line >> pointIndex;
  }
  line >> cell.second;
  return cell;
}

MeshioView
ParseMeshioDump(const std::string & dump)
{
  MeshioView         view;
  std::istringstream lines(dump);
  std::string        text;
  while (std::getline(lines, text))
  {
    std::istringstream line(text);
    std::string        keyword;
    line >> keyword;
    if (keyword == "point")
    {
      Vector3 point;
      line >> point[0] >> point[1] >> point[2];
      view.points.push_back(point);
    }
    else if (keyword == "tetra")
    {
      view.tetrahedra.push_back(ParseCell<4>(line));
    }
    else if (keyword == "triangle")
    {
      view.triangles.push_back(ParseCell<3>(line));
    }
    else if (keyword == "group")
    {
      std::string name;
      line >> name;
      line >> view.groups[name].first >> view.groups[name].second;
    }
    else
    {
      ADD_FAILURE() << "unexpected line from meshio: " << text;
    }
  }
  return view;
}

std::vector<std::pair<Tetrahedron, Label>>
LabelledTetrahedra(const TetrahedralMesh & mesh)
{
  std::vector<std::pair<Tetrahedron, Label>> tetrahedra;
  for (std::size_t tetrahedronIndex = 0; tetrahedronIndex < mesh.tetrahedra.size(); ++tetrahedronIndex)
  {
    tetrahedra.emplace_back(mesh.tetrahedra[tetrahedronIndex], mesh.tetrahedronLabels[tetrahedronIndex]);
  }
  return tetrahedra;
}

/** The tag that the file gives each label pair, checking that it gives one tag per pair and that interface tags
 * differ from each other and from the tissue labels. */
std::map<LabelPair, Label>
InterfaceTagsSeen(const TetrahedralMesh & mesh, const std::vector<std::pair<Triangle, Label>> & trianglesSeen)
{
  std::map<Triangle, LabelPair> labelPairOfTriangle;
  for (std::size_t triangleIndex = 0; triangleIndex < mesh.boundaryTriangles.size(); ++triangleIndex)
  {
    labelPairOfTriangle[mesh.boundaryTriangles[triangleIndex]] = mesh.boundaryTriangleLabels[triangleIndex];
  }
  std::map<LabelPair, Label> tagOfPair;
  for (const auto & triangleAndTag : trianglesSeen)
  {
    const auto found = labelPairOfTriangle.find(triangleAndTag.first);
    if (found == labelPairOfTriangle.end())
    {
      ADD_FAILURE() << "a triangle that is not a boundary triangle of the mesh (or is flipped)";
      continue;
    }
    const auto inserted = tagOfPair.emplace(found->second, triangleAndTag.second);
    EXPECT_EQ(inserted.first->second, triangleAndTag.second) << "two tags for one label pair";
  }
  std::set<Label> tags(mesh.tetrahedronLabels.begin(), mesh.tetrahedronLabels.end());
  for (const auto & pairAndTag : tagOfPair)
  {
    EXPECT_TRUE(tags.insert(pairAndTag.second).second) << "interface tag " << pairAndTag.second << " reused";
  }
  // The documented numbering (DelaunayImageToMeshWriters.h): the largest positive tetrahedron label (0 if none) plus
  // the pair's rank among the mesh's distinct pairs in lexicographic order, 1 for the first; readers of one format
  // rely on it as well as on the other's agreeing.
  const std::set<LabelPair> pairs(mesh.boundaryTriangleLabels.begin(), mesh.boundaryTriangleLabels.end());
  Label                     largest = 0;
  for (const Label label : mesh.tetrahedronLabels)
  {
    largest = std::max(largest, label);
  }
  Label expected = largest;
  for (const LabelPair & pair : pairs)
  {
    ++expected;
    const auto found = tagOfPair.find(pair);
    if (found != tagOfPair.end())
    {
      EXPECT_EQ(found->second, expected) << "the interface tag of labels " << pair[0] << " and " << pair[1];
    }
  }
  return tagOfPair;
}

template <typename TCell>
std::vector<TCell>
Sorted(std::vector<TCell> cells)
{
  std::sort(cells.begin(), cells.end());
  return cells;
}

/** Gmsh groups elements by entity, so cells are compared as sets; every orientation must be kept. */
void
ExpectSameCells(const TetrahedralMesh & mesh, const MeshioView & view, bool formatHasBoundaryTriangles)
{
  EXPECT_EQ(Sorted(view.tetrahedra), Sorted(LabelledTetrahedra(mesh)));
  if (!formatHasBoundaryTriangles)
  {
    EXPECT_TRUE(view.triangles.empty());
    return;
  }
  std::vector<Triangle> trianglesSeen;
  for (const auto & triangleAndTag : view.triangles)
  {
    trianglesSeen.push_back(triangleAndTag.first);
  }
  EXPECT_EQ(Sorted(trianglesSeen), Sorted(mesh.boundaryTriangles));
}

void
ExpectGmshGroups(const TetrahedralMesh & mesh, const MeshioView & view)
{
  std::map<std::string, std::pair<Label, int>> expectedGroups;
  for (const Label label : mesh.tetrahedronLabels)
  {
    expectedGroups["label_" + std::to_string(label)] = { label, 3 };
  }
  for (const auto & pairAndTag : InterfaceTagsSeen(mesh, view.triangles))
  {
    const LabelPair & pair = pairAndTag.first;
    expectedGroups["interface_" + std::to_string(pair[0]) + "_" + std::to_string(pair[1])] = { pairAndTag.second, 2 };
  }
  EXPECT_EQ(view.groups, expectedGroups);
}

// ---------------------------------------------------------------------------------------------------------------

class DelaunayImageToMeshWriters : public ::testing::Test
{
protected:
  void
  SetUp() override
  {
    std::string pattern = (std::filesystem::temp_directory_path() / "DelaunayImageToMeshWriters-XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr) << "cannot create a temporary directory";
    m_Directory = pattern;
  }

  void
  TearDown() override
  {
    if (!m_Directory.empty())
    {
      std::filesystem::remove_all(m_Directory);
    }
  }

  std::string
  PathOf(const std::string & fileName) const
  {
    return (m_Directory / fileName).string();
  }

  MeshioView
  ReadWithMeshio(const std::string & path, const MeshioFormat & format) const
  {
    static const std::string python = PythonWithMeshio();
    if (python.empty())
    {
      ADD_FAILURE() << "no python3 can import meshio: install Debian's python3-meshio";
      return {};
    }
    return ParseMeshioDump(RunMeshioDump(python, path, format));
  }

  /** Writes the mesh, reads it with meshio and checks the points (exactly), the cells and their labels. */
  MeshioView
  ExpectMeshioReadsBack(const MeshioFormat & format) const
  {
    const std::string path = PathOf(format.fileName);
    WriteTetrahedralMesh(m_Mesh, path);
    MeshioView view = ReadWithMeshio(path, format);
    EXPECT_EQ(view.points, m_Mesh.points);
    ExpectSameCells(m_Mesh, view, format.hasBoundaryTriangles);
    if (format.hasBoundaryTriangles)
    {
      InterfaceTagsSeen(m_Mesh, view.triangles);
    }
    return view;
  }

  std::filesystem::path m_Directory;
  const TetrahedralMesh m_Mesh{ MakeTwoLabelBox() };
};

TEST_F(DelaunayImageToMeshWriters, TestMeshIsValid)
{
  ASSERT_EQ(m_Mesh.tetrahedra.size(), 6U);
  for (const Tetrahedron & tetrahedron : m_Mesh.tetrahedra)
  {
    EXPECT_GT(SignedVolumeTimesSix(m_Mesh, tetrahedron), 0.0);
  }
  // 12 triangles on the box faces, plus the 2 facets between the labels.
  EXPECT_EQ(m_Mesh.boundaryTriangles.size(), 14U);
  EXPECT_NE(std::find(m_Mesh.boundaryTriangleLabels.begin(), m_Mesh.boundaryTriangleLabels.end(), LabelPair{ 1, 2 }),
            m_Mesh.boundaryTriangleLabels.end());
}

TEST_F(DelaunayImageToMeshWriters, SupportedExtensions)
{
  EXPECT_EQ(SupportedMeshFileExtensions(), (std::vector<std::string>{ ".vtu", ".vtk", ".msh", ".mesh" }));
}

TEST_F(DelaunayImageToMeshWriters, VtuReadBackByVtk)
{
  const std::string path = PathOf("mesh.vtu");
  WriteTetrahedralMesh(m_Mesh, path);
  ExpectSameAsVtkGrid(m_Mesh, ReadWithVtk<vtkXMLUnstructuredGridReader>(path));
}

TEST_F(DelaunayImageToMeshWriters, LegacyVtkReadBackByVtk)
{
  const std::string path = PathOf("mesh.vtk");
  WriteTetrahedralMesh(m_Mesh, path);
  ExpectSameAsVtkGrid(m_Mesh, ReadWithVtk<vtkUnstructuredGridReader>(path));
}

TEST_F(DelaunayImageToMeshWriters, ExtensionIsCaseInsensitive)
{
  const std::string path = PathOf("MESH.VTU");
  WriteTetrahedralMesh(m_Mesh, path);
  ExpectSameAsVtkGrid(m_Mesh, ReadWithVtk<vtkXMLUnstructuredGridReader>(path));
}

TEST_F(DelaunayImageToMeshWriters, VtuReadBackByMeshio)
{
  ExpectMeshioReadsBack({ "mesh.vtu", "vtu", "label", false });
}

TEST_F(DelaunayImageToMeshWriters, LegacyVtkReadBackByMeshio)
{
  ExpectMeshioReadsBack({ "mesh.vtk", "vtk", "label", false });
}

TEST_F(DelaunayImageToMeshWriters, GmshReadBackByMeshio)
{
  ExpectGmshGroups(m_Mesh, ExpectMeshioReadsBack({ "mesh.msh", "gmsh", "gmsh:physical", true }));
}

/** Gmsh's $Entities give each surface (a label pair) and volume (a label) the bounding box of its cells, which Gmsh
 * uses to place and index them; meshio skips that section, so it is read here: every box is its cells' box, to the
 * last digit (the points are written with 17 significant digits). */
TEST_F(DelaunayImageToMeshWriters, GmshEntitiesHaveTheBoxesOfTheirCells)
{
  const std::string path = PathOf("entities.msh");
  WriteTetrahedralMesh(m_Mesh, path);
  std::ifstream file(path);
  std::string   line;
  while (std::getline(file, line) && line != "$Entities")
  {}
  ASSERT_TRUE(file) << "no $Entities section in " << path;
  std::size_t points = 0, curves = 0, surfaces = 0, volumes = 0;
  file >> points >> curves >> surfaces >> volumes;

  // The boxes expected, surfaces first, each kind in increasing order of its label pair or label.
  const auto boxOf = [this](const auto & cells, const auto & labels, const auto & label) {
    constexpr double      infinity = std::numeric_limits<double>::infinity();
    std::array<double, 6> box{ { infinity, infinity, infinity, -infinity, -infinity, -infinity } };
    for (std::size_t cell = 0; cell < cells.size(); ++cell)
    {
      if (labels[cell] != label)
      {
        continue;
      }
      for (const uint32_t point : cells[cell])
      {
        for (std::size_t axis = 0; axis < 3; ++axis)
        {
          box[axis] = std::min(box[axis], m_Mesh.points[point][axis]);
          box[3 + axis] = std::max(box[3 + axis], m_Mesh.points[point][axis]);
        }
      }
    }
    return box;
  };
  const std::set<LabelPair> pairs(m_Mesh.boundaryTriangleLabels.begin(), m_Mesh.boundaryTriangleLabels.end());
  const std::set<Label>     labels(m_Mesh.tetrahedronLabels.begin(), m_Mesh.tetrahedronLabels.end());
  ASSERT_EQ(points + curves, 0u);
  ASSERT_EQ(surfaces, pairs.size());
  ASSERT_EQ(volumes, labels.size());
  std::vector<std::array<double, 6>> expected;
  for (const LabelPair & pair : pairs)
  {
    expected.push_back(boxOf(m_Mesh.boundaryTriangles, m_Mesh.boundaryTriangleLabels, pair));
  }
  for (const Label label : labels)
  {
    expected.push_back(boxOf(m_Mesh.tetrahedra, m_Mesh.tetrahedronLabels, label));
  }
  for (std::size_t entity = 0; entity < expected.size(); ++entity)
  {
    std::size_t           tag = 0;
    std::array<double, 6> box{};
    file >> tag;
    for (double & coordinate : box)
    {
      file >> coordinate;
    }
    std::getline(file, line);
    ASSERT_TRUE(file) << "entity " << entity;
    EXPECT_EQ(box, expected[entity]) << "entity " << entity << " (tag " << tag << ")";
  }
}

/** Gmsh identifies elements by their tags, which meshio drops: read here, every element's tag is its own, and the
 * tags are 1 to the number of elements, as the section's header says (a tag given twice would make Gmsh merge or
 * drop elements). */
TEST_F(DelaunayImageToMeshWriters, GmshElementTagsAreDistinctAndAsTheHeaderSays)
{
  const std::string path = PathOf("tags.msh");
  WriteTetrahedralMesh(m_Mesh, path);
  std::ifstream file(path);
  std::string   line;
  while (std::getline(file, line) && line != "$Elements")
  {}
  ASSERT_TRUE(file) << "no $Elements section in " << path;
  std::size_t blocks = 0, elements = 0, smallestTag = 0, largestTag = 0;
  file >> blocks >> elements >> smallestTag >> largestTag;
  ASSERT_EQ(elements, m_Mesh.tetrahedra.size() + m_Mesh.boundaryTriangles.size());
  EXPECT_EQ(smallestTag, 1u);
  EXPECT_EQ(largestTag, elements);
  std::set<std::size_t> tags;
  std::size_t           read = 0;
  for (std::size_t block = 0; block < blocks; ++block)
  {
    int         dimension = 0, entity = 0, type = 0;
    std::size_t count = 0;
    file >> dimension >> entity >> type >> count;
    ASSERT_TRUE(type == 2 || type == 4) << "block " << block << " has element type " << type;
    const int nodes = type == 2 ? 3 : 4;
    for (std::size_t element = 0; element < count; ++element)
    {
      std::size_t tag = 0, node = 0;
      file >> tag;
      for (int corner = 0; corner < nodes; ++corner)
      {
        file >> node;
      }
      ASSERT_TRUE(file) << "block " << block << ", element " << element;
      EXPECT_TRUE(tags.insert(tag).second) << "tag " << tag << " is given twice";
      ++read;
    }
  }
  EXPECT_EQ(read, elements);
  ASSERT_FALSE(tags.empty());
  EXPECT_EQ(*tags.begin(), smallestTag);
  EXPECT_EQ(*tags.rbegin(), largestTag);
  std::getline(file, line);
  std::getline(file, line);
  EXPECT_EQ(line, "$EndElements");
}

TEST_F(DelaunayImageToMeshWriters, MeditReadBackByMeshio)
{
  ExpectMeshioReadsBack({ "mesh.mesh", "medit", "medit:ref", true });
}

/** A VTK reader's view of a file written from an empty mesh: no error, no point, no cell. The errors are counted
 * from the reader's error events: the XML reader leaves its error code at 0 on a truncated file. */
template <typename TReader>
void
ExpectVtkReadsEmpty(const std::string & path)
{
  vtkNew<TReader>            reader;
  int                        errors = 0;
  vtkNew<vtkCallbackCommand> countError;
  countError->SetClientData(&errors);
  countError->SetCallback([](vtkObject *, unsigned long, void * count, void *) { ++*static_cast<int *>(count); });
  reader->AddObserver(vtkCommand::ErrorEvent, countError);
  reader->SetFileName(path.c_str());
  reader->Update();
  EXPECT_EQ(errors, 0) << path;
  ASSERT_NE(reader->GetOutput(), nullptr) << path;
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0) << path;
  EXPECT_EQ(reader->GetOutput()->GetNumberOfCells(), 0) << path;
}

// An empty mesh is a file of each format that a reader takes as empty, not just a file: VTK reads the VTK formats,
// meshio the Medit one; meshio cannot read an empty Gmsh or VTK file (its readers take the largest of no tags), so
// the Gmsh file's node and element sections are read here: no block, no node, no element.
TEST_F(DelaunayImageToMeshWriters, EmptyMeshIsWritten)
{
  for (const std::string & extension : SupportedMeshFileExtensions())
  {
    EXPECT_NO_THROW(WriteTetrahedralMesh(TetrahedralMesh{}, PathOf("empty" + extension))) << extension;
  }
  ExpectVtkReadsEmpty<vtkXMLUnstructuredGridReader>(PathOf("empty.vtu"));
  ExpectVtkReadsEmpty<vtkUnstructuredGridReader>(PathOf("empty.vtk"));
  const MeshioView medit = ReadWithMeshio(PathOf("empty.mesh"), { "empty.mesh", "medit", "medit:ref", true });
  EXPECT_TRUE(medit.points.empty());
  EXPECT_TRUE(medit.tetrahedra.empty());
  EXPECT_TRUE(medit.triangles.empty());
  std::ifstream            gmsh(PathOf("empty.msh"));
  std::vector<std::string> lines;
  for (std::string line; std::getline(gmsh, line);)
  {
    lines.push_back(line);
  }
  for (const std::string section : { "$Nodes", "$Elements" })
  {
    const auto found = std::find(lines.begin(), lines.end(), section);
    ASSERT_NE(found, lines.end()) << "no " << section;
    ASSERT_NE(found + 1, lines.end()) << section;
    EXPECT_EQ(*(found + 1), "0 0 0 0") << section;
  }
}

template <typename TException>
std::string
MessageOfWriteError(const TetrahedralMesh & mesh, const std::string & fileName)
{
  try
  {
    WriteTetrahedralMesh(mesh, fileName);
  }
  catch (const TException & error)
  {
    return error.what();
  }
  ADD_FAILURE() << "writing " << fileName << " did not throw the expected exception";
  return {};
}

void
ExpectMentions(const std::string & message, const std::string & expectedPart)
{
  EXPECT_NE(message.find(expectedPart), std::string::npos) << '"' << message << "\" lacks \"" << expectedPart << '"';
}

TEST_F(DelaunayImageToMeshWriters, UnknownExtensionIsRejected)
{
  const std::string path = PathOf("mesh.stl");
  const std::string message = MessageOfWriteError<std::invalid_argument>(m_Mesh, path);
  ExpectMentions(message, path);
  ExpectMentions(message, "\".stl\"");
  for (const std::string & extension : SupportedMeshFileExtensions())
  {
    ExpectMentions(message, extension);
  }
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST_F(DelaunayImageToMeshWriters, MissingExtensionIsRejected)
{
  const std::string path = PathOf("mesh");
  ExpectMentions(MessageOfWriteError<std::invalid_argument>(m_Mesh, path), path);
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST_F(DelaunayImageToMeshWriters, UnwritablePathIsReported)
{
  for (const std::string & extension : SupportedMeshFileExtensions())
  {
    const std::string path = PathOf("no-such-directory/mesh" + extension);
    ExpectMentions(MessageOfWriteError<std::runtime_error>(m_Mesh, path), path);
    EXPECT_FALSE(std::filesystem::exists(path));
  }
}

/** /dev/full accepts the open and fails the writes, as a full disk does: nothing may pass for a complete file. */
TEST_F(DelaunayImageToMeshWriters, FullDiskIsReported)
{
  if (!std::filesystem::exists("/dev/full"))
  {
    GTEST_SKIP() << "no /dev/full on this system";
  }
  for (const std::string & extension : SupportedMeshFileExtensions())
  {
    const std::string path = PathOf("full" + extension);
    std::filesystem::create_symlink("/dev/full", path);
    ExpectMentions(MessageOfWriteError<std::runtime_error>(m_Mesh, path), path);
    EXPECT_FALSE(std::filesystem::exists(std::filesystem::symlink_status(path))) << "incomplete " << path << " kept";
  }
}

TEST_F(DelaunayImageToMeshWriters, InconsistentMeshIsRejected)
{
  TetrahedralMesh missingLabel = m_Mesh;
  missingLabel.tetrahedronLabels.pop_back();
  ExpectMentions(MessageOfWriteError<std::invalid_argument>(missingLabel, PathOf("mesh.vtu")), "tetrahedronLabels");

  TetrahedralMesh missingPoint = m_Mesh;
  missingPoint.points.pop_back();
  ExpectMentions(MessageOfWriteError<std::invalid_argument>(missingPoint, PathOf("mesh.msh")), "point index 7");

  EXPECT_FALSE(std::filesystem::exists(PathOf("mesh.vtu")));
  EXPECT_FALSE(std::filesystem::exists(PathOf("mesh.msh")));
}

TEST_F(DelaunayImageToMeshWriters, GmshRejectsNonPositiveLabels)
{
  TetrahedralMesh backgroundTetrahedron = m_Mesh;
  backgroundTetrahedron.tetrahedronLabels[0] = BackgroundLabel;
  const std::string path = PathOf("mesh.msh");
  ExpectMentions(MessageOfWriteError<std::invalid_argument>(backgroundTetrahedron, path), "label 0");
  EXPECT_FALSE(std::filesystem::exists(path));
}

} // namespace
