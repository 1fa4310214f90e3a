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
#ifndef DelaunayRefinementRules_h
#define DelaunayRefinementRules_h

// The rules R1-R4 and R4' (docs/algorithm.md, "Rules"): for a tetrahedron, whether some rule may apply to it
// (Classify, asked once when it is created) and which rule applies and what point it inserts (FindApplicableRule,
// asked when it is popped). Each rule's test and its point stand side by side; the quality test (R4, R4') is
// written once and serves both questions, as CGAL Mesh_3's compute_badness and TetGen's checktet4split do. The
// rules only read the mesh: what their actions do to it is the driver's and the mesh state's business.

#include "DelaunayRefinementGeometry.h"
#include "DelaunayRefinementMeshQuality.h"
#include "DelaunayRefinementMeshState.h"
#include "DelaunayRefinementParameters.h"
#include "DelaunayRefinementQueue.h"
#include "DelaunayRefinementSizing.h"
#include "DelaunayRefinementTestHooks.h"

#include <array>
#include <cmath>
#include <optional>

namespace delaunay_refinement
{
namespace detail
{

/** Rules, in the order docs/algorithm.md checks them. */
enum class Rule
{
  R1,
  R2,
  R3,
  R4,
  R4Dihedral
};

/** A rule that applies to a tetrahedron, with the point it wants inserted. */
struct Action
{
  Rule    rule;
  Vector3 point;
  /** The sampling distance the insertion honours (the local δ, or less for R3, see LargeSurfaceBall): a new
   * feature vertex clears the free vertices within twice it, as the paper's do within 2δ. */
  double localDelta;
  /** R3: the surface ball's radius, how far the new vertex is from every vertex (the ball is empty); 0 otherwise. */
  double ballRadius{ 0.0 };
};

/** R2 splits an intersecting tetrahedron whose circumradius reaches this many times the local δ; the paper uses 2.
 * Of the paper's proofs only Lemma 4 uses this constant (every surface point within δ + 2 × it × δ of a feature
 * vertex), so 3 costs a constant of its fidelity theorem and keeps every other bound; the census, not R2, keeps
 * every part a δ across. With 2, R2's free vertices were all those inside the labels (σ = 0), more than CGAL Mesh_3
 * puts inside the same surface; 3 gives up to 11 % fewer tetrahedra at the same distance to the surface within 4 %
 * (docs/algorithm.md, "Where the method departs from the paper"). */
constexpr double IntersectingCircumradiusFactor = 3.0;

/** The rules, asked of one tetrahedron at a time. */
class RefinementRules
{
public:
  /** `box` is the bounding box, set before the first cell is classified. `hooks` is RefinementTestHooks{} except in the
   * tests that reach a step no known input needs. */
  RefinementRules(const LabelOracle & oracle, const RefinementParameters & parameters, const MeshState & state,
                  const LocalSampling & sizing, const AxisAlignedBox & box, const RefinementTestHooks & hooks)
    : m_Oracle(oracle)
    , m_Parameters(parameters)
    , m_Delta(parameters.surfaceSamplingDistance)
    , m_DihedralBound(parameters.minimumDihedralAngle)
    , m_R1TieFactor(1.0 + hooks.r1TieMargin)
    , m_State(state)
    , m_Sizing(sizing)
    , m_Box(box)
  {}

  /** Which queue a tetrahedron belongs in, or none when no rule can ever apply to it while it exists. */
  std::optional<QueueLevel>
  Classify(CellHandle cell) const
  {
    // The label test first: it is cheap and often decides without the oracle's distance.
    if (HasLabelChangeAcrossAFacet(cell) || IsIntersecting(cell))
    {
      return QueueLevel::Surface;
    }
    if (cell->cache.label != BackgroundLabel)
    {
      if (const std::optional<Rule> rule = QualityRuleFor(cell))
      {
        return *rule == Rule::R4 ? QueueLevel::Quality : QueueLevel::Sliver;
      }
    }
    return std::nullopt;
  }

