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
#ifndef itkDelaunayImageToMeshFilterTestHelpers_h
#define itkDelaunayImageToMeshFilterTestHelpers_h

// What the filter's driver tests, GoogleTests and randomized checks share: test images, the conversion of the
// filter's ITK outputs back to the core's mesh (so that every measure of DelaunayRefinementMeshQuality.h, the
// facet-by-facet check of the boundary against the tetrahedra among them, is taken on what a user receives),
// and the mesh invariants that the regression baselines store. No GoogleTest here: the driver tests and the
// fuzzer include it too.

#include "DelaunayImageToMeshSurfaceExtraction.h"
#include "DelaunayRefinementIndependentAngles.h"
#include "DelaunayRefinementMeshQuality.h"
#include "itkDefaultStaticMeshTraits.h"
#include "itkImage.h"
#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkImageRegionIteratorWithIndex.h"
#include "itkMesh.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <array>
#include <cstdint>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace itk
{
namespace delaunay_image_to_mesh_test
{

namespace dr = delaunay_refinement;
// The core's vector operators act on std::array, which argument-dependent lookup does not search them for.
using dr::operator+;
using dr::operator-;
using dr::operator*;
// The library's boundary measures, by the names the filter's tests have always called them.
using dr::BoundaryConsistency;
using dr::CheckBoundaryAgainstTetrahedra;
using dr::LargestBoundaryCircumradius;

/** Double-precision points: the default itk::Mesh stores floats, which would blur the measured guarantees. */
using MeshType = Mesh<int32_t, 3, DefaultStaticMeshTraits<int32_t, 3, 3, double, double, int32_t>>;
using LabelImageType = Image<uint8_t, 3>;

/** The directory of the real test images (Debian package insighttoolkit5-examples), set by FilterTests.cmake. */
inline std::string
ExamplesDataDirectory()
{
#ifdef DelaunayImageToMesh_EXAMPLES_DATA
  return DelaunayImageToMesh_EXAMPLES_DATA "/";
#else
  return "/usr/share/doc/insighttoolkit5-examples/examples/Data/";
#endif
}

/** An image whose voxels are 1 where their centre is within `radius` (mm) of `center` (physical), else 0. */
inline LabelImageType::Pointer
MakeBallImage(const LabelImageType::SizeType & size, const LabelImageType::SpacingType & spacing,
              const LabelImageType::PointType & origin, const LabelImageType::DirectionType & direction,
              const dr::Vector3 & center, double radius)
{
  auto image = LabelImageType::New();
  image->SetRegions(size);
  image->SetSpacing(spacing);
  image->SetOrigin(origin);
  image->SetDirection(direction);
  image->Allocate();
  for (ImageRegionIteratorWithIndex<LabelImageType> it(image, image->GetBufferedRegion()); !it.IsAtEnd(); ++it)
  {
    LabelImageType::PointType point;
    image->TransformIndexToPhysicalPoint(it.GetIndex(), point);
    it.Set(dr::Distance({ { point[0], point[1], point[2] } }, center) <= radius ? 1 : 0);
  }
  return image;
}

/** The physical position of a voxel centre as the core's vector. */
template <typename TImage>
dr::Vector3
PhysicalCenterOf(const TImage & image, const typename TImage::IndexType & index)
{
  typename TImage::PointType point;
  image.TransformIndexToPhysicalPoint(index, point);
  return { { point[0], point[1], point[2] } };
}

/** The image's buffered voxels as a LabelVolume, each value mapped by `toLabel` (0 = background), in the same
 * physical space: the origin moves to the region's first voxel so that a region index need not be zero. */
template <typename TImage>
dr::LabelVolume
LabelVolumeOf(const TImage & image, const std::function<dr::Label(double)> & toLabel)
{
  const auto &    region = image.GetBufferedRegion();
  dr::LabelVolume volume;
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    volume.size[axis] = region.GetSize()[axis];
    volume.spacing[axis] = image.GetSpacing()[axis];
    for (unsigned int column = 0; column < 3; ++column)
    {
      volume.direction[axis][column] = image.GetDirection()[axis][column];
    }
  }
  volume.origin = PhysicalCenterOf(image, region.GetIndex());
  volume.labels.reserve(region.GetNumberOfPixels());
  // The region iterator runs x fastest, then y, then z: the LabelVolume order.
  for (ImageRegionConstIteratorWithIndex<TImage> it(&image, region); !it.IsAtEnd(); ++it)
  {
    volume.labels.push_back(toLabel(static_cast<double>(it.Get())));
  }
  return volume;
}

/** Maps every label in `tissues` to itself and everything else to background. */
inline std::function<dr::Label(double)>
KeepLabels(const std::vector<dr::Label> & tissues)
{
  const std::set<dr::Label> kept(tissues.begin(), tissues.end());
  return [kept](double value) {
    const auto label = static_cast<dr::Label>(value);
    return kept.count(label) ? label : dr::BackgroundLabel;
  };
}

/** Maps every non-zero value to 1. */
inline dr::Label
NonZeroToOne(double value)
{
  return value != 0.0 ? 1 : dr::BackgroundLabel;
}

/** A copy of `image` with every value mapped by `toLabel`. */
template <typename TImage>
LabelImageType::Pointer
MapLabels(const TImage & image, const std::function<dr::Label(double)> & toLabel)
{
  auto mapped = LabelImageType::New();
  mapped->CopyInformation(&image);
  mapped->SetRegions(image.GetBufferedRegion());
  mapped->Allocate();
  ImageRegionConstIteratorWithIndex<TImage> from(&image, image.GetBufferedRegion());
  for (ImageRegionIteratorWithIndex<LabelImageType> to(mapped, mapped->GetBufferedRegion()); !to.IsAtEnd();
       ++to, ++from)
  {
    to.Set(static_cast<LabelImageType::PixelType>(toLabel(static_cast<double>(from.Get()))));
  }
  return mapped;
}

/** The filter's two outputs (tetrahedra with labels, interface triangles with GetInterfaceLabels()) as the
 * core's mesh, with the point kinds of GetRefinedMesh() (the ITK mesh has no place for them). */
template <typename TFilter>
dr::TetrahedralMesh
TetrahedralMeshFromOutputs(TFilter & filter)
{
  const auto *        tetrahedra = filter.GetOutput();
  const auto *        interfaces = filter.GetInterfaceMesh();
  dr::TetrahedralMesh mesh;
  for (auto point = tetrahedra->GetPoints()->Begin(); point != tetrahedra->GetPoints()->End(); ++point)
  {
    mesh.points.push_back({ { point.Value()[0], point.Value()[1], point.Value()[2] } });
  }
  mesh.pointKinds = filter.GetRefinedMesh().pointKinds;
  for (auto cell = tetrahedra->GetCells()->Begin(); cell != tetrahedra->GetCells()->End(); ++cell)
  {
    const auto * ids = cell.Value()->GetPointIds();
    mesh.tetrahedra.push_back({ { static_cast<uint32_t>(ids[0]),
                                  static_cast<uint32_t>(ids[1]),
                                  static_cast<uint32_t>(ids[2]),
                                  static_cast<uint32_t>(ids[3]) } });
    typename TFilter::OutputMeshType::CellPixelType label{};
    tetrahedra->GetCellData(cell.Index(), &label);
    mesh.tetrahedronLabels.push_back(static_cast<dr::Label>(label));
  }
  for (auto cell = interfaces->GetCells()->Begin(); cell != interfaces->GetCells()->End(); ++cell)
  {
    const auto * ids = cell.Value()->GetPointIds();
    mesh.boundaryTriangles.push_back(
      { { static_cast<uint32_t>(ids[0]), static_cast<uint32_t>(ids[1]), static_cast<uint32_t>(ids[2]) } });
  }
  const auto & interfaceLabels = filter.GetInterfaceLabels();
  mesh.boundaryTriangleLabels.assign(interfaceLabels.begin(), interfaceLabels.end());
  return mesh;
}

/** The triangles of the boundary whose label pair passes `keep`. */
inline std::vector<std::array<uint32_t, 3>>
BoundaryTrianglesWhere(const dr::TetrahedralMesh &                                   mesh,
                       const std::function<bool(const std::array<dr::Label, 2> &)> & keep)
{
  std::vector<std::array<uint32_t, 3>> triangles;
  for (std::size_t i = 0; i < mesh.boundaryTriangles.size(); ++i)
  {
    if (keep(mesh.boundaryTriangleLabels[i]))
    {
      triangles.push_back(mesh.boundaryTriangles[i]);
    }
  }
  return triangles;
}

/** Volume-weighted centroid of the tetrahedra. */
inline dr::Vector3
CentroidOf(const dr::TetrahedralMesh & mesh)
{
  dr::Vector3 weighted{ { 0.0, 0.0, 0.0 } };
  double      volume = 0.0;
  for (const auto & t : mesh.tetrahedra)
  {
    const dr::Vector3 & p0 = mesh.points[t[0]];
    const double v = dr::Dot(mesh.points[t[1]] - p0, dr::Cross(mesh.points[t[2]] - p0, mesh.points[t[3]] - p0)) / 6.0;
    weighted = weighted + (v / 4.0) * (p0 + mesh.points[t[1]] + mesh.points[t[2]] + mesh.points[t[3]]);
    volume += v;
  }
  return (1.0 / volume) * weighted;
}

/** What the regression baselines store of a mesh: sizes, and the topology of each tissue's boundary. */
struct MeshInvariants
{
  std::size_t tetrahedra{ 0 };
  std::size_t boundaryTriangles{ 0 };
  struct Tissue
  {
    std::size_t tetrahedra{ 0 };
    int         components{ 0 };
    int         genus{ 0 };
  };
  std::map<dr::Label, Tissue> tissues;
};

inline MeshInvariants
InvariantsOf(const dr::TetrahedralMesh & mesh)
{
  MeshInvariants invariants;
  invariants.tetrahedra = mesh.tetrahedra.size();
  invariants.boundaryTriangles = mesh.boundaryTriangles.size();
  for (const dr::Label label : mesh.tetrahedronLabels)
  {
    ++invariants.tissues[label].tetrahedra;
  }
  for (auto & entry : invariants.tissues)
  {
    const dr::SurfaceTopology topology = dr::ComputeLabelBoundaryTopology(mesh, entry.first);
    entry.second.components = topology.numberOfComponents;
    entry.second.genus = topology.totalGenus;
  }
  return invariants;
}

/** One `key value...` line per invariant; lines starting with '#' are comments. */
inline void
WriteInvariants(const MeshInvariants & invariants, const std::string & comment, const std::string & fileName)
{
  std::ofstream file(fileName);
  file << "# " << comment << "\n";
  file << "# Compared by itkDelaunayImageToMeshFilterRealImageTest: counts within +-3 %; unless countsOnly,\n"
       << "# components and genus exactly.\n";
  file << "tetrahedra " << invariants.tetrahedra << "\n";
  file << "boundaryTriangles " << invariants.boundaryTriangles << "\n";
  for (const auto & entry : invariants.tissues)
  {
    file << "tissue " << entry.first << " tetrahedra " << entry.second.tetrahedra << " components "
         << entry.second.components << " genus " << entry.second.genus << "\n";
  }
  if (!file)
  {
    throw std::runtime_error("cannot write " + fileName);
  }
}

inline MeshInvariants
ReadInvariants(const std::string & fileName)
{
  std::ifstream file(fileName);
  if (!file)
  {
    throw std::runtime_error("cannot read " + fileName);
  }
  MeshInvariants invariants;
  std::string    line;
  while (std::getline(file, line))
  {
    std::istringstream words(line);
    std::string        key;
    if (!(words >> key) || key[0] == '#')
    {
      continue;
    }
    bool parsed = false;
    if (key == "tetrahedra")
    {
      parsed = static_cast<bool>(words >> invariants.tetrahedra);
    }
    else if (key == "boundaryTriangles")
    {
      parsed = static_cast<bool>(words >> invariants.boundaryTriangles);
    }
    else if (key == "tissue")
    {
      dr::Label              label = 0;
      MeshInvariants::Tissue tissue;
      std::string            tetrahedraKey, componentsKey, genusKey;
      parsed = static_cast<bool>(words >> label >> tetrahedraKey >> tissue.tetrahedra >> componentsKey >>
                                 tissue.components >> genusKey >> tissue.genus);
      invariants.tissues[label] = tissue;
    }
    if (!parsed)
    {
      throw std::runtime_error("cannot parse the line '" + line + "' of " + fileName);
    }
  }
  return invariants;
}

/** Tetrahedra flat to rounding, which a solver cannot use: volume <= 1e-6 × shortest edge cubed, computed here
 * from the coordinates alone (none of the library's metric code; issue #15's bar). */
inline std::size_t
CountFlatTetrahedra(const dr::TetrahedralMesh & mesh)
{
  std::size_t flatTetrahedra = 0;
  for (const auto & tetrahedron : mesh.tetrahedra)
  {
    std::array<std::array<double, 3>, 4> corner{};
    for (int k = 0; k < 4; ++k)
    {
      corner[k] = mesh.points[tetrahedron[k]];
    }
    double shortest = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 4; ++a)
    {
      for (int b = a + 1; b < 4; ++b)
      {
        const double dx = corner[a][0] - corner[b][0];
        const double dy = corner[a][1] - corner[b][1];
        const double dz = corner[a][2] - corner[b][2];
        shortest = std::min(shortest, std::sqrt(dx * dx + dy * dy + dz * dz));
      }
    }
    std::array<std::array<double, 3>, 3> e{};
    for (int k = 0; k < 3; ++k)
    {
      for (int axis = 0; axis < 3; ++axis)
      {
        e[k][axis] = corner[k + 1][axis] - corner[0][axis];
      }
    }
    const double volume =
      std::abs(e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
               e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])) /
      6.0;
    flatTetrahedra += volume <= 1e-6 * shortest * shortest * shortest;
  }
  return flatTetrahedra;
}

