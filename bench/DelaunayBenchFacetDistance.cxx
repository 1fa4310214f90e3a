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

bool
IsWithinTolerance(double value, double target)
{
  return std::abs(value - target) <= FidelityTolerance * target;
}

} // namespace

CgalCriteria
CgalCriteriaForDelta(double delta, double facetDistance, bool optimize)
{
  return { FacetSizePerDelta * delta, facetDistance, CellSizePerDelta * delta, optimize };
}

double
MeanTwoSidedDistance(const delaunay_refinement::TetrahedralMesh & mesh,
                     const delaunay_refinement::TriangleSurface & marchingCubes, double sampleSpacing)
{
  return delaunay_refinement::ComputeTwoSidedDistance(
           mesh.points, mesh.boundaryTriangles, marchingCubes.points, marchingCubes.triangles, sampleSpacing)
    .combined.mean;
}

/** facet_distance off first: it is CGAL's loosest surface, and if even that is closer than ours nothing can
 * match. Then the bound is halved from δ/2 until CGAL is closer than we are, and the last bracket bisected in
 * log scale: CGAL's mean distance grows with the bound, and tight bounds are the expensive trials, so the search
 * comes from the loose side. */
FacetDistanceMatch
MatchFacetDistance(const LabelImage & image, double delta, double targetMeanDistance, double sampleSpacing,
                   const delaunay_refinement::TriangleSurface & marchingCubes)
{
  FacetDistanceMatch best;
  double             bestError = std::numeric_limits<double>::infinity();
  const auto         trial = [&](double facetDistance) {
    const CgalCriteria criteria = CgalCriteriaForDelta(delta, facetDistance, false);
    const MeasuredRun  run = RunInChildProcess([&] { return RunCgalMesh3(image, criteria); });
    const double       mean = MeanTwoSidedDistance(run.output.mesh, marchingCubes, sampleSpacing);
    std::cerr << "    facet_distance " << facetDistance << " mm: mean distance " << mean << " mm (ours "
              << targetMeanDistance << ")\n";
    ++best.trials;
    if (std::abs(mean - targetMeanDistance) < bestError)
    {
      bestError = std::abs(mean - targetMeanDistance);
      best.facetDistance = facetDistance;
      best.cgalMeanDistance = mean;
      best.matched = IsWithinTolerance(mean, targetMeanDistance);
    }
    return mean;
  };
  if (trial(0.0) <= targetMeanDistance || best.matched)
  {
    return best;
  }
  double loose = delta;
  double tight = 0.5 * delta;
  while (!best.matched && best.trials < MaximumFacetDistanceTrials && trial(tight) > targetMeanDistance)
  {
    loose = tight;
    tight *= 0.5;
  }
  while (!best.matched && best.trials < MaximumFacetDistanceTrials)
  {
    const double middle = std::sqrt(tight * loose);
    (trial(middle) > targetMeanDistance ? loose : tight) = middle;
  }
  return best;
}

} // namespace delaunay_bench
