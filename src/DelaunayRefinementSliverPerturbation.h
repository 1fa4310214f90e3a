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
#ifndef DelaunayRefinementSliverPerturbation_h
#define DelaunayRefinementSliverPerturbation_h

// R4′'s second way (docs/algorithm.md, "R4′ moves a vertex"): a sliver that no split point can remove without
// breaking a bound (SliverSplit), or a tetrahedron flat to rounding, which no split may remove, is removed by moving
// one of its corners a little: a free corner through space, a surface corner along the surface (to where the label
// changes along the surface's normal near the shifted point, so boundary vertices stay on the surface, Lemma 5). A
// move is made for real and kept only when it passes the acceptance test: no rule but R4′ applies to any
// tetrahedron it creates (so radius-edge < ρ, the δ rules and the 30° bound of R3 hold there), every boundary
// triangle it creates has surface vertices only, no vertex it touches becomes non-manifold, the smallest dihedral
// angle of the tissue tetrahedra it creates is larger than that of the moved vertex's star before, and, with σ = 0,
// Lemma 2's spacing holds at the moved vertex (99 % of it at the last level, SpacingMayBreak). Otherwise the vertex is
// moved back, which restores the triangulation exactly (MeshState::MoveVertex). A tetrahedron flat to rounding left
// after the refinement may be moved under a relaxed test (Acceptance), the refinement resuming after it. Each accepted
// move raises the local smallest angle, and each sliver is tried once per pass, so the process ends. This is the
// perturbation of CGAL's sliver perturber and of Tournois et al. (Perturbing slivers in 3D Delaunay meshes, 2009), held
// to the refinement's own bounds instead of to the angle alone.

#include "DelaunayRefinementBoxProtection.h"
#include "DelaunayRefinementGeometry.h"
#include "DelaunayRefinementMeshState.h"
#include "DelaunayRefinementRules.h"
#include "DelaunayRefinementSizing.h"
#include "DelaunayRefinementVertexLinks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <iterator>
#include <limits>
#include <set>
#include <utility>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{

class SliverPerturbation
{
public:
  /** What an attempt did. */
  enum class Outcome
  {
    /** A corner moved; the sliver is gone. */
    Moved,
    /** Moves were tried and undone: the triangulation is as it was, but the sliver is a new cell, queued again. */
    Undone,
    /** Nothing was tried (the sliver was tried before, no corner can move, or every move was predicted to fail,
     * SplitsABoundaryTriangle): the sliver's cell is as it was. */
    NotTried
  };

  /** How far a corner moves, as fractions of the sliver's shortest edge: far enough to change the Delaunay
   * triangulation around it, not so far that its other tetrahedra degrade. */
  static constexpr std::array<double, 2> StepFractions{ 0.2, 0.4 };

  /** The same for a tetrahedron flat to rounding: any step well above rounding breaks the co-circularity. */
  static constexpr std::array<double, 3> FlatStepFractions{ 0.0001, 0.001, 0.01 };

  /** How many moves are made for real per sliver, the most promising first; each costs a removal and an insertion
   * and the same again to undo it. A tetrahedron flat to rounding, rare and unusable, gets every candidate. */
  static constexpr std::size_t MovesTried = 3;

  SliverPerturbation(const LabelOracle & oracle, const RefinementParameters & parameters, MeshState & state,
                     const RefinementRules & rules, const LocalSampling & sizing, const BoxProtection & box)
    : m_Oracle(oracle)
    , m_State(state)
    , m_Rules(rules)
    , m_Sizing(sizing)
    , m_Box(box)
    , m_Delta(parameters.surfaceSamplingDistance)
    , m_FreeSpacing(std::min(parameters.radiusEdgeBound, 2.0))
    , m_KeepsLemma2(!(parameters.minimumDihedralAngle > 0.0))
  {}