  /** R1, R2, R3, R4 (and R4'), checked in that order: the first that applies. */
  std::optional<Action>
  FindApplicableRule(CellHandle cell) const
  {
    const CellCache & cache = cell->cache;
    if (IsIntersecting(cell))
    {
      const SurfacePoint closest = ClosestSurfacePointTo(cache.circumcenter);
      const double       deltaAtClosest = m_Sizing.LocalDelta(closest.point);
      if (!m_State.AnyFeatureVertexWithin(closest.point, deltaAtClosest * m_R1TieFactor))
      {
        return Action{ Rule::R1, closest.point, deltaAtClosest };
      }
      const double deltaAtCenter = m_Sizing.DeltaForCircumball(cache.circumcenter, std::sqrt(cache.squaredRadius));
      const double reach = IntersectingCircumradiusFactor * deltaAtCenter;
      if (cache.squaredRadius >= reach * reach)
      {
        return Action{ Rule::R2, cache.circumcenter, deltaAtCenter };
      }
    }
    if (const std::optional<Action> surfaceBall = LargeSurfaceBall(cell))
    {
      return surfaceBall;
    }
    // R4. The paper calls a tetrahedron skinny only when it is not intersecting; we also split intersecting ones
    // (left here by R1-R3 with r < 3δ, IntersectingCircumradiusFactor): with every edge >= δ (Lemma 2) their
    // radius-edge ratio can reach 3, and the paper's proof of Theorem 2 skips this case. The point is at least
    // ρ times the shortest edge from every vertex, so a free vertex is still 2δ from every feature vertex for ρ >= 2.
    if (cache.label != BackgroundLabel)
    {
      if (const std::optional<Rule> rule = QualityRuleFor(cell))
      {
        return Action{ *rule, cache.circumcenter, m_Delta };
      }
    }
    return std::nullopt;
  }

  /** R3's threshold for a restricted facet with corners `a`, `b`, `c` whose surface ball is centred at `center`: the
   * local δ there, with LatticeTieMargin (balls of radius δ exactly, which the lattice makes: on the brain mask's
   * 2 × 3 × 2 mm voxels at δ = 2.5 mm, 3,185 R3 insertions and 43,591 tetrahedra at δ, 2,699 and 41,336 at
   * δ (1 + 1e-9)), or the facet's shortest edge if shorter (LargeSurfaceBall), shortened by
   * ShortestEdgeFactorForPlanarAngleMargin so that a facet R3 keeps has its angles above 30° by the margin every
   * check of the bound uses. Without it a triangle whose circumradius equals its shortest edge (a 30° angle, which
   * the voxel lattice makes exactly) stayed or went by rounding: the randomized ManyLabels seed 5045684 kept one at
   * 29.99999999999974°. A surface ball is at least the facet's circumcircle, so a facet whose circumradius reaches
   * it is split surely; SliverPerturbation predicts its moves' failures with it. */
  double
  SurfaceBallThreshold(const Vector3 & center, const Vector3 & a, const Vector3 & b, const Vector3 & c) const
  {
    return std::min(m_Sizing.LocalDelta(center) * (1.0 + LatticeTieMargin),
                    ShortestEdgeFactorForPlanarAngleMargin * ShortestEdgeLength(a, b, c));
  }

  /** The surface ball of a restricted facet with corners `a`, `b`, `c` whose dual Voronoi edge joins `center` and
   * `otherEnd` (centred where the edge crosses the surface), with R3's threshold for it. The ends are floating-point
   * constructions (cached circumcentres, or a far point of a Voronoi ray), and the circumcentre of a flat tetrahedron
   * can be off its exact place by far more than rounding. Where the crossing's distances to the corners differ by more
   * than OffVoronoiLineTolerance, the crossing is searched again between the ends put on the facet's exact Voronoi
   * line (NearestPointOnCircumcenterAxis), so that the ball's centre is as far from each corner as its radius says
   * and still on the surface (the crossing itself, put on the line, moved off the voxels' surface by 2e-4 δ on the
   * randomized Blobs 1000086, twice the oracle's tolerance). Ends whose labels the move made equal (an end within
   * its error of the surface) keep the crossing as it was. From a crossing taken as it was, the randomized
   * SaltAndPepper 2073625 (ρ = 2, σ = 0) inserted a feature vertex 1.3e-8 of the local δ closer than the radius to
   * another corner (Lemma 2's spacing); measuring the radius to the nearest corner instead let SaltAndPepper 2076891
   * keep a facet whose circumradius reached the threshold by 1e-9 (a planar angle of 29.999999998717°). On the line
   * both hold: the radius is the nearest corner's distance and at least the facet's circumradius, to rounding. */
  struct SurfaceBall
  {
    Vector3 center;
    double  squaredRadius;
    double  threshold;

