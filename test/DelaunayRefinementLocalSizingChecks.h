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
#ifndef DelaunayRefinementLocalSizingChecks_h
#define DelaunayRefinementLocalSizingChecks_h

// Lemma 2's shortest edges checked edge by edge against the sizing the refinement exported with its mesh
// (TetrahedralMesh::pointSamplingDistances), not against the statistics it reports about itself (issue #17). ITK-free:
// the core's tests and the filter's randomized checks share it.

#include "DelaunayRefinementTypes.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

namespace delaunay_refinement
{

/** What is wrong with a mesh's edges against its exported sizing; empty `problems` when nothing is. */
struct LocalSizingReport
{
  std::vector<std::string> problems;
  /** Whether some point's sampling distance is below δ (the opt-in manifold refinement acted there). */
  bool refinedLocally{ false };
};

/** The exported sizing must have one value per point, each δ halved at most `levels` times, or up to `tieMargin` of
 * that below it (never coarser than δ: a refinement that silently used a larger δ fails here); every edge with a
 * feature end is at least the smaller sampling distance at its two ends (the finest of the mesh where the sizing is not
 * uniform, see below), every edge with a free end min(ρ, 2) times that, every edge with a box end 2δ; when the mesh
 * lists points moved below the spacing (TetrahedralMesh::pointsMovedBelowSpacing), every edge LastResortSpacingFraction
 * of that. The R4' variant (`checkFeatureAndFree` false) has no bound on its feature and free edges. */
inline LocalSizingReport
CheckEdgesAgainstLocalSizing(const TetrahedralMesh & mesh, double delta, double rho, unsigned int levels,
                             bool checkFeatureAndFree, double roundingSlack = 1e-9, double tieMargin = 0.0)
{
  LocalSizingReport  report;
  std::ostringstream text;
  text.precision(17);
  if (mesh.pointSamplingDistances.size() != mesh.points.size())
  {
    text << "the mesh exports " << mesh.pointSamplingDistances.size() << " sampling distances for "
         << mesh.points.size() << " points";
    report.problems.push_back(text.str());
    return report;
  }
  if (mesh.points.empty())
  {
    return report;
  }
  const double finest = std::ldexp(delta, -static_cast<int>(levels));
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
  {
    const double local = mesh.pointSamplingDistances[i];
    report.refinedLocally = report.refinedLocally || local < delta;
    if (!(local <= delta && local >= finest * (1.0 - tieMargin) * (1.0 - roundingSlack)))
    {
      text << "point " << i << " has sampling distance " << local << " outside [" << finest << ", " << delta << "]";
      report.problems.push_back(text.str());
      return report;
    }
  }
  // Where the opt-in manifold refinement made zones of smaller δ, R3 also splits restricted facets whose circumradius
  // reaches their shortest edge (docs/algorithm.md, departures), and the new vertex may come as close to its
  // neighbours as that edge: a zone's δ spreads beyond the zone, feature vertex by feature vertex (measured: Mixed
  // seed 8000314 has feature edges of 0.84 δ between points at sampling distance δ, next to zones of δ / 2). There the
  // edges are held to the finest sampling distance the mesh exports; with a uniform δ, to the δ at their ends.
  for (std::size_t i = 0; i < mesh.pointsMovedBelowSpacing.size(); ++i)
  {
    const uint32_t point = mesh.pointsMovedBelowSpacing[i];
    if (point >= mesh.points.size() || (i > 0 && point <= mesh.pointsMovedBelowSpacing[i - 1]))
    {
      text << "the points moved below the spacing are not increasing indices of points (" << point << ")";
      report.problems.push_back(text.str());
      return report;
    }
  }
  // Where the mesh lists points moved to remove a tetrahedron flat to rounding that nothing else removed, their
  // edges keep LastResortSpacingFraction of the bounds, and R3, whose threshold is a facet's shortest edge when that
  // is below δ, carries the shorter length to the feature vertices it inserts next to them (as from the zones
  // below): every edge is held to that fraction then, and no less.
  const double share = mesh.pointsMovedBelowSpacing.empty() ? 1.0 : LastResortSpacingFraction;
  const double finestExported =
    *std::min_element(mesh.pointSamplingDistances.begin(), mesh.pointSamplingDistances.end());
  std::size_t tooShort = 0;
  for (const auto & tetrahedron : mesh.tetrahedra)
  {
    for (int first = 0; first < 4; ++first)
    {
      for (int second = first + 1; second < 4; ++second)
      {
        const uint32_t   a = tetrahedron[first];
        const uint32_t   b = tetrahedron[second];
        const VertexKind kindA = mesh.pointKinds[a];
        const VertexKind kindB = mesh.pointKinds[b];
        const double     local = report.refinedLocally
                                   ? finestExported
                                   : std::min(mesh.pointSamplingDistances[a], mesh.pointSamplingDistances[b]);
        const auto isBox = [](VertexKind kind) { return kind == VertexKind::BoxEdge || kind == VertexKind::BoxFace; };
        double     bound = isBox(kindA) || isBox(kindB) ? 2.0 * delta : 0.0;
        if (checkFeatureAndFree && (kindA == VertexKind::Feature || kindB == VertexKind::Feature))
        {
          bound = std::max(bound, local);
        }
        if (checkFeatureAndFree && (kindA == VertexKind::Free || kindB == VertexKind::Free))
        {
          bound = std::max(bound, std::min(rho, 2.0) * local);
        }
        bound *= share;
        const double length = Distance(mesh.points[a], mesh.points[b]);
        if (!(length >= bound * (1.0 - roundingSlack)) && tooShort++ < 3)
        {
          std::ostringstream edge;
          edge.precision(17);
          edge << "edge " << a << " - " << b << " (kinds " << static_cast<int>(kindA) << ", " << static_cast<int>(kindB)
               << ", local delta " << mesh.pointSamplingDistances[a] << ", " << mesh.pointSamplingDistances[b]
               << ") has length " << length << " < " << bound;
          report.problems.push_back(edge.str());
        }
      }
    }
  }
  return report;
}

/** The census counts a part's ball up to this fraction below δ / 2 as a diameter of δ, and samples it at its radius
 * (docs/algorithm.md, "Topology", step 4: "Both thresholds count a radius up to 1e-4 below them"). */
constexpr double CensusTieMargin = 1e-4;

/** CheckEdgesAgainstLocalSizing for a mesh the filter or the core made: δ is halved at most once per level of the
 * opt-in manifold refinement (`manifoldLevels`), and once per round of the sampling of thick parts that had no
 * tetrahedron (`thickPartRounds`; the first at the part's largest ball, at least δ / 2 up to the census's tie
 * margin: docs/algorithm.md, "Topology", step 4; found by the randomized ManyLabels 5062585, a zone at 0.99997 δ / 2).
 * Feature and free edges are checked with σ = 0 only (R4′ has no bound on them). */
inline LocalSizingReport
CheckEdgesAgainstTheRefinementsSizing(const TetrahedralMesh & mesh, double delta, double rho, double sigma,
                                      unsigned int manifoldLevels, std::size_t thickPartRounds, double roundingSlack)
{
  const unsigned int halvings = std::max<unsigned int>(manifoldLevels, static_cast<unsigned int>(thickPartRounds));
  return CheckEdgesAgainstLocalSizing(
    mesh, delta, rho, halvings, !(sigma > 0.0), roundingSlack, thickPartRounds > 0 ? CensusTieMargin : 0.0);
}

} // namespace delaunay_refinement

#endif