  /** What a move must keep besides Lemma 2's spacing (σ = 0) and a larger smallest angle, from the strictest; a
   * tetrahedron flat to rounding whose moves all fail one level tries them again at the next, up to the level the
   * caller allows. The later levels are for when the refinement is otherwise done: a flat tetrahedron is a
   * singular element for any solver, worse than a tetrahedron the refinement must split or a non-manifold vertex
   * that the topology repair, which follows, may mend. */
  enum class Acceptance
  {
    /** No rule but R4′ applies to a tetrahedron the move creates, no boundary triangle it creates has a free
     * vertex, and no vertex it touches becomes non-manifold: the move leaves nothing to refine. */
    EveryRule,
    /** R1–R4 may apply to the tetrahedra it creates, and a boundary triangle may have a free vertex: the refinement,
     * resumed after the move, splits them (where ρ is near 1 almost every tetrahedron a move creates reaches ρ). */
    RefinementMayFollow,
    /** As RefinementMayFollow, and a vertex may become non-manifold (in sheets thinner than δ, every move of a
     * corner may change a link). */
    NonManifoldMayFollow,
    /** As NonManifoldMayFollow, and with σ = 0 the moved vertex keeps only LastResortSpacingFraction of Lemma 2's
     * spacing. Only for the flat tetrahedra that every level before and the edge removal of the extracted mesh left
     * (Refiner::ExtractWithoutFlatTetrahedra): where the surface samples sit on a lattice about δ apart every move
     * breaks the spacing (δ ≤ h/√2 for voxels of h: four voxel-face centres around a voxel edge make a flat square
     * inside a tissue; the atlas phantom at δ = 0.70710678 mm kept 52). A singular element is worse for a solver
     * than an edge 1 % shorter than δ. The moved vertices are remembered (MovedBelowSpacing). */
    SpacingMayBreak
  };

  /** Tries to remove the sliver `cell` by moving one of its corners (see the file's comment). Deterministic: the
   * candidates are fixed points in a fixed order. A tetrahedron flat to rounding tries every candidate at each
   * acceptance level up to `lastResort`. */
  Outcome
  Perturb(CellHandle sliver, Acceptance lastResort = Acceptance::EveryRule)
  {
    const std::array<Vector3, 4> corners = m_State.CornersOf(sliver);
    if (!m_Tried.insert(m_State.SortedCornersOf(sliver)).second)
    {
      return Outcome::NotTried;
    }
    std::vector<Candidate> candidates = CandidatesFor(sliver, corners);
    if (candidates.empty())
    {
      return Outcome::NotTried;
    }
    std::array<VertexHandle, 4> vertices{ sliver->vertex(0), sliver->vertex(1), sliver->vertex(2), sliver->vertex(3) };
    const bool                  isFlat = IsFlatToRounding(corners);
    const std::size_t           tries = isFlat ? candidates.size() : MovesTried;
    const Acceptance            lastLevel = isFlat ? lastResort : Acceptance::EveryRule;
    bool                        anyMade = false;
    for (Acceptance acceptance = Acceptance::EveryRule; acceptance <= lastLevel;
         acceptance = static_cast<Acceptance>(static_cast<int>(acceptance) + 1))
    {
      std::size_t made = 0;
      for (std::size_t index = 0; index < candidates.size() && made < tries; ++index)
      {
        const Candidate & candidate = candidates[index];
        VertexHandle &    vertex = vertices[candidate.corner];
        if (m_KeepsLemma2 && IsNearerThanTheFinestDeltaToANeighbor(vertex, candidate.point, SpacingKeptAt(acceptance)))
        {
          ++made;
          continue;
        }
        if (!isFlat && vertex->info().kind == VertexKind::Feature && SplitsABoundaryTriangle(vertex, candidate.point))
        {
          continue;
        }
        ++made;
        anyMade = true;
        const Vector3 from = m_State.PointOf(vertex);
        const double  cosineBefore = LargestCosineAmongTissueCells(StarOf(vertex));
        const int     nonManifoldBefore = CountNonManifoldAroundBefore(vertex);
        vertex = m_State.MoveVertex(vertex, candidate.point, m_NewCells);
        if (IsAccepted(vertex, cosineBefore, nonManifoldBefore, acceptance))
        {
          if (acceptance == Acceptance::SpacingMayBreak && m_KeepsLemma2)
          {
            m_MovedBelowSpacing.insert(candidate.point);
          }
          return Outcome::Moved;
        }
        vertex = m_State.MoveVertex(vertex, from, m_NewCells);
      }
    }
    return anyMade ? Outcome::Undone : Outcome::NotTried;
  }