    /** Whether R3 splits the facet. */
    bool
    ReachesThreshold() const
    {
      return squaredRadius >= threshold * threshold;
    }
  };

  SurfaceBall
  SurfaceBallOf(const Vector3 & center, const Vector3 & otherEnd, const Vector3 & a, const Vector3 & b,
                const Vector3 & c) const
  {
    const auto ballAt = [&](const Vector3 & ballCenter) {
      return SurfaceBall{ ballCenter, SquaredNorm(ballCenter - a), SurfaceBallThreshold(ballCenter, a, b, c) };
    };
    const Vector3 crossing = m_Oracle.SurfaceCrossing(center, otherEnd);
    const auto [nearest, farthest] =
      std::minmax({ SquaredNorm(crossing - a), SquaredNorm(crossing - b), SquaredNorm(crossing - c) });
    if (farthest - nearest <= OffVoronoiLineTolerance * farthest)
    {
      return ballAt(crossing);
    }
    const Vector3 lineStart = NearestPointOnCircumcenterAxis(a, b, c, center);
    const Vector3 lineEnd = NearestPointOnCircumcenterAxis(a, b, c, otherEnd);
    if (m_Oracle.LabelAt(lineStart) == m_Oracle.LabelAt(lineEnd))
    {
      return ballAt(crossing);
    }
    return ballAt(m_Oracle.SurfaceCrossing(lineStart, lineEnd));
  }

private:
  /** SurfaceBallOf moves a crossing onto its facet's Voronoi line only when its squared distances to the corners
   * differ by more than this fraction: far above rounding (the bench's images at 2-4 mm: 1e-14 typical, none above
   * 1e-10 in 500,000 balls), far below what any bound resolves (the tests allow 1e-9). Moving every ball by its
   * last bits would change which way the lattice's cospherical ties fall, and so every mesh, for nothing. */
  static constexpr double OffVoronoiLineTolerance = 1e-10;

  /** The oracle's closest surface point, remembered for the last query: R1 asks for the point right after
   * IsIntersecting() asked for its distance, and the image oracle's search is its most expensive call. */
  const SurfacePoint &
  ClosestSurfacePointTo(const Vector3 & query) const
  {
    if (!(m_LastSurfaceQueryValid && query == m_LastSurfaceQuery))
    {
      m_LastSurfacePoint = m_Oracle.ClosestSurfacePoint(query);
      m_LastSurfaceQuery = query;
      m_LastSurfaceQueryValid = true;
    }
    return m_LastSurfacePoint;
  }

  /** Whether the cell's circumsphere meets the surface. The oracle's cheap distance bounds decide most cells;
   * the others get the circumcentre's distance to the surface, cached. Classification asks this of every new
   * cell, and nearly half of them are destroyed before they are popped, so the closest point itself waits until
   * R1 asks for it. The answer is the same either way, so the mesh does not depend on the bounds. */
  bool
  IsIntersecting(CellHandle cell) const
  {
    CellCache & cache = cell->cache;
    if (cache.surfaceDistance == CellCache::NotYetComputed)
    {
      // A deciding bound is kept in place of the distance: it gives the same answer when the cell is popped.
      const SurfaceDistanceBounds bounds = m_Oracle.BoundSurfaceDistance(cache.circumcenter);
      if (bounds.upper * bounds.upper <= cache.squaredRadius)
      {
        cache.surfaceDistance = bounds.upper;
      }
      else if (bounds.lower * bounds.lower > cache.squaredRadius)
      {
        cache.surfaceDistance = bounds.lower;
      }
      else
      {
        cache.surfaceDistance = ClosestSurfacePointTo(cache.circumcenter).distance;
      }
    }
    return cache.surfaceDistance * cache.surfaceDistance <= cache.squaredRadius;
  }

  bool
  HasLabelChangeAcrossAFacet(CellHandle cell) const
  {
    for (int facet = 0; facet < 4; ++facet)
    {
      if (m_State.LabelBeyondFacet(cell, facet) != cell->cache.label)
      {
        return true;
      }
    }
    return false;
  }

