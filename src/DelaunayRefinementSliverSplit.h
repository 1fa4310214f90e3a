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
#ifndef DelaunayRefinementSliverSplit_h
#define DelaunayRefinementSliverSplit_h

// Where R4' splits a sliver (docs/algorithm.md, "R4′ picks its point"): not necessarily at its circumcentre, but
// at the best point of a small ball around it, the picking region of Chew (Guaranteed-quality Delaunay meshing in
// 3D, 1997) and Li and Teng (Generating well-shaped Delaunay meshes in 3D, 2001), or at a surface point near it. A
// point there is still a fixed share of the circumradius from every vertex, since the sliver's circumball is
// empty, so the refinement keeps its spacing argument; but its new tetrahedra, and the boundary triangles it
// makes, differ from candidate to candidate, and every candidate is held to the same acceptance test: new
// tetrahedra below ρ, new boundary triangles with surface vertices only and angles > 30°.

#include "DelaunayRefinementBoxProtection.h"
#include "DelaunayRefinementConflictRegions.h"
#include "DelaunayRefinementGeometry.h"
#include "DelaunayRefinementMeshState.h"
#include "DelaunayRefinementRules.h"
#include "DelaunayRefinementVertexLinks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <optional>
#include <queue>
#include <stdexcept>
#include <tuple>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{

class SliverSplit
{
public:
  /** The picking region's radius, as a fraction of the sliver's circumradius. */
  static constexpr double PickingRadius = 0.3;

  /** How far from the circumcentre, as a fraction of the circumradius, the surface point may be. Larger than the
   * picking region's: the surface near a sliver on a boundary often passes farther from its circumcentre
   * (measured on the k-means tissues at 4 mm, σ = 15°: of the slivers with no accepted free point, 0.3 found a
   * surface point for 16 %, 0.5 for 55 %); the point is still at least half the circumradius from every vertex. */
  static constexpr double SurfacePickingRadius = 0.5;

  /** How far from the circumcentre, as a fraction of the circumradius, the surface points closest to the free
   * candidates may be (ConsiderSurfacePointsNearTheFreeCandidates): inside the circumball, whose emptiness keeps
   * them 0.1 of the circumradius from every vertex; the acceptance test bounds the new tetrahedra's radius-edge
   * ratios as for any candidate. Measured with σ = 10° (the slivers split failing the acceptance test, without
   * them / with them at 0.5 / at 0.7 / at 0.9): k-means tissues at 4 mm 183 / 153 / 90 / 71, atlas phantom at
   * 2 mm 80 / 77 / 52 / 47, k-means tissues on the 1 mm grid at 4 mm 48 / 30 / 9 / 8; 1.6-2.2 % more tetrahedra
   * at 0.9, and no change of the time that five paired rounds resolve. */
  static constexpr double ProjectedPickingRadius = 0.9;

  /** A point to insert and its kind: free, or feature when it is on the surface. */
  struct Split
  {
    Vector3    point;
    VertexKind kind;
    /** Whether some boundary or interface triangle changes (else the split leaves every one as it was). */
    bool changesBoundary;
    /** Whether the point passed the acceptance test (else it is the least bad one, see Choose). */
    bool accepted;
    /** Whether R3 will split a boundary triangle at the point's new tetrahedra, for an accepted point
     * (WillBeSplitByR3). */
    bool splitByR3{ false };
  };

  SliverSplit(const LabelOracle & oracle, const MeshState & state, const BoxProtection & box,
              const RefinementRules & rules, double radiusEdgeBound, double minimumDihedralAngle)
    : m_Oracle(oracle)
    , m_State(state)
    , m_Box(box)
    , m_Rules(rules)
    , m_RadiusEdgeBound(radiusEdgeBound)
    , m_DihedralBound(minimumDihedralAngle)
  {}