  /** Where the vertices moved at the level SpacingMayBreak went, with σ = 0 (TetrahedralMesh::pointsMovedBelowSpacing).
   */
  const std::set<Vector3> &
  MovedBelowSpacing() const
  {
    return m_MovedBelowSpacing;
  }

  /** Lets every sliver be tried again: once no rule applies anywhere, a move that failed because a rule still
   * applied near it (its neighbourhood was not refined yet) may pass. */
  void
  ForgetTried()
  {
    m_Tried.clear();
  }

private:
  /** A corner of the sliver, the point it would move to, and how promising the move is (smaller first). */
  struct Candidate
  {
    int     corner;
    Vector3 point;
    double  score;
  };

  /** A sliver gets height when a corner moves away from the plane of its opposite facet (MoveCorner); these are
   * ordered by the sliver's smallest angle after the move, best first. A tetrahedron flat to rounding has its four
   * corners on one circle of a plane (docs/algorithm.md, "Flat caps"): a corner moves in that plane, away from the
   * others' centre, which breaks the co-circularity and lets the Delaunay triangulation flip the tetrahedron away,
   * or, when the plane is across the surface (the four lateral face centres of one voxel), out of the plane, which
   * leaves a tetrahedron with volume; these are ordered by direction, then by step, shortest first. A point that
   * is already a vertex, outside the box, or barely moves is not a candidate. */
  std::vector<Candidate>
  CandidatesFor(CellHandle sliver, const std::array<Vector3, 4> & corners) const
  {
    std::vector<Candidate>    candidates;
    const double              shortestEdge = ShortestEdgeLength(corners);
    const bool                isFlat = IsFlatToRounding(corners);
    const Vector3             centroid = 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
    const std::vector<double> fractions = isFlat
                                            ? std::vector<double>(FlatStepFractions.begin(), FlatStepFractions.end())
                                            : std::vector<double>(StepFractions.begin(), StepFractions.end());
    // What each corner moves along, computed once: a sliver's corner gains height; a flat tetrahedron's moves in
    // its plane, away from the others' centre, else across its plane (when that plane is across the surface: four
    // face centres around one voxel). A surface corner's normal comes from its boundary facets; a flat
    // tetrahedron gives two more where that estimate is poor at a corner of the surface: its plane's, when it lies
    // in the surface, and the outward direction in its plane, when its plane is across it.
    std::array<std::vector<Vector3>, 4> directions;
    std::array<std::vector<Vector3>, 4> normals;
    for (int corner = 0; corner < 4; ++corner)
    {
      const Vector3 facetNormal = OutwardFaceNormal(corners, corner);
      const Vector3 height = (-1.0 / Norm(facetNormal)) * facetNormal;
      directions[corner] = { height };
      if (sliver->vertex(corner)->info().kind == VertexKind::Feature)
      {
        normals[corner] = { SurfaceNormalAt(sliver->vertex(corner)) };
      }
      if (isFlat)
      {
        const Vector3 outward = corners[corner] - centroid;
        const Vector3 inPlane = outward - Dot(outward, height) * height;
        directions[corner] = { inPlane, height, -1.0 * height };
        if (!normals[corner].empty())
        {
          normals[corner].push_back(height);
          normals[corner].push_back((1.0 / Norm(inPlane)) * inPlane);
        }
      }
    }
    for (const double fraction : fractions)
    {
      const double step = fraction * shortestEdge;
      const double bracket = std::max(step, BracketFraction * shortestEdge);
      for (int corner = 0; corner < 4; ++corner)
      {
        const VertexKind kind = sliver->vertex(corner)->info().kind;
        if (kind != VertexKind::Free && kind != VertexKind::Feature)
        {
          continue;
        }
        for (std::size_t index = 0; index < directions[corner].size(); ++index)
        {
          const std::optional<Vector3> moved =
            MoveCorner(corners[corner], kind, directions[corner][index], normals[corner], step, bracket);
          if (!moved || !(Distance(*moved, corners[corner]) >= MinimumMoveFraction * step) ||
              !m_Box.IsStrictlyInsideBox(*moved) || IsAVertex(*moved, sliver))
          {
            continue;
          }
          std::array<Vector3, 4> after = corners;
          after[corner] = *moved;
          const double score = isFlat ? static_cast<double>(index) + fraction : CosineOfSmallestDihedralAngle(after);
          candidates.push_back({ corner, *moved, score });
        }
      }
    }
    std::stable_sort(
      candidates.begin(), candidates.end(), [](const Candidate & a, const Candidate & b) { return a.score < b.score; });
    return candidates;
  }

