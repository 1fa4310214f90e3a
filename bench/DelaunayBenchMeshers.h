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
#ifndef DelaunayBenchMeshers_h
#define DelaunayBenchMeshers_h

#include "DelaunayBenchImages.h"
#include "DelaunayRefinementTypes.h"

namespace delaunay_bench
{

/** A mesh and what it cost. Both meshers hand back a delaunay_refinement::TetrahedralMesh, so that every
 * quality measure is computed by the module's own code for both. */
struct MesherOutput
{
  delaunay_refinement::TetrahedralMesh mesh;
  /** Wall time of the whole mesher: our filter's Update(), or CGAL's domain creation plus make_mesh_3. */
  double totalSeconds{ 0.0 };
  /** CPU time of the same span (both meshers run on one thread): what the other users of a shared machine
   * inflate least. */
  double totalCpuSeconds{ 0.0 };
  /** Ours: the refinement alone (the core's RefinementStatistics::refinementSeconds); CGAL: totalSeconds. */
  double refinementSeconds{ 0.0 };
  /** Ours: CPU time after the oracle's set-up (refinement, extraction, output mesh), an upper bound on the
   * refinement's CPU time; CGAL: totalCpuSeconds. */
  double refinementCpuSeconds{ 0.0 };
  /** PeakResidentBytes() right after meshing, before the mesh is converted or measured. */
  std::size_t peakResidentBytes{ 0 };
};

/** itk::DelaunayImageToMeshFilter with its defaults (nearest-neighbour oracle, ρ = 2, every non-zero label), and
 * R4′ at `minimumDihedralAngle` degrees (0 = off, the default). */
MesherOutput
RunOurFilter(const LabelImage & image, double delta, double minimumDihedralAngle);

/** CGAL Mesh_3 criteria (0 disables a criterion). Facet angle 30° and radius-edge ratio 2 are fixed: they are
 * our mesher's guarantees. */
struct CgalCriteria
{
  double facetSize{ 0.0 };
  double facetDistance{ 0.0 };
  double cellSize{ 0.0 };
  /** CGAL's default perturbation and exudation after the refinement; false = neither. */
  bool optimize{ false };
  /** CGAL's manifold() option: refine until every surface patch is a manifold (issue #18's row beside our
   * topology). */
  bool manifold{ false };
};

/** CGAL::make_mesh_3 on Labeled_mesh_domain_3::create_labeled_image_mesh_domain() of the same image,
 * sequential. Labels = subdomain indices; boundary triangles = facets between different subdomains. */
MesherOutput
RunCgalMesh3(const LabelImage & image, const CgalCriteria & criteria);

/** Wall time of CGAL's Delaunay_triangulation_3 built from `points` in one range insertion (spatially
 * sorted): a floor for any Delaunay mesher that ends with these vertices. */
double
BulkDelaunaySeconds(const std::vector<delaunay_refinement::Vector3> & points);

} // namespace delaunay_bench

#endif