  /** The point to insert for the sliver `cell` (circumcentre `center`, squared circumradius `squaredRadius`).
   * Candidates: the circumcentre, 14 points on the sphere of the picking radius around it (the six axis directions
   * and the eight diagonals), then the surface point closest to the circumcentre when it is within
   * SurfacePickingRadius, and, when none of these passes the acceptance test, the surface points closest to the free
   * ones (ConsiderSurfacePointsNearTheFreeCandidates). A second sphere at half the radius cost 10 to 20 % of the time
   * with σ = 15° for 0 to 1.7 % fewer tetrahedra (k-means tissues, atlas phantom, brain mask). Every candidate passes
   * one acceptance test (Evaluate): its new tetrahedra have radius-edge ratio < ρ, and every triangle it puts on a
   * boundary has only surface vertices and angles > 30°. Among the accepted ones, a candidate that leaves every
   * boundary triangle as it was comes first, then the one whose new tetrahedra have the largest smallest dihedral
   * angle; the search ends at the first that leaves the boundary and reaches σ. With no accepted candidate, the best
   * one whose only fault is a free vertex on a boundary or a triangle there below 30°, else the circumcentre: the
   * sliver is split whatever it costs (docs/algorithm.md, "R4′ picks its point"). Deterministic: fixed candidates in a
   * fixed order, the first best wins. An accepted point also says whether R3 will split a boundary triangle at its new
   * tetrahedra (Split::splitByR3), for the refiner, which then tries to move a corner first. */
  Split
  Choose(CellHandle cell, const Vector3 & center, double squaredRadius) const
  {
    Split split = ChooseAmongCandidates(cell, center, squaredRadius);
    // WillBeSplitByR3 pairs the region's boundary edges in the order CGAL's search lists the facets, and which end
    // of a Voronoi edge its surface crossing starts from follows that order.
    m_Regions.Clear();
    split.splitByR3 = split.accepted && WillBeSplitByR3(split, cell);
    return split;
  }

private:
  /** See Choose. */
  Split
  ChooseAmongCandidates(CellHandle cell, const Vector3 & center, double squaredRadius) const
  {
    const double radius = std::sqrt(squaredRadius);
    const Ranked best = BestCandidate(cell, center, radius);
    if (best.fault == Fault::Uninsertable)
    {
      return { center, VertexKind::Free, true, false };
    }
    if (!best.split.changesBoundary)
    {
      return best.split;
    }
    // The best point changes a boundary: if that makes a boundary non-manifold somewhere, the best point that
    // does not, when it is as good by the acceptance test. Every non-manifold place a split makes costs a round
    // of the topology repair later, and most of the repair's time (measured on the k-means tissues at 4.5 mm,
    // σ = 15°: 992 of 7,977 splits made one).
    Evaluate(best.split.point, best.split.kind, cell, Ranked());
    if (!MakesANonManifoldPlace())
    {
      return best.split;
    }
    const Ranked keepingTopology = BestKeepingTopology(cell);
    return keepingTopology.fault <= best.fault ? keepingTopology.split : best.split;
  }

  /** Why a candidate fails the acceptance test, from the mildest. */
  enum class Fault
  {
    None,
    /** A free vertex on a boundary or interface, or a triangle there with an angle <= 30°. */
    Boundary,
    /** Outside the box, on a vertex, a new tetrahedron on the hull or one with radius-edge ratio >= ρ. */
    Uninsertable
  };

  /** Worse than the cosine of any angle. */
  static constexpr double Unusable = 2.0;

  /** A candidate with what the acceptance test found. */
  struct Ranked
  {
    Split  split{ {}, VertexKind::Free, true, false };
    Fault  fault{ Fault::Uninsertable };
    double cosine{ Unusable };

    /** Accepted before not; leaving the boundary before changing it; then the larger smallest angle (the
     * smaller cosine). */
    bool
    IsBetterThan(const Ranked & other) const
    {
      if (fault != other.fault)
      {
        return fault < other.fault;
      }
      if (fault == Fault::Uninsertable)
      {
        return false;
      }
      if (split.changesBoundary != other.split.changesBoundary)
      {
        return !split.changesBoundary;
      }
      return cosine < other.cosine;
    }
  };

  /** The six axis directions and the eight diagonals, unit length. */
  static const std::array<Vector3, 14> &
  Directions()
  {
    static const std::array<Vector3, 14> directions = [] {
      std::array<Vector3, 14> result{};
      std::size_t             next = 0;
      for (int axis = 0; axis < 3; ++axis)
      {
        for (const double sign : { -1.0, 1.0 })
        {
          Vector3 direction{ { 0.0, 0.0, 0.0 } };
          direction[axis] = sign;
          result[next++] = direction;
        }
      }
      const double diagonal = 1.0 / std::sqrt(3.0);
      for (const double x : { -diagonal, diagonal })
      {
        for (const double y : { -diagonal, diagonal })
        {
          for (const double z : { -diagonal, diagonal })
          {
            result[next++] = Vector3{ { x, y, z } };
          }
        }
      }
      return result;
    }();
    return directions;
  }

  /** What Evaluate found for a candidate (its point and kind are `ranked.split`'s). The first pass (BestCandidate)
   * keeps them all: the second (BestKeepingTopology) goes over the same candidates in the same triangulation, and
   * searches a conflict region again only where it must know it: for labels the first pass did not ask for, or for
   * the manifold test. */
  struct Evaluated
  {
    Ranked ranked;
    /** Whether its conflict region holds a cell of another label than the sliver's (the boundary changes surely). */
    bool replacesAnotherLabel;
    /** Whether the labels were asked for: `ranked` is then the whole acceptance test's result, whatever the best;
     * else its cosine may be only a bound from below (Evaluate). */
    bool labelled;
  };

  /** Whether a candidate (smallest angle's cosine `cosine`) cannot beat `best` whatever its new labels: an accepted
   * best is beaten only by an accepted candidate that leaves the boundary as it is while the best changes it, or
   * that does as the best does with a larger angle (Ranked::IsBetterThan), and a replaced cell of another label
   * changes the boundary whatever the new labels are. */
  static bool
  CannotBeat(double cosine, bool replacesAnotherLabel, const Ranked & best)
  {
    if (!best.split.accepted)
    {
      return false;
    }
    const bool largerAngle = cosine < best.cosine;
    return best.split.changesBoundary ? replacesAnotherLabel && !largerAngle : replacesAnotherLabel || !largerAngle;
  }