  /** Where a corner at `from` lands when it moves by `step` in `direction`: a free corner straight there, a surface
   * corner along the surface (MoveAlongSurface), with the first of the estimates of the surface's normal there
   * that finds the surface. */
  std::optional<Vector3>
  MoveCorner(const Vector3 & from, VertexKind kind, const Vector3 & direction, const std::vector<Vector3> & normals,
             double step, double bracket) const
  {
    const double length = Norm(direction);
    if (!(length > 0.0))
    {
      return std::nullopt;
    }
    if (kind == VertexKind::Free)
    {
      return from + (step / length) * direction;
    }
    for (const Vector3 & normal : normals)
    {
      if (const std::optional<Vector3> moved = MoveAlongSurface(from, direction, normal, step, bracket))
      {
        return moved;
      }
    }
    return std::nullopt;
  }

  /** The point of the surface reached from `from` by a step of `length` along the part of `direction` tangent to
   * the surface (of unit normal `normal`): the shifted point is taken back to the surface along the normal, where
   * the label changes between `bracket` above and below it. None when the direction is nearly normal or no
   * label changes there. The surface samples the oracle returns (ClosestSurfacePoint) can be a discrete set, the
   * voxel faces' centres for labels that change half-way between voxels, so the closest surface point to a
   * shifted sample is often the sample itself; the crossing is not. */
  std::optional<Vector3>
  MoveAlongSurface(const Vector3 & from, const Vector3 & direction, const Vector3 & normal, double length,
                   double bracket) const
  {
    const Vector3 tangent = direction - Dot(direction, normal) * normal;
    const double  tangentLength = Norm(tangent);
    if (!(tangentLength > MinimumTangentFraction * Norm(direction)))
    {
      return std::nullopt;
    }
    const Vector3 shifted = from + (length / tangentLength) * tangent;
    const Vector3 above = shifted + bracket * normal;
    const Vector3 below = shifted - bracket * normal;
    if (m_Oracle.LabelAt(above) == m_Oracle.LabelAt(below))
    {
      return std::nullopt;
    }
    return m_Oracle.SurfaceCrossing(above, below);
  }

  /** The unit normal of the surface at a surface vertex, from the boundary facets of its star, area-weighted, each
   * turned from the smaller label towards the larger (zero when it has none). */
  Vector3
  SurfaceNormalAt(VertexHandle vertex) const
  {
    const Triangulation & triangulation = m_State.GetTriangulation();
    Vector3               sum{ { 0.0, 0.0, 0.0 } };
    for (const CellHandle cell : StarOf(vertex))
    {
      if (triangulation.is_infinite(cell))
      {
        continue;
      }
      const std::array<Vector3, 4> corners = m_State.CornersOf(cell);
      for (int facet = 0; facet < 4; ++facet)
      {
        const Label beyond = m_State.LabelBeyondFacet(cell, facet);
        if (facet == cell->index(vertex) || beyond == cell->cache.label)
        {
          continue;
        }
        // Turned from the smaller label towards the larger, whichever of its two cells it is seen from.
        const Vector3 outward = OutwardFaceNormal(corners, facet);
        sum = cell->cache.label < beyond ? sum + outward : sum - outward;
      }
    }
    const double length = Norm(sum);
    return length > 0.0 ? (1.0 / length) * sum : sum;
  }

