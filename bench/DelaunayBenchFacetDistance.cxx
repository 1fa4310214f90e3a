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
#include "DelaunayBenchFacetDistance.h"
#include "DelaunayBenchChildProcess.h"
#include "DelaunayRefinementMeshQuality.h"

#include <cmath>
#include <iostream>
#include <limits>

namespace delaunay_bench
{
namespace
{

/** Neither of our measures is worse than CGAL's by more than the tolerance. */
bool
OursIsNotWorse(const delaunay_refinement::DistanceStatistics & ours,
               const delaunay_refinement::DistanceStatistics & cgal)
{
  return ours.mean <= (1.0 + FidelityTolerance) * cgal.mean &&
         ours.percentile95 <= (1.0 + FidelityTolerance) * cgal.percentile95;
}

/** CGAL's surface is within the tolerance of ours on at least one measure: not simply a coarser surface. */
bool
CgalIsClose(const delaunay_refinement::DistanceStatistics & ours, const delaunay_refinement::DistanceStatistics & cgal)
{
  return cgal.mean <= (1.0 + FidelityTolerance) * ours.mean ||
         (ours.percentile95 > 0.0 && cgal.percentile95 <= (1.0 + FidelityTolerance) * ours.percentile95);
}

} // namespace

CgalCriteria
CgalCriteriaForDelta(double delta, double facetDistance, bool optimize)
{
  return { FacetSizePerDelta * delta, facetDistance, CellSizePerDelta * delta, optimize };
}

delaunay_refinement::DistanceStatistics
TwoSidedDistance(const delaunay_refinement::TetrahedralMesh & mesh,
                 const delaunay_refinement::TriangleSurface & marchingCubes, double sampleSpacing)
{
  return delaunay_refinement::ComputeTwoSidedDistance(
           mesh.points, mesh.boundaryTriangles, marchingCubes.points, marchingCubes.triangles, sampleSpacing)
    .combined;
}

/** facet_distance off first: CGAL's loosest surface. If ours is worse than even that, no bound helps (CGAL's
 * distances grow with the bound). If CGAL is close to ours there, off is the match. Else the bound is halved from
 * δ/2 while ours stays not worse and CGAL not close, and the bracket between the last bound where ours was not
 * worse and the first where it was is bisected in log scale: the tightest bound where ours is not worse is kept,
 * the most accurate surface CGAL can be asked for without beating ours. Tight bounds are the expensive trials, so
 * the search comes from the loose side. */
FacetDistanceMatch
MatchFacetDistance(const LabelImage & image, double delta, const delaunay_refinement::DistanceStatistics & ours,
                   double sampleSpacing, const delaunay_refinement::TriangleSurface & marchingCubes)
{
  const auto looseness = [](double facetDistance) {
    return facetDistance > 0.0 ? facetDistance : std::numeric_limits<double>::infinity();
  };
  FacetDistanceMatch best;
  bool               anyNotWorse = false;
  const auto         trial = [&](double facetDistance) {
    const CgalCriteria criteria = CgalCriteriaForDelta(delta, facetDistance, false);
    const MeasuredRun  run = RunInChildProcess([&] { return RunCgalMesh3(image, criteria); });
    const delaunay_refinement::DistanceStatistics cgal =
      TwoSidedDistance(run.output.mesh, marchingCubes, sampleSpacing);
    const bool oursIsNotWorse = OursIsNotWorse(ours, cgal);
    std::cerr << "    facet_distance " << facetDistance << " mm: CGAL mean / p95 " << cgal.mean << " / "
              << cgal.percentile95 << " mm, ours " << ours.mean << " / " << ours.percentile95 << " mm"
              << (oursIsNotWorse ? "" : " (ours worse)") << "\n";
    ++best.trials;
    // The first trial (off) stands until a bound where ours is not worse; then the tightest such bound.
    if (best.trials == 1 ||
        (oursIsNotWorse && (!anyNotWorse || looseness(facetDistance) < looseness(best.facetDistance))))
    {
      best.facetDistance = facetDistance;
      best.cgalDistance = cgal;
      best.matched = oursIsNotWorse && CgalIsClose(ours, cgal);
      best.oursIsNotWorse = oursIsNotWorse;
    }
    anyNotWorse = anyNotWorse || oursIsNotWorse;
    return oursIsNotWorse;
  };
  if (!trial(0.0) || best.matched)
  {
    return best;
  }
  double notWorse = delta; // off, or so loose that it is as good as off
  double worse = 0.0;
  for (double bound = 0.5 * delta; best.trials < MaximumFacetDistanceTrials; bound *= 0.5)
  {
    if (!trial(bound))
    {
      worse = bound;
      break;
    }
    if (best.matched)
    {
      return best;
    }
    notWorse = bound;
  }
  while (worse > 0.0 && !best.matched && best.trials < MaximumFacetDistanceTrials)
  {
    const double middle = std::sqrt(notWorse * worse);
    (trial(middle) ? notWorse : worse) = middle;
  }
  return best;
}

} // namespace delaunay_bench
