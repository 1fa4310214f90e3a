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
#ifndef DelaunayBenchFacetDistance_h
#define DelaunayBenchFacetDistance_h

#include "DelaunayBenchImages.h"
#include "DelaunayBenchMeshers.h"
#include "DelaunayImageToMeshSurfaceExtraction.h"
#include "DelaunayRefinementMeshQuality.h"

namespace delaunay_bench
{

/** CGAL's facet_size bounds the radius of surface Delaunay balls, which is exactly what our rule R3 bounds by δ. */
constexpr double FacetSizePerDelta = 1.0;
/** Our rules bound no interior size (only the radius-edge ratio, which grades the mesh); CGAL's cell_size is
 * set loose enough not to bind before its radius-edge criterion does on these images (bench/README.md). */
constexpr double CellSizePerDelta = 8.0;
/** Fidelity is matched (issue #18) when neither our mean nor our 95th percentile of the two-sided distance to the
 * marching-cubes surface is worse than CGAL's by more than this fraction, with CGAL's facet_distance as loose as
 * that allows: CGAL gets the most accurate surface it needs, and ours is never the clearly better one. */
constexpr double FidelityTolerance = 0.1;
constexpr int    MaximumFacetDistanceTrials = 8;

/** CGAL Mesh_3's criteria at surface sampling distance δ: facet_size and cell_size as above. */
CgalCriteria
CgalCriteriaForDelta(double delta, double facetDistance, bool optimize);

/** ComputeQualityReport()'s two-sided distance to the marching-cubes surface, with that surface computed once. */
delaunay_refinement::DistanceStatistics
TwoSidedDistance(const delaunay_refinement::TetrahedralMesh & mesh,
                 const delaunay_refinement::TriangleSurface & marchingCubes, double sampleSpacing);

/** The facet_distance that matches CGAL's fidelity to ours, and whether it does. */
struct FacetDistanceMatch
{
  /** 0 = CGAL's facet_distance criterion off. */
  double                                  facetDistance{ 0.0 };
  delaunay_refinement::DistanceStatistics cgalDistance;
  /** Neither of our mean and 95th percentile is worse than CGAL's by more than FidelityTolerance, and CGAL's is
   * not worse than ours by more than that on both: CGAL could not be given a looser bound. */
  bool matched{ false };
  /** Neither of our measures is worse than CGAL's by more than FidelityTolerance at this bound (false: CGAL is
   * closer even with facet_distance off). */
  bool oursIsNotWorse{ false };
  int  trials{ 0 };
};

/** Searches CGAL's facet_distance (without optimisers) for the loosest bound at which neither our mean nor our
 * 95th percentile distance to `marchingCubes` (the segmentation's surface, sampled every `sampleSpacing` mm) is
 * worse than CGAL's by more than FidelityTolerance. A target percentile of 0 leaves the percentile out (the mean
 * alone is matched). Each trial runs in a child process; progress goes to stderr. */
FacetDistanceMatch
MatchFacetDistance(const LabelImage & image, double delta, const delaunay_refinement::DistanceStatistics & ours,
                   double sampleSpacing, const delaunay_refinement::TriangleSurface & marchingCubes);

} // namespace delaunay_bench

#endif