  /** R4 and R4': the rule that splits the tetrahedron for its shape (radius-edge ratio >= ρ, then a dihedral
   * angle below σ), if any. Both Classify and FindApplicableRule ask this, so the test exists once. */
  std::optional<Rule>
  QualityRuleFor(CellHandle cell) const
  {
    const std::array<Vector3, 4> corners = m_State.CornersOf(cell);
    if (ReachesRadiusEdgeBound(cell->cache.squaredRadius, corners, m_Parameters.radiusEdgeBound))
    {
      return Rule::R4;
    }
    if (IsSliver(corners))
    {
      return Rule::R4Dihedral;
    }
    return std::nullopt;
  }

  /** R4' (the paper's variant): a dihedral angle below σ (when σ > 0), or a tetrahedron flat to rounding,
   * whatever σ (a singular element for any solver; the refiner removes it by moving a corner, never by a split,
   * docs/algorithm.md, "R4′ moves a vertex"). The paper proves nothing for R4': termination rests on the vertex
   * cap, and with σ > 0 its free vertices may come closer than δ to others, so the 30° bound on boundary angles
   * (Theorem 2) is not guaranteed then. */
  bool
  IsSliver(const std::array<Vector3, 4> & corners) const
  {
    return m_DihedralBound.IsSliver(corners) || IsFlatToRounding(corners);
  }

  /** The far end of the Voronoi ray dual to a convex-hull facet: beyond the box, so labelled background. */
  Vector3
  FarEndOfVoronoiRay(CellHandle cell, int facet) const
  {
    const Vector3 normal = OutwardFaceNormal(m_State.CornersOf(cell), facet);
    const double  boxDiagonal = Distance(m_Box.lower, m_Box.upper);
    return cell->cache.circumcenter + (2.0 * boxDiagonal / Norm(normal)) * normal;
  }

  /** R3: the largest surface ball among the cell's restricted facets whose radius reaches the facet's
   * threshold: the local δ at the ball's centre, or the facet's shortest edge if shorter. Where δ is uniform
   * every edge is >= δ (Lemma 2) and this is the paper's rule; where δ was refined locally it also splits any
   * restricted facet with circumradius >= its shortest edge, so boundary angles > 30° hold there too. The new
   * vertex is at least the ball's radius from every vertex, so edges never get shorter than they were. */
  std::optional<Action>
  LargeSurfaceBall(CellHandle cell) const
  {
    std::optional<Action> best;
    double                bestSquaredRadius = 0.0;
    for (int facet = 0; facet < 4; ++facet)
    {
      const Label otherLabel = m_State.LabelBeyondFacet(cell, facet);
      if (otherLabel == cell->cache.label)
      {
        continue;
      }
      const CellHandle  neighbor = cell->neighbor(facet);
      const Vector3     otherEnd = m_State.GetTriangulation().is_infinite(neighbor) ? FarEndOfVoronoiRay(cell, facet)
                                                                                    : neighbor->cache.circumcenter;
      const SurfaceBall ball = SurfaceBallOf(cell->cache.circumcenter,
                                             otherEnd,
                                             m_State.PointOf(cell->vertex((facet + 1) & 3)),
                                             m_State.PointOf(cell->vertex((facet + 2) & 3)),
                                             m_State.PointOf(cell->vertex((facet + 3) & 3)));
      if (ball.ReachesThreshold() && ball.squaredRadius > bestSquaredRadius)
      {
        bestSquaredRadius = ball.squaredRadius;
        best = Action{ Rule::R3, ball.center, ball.threshold, std::sqrt(ball.squaredRadius) };
      }
    }
    return best;
  }

  const LabelOracle &          m_Oracle;
  const RefinementParameters & m_Parameters;
  const double                 m_Delta;
  const DihedralAngleBound     m_DihedralBound;
  /** R1 counts a feature vertex up to this many times the local δ away as within it (1 + LatticeTieMargin). */
  const double           m_R1TieFactor;
  const MeshState &      m_State;
  const LocalSampling &  m_Sizing;
  const AxisAlignedBox & m_Box;
  mutable Vector3        m_LastSurfaceQuery{};
  mutable SurfacePoint   m_LastSurfacePoint{};
  mutable bool           m_LastSurfaceQueryValid{ false };
};

} // namespace detail
} // namespace delaunay_refinement

#endif
