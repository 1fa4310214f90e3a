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
#ifndef DelaunayRefinementSizing_h
#define DelaunayRefinementSizing_h

// The sizing field (docs/algorithm.md, "Local sampling distance"): the δ each rule uses at a point. It is δ
// everywhere except in zones of finer sampling (around small parts of the labels, and where the opt-in manifold
// refinement refined), as CGAL Mesh_3's sizing fields are queried by its criteria.

#include "DelaunayRefinementGeometry.h"
#include "DelaunayRefinementSpatialGrid.h"
#include "DelaunayRefinementTypes.h"

#include <algorithm>
#include <cstddef>
#include <map>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{

/** Which rules a zone of finer sampling reaches: those whose own point (a circumcentre, a surface point, a surface
 * ball's centre) lies in it, or R2 also for every circumball that meets it (LocalSampling::DeltaForCircumball). */
enum class ZoneReach
{
  Points,
  Circumballs
};

/** The local surface sampling distance: δ everywhere, except in balls (zones) around the small parts of the labels
 * that must get a tetrahedron (Refiner::SampleThinPartsFinely, Refiner::WithEveryThickPart) and, with the opt-in
 * manifold refinement, around places where the restricted surface was not a 2-manifold (halved once per level). */
class LocalSampling
{
public:
  explicit LocalSampling(double delta)
    : m_Delta(delta)
    , m_ZoneCenters(2.0 * ZoneRadiusFactor * delta)
  {}

  double
  LocalDelta(const Vector3 & point) const
  {
    return SmallestDeltaMeeting(point, 0.0);
  }

  /** The δ R2 uses for a tetrahedron whose circumball has `radius` around `center`: the δ at the circumcentre, or the
   * δ of a finer zone of reach ZoneReach::Circumballs that the circumball meets. Such a zone is made for a part of a
   * label that the refinement left without a tetrahedron (Refiner::WithEveryThickPart): the part can sit inside
   * tetrahedra of another label whose circumcentres lie outside its zone, where no rule reading the δ at its own
   * point would see the zone (docs/algorithm.md, "Local sampling distance"). Until such a zone exists the scan stays
   * as small as LocalDelta's. */
  double
  DeltaForCircumball(const Vector3 & center, double radius) const
  {
    return SmallestDeltaMeeting(center, m_AnyZoneReachesCircumballs ? radius : 0.0);
  }

  /** Records that a vertex was inserted at `point` honouring `delta`, when that is finer than the δ of the zones
   * holding `point`: R2's free vertex for a circumball that met a zone (DeltaForCircumball), which lies outside the
   * zone; R3's feature vertex for a facet whose shortest edge was its threshold, which happens beside a zone, where the
   * zone's short edges reach its facets (RefinementRules::SurfaceBallThreshold); R4's free vertex whose circumradius
   * is below min(ρ, 2) × the δ there, beside such short edges (its edges are the circumradius or longer, and Lemma 2
   * asks min(ρ, 2) δ of a free vertex's edges: it is noted at the circumradius over min(ρ, 2)). Such a vertex's edges
   * are bounded by `delta`, not by LocalDelta there. The exported sizing reads it back (SamplingDistanceOf), so that it
   * states what the refinement honoured at every point, even where the zone's own points are not in the mesh (the
   * randomized SaltAndPepper 2240051: an R3 point 0.90 δ from its neighbours, with every output point at δ). */
  void
  NoteFinerSample(const Vector3 & point, double delta)
  {
    if (delta < LocalDelta(point))
    {
      double & recorded = m_FinerSamples.emplace(point, delta).first->second;
      recorded = std::min(recorded, delta);
    }
  }

  /** The sampling distance a vertex at `point` honours: the local δ, or the finer δ R2 inserted it with. */
  double
  SamplingDistanceOf(const Vector3 & point) const
  {
    const double local = LocalDelta(point);
    const auto   finer = m_FinerSamples.find(point);
    return finer == m_FinerSamples.end() ? local : std::min(local, finer->second);
  }

  /** Whether a triangle with these corners keeps R1's bound as a boundary facet: its circumradius below the local δ
   * at each corner. A step that puts a facet on a boundary without a rule's insertion (a relabelling, a cap peeled
   * off) must keep it, as R1 and R3 keep it for the facets they make. */
  bool
  KeepsBoundaryFacetBound(const Vector3 & a, const Vector3 & b, const Vector3 & c) const
  {
    const double localDelta = std::min({ LocalDelta(a), LocalDelta(b), LocalDelta(c) });
    return TriangleCircumradius(a, b, c) < localDelta;
  }

  /** Samples at `delta` around `point` (where that is finer than elsewhere); the zone covers the facets around
   * it. Returns the zone's radius: outside it nothing changed. */
  double
  AddZone(const Vector3 & point, double delta)
  {
    return AddZone(point, delta, ZoneRadiusFactor * 2.0 * delta);
  }

  /** Samples at `delta` within `radius` of `point`; `radius` at most ZoneRadiusFactor times the δ everywhere else. */
  double
  AddZone(const Vector3 & point, double delta, double radius, ZoneReach reach = ZoneReach::Points)
  {
    radius = std::min(radius, ZoneRadiusFactor * m_Delta);
    m_ZoneCenters.Insert(point, m_Zones.size());
    m_Zones.push_back({ point, radius, delta, reach });
    m_FinestDelta = std::min(m_FinestDelta, delta);
    m_AnyZoneReachesCircumballs = m_AnyZoneReachesCircumballs || reach == ZoneReach::Circumballs;
    return radius;
  }

  std::size_t
  NumberOfZones() const
  {
    return m_Zones.size();
  }

  /** The smallest δ of the zones, δ without one (R3 asks for it at each insertion). */
  double
  FinestDelta() const
  {
    return m_FinestDelta;
  }

private:
  /** The smallest δ of the zones that hold `center` (reach ZoneReach::Points) or that the ball of `radius` around it
   * meets (reach ZoneReach::Circumballs), δ when none does; with `radius` 0 both mean the zones holding `center`. */
  double
  SmallestDeltaMeeting(const Vector3 & center, double radius) const
  {
    double delta = m_Delta;
    if (m_Zones.empty())
    {
      return delta;
    }
    m_ZoneCenters.ForEachWithin(center, radius + ZoneRadiusFactor * m_Delta, [&](std::size_t zone) {
      const Zone & candidate = m_Zones[zone];
      const double reach = candidate.reach == ZoneReach::Circumballs ? radius + candidate.radius : candidate.radius;
      if (SquaredNorm(center - candidate.center) < reach * reach)
      {
        delta = std::min(delta, candidate.delta);
      }
    });
    return delta;
  }

  /** Zone radius in units of the sampling distance it refines: wide enough to hold the restricted facets
   * (circumradius < δ) around the offending vertex. */
  static constexpr double ZoneRadiusFactor = 3.0;

  struct Zone
  {
    Vector3   center;
    double    radius;
    double    delta;
    ZoneReach reach;
  };

  double                   m_Delta;
  double                   m_FinestDelta{ m_Delta };
  std::vector<Zone>        m_Zones;
  SpatialGrid<std::size_t> m_ZoneCenters;
  bool                     m_AnyZoneReachesCircumballs{ false };
  /** NoteFinerSample's points; few, since only zones make them (R2's near a zone of reach ZoneReach::Circumballs, R3's
   * and R4's beside any zone's short edges). */
  std::map<Vector3, double> m_FinerSamples;
};

} // namespace detail
} // namespace delaunay_refinement

#endif