  /** Whether the search may end at `best`: accepted, leaving the boundary as it is, and reaching σ. */
  bool
  IsGoodEnough(const Ranked & best) const
  {
    return best.split.accepted && !best.split.changesBoundary && m_DihedralBound.IsReachedBy(best.cosine);
  }

  /** The best of the candidates m_Evaluated holds (the first pass's, which went over all of them: it ended early
   * only at a candidate that leaves the boundary as it is, and then Choose needs no second pass) among those that
   * make no boundary non-manifold where it was not; Fault::Uninsertable when none is insertable. Best first: each
   * candidate is ranked by what the first pass found, optimistically where it did not ask for the labels (accepted,
   * and leaving the boundary unless a replaced cell of another label changes it surely); such a candidate is
   * evaluated when it comes to the top, and goes back with its true rank; the first with a true rank that keeps
   * every boundary a manifold is the answer. Ties go to the earlier candidate, so the answer is the one a scan in
   * the candidates' order would keep; but the manifold test, a conflict search and a pass over the region's stars,
   * runs only for the candidates ranked above it (measured: it had taken 0.74 s of the k-means tissues at 4.5 mm
   * with σ = 15°, testing every candidate that improved on the scan's best so far). */
  Ranked
  BestKeepingTopology(CellHandle cell) const
  {
    struct Entry
    {
      Ranked      ranked;
      std::size_t index;
      bool        exact;
    };
    const auto comesAfter = [](const Entry & a, const Entry & b) {
      if (a.ranked.IsBetterThan(b.ranked) || b.ranked.IsBetterThan(a.ranked))
      {
        return b.ranked.IsBetterThan(a.ranked);
      }
      return a.index > b.index;
    };
    std::priority_queue<Entry, std::vector<Entry>, decltype(comesAfter)> queue(comesAfter);
    for (std::size_t index = 0; index < m_Evaluated.size(); ++index)
    {
      const Evaluated & evaluated = m_Evaluated[index];
      if (evaluated.ranked.fault == Fault::Uninsertable)
      {
        continue;
      }
      Entry entry{ evaluated.ranked, index, evaluated.labelled };
      if (!evaluated.labelled)
      {
        entry.ranked.fault = Fault::None;
        entry.ranked.split.accepted = true;
        entry.ranked.split.changesBoundary = evaluated.replacesAnotherLabel;
      }
      queue.push(entry);
    }
    std::size_t regionOf = m_Evaluated.size();
    while (!queue.empty())
    {
      Entry entry = queue.top();
      queue.pop();
      const Evaluated & evaluated = m_Evaluated[entry.index];
      if (!entry.exact || (entry.ranked.split.changesBoundary && regionOf != entry.index))
      {
        entry.ranked = Evaluate(evaluated.ranked.split.point, evaluated.ranked.split.kind, cell, Ranked()).ranked;
        regionOf = entry.index;
        if (!entry.exact)
        {
          entry.exact = true;
          if (entry.ranked.fault != Fault::Uninsertable)
          {
            queue.push(entry);
          }
          continue;
        }
      }
      if (!entry.ranked.split.changesBoundary || !MakesANonManifoldPlace())
      {
        return entry.ranked;
      }
    }
    return Ranked();
  }

  /** The best candidate (see Choose); Fault::Uninsertable when none is insertable. Each candidate and what Evaluate
   * found go into m_Evaluated, for BestKeepingTopology. */
  Ranked
  BestCandidate(CellHandle cell, const Vector3 & center, double radius) const
  {
    Ranked best;
    m_Evaluated.clear();
    const auto consider = [&](const Vector3 & point, VertexKind kind) {
      m_Evaluated.push_back(Evaluate(point, kind, cell, best));
      if (m_Evaluated.back().ranked.IsBetterThan(best))
      {
        best = m_Evaluated.back().ranked;
      }
      return IsGoodEnough(best);
    };
    if (consider(center, VertexKind::Free))
    {
      return best;
    }
    // The points around the circumcentre, whose conflict regions one search finds (ConflictRegions); the
    // circumcentre is searched for on its own, since the search ends there for some slivers (one in seven on the
    // atlas phantom at 2 mm with σ = 15°), which then need no other region.
    std::vector<Vector3> aroundCenter;
    for (const Vector3 & direction : Directions())
    {
      aroundCenter.push_back(center + (PickingRadius * radius) * direction);
    }
    m_Regions.Find(m_State.GetTriangulation(), cell, aroundCenter);
    for (const Vector3 & point : aroundCenter)
    {
      if (consider(point, VertexKind::Free))
      {
        return best;
      }
    }
    // A sliver on a boundary may have no free point that leaves the boundary good: points on the surface, which
    // the boundary may pass through, are tried last.
    const SurfacePoint onSurface = m_Oracle.ClosestSurfacePoint(center);
    if (onSurface.distance <= SurfacePickingRadius * radius)
    {
      consider(onSurface.point, VertexKind::Feature);
    }
    if (!best.split.accepted)
    {
      ConsiderSurfacePointsNearTheFreeCandidates(center, radius, onSurface, consider);
    }
    return best;
  }