  /** Whether R3 would split a boundary triangle at the surface vertex `vertex` once it is moved to `point`, were
   * the boundary's triangles there to stay the same: one whose circumradius reaches R3's threshold
   * (RefinementRules::SurfaceBallThreshold, with the local δ at the moved point). A move of a surface vertex along
   * the surface can change the Delaunay triangulation around it, so this only predicts the acceptance test; but
   * it predicts most of its failures for free, where making and undoing the move costs a removal and an insertion
   * each (measured on the k-means tissues at 4.5 mm with σ = 15°: R3 failed 1,929 of 3,500 failing moves). A
   * candidate predicted to fail is not made and does not count as one of the MovesTried. */
  bool
  SplitsABoundaryTriangle(VertexHandle vertex, const Vector3 & point) const
  {
    const Triangulation & triangulation = m_State.GetTriangulation();
    for (const CellHandle cell : StarOf(vertex))
    {
      if (triangulation.is_infinite(cell))
      {
        continue;
      }
      const int moved = cell->index(vertex);
      for (int facet = 0; facet < 4; ++facet)
      {
        if (facet == moved || m_State.LabelBeyondFacet(cell, facet) == cell->cache.label)
        {
          continue;
        }
        std::array<Vector3, 3> triangle{};
        for (int corner = 0; corner < 3; ++corner)
        {
          const int index = Triangulation::vertex_triple_index(facet, corner);
          triangle[corner] = index == moved ? point : m_State.PointOf(cell->vertex(index));
        }
        if (TriangleCircumradius(triangle[0], triangle[1], triangle[2]) >=
            m_Rules.SurfaceBallThreshold(point, triangle[0], triangle[1], triangle[2]))
        {
          return true;
        }
      }
    }
    return false;
  }

  /** The acceptance test of a move just made, whose new cells are in m_NewCells (see the file's comment). */
  bool
  IsAccepted(VertexHandle moved, double cosineBefore, int nonManifoldBefore, Acceptance acceptance) const
  {
    const Triangulation & triangulation = m_State.GetTriangulation();
    // The tests that read the new cells' caches only come first, the rules (oracle queries) after them: the answer
    // is the same, and a move that fails its angle fails sooner (about half of the moves that fail: 703 of 1,386 on
    // the k-means tissues at δ = 4 mm with σ = 15°, where the rules turned down 348).
    double cosineAfter = -1.0;
    for (const CellHandle cell : m_NewCells)
    {
      if (cell->cache.label != BackgroundLabel)
      {
        cosineAfter = std::max(cosineAfter, CosineOfSmallestDihedralAngle(m_State.CornersOf(cell)));
      }
      for (int facet = 0; facet < 4; ++facet)
      {
        if (acceptance == Acceptance::EveryRule && m_State.LabelBeyondFacet(cell, facet) != cell->cache.label &&
            HasAFreeCorner(cell, facet))
        {
          return false;
        }
      }
    }
    if (!(cosineAfter < cosineBefore))
    {
      return false;
    }
    if (acceptance == Acceptance::EveryRule)
    {
      for (const CellHandle cell : m_NewCells)
      {
        const std::optional<Action> action = m_Rules.FindApplicableRule(cell);
        if (action && action->rule != Rule::R4Dihedral)
        {
          return false;
        }
      }
    }
    if (m_KeepsLemma2 && !KeepsLemma2Spacing(moved, SpacingKeptAt(acceptance)))
    {
      return false;
    }
    if (acceptance >= Acceptance::NonManifoldMayFollow)
    {
      return true;
    }
    m_Touched.clear();
    for (const CellHandle cell : m_NewCells)
    {
      for (int corner = 0; corner < 4; ++corner)
      {
        if (!triangulation.is_infinite(cell->vertex(corner)))
        {
          m_Touched.push_back(cell->vertex(corner));
        }
      }
    }
    std::sort(m_Touched.begin(), m_Touched.end());
    m_Touched.erase(std::unique(m_Touched.begin(), m_Touched.end()), m_Touched.end());
    // Boundaries may be non-manifold while the refinement runs (the repair comes after it): a move may leave a
    // place as it was, never add one.
    return std::none_of(m_Touched.begin(), m_Touched.end(), [&](VertexHandle vertex) {
      const int after = m_Links.NonManifoldLabelsAt(triangulation, vertex, StarOf(vertex));
      if (vertex == moved)
      {
        return after > nonManifoldBefore;
      }
      const auto known = std::lower_bound(
        m_NeighborsBefore.begin(), m_NeighborsBefore.end(), std::make_pair(vertex, std::numeric_limits<int>::min()));
      const int before = known != m_NeighborsBefore.end() && known->first == vertex ? known->second : 0;
      return after > before;
    });
  }

