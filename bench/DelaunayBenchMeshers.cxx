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
#include "DelaunayBenchMeshers.h"
#include "DelaunayBenchChildProcess.h"

#include "itkDelaunayImageToMeshFilter.h"
#include "itkMesh.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Image_3.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/make_mesh_3.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <unordered_map>

#ifdef CGAL_CONCURRENT_MESH_3
#  error "The benchmark compares sequential meshers: build it without CGAL_CONCURRENT_MESH_3."
#endif

namespace delaunay_bench
{
namespace
{

using delaunay_refinement::Label;
using delaunay_refinement::TetrahedralMesh;
using delaunay_refinement::Vector3;
using delaunay_refinement::VertexKind;
// The vector operators live in the core's namespace, which argument-dependent lookup on std::array misses.
using delaunay_refinement::operator-;

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Domain = CGAL::Labeled_mesh_domain_3<Kernel>;
using MeshTriangulation = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using Complex = CGAL::Mesh_complex_3_in_triangulation_3<MeshTriangulation>;
using Criteria = CGAL::Mesh_criteria_3<MeshTriangulation>;
using MeshVertexHandle = MeshTriangulation::Vertex_handle;
using MeshCellHandle = MeshTriangulation::Cell_handle;

double
SecondsSince(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double
ProcessCpuSeconds()
{
  timespec time{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &time);
  return static_cast<double>(time.tv_sec) + 1e-9 * static_cast<double>(time.tv_nsec);
}

/** CGAL's image: x fastest, voxel (i, j, k) centred at (tx + i·vx, ty + j·vy, tz + k·vz), as in ITK with an
 * identity direction. */
CGAL::Image_3
ToCgalImage(const LabelImage & image)
{
  RequireIdentityDirection(image, "given to CGAL");
  const auto &          region = image.GetBufferedRegion();
  const auto &          size = region.GetSize();
  const auto &          spacing = image.GetSpacing();
  LabelImage::PointType origin;
  image.TransformIndexToPhysicalPoint(region.GetIndex(), origin);
  _image * raw = ::_createImage(
    size[0], size[1], size[2], 1, spacing[0], spacing[1], spacing[2], sizeof(uint8_t), WK_FIXED, SGN_UNSIGNED);
  raw->vectMode = VM_SCALAR;
  raw->tx = static_cast<float>(origin[0]);
  raw->ty = static_cast<float>(origin[1]);
  raw->tz = static_cast<float>(origin[2]);
  std::copy_n(image.GetBufferPointer(), region.GetNumberOfPixels(), static_cast<uint8_t *>(raw->data));
  return CGAL::Image_3(raw);
}

Vector3
PointOf(const MeshTriangulation & triangulation, MeshVertexHandle vertex)
{
  const auto & point = triangulation.point(vertex).point();
  return { point.x(), point.y(), point.z() };
}

/** Output indices of the complex's vertices, in the order the cells first use them. */
class VertexNumbering
{
public:
  VertexNumbering(const MeshTriangulation & triangulation, const Complex & complex, TetrahedralMesh & mesh)
    : m_Triangulation(triangulation)
    , m_Complex(complex)
    , m_Mesh(mesh)
  {}

  uint32_t
  IndexOf(MeshVertexHandle vertex)
  {
    const auto [entry, isNew] = m_Indices.emplace(vertex, static_cast<uint32_t>(m_Mesh.points.size()));
    if (isNew)
    {
      m_Mesh.points.push_back(PointOf(m_Triangulation, vertex));
      // Mesh_3's surface vertices have dimension 2 (or less on features); the rest are interior.
      m_Mesh.pointKinds.push_back(m_Complex.in_dimension(vertex) < 3 ? VertexKind::Feature : VertexKind::Free);
    }
    return entry->second;
  }

private:
  const MeshTriangulation &                      m_Triangulation;
  const Complex &                                m_Complex;
  TetrahedralMesh &                              m_Mesh;
  std::unordered_map<MeshVertexHandle, uint32_t> m_Indices;
};

double
SignedVolume(const TetrahedralMesh & mesh, const std::array<uint32_t, 4> & t)
{
  const Vector3 & p = mesh.points[t[0]];
  return delaunay_refinement::Dot(mesh.points[t[1]] - p,
                                  delaunay_refinement::Cross(mesh.points[t[2]] - p, mesh.points[t[3]] - p));
}

Label
SubdomainBeyond(const Complex & complex, MeshCellHandle cell, int facet)
{
  const MeshCellHandle neighbor = cell->neighbor(facet);
  return complex.is_in_complex(neighbor) ? static_cast<Label>(complex.subdomain_index(neighbor))
                                         : delaunay_refinement::BackgroundLabel;
}

/** The facet's vertices ordered so that its normal points away from `cell` (TetrahedralMesh's convention). */
std::array<uint32_t, 3>
OutwardFacet(const TetrahedralMesh & mesh, const std::array<uint32_t, 4> & cell, int facet)
{
  std::array<uint32_t, 3> triangle{ cell[(facet + 1) & 3], cell[(facet + 2) & 3], cell[(facet + 3) & 3] };
  const Vector3 &         a = mesh.points[triangle[0]];
  const Vector3 normal = delaunay_refinement::Cross(mesh.points[triangle[1]] - a, mesh.points[triangle[2]] - a);
  if (delaunay_refinement::Dot(normal, mesh.points[cell[facet]] - a) > 0.0)
  {
    std::swap(triangle[1], triangle[2]);
  }
  return triangle;
}

/** The complex's cells as tetrahedra labelled by subdomain index, and every facet between two different
 * subdomains once (from the background's other side, or else from the smaller label), as our mesher does. */
TetrahedralMesh
ToTetrahedralMesh(const Complex & complex)
{
  const MeshTriangulation & triangulation = complex.triangulation();
  TetrahedralMesh           mesh;
  VertexNumbering           numbering(triangulation, complex, mesh);
  for (auto cell = complex.cells_in_complex_begin(); cell != complex.cells_in_complex_end(); ++cell)
  {
    std::array<uint32_t, 4> corners;
    for (int corner = 0; corner < 4; ++corner)
    {
      corners[corner] = numbering.IndexOf(cell->vertex(corner));
    }
    const auto label = static_cast<Label>(complex.subdomain_index(cell));
    for (int facet = 0; facet < 4; ++facet)
    {
      const Label otherLabel = SubdomainBeyond(complex, cell, facet);
      if (otherLabel != label && (otherLabel == delaunay_refinement::BackgroundLabel || label < otherLabel))
      {
        mesh.boundaryTriangles.push_back(OutwardFacet(mesh, corners, facet));
        mesh.boundaryTriangleLabels.push_back({ label, otherLabel });
      }
    }
    if (SignedVolume(mesh, corners) < 0.0)
    {
      std::swap(corners[2], corners[3]);
    }
    mesh.tetrahedra.push_back(corners);
    mesh.tetrahedronLabels.push_back(label);
  }
  return mesh;
}

} // namespace

MesherOutput
RunOurFilter(const LabelImage & image, double delta, double minimumDihedralAngle)
{
  using MeshType = itk::Mesh<double, 3>;
  using FilterType = itk::DelaunayImageToMeshFilter<LabelImage, MeshType>;
  const auto   start = std::chrono::steady_clock::now();
  const double cpuStart = ProcessCpuSeconds();
  auto         filter = FilterType::New();
  filter->SetInput(&image);
  filter->SetSurfaceSamplingDistance(delta);
  filter->SetRadiusEdgeBound(2.0);
  filter->SetMinimumDihedralAngle(minimumDihedralAngle);
  // The filter reports its first non-zero progress when the oracle's set-up is done.
  double setupCpuSeconds = -1.0;
  filter->AddObserver(itk::ProgressEvent(), [&](const itk::EventObject &) {
    if (setupCpuSeconds < 0.0 && filter->GetProgress() > 0.0f)
    {
      setupCpuSeconds = ProcessCpuSeconds() - cpuStart;
    }
  });
  filter->Update();
  MesherOutput output;
  output.totalSeconds = SecondsSince(start);
  output.totalCpuSeconds = ProcessCpuSeconds() - cpuStart;
  output.refinementSeconds = filter->GetRefinementStatistics().refinementSeconds;
  output.refinementCpuSeconds = output.totalCpuSeconds - std::max(setupCpuSeconds, 0.0);
  output.peakResidentBytes = PeakResidentBytes();
  output.mesh = filter->GetRefinedMesh();
  return output;
}

MesherOutput
RunCgalMesh3(const LabelImage & image, const CgalCriteria & criteria)
{
  namespace parameters = CGAL::parameters;
  const auto          start = std::chrono::steady_clock::now();
  const double        cpuStart = ProcessCpuSeconds();
  const CGAL::Image_3 cgalImage = ToCgalImage(image);
  const Domain        domain = Domain::create_labeled_image_mesh_domain(cgalImage);
  const Criteria      meshCriteria(parameters::facet_angle = 30.0,
                              parameters::facet_size = criteria.facetSize,
                              parameters::facet_distance = criteria.facetDistance,
                              parameters::cell_radius_edge_ratio = 2.0,
                              parameters::cell_size = criteria.cellSize);
  const auto          topology = criteria.manifold ? parameters::manifold() : parameters::non_manifold();
  const Complex       complex =
    criteria.optimize
            ? CGAL::make_mesh_3<Complex>(domain, meshCriteria, topology)
            : CGAL::make_mesh_3<Complex>(domain, meshCriteria, parameters::no_perturb(), parameters::no_exude(), topology);
  MesherOutput output;
  output.totalSeconds = SecondsSince(start);
  output.totalCpuSeconds = ProcessCpuSeconds() - cpuStart;
  output.refinementSeconds = output.totalSeconds;
  output.refinementCpuSeconds = output.totalCpuSeconds;
  output.peakResidentBytes = PeakResidentBytes();
  output.mesh = ToTetrahedralMesh(complex);
  return output;
}

double
BulkDelaunaySeconds(const std::vector<Vector3> & points)
{
  std::vector<Kernel::Point_3> cgalPoints;
  cgalPoints.reserve(points.size());
  for (const Vector3 & point : points)
  {
    cgalPoints.emplace_back(point[0], point[1], point[2]);
  }
  const auto                                   start = std::chrono::steady_clock::now();
  const CGAL::Delaunay_triangulation_3<Kernel> triangulation(cgalPoints.begin(), cgalPoints.end());
  const double                                 seconds = SecondsSince(start);
  if (triangulation.number_of_vertices() != points.size())
  {
    throw std::logic_error("the bulk Delaunay triangulation lost vertices");
  }
  return seconds;
}

} // namespace delaunay_bench