  /** For a sliver none of whose candidates passed the acceptance test: the surface points closest to its free
   * candidates, in their order, each within ProjectedPickingRadius of the circumcentre, until one passes. Most such
   * slivers lie within δ of the surface with every corner on it, and every free point near their circumcentre puts
   * a free vertex on a boundary; the surface point beside it may not. Each distinct point is considered once:
   * `nearestToCenter`, the circumcentre's own (the first free candidate's), is not asked for again, nor evaluated
   * again when BestCandidate already did. */
  template <typename TConsider>
  void
  ConsiderSurfacePointsNearTheFreeCandidates(const Vector3 & center, double radius,
                                             const SurfacePoint & nearestToCenter, TConsider & consider) const
  {
    std::vector<Vector3> considered;
    if (nearestToCenter.distance <= SurfacePickingRadius * radius)
    {
      considered.push_back(nearestToCenter.point);
    }
    const std::size_t candidates = m_Evaluated.size();
    for (std::size_t index = 0; index < candidates; ++index)
    {
      const Split & candidate = m_Evaluated[index].ranked.split;
      if (candidate.kind != VertexKind::Free)
      {
        continue;
      }
      const Vector3 point =
        candidate.point == center ? nearestToCenter.point : m_Oracle.ClosestSurfacePoint(candidate.point).point;
      if (!(Distance(point, center) <= ProjectedPickingRadius * radius) ||
          std::find(considered.begin(), considered.end(), point) != considered.end())
      {
        continue;
      }
      considered.push_back(point);
      consider(point, VertexKind::Feature);
      if (m_Evaluated.back().ranked.split.accepted)
      {
        return;
      }
    }
  }

  /** The acceptance test and the score of inserting `point` as a vertex of `kind` to split `sliver`. Its new
   * tetrahedra are its conflict region's boundary facets joined to it; each carries the label at its circumcentre.
   * The labels are asked for only when the candidate's angles could beat `best`, since they cost an oracle query
   * each, and only until one differs from the sliver's when changing the boundary alone keeps it from beating `best`.
   * The conflict region stays in the members for MakesANonManifoldPlace. */
  Evaluated
  Evaluate(const Vector3 & point, VertexKind kind, CellHandle sliver, const Ranked & best) const
  {
    Evaluated evaluated{ Ranked(), false, false };
    Ranked &  result = evaluated.ranked;
    result.split = { point, kind, true, false };
    if (!m_Box.IsStrictlyInsideBox(point) || !FindConflicts(point, sliver))
    {
      return evaluated;
    }
    evaluated.replacesAnotherLabel = ReplacesAnotherLabel(sliver->cache.label);
    double largestCosine = -1.0;
    for (const std::array<Vector3, 4> & corners : m_NewTetrahedra)
    {
      // Written so that a NaN (a degenerate new tetrahedron) fails: the second pass orders candidates by their
      // angles, which a NaN would leave without an order.
      if (!(RadiusEdgeRatio(corners) < m_RadiusEdgeBound))
      {
        return evaluated;
      }
      largestCosine = std::max(largestCosine, CosineOfSmallestDihedralAngle(corners));
      // A candidate that cannot beat `best` with the tetrahedra seen so far cannot with all of them: its angle only
      // gets smaller. It is left unlabelled, and its cosine, a bound, makes it look no worse than it is: the second
      // pass evaluates it in full if it comes to the top (BestKeepingTopology). Most candidates end here.
      if (CannotBeat(largestCosine, evaluated.replacesAnotherLabel, best))
      {
        result.cosine = largestCosine;
        result.fault = Fault::Boundary;
        return evaluated;
      }
    }
    result.cosine = largestCosine;
    result.fault = Fault::Boundary;
    evaluated.labelled = true;
    m_NewLabels.clear();
    m_NewCenters.clear();
    // A candidate that cannot beat `best` once it changes the boundary stops at its first new tetrahedron of
    // another label than the sliver's, left unlabelled as above.
    const bool losesIfItChangesBoundary = CannotBeat(largestCosine, true, best);
    for (const std::array<Vector3, 4> & corners : m_NewTetrahedra)
    {
      m_NewCenters.push_back(TetrahedronCircumcenter(corners));
      m_NewLabels.push_back(m_Oracle.LabelAt(m_NewCenters.back()));
      if (losesIfItChangesBoundary && m_NewLabels.back() != sliver->cache.label)
      {
        evaluated.labelled = false;
        return evaluated;
      }
    }
    result.split.changesBoundary = ChangesBoundary(sliver->cache.label);
    result.split.accepted = !result.split.changesBoundary || NewBoundaryTrianglesAreGood(point, kind);
    result.fault = result.split.accepted ? Fault::None : Fault::Boundary;
    return evaluated;
  }