  /** The non-manifold (vertex, label) pairs at a vertex about to move; its neighbours' are kept for the
   * acceptance test (the vertices a small move touches). */
  int
  CountNonManifoldAroundBefore(VertexHandle vertex)
  {
    const Triangulation & triangulation = m_State.GetTriangulation();
    m_NeighborsBefore.clear();
    m_Neighbors.clear();
    triangulation.adjacent_vertices(vertex, std::back_inserter(m_Neighbors));
    for (const VertexHandle neighbor : m_Neighbors)
    {
      if (!triangulation.is_infinite(neighbor))
      {
        m_NeighborsBefore.emplace_back(neighbor,
                                       m_Links.NonManifoldLabelsAt(triangulation, neighbor, StarOf(neighbor)));
      }
    }
    std::sort(m_NeighborsBefore.begin(), m_NeighborsBefore.end());
    return m_Links.NonManifoldLabelsAt(triangulation, vertex, StarOf(vertex));
  }

  /** The share of Lemma 2's spacing a move at this level keeps (with σ = 0): all of it, but at the last level. */
  static double
  SpacingKeptAt(Acceptance acceptance)
  {
    return acceptance == Acceptance::SpacingMayBreak ? LastResortSpacingFraction : 1.0;
  }

  /** Whether `point` is nearer than `share` of the finest δ to a neighbour of `vertex`: then moving the vertex there
   * fails KeepsLemma2Spacing() surely (the moved point's nearest vertex is its neighbour after the move, no farther
   * than that one, and every spacing bound is at least the finest δ), and the move is not made. Where the surface
   * samples are exactly δ apart (δ = h/√2 for voxels of h), every move of a flat tetrahedron's corner is such a
   * move, and making and undoing them all took minutes (the atlas phantom at δ = 0.70710678 mm ran 10 minutes
   * without ending). */
  bool
  IsNearerThanTheFinestDeltaToANeighbor(VertexHandle vertex, const Vector3 & point, double share) const
  {
    const Triangulation & triangulation = m_State.GetTriangulation();
    const double          finest = share * m_Sizing.FinestDelta();
    m_Neighbors.clear();
    triangulation.adjacent_vertices(vertex, std::back_inserter(m_Neighbors));
    return std::any_of(m_Neighbors.begin(), m_Neighbors.end(), [&](VertexHandle neighbor) {
      return !triangulation.is_infinite(neighbor) && Distance(point, m_State.PointOf(neighbor)) < finest;
    });
  }