/** Whether a tetrahedron of `label` contains `point` (on its boundary included), from the signs of the four volumes
 * the point makes with its facets: computed here, not with the library's geometry. */
inline bool
ATetrahedronOfTheLabelContains(const dr::TetrahedralMesh & mesh, dr::Label label, const dr::Vector3 & point)
{
  const auto volume = [](const dr::Vector3 & a, const dr::Vector3 & b, const dr::Vector3 & c, const dr::Vector3 & d) {
    const double u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
    const double v[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
    const double w[3] = { d[0] - a[0], d[1] - a[1], d[2] - a[2] };
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
  };
  for (std::size_t index = 0; index < mesh.tetrahedra.size(); ++index)
  {
    if (mesh.tetrahedronLabels[index] != label)
    {
      continue;
    }
    std::array<dr::Vector3, 4> corners{};
    for (int corner = 0; corner < 4; ++corner)
    {
      corners[corner] = mesh.points[mesh.tetrahedra[index][corner]];
    }
    const double whole = volume(corners[0], corners[1], corners[2], corners[3]);
    bool         inside = whole != 0.0;
    for (int corner = 0; corner < 4 && inside; ++corner)
    {
      std::array<dr::Vector3, 4> withPoint = corners;
      withPoint[corner] = point;
      // The same sign as the whole tetrahedron's, or zero: the point is on the facet's inner side.
      inside = volume(withPoint[0], withPoint[1], withPoint[2], withPoint[3]) * whole >= 0.0;
    }
    if (inside)
    {
      return true;
    }
  }
  return false;
}

using delaunay_refinement::SmallestDihedralAngleFromNormals;

} // namespace delaunay_image_to_mesh_test
} // namespace itk

#endif