  /** The conflict region of `point` (its cells and boundary facets) and the corners of the tetrahedra it would
   * create; false when the point cannot be inserted there (on a vertex, or a new tetrahedron on the hull). */
  bool
  FindConflicts(const Vector3 & point, CellHandle hint) const
  {
    const Triangulation & triangulation = m_State.GetTriangulation();
    m_EdgesFound = false;
    if (const std::optional<std::size_t> index = m_Regions.IndexOf(point))
    {
      m_Regions.RegionOf(*index, m_ConflictCells, m_BoundaryFacets);
    }
    else
    {
      const CgalPoint            cgalPoint = ToCgal(point);
      Triangulation::Locate_type locateType;
      int                        li = 0;
      int                        lj = 0;
      const CellHandle           start = triangulation.locate(cgalPoint, locateType, li, lj, hint);
      if (locateType == Triangulation::VERTEX || triangulation.is_infinite(start))
      {
        return false;
      }
      m_BoundaryFacets.clear();
      m_ConflictCells.clear();
      triangulation.find_conflicts(
        cgalPoint, start, std::back_inserter(m_BoundaryFacets), std::back_inserter(m_ConflictCells));
    }
    m_NewTetrahedra.clear();
    for (const auto & [cell, opposite] : m_BoundaryFacets)
    {
      std::array<Vector3, 4> corners{};
      int                    next = 0;
      for (int vertex = 0; vertex < 4; ++vertex)
      {
        if (vertex == opposite)
        {
          continue;
        }
        if (triangulation.is_infinite(cell->vertex(vertex)))
        {
          return false;
        }
        corners[next++] = m_State.PointOf(cell->vertex(vertex));
      }
      corners[3] = point;
      m_NewTetrahedra.push_back(corners);
    }
    return true;
  }

  /** Whether some boundary or interface triangle would change: unless the tetrahedra replaced and those created
   * all carry the sliver's label, a facet changes side. When they do, the restricted facets are the same
   * triangles, and the split cannot touch the boundary's topology, its angles or its distance to the surface. */
  bool
  ChangesBoundary(Label sliverLabel) const
  {
    return ReplacesAnotherLabel(sliverLabel) ||
           std::any_of(
             m_NewLabels.begin(), m_NewLabels.end(), [sliverLabel](Label label) { return label != sliverLabel; });
  }

  /** Whether the conflict region holds a cell whose label is not the sliver's. */
  bool
  ReplacesAnotherLabel(Label sliverLabel) const
  {
    return std::any_of(m_ConflictCells.begin(), m_ConflictCells.end(), [sliverLabel](CellHandle cell) {
      return cell->cache.label != sliverLabel;
    });
  }

  /** Whether every triangle that the insertion puts on a boundary (a facet whose two tetrahedra come to differ in
   * label) has only surface vertices and angles > 30°: the bound and Lemma 5's "boundary vertices lie on the
   * surface" hold for the new boundary as for the old. Such a triangle is a facet of the conflict region's
   * boundary, or joins the new point to an edge of it. */
  bool
  NewBoundaryTrianglesAreGood(const Vector3 & point, VertexKind kind) const
  {
    for (std::size_t index = 0; index < m_BoundaryFacets.size(); ++index)
    {
      const auto & [cell, opposite] = m_BoundaryFacets[index];
      const Label                       outsideLabel = m_State.LabelBeyondFacet(cell, opposite);
      const std::array<VertexHandle, 3> corners = CornersOfBoundaryFacet(index);
      const bool                        wasOnBoundary = cell->cache.label != outsideLabel;
      const bool                        isOnBoundary = m_NewLabels[index] != outsideLabel;
      if (isOnBoundary && !wasOnBoundary &&
          (IsFree(corners[0]) || IsFree(corners[1]) || IsFree(corners[2]) ||
           !HasPlanarAnglesAbove30Degrees(
             m_State.PointOf(corners[0]), m_State.PointOf(corners[1]), m_State.PointOf(corners[2]))))
      {
        return false;
      }
    }
    // The triangle joining the new point to an edge of the region's boundary is on a boundary when the new
    // tetrahedra on the edge's two facets differ in label. A free point must be on none: since the region's boundary
    // is a sphere, whose facets are all joined through their edges, that is when every new tetrahedron has one
    // label, and the edges need not be paired (14 of R4′'s 16 candidates are free).
    if (kind == VertexKind::Free)
    {
      return std::all_of(
        m_NewLabels.begin(), m_NewLabels.end(), [this](Label label) { return label == m_NewLabels.front(); });
    }
    return !AnyNewTriangleOnABoundary([this, &point](const EdgeOfFacet & edge, const EdgeOfFacet &) {
      return IsFree(edge.a) || IsFree(edge.b) ||
             !HasPlanarAnglesAbove30Degrees(m_State.PointOf(edge.a), m_State.PointOf(edge.b), point);
    });
  }