  /** Lemma 2 at the moved vertex, as the refinement keeps it with σ = 0, or `share` of it: every edge at least the
   * local δ long (the smaller of its ends'), min(ρ, 2) times that when an end is free, 2δ to a vertex of the box. */
  bool
  KeepsLemma2Spacing(VertexHandle moved, double share) const
  {
    const Triangulation & triangulation = m_State.GetTriangulation();
    const Vector3         point = m_State.PointOf(moved);
    const double          deltaHere = m_Sizing.LocalDelta(point);
    m_Neighbors.clear();
    triangulation.adjacent_vertices(moved, std::back_inserter(m_Neighbors));
    for (const VertexHandle neighbor : m_Neighbors)
    {
      if (triangulation.is_infinite(neighbor))
      {
        continue;
      }
      const Vector3    other = m_State.PointOf(neighbor);
      const VertexKind kind = neighbor->info().kind;
      const double     delta = std::min(deltaHere, m_Sizing.LocalDelta(other));
      double           bound = delta;
      if (kind == VertexKind::Free || moved->info().kind == VertexKind::Free)
      {
        bound = m_FreeSpacing * delta;
      }
      if (kind == VertexKind::BoxFace || kind == VertexKind::BoxEdge)
      {
        bound = std::max(bound, 2.0 * m_Delta);
      }
      if (!(Distance(point, other) >= share * bound))
      {
        return false;
      }
    }
    return true;
  }

  /** The cosine of the smallest dihedral angle among the cells of a tissue (the background's are not output). */
  double
  LargestCosineAmongTissueCells(const std::vector<CellHandle> & cells) const
  {
    double largest = -1.0;
    for (const CellHandle cell : cells)
    {
      if (!m_State.GetTriangulation().is_infinite(cell) && cell->cache.label != BackgroundLabel)
      {
        largest = std::max(largest, CosineOfSmallestDihedralAngle(m_State.CornersOf(cell)));
      }
    }
    return largest;
  }

  bool
  HasAFreeCorner(CellHandle cell, int facet) const
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      if (cell->vertex(Triangulation::vertex_triple_index(facet, corner))->info().kind == VertexKind::Free)
      {
        return true;
      }
    }
    return false;
  }

  bool
  IsAVertex(const Vector3 & point, CellHandle hint) const
  {
    Triangulation::Locate_type locateType;
    int                        li = 0;
    int                        lj = 0;
    m_State.GetTriangulation().locate(ToCgal(point), locateType, li, lj, hint);
    return locateType == Triangulation::VERTEX;
  }

  const std::vector<CellHandle> &
  StarOf(VertexHandle vertex) const
  {
    m_Star.clear();
    m_State.GetTriangulation().incident_cells(vertex, std::back_inserter(m_Star));
    return m_Star;
  }

  /** A move shorter than this fraction of its step does not count (a surface corner whose shift was mostly across
   * the surface). */
  static constexpr double MinimumMoveFraction = 0.25;

  /** How far above and below the surface a moved surface vertex is looked for, in shortest edges (at least its
   * step): where the surface bends at the vertex (a voxel edge), a tiny step along the estimated tangent can leave
   * it by more than the step. */
  static constexpr double BracketFraction = 0.1;

  /** A direction whose part tangent to the surface is shorter than this fraction of it is across the surface. */
  static constexpr double MinimumTangentFraction = 0.2;

  const LabelOracle &     m_Oracle;
  MeshState &             m_State;
  const RefinementRules & m_Rules;
  const LocalSampling &   m_Sizing;
  const BoxProtection &   m_Box;
  double                  m_Delta;
  /** Lemma 2's spacing of a free vertex from any other, in units of the local δ: min(ρ, 2). */
  double m_FreeSpacing;
  /** With σ = 0 every bound of Theorem 2 holds, Lemma 2's spacing among them, and a move must keep it. */
  bool                              m_KeepsLemma2;
  VertexLinks                       m_Links;
  std::set<std::array<Vector3, 4>>  m_Tried;
  std::set<Vector3>                 m_MovedBelowSpacing;
  std::vector<CellHandle>           m_NewCells;
  mutable std::vector<CellHandle>   m_Star;
  mutable std::vector<VertexHandle> m_Touched;
  mutable std::vector<VertexHandle> m_Neighbors;
  /** The moving vertex's neighbours with their non-manifold pairs before the move, by handle. */
  std::vector<std::pair<VertexHandle, int>> m_NeighborsBefore;
};

} // namespace detail
} // namespace delaunay_refinement

#endif