  /** Whether visit(edge, twin) returns true for an edge of the conflict region's boundary (its two copies, m_Edges)
   * whose new tetrahedra on its two facets differ in label: the triangle joining the new point to that edge is then
   * on a boundary. Stops at the first. */
  template <typename TVisit>
  bool
  AnyNewTriangleOnABoundary(TVisit && visit) const
  {
    FindEdgesOfBoundaryFacets();
    for (std::size_t index = 0; index + 1 < m_Edges.size(); index += 2)
    {
      const EdgeOfFacet & edge = m_Edges[index];
      const EdgeOfFacet & twin = m_Edges[index + 1];
      if (m_NewLabels[edge.facet] != m_NewLabels[twin.facet] && visit(edge, twin))
      {
        return true;
      }
    }
    return false;
  }

  /** Whether R3 will split a boundary triangle at the tetrahedra that inserting `split` (a point Evaluate found
   * insertable) creates: one whose surface ball, centred where its dual Voronoi edge crosses the surface, reaches
   * R3's threshold (RefinementRules::SurfaceBallOf, as R3 itself tests it). The insertion moves the ends of those
   * edges, so the triangles it leaves on a boundary change their surface balls too, not only those it puts there. The
   * point's conflict region is searched again, since the ranking may have evaluated other candidates after it. */
  bool
  WillBeSplitByR3(const Split & split, CellHandle sliver) const
  {
    // Against no best, Evaluate asks for the labels of an insertable point; the guard keeps the arrays below from
    // being another candidate's, should that ever change.
    if (!Evaluate(split.point, split.kind, sliver, Ranked()).labelled)
    {
      return false;
    }
    const Triangulation & triangulation = m_State.GetTriangulation();
    for (std::size_t index = 0; index < m_BoundaryFacets.size(); ++index)
    {
      const auto & [cell, opposite] = m_BoundaryFacets[index];
      const CellHandle outside = cell->neighbor(opposite);
      if (m_NewLabels[index] == m_State.LabelBeyondFacet(cell, opposite) || triangulation.is_infinite(outside))
      {
        continue;
      }
      const std::array<VertexHandle, 3> corners = CornersOfBoundaryFacet(index);
      const auto                        ball = m_Rules.SurfaceBallOf(m_NewCenters[index],
                                              outside->cache.circumcenter,
                                              m_State.PointOf(corners[0]),
                                              m_State.PointOf(corners[1]),
                                              m_State.PointOf(corners[2]));
      if (ball.ReachesThreshold())
      {
        return true;
      }
    }
    return AnyNewTriangleOnABoundary([this, &split](const EdgeOfFacet & edge, const EdgeOfFacet & twin) {
      return m_Rules
        .SurfaceBallOf(m_NewCenters[edge.facet],
                       m_NewCenters[twin.facet],
                       m_State.PointOf(edge.a),
                       m_State.PointOf(edge.b),
                       split.point)
        .ReachesThreshold();
    });
  }

  std::array<VertexHandle, 3>
  CornersOfBoundaryFacet(std::size_t index) const
  {
    const auto & [cell, opposite] = m_BoundaryFacets[index];
    return { cell->vertex(Triangulation::vertex_triple_index(opposite, 0)),
             cell->vertex(Triangulation::vertex_triple_index(opposite, 1)),
             cell->vertex(Triangulation::vertex_triple_index(opposite, 2)) };
  }

  /** The edges of the conflict region's boundary facets into m_Edges, by their ends' ids: the region is a ball, so
   * each edge is on exactly two facets, and the two copies come one after the other. */
  void
  FindEdgesOfBoundaryFacets() const
  {
    // The acceptance test and the manifold test both ask for them, for the same candidate.
    if (m_EdgesFound)
    {
      return;
    }
    m_EdgesFound = true;
    m_Edges.clear();
    for (std::size_t index = 0; index < m_BoundaryFacets.size(); ++index)
    {
      const std::array<VertexHandle, 3> corners = CornersOfBoundaryFacet(index);
      for (int edge = 0; edge < 3; ++edge)
      {
        VertexHandle a = corners[edge];
        VertexHandle b = corners[(edge + 1) % 3];
        if (b->info().id < a->info().id)
        {
          std::swap(a, b);
        }
        m_Edges.push_back({ a, b, a->info().id, b->info().id, index });
      }
    }
    std::sort(m_Edges.begin(), m_Edges.end(), [](const EdgeOfFacet & x, const EdgeOfFacet & y) {
      return std::tie(x.idA, x.idB, x.facet) < std::tie(y.idA, y.idB, y.facet);
    });
    for (std::size_t index = 0; index < m_Edges.size(); index += 2)
    {
      if (index + 1 == m_Edges.size() || m_Edges[index].a != m_Edges[index + 1].a ||
          m_Edges[index].b != m_Edges[index + 1].b ||
          (index + 2 < m_Edges.size() && m_Edges[index + 2].a == m_Edges[index].a &&
           m_Edges[index + 2].b == m_Edges[index].b))
      {
        throw std::logic_error("SliverSplit: a conflict region's boundary is not a closed surface");
      }
    }
  }

  /** Whether the insertion last evaluated (its conflict region and new labels, Evaluate) would make a boundary
   * non-manifold at a vertex where it was not, or at the new point: each vertex of the region's boundary is tested
   * with its star as it would be (VertexLinks). Only those vertices' stars change. */
  bool
  MakesANonManifoldPlace() const
  {
    const Triangulation &     triangulation = m_State.GetTriangulation();
    const ConflictRegionMarks marks(m_ConflictCells);
    const auto                inConflict = [](CellHandle cell) { return cell->cache.inConflictRegion; };
    // The triangles joining the new point to an edge of the region's boundary, between the new tetrahedra on the
    // edge's two facets (m_Edges pairs them).
    FindEdgesOfBoundaryFacets();
    FindCornersOfTheRegion();
    for (auto first = m_FacetCorners.begin(); first != m_FacetCorners.end();)
    {
      const VertexHandle vertex = first->vertex;
      const auto         last = std::find_if(
        first, m_FacetCorners.end(), [vertex](const Incidence & incidence) { return incidence.vertex != vertex; });
      const auto facetsAtVertex = std::make_pair(first, last);
      first = last;
      if (!LinkMayChangeAt(vertex, facetsAtVertex))
      {
        continue;
      }
      m_Star.clear();
      triangulation.incident_cells(vertex, std::back_inserter(m_Star));
      m_FacetsAtVertex.clear();
      // Triangles between two tetrahedra that stay.
      for (const CellHandle cell : m_Star)
      {
        if (inConflict(cell))
        {
          continue;
        }
        const int own = cell->index(vertex);
        for (int facet = 0; facet < 4; ++facet)
        {
          const CellHandle neighbor = cell->neighbor(facet);
          if (facet == own || inConflict(neighbor) || neighbor < cell)
          {
            continue;
          }
          m_FacetsAtVertex.push_back({ VertexLinks::LinkEdgeOf(cell, own, facet), LabelOf(cell), LabelOf(neighbor) });
        }
      }
      // The region's boundary facets at the vertex, between a tetrahedron that stays and a new one.
      for (auto incidence = facetsAtVertex.first; incidence != facetsAtVertex.second; ++incidence)
      {
        const std::size_t index = incidence->index;
        const auto & [cell, opposite] = m_BoundaryFacets[index];
        std::array<VertexHandle, 2> edge{};
        int                         count = 0;
        for (const VertexHandle v : CornersOfBoundaryFacet(index))
        {
          if (v != vertex && count < 2)
          {
            edge[count++] = v;
          }
        }
        m_FacetsAtVertex.push_back({ edge, LabelOf(cell->neighbor(opposite)), m_NewLabels[index] });
      }
      // The new triangles at the vertex: the new point and the other end of a boundary edge at the vertex.
      AddNewTrianglesAt(vertex);
      // The links as they are now are built only where the insertion leaves some label non-manifold at the vertex:
      // elsewhere it cannot have made a place (most vertices).
      const int after = m_Links.NonManifoldLabelsAmongFacets(m_FacetsAtVertex);
      if (after > 0 && after > m_Links.NonManifoldLabelsAt(triangulation, vertex, m_Star))
      {
        return true;
      }
    }
    if (std::all_of(m_NewLabels.begin(), m_NewLabels.end(), [this](Label label) { return label == m_NewLabels[0]; }))
    {
      return false;
    }
    m_FacetsAtVertex.clear();
    AddNewTrianglesAt(VertexHandle());
    return m_Links.NonManifoldLabelsAmongFacets(m_FacetsAtVertex) > 0;
  }

  /** The conflict region's cells marked (CellCache::inConflictRegion) while the manifold test runs: it asks whether a
   * cell is in the region for every cell of every vertex's star and their neighbours, and a search in the sorted
   * region there took half of the test's time. */
  class ConflictRegionMarks
  {
  public:
    explicit ConflictRegionMarks(const std::vector<CellHandle> & cells)
      : m_Cells(cells)
    {
      for (const CellHandle cell : m_Cells)
      {
        cell->cache.inConflictRegion = true;
      }
    }
    ~ConflictRegionMarks()
    {
      for (const CellHandle cell : m_Cells)
      {
        cell->cache.inConflictRegion = false;
      }
    }
    ConflictRegionMarks(const ConflictRegionMarks &) = delete;
    ConflictRegionMarks &
    operator=(const ConflictRegionMarks &) = delete;

  private:
    const std::vector<CellHandle> & m_Cells;
  };

  /** A vertex and a boundary facet of the conflict region at it (`index` into m_BoundaryFacets), or a cell of the
   * region at it (`index` into m_ConflictCells). */
  struct Incidence
  {
    VertexHandle vertex;
    std::size_t  index;

    bool
    operator<(const Incidence & other) const
    {
      return std::tie(vertex, index) < std::tie(other.vertex, other.index);
    }
  };
  using IncidenceRange = std::pair<std::vector<Incidence>::const_iterator, std::vector<Incidence>::const_iterator>;

  /** The region's boundary facets and cells by vertex, into m_FacetCorners and m_CellCorners: each vertex's then
   * comes as one range, instead of a pass over the whole region per vertex. */
  void
  FindCornersOfTheRegion() const
  {
    m_FacetCorners.clear();
    for (std::size_t index = 0; index < m_BoundaryFacets.size(); ++index)
    {
      for (const VertexHandle vertex : CornersOfBoundaryFacet(index))
      {
        m_FacetCorners.push_back({ vertex, index });
      }
    }
    std::sort(m_FacetCorners.begin(), m_FacetCorners.end());
    m_CellCorners.clear();
    for (std::size_t index = 0; index < m_ConflictCells.size(); ++index)
    {
      for (int corner = 0; corner < 4; ++corner)
      {
        m_CellCorners.push_back({ m_ConflictCells[index]->vertex(corner), index });
      }
    }
    std::sort(m_CellCorners.begin(), m_CellCorners.end());
  }

  /** Whether a boundary's link at `vertex`, a vertex of the conflict region (its boundary facets there:
   * `facetsAtVertex`), may change: unless the replaced tetrahedra at it and the new ones there all carry one
   * label, a triangle at it changes sides. When they do, the triangles it had on a boundary stay there, between
   * the same labels, and no other comes. */
  bool
  LinkMayChangeAt(VertexHandle vertex, const IncidenceRange & facetsAtVertex) const
  {
    std::optional<Label> only;
    const auto           differs = [&only](Label label) {
      if (!only)
      {
        only = label;
      }
      return *only != label;
    };
    const auto cellsAtVertex = std::equal_range(
      m_CellCorners.begin(), m_CellCorners.end(), Incidence{ vertex, 0 }, [](const Incidence & a, const Incidence & b) {
        return a.vertex < b.vertex;
      });
    for (auto incidence = cellsAtVertex.first; incidence != cellsAtVertex.second; ++incidence)
    {
      if (differs(m_ConflictCells[incidence->index]->cache.label))
      {
        return true;
      }
    }
    for (auto incidence = facetsAtVertex.first; incidence != facetsAtVertex.second; ++incidence)
    {
      if (differs(m_NewLabels[incidence->index]))
      {
        return true;
      }
    }
    return false;
  }

  /** Adds to m_FacetsAtVertex the new triangles (the new point joined to an edge of the region's boundary) at
   * `vertex`, or at the new point when it is null: their edge opposite it, and the labels of the new tetrahedra on
   * the edge's two facets. */
  void
  AddNewTrianglesAt(VertexHandle vertex) const
  {
    for (std::size_t index = 0; index + 1 < m_Edges.size(); index += 2)
    {
      const EdgeOfFacet & edge = m_Edges[index];
      const EdgeOfFacet & twin = m_Edges[index + 1];
      const Label         label = m_NewLabels[edge.facet];
      const Label         other = m_NewLabels[twin.facet];
      if (vertex == VertexHandle())
      {
        m_FacetsAtVertex.push_back({ { edge.a, edge.b }, label, other });
      }
      else if (edge.a == vertex || edge.b == vertex)
      {
        m_FacetsAtVertex.push_back({ { edge.a == vertex ? edge.b : edge.a, VertexHandle() }, label, other });
      }
    }
  }

  Label
  LabelOf(CellHandle cell) const
  {
    return m_State.GetTriangulation().is_infinite(cell) ? BackgroundLabel : cell->cache.label;
  }

  static bool
  IsFree(const VertexHandle & vertex)
  {
    return vertex->info().kind == VertexKind::Free;
  }

  /** An edge of a facet of the conflict region's boundary, its ends by ascending vertex id; the ids are kept beside
   * the handles so that sorting the edges does not read the vertices. */
  struct EdgeOfFacet
  {
    VertexHandle a;
    VertexHandle b;
    VertexId     idA;
    VertexId     idB;
    std::size_t  facet;
  };

  const LabelOracle &     m_Oracle;
  const MeshState &       m_State;
  const BoxProtection &   m_Box;
  const RefinementRules & m_Rules;
  double                  m_RadiusEdgeBound;
  DihedralAngleBound      m_DihedralBound;
  /** The conflict regions of the free candidates around the circumcentre, during Choose (BestCandidate). */
  mutable ConflictRegions                     m_Regions;
  mutable std::vector<Triangulation::Facet>   m_BoundaryFacets;
  mutable std::vector<CellHandle>             m_ConflictCells;
  mutable std::vector<std::array<Vector3, 4>> m_NewTetrahedra;
  mutable std::vector<Label>                  m_NewLabels;
  /** The circumcentres of m_NewTetrahedra, where m_NewLabels were asked for. */
  mutable std::vector<Vector3> m_NewCenters;
  /** The first pass's candidates (BestCandidate). */
  mutable std::vector<Evaluated>   m_Evaluated;
  mutable std::vector<EdgeOfFacet> m_Edges;
  /** Whether m_Edges holds the edges of m_BoundaryFacets (FindConflicts clears it). */
  mutable bool                                    m_EdgesFound{ false };
  VertexLinks                                     m_Links;
  mutable std::vector<Incidence>                  m_FacetCorners;
  mutable std::vector<Incidence>                  m_CellCorners;
  mutable std::vector<CellHandle>                 m_Star;
  mutable std::vector<VertexLinks::FacetAtVertex> m_FacetsAtVertex;
};

} // namespace detail
} // namespace delaunay_refinement

#endif
