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
#ifndef DelaunayRefinementTopologyRelabel_h
#define DelaunayRefinementTopologyRelabel_h

// Relabelling at the places still non-manifold (docs/algorithm.md, "Topology", step 3). A label's boundary is a
// manifold at a vertex when the vertex's link in it (the edges opposite the vertex in its boundary facets) is empty
// or one cycle; that depends on the vertex's star only, so every check here is local. At a vertex where some
// boundary is not a manifold, a tetrahedron of the star, or a group of the star's tetrahedra on one side of the
// offending boundary (a cone to cut off, a gap to fill), may take the label of the other side, when that leaves
// fewer non-manifold (vertex, label) pairs at the corners of the changed tetrahedra (the only vertices whose star
// changes) and every facet it puts on a boundary has its three corners on the surface (feature vertices) and its
// angles above 30° and its circumradius below δ: the boundary stays made of surface samples and keeps the bounds
// of R1 and R3. With σ > 0 it gives a tissue no sliver, and leaves every sliver that R4′ left to the flat-cap step
// a cap on the background. Each move lowers the number of non-manifold pairs, so the process ends. The changed
// tetrahedra no longer carry the label at their circumcentre; they are marked, counted, exported, and given their
// label back before the refinement resumes.

#include "DelaunayRefinementFlatCaps.h"
#include "DelaunayRefinementGeometry.h"
#include "DelaunayRefinementMeshState.h"
#include "DelaunayRefinementNonManifoldPlaces.h"
#include "DelaunayRefinementSizing.h"
#include "DelaunayRefinementVertexLinks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{

class TopologyRelabel
{
public:
  TopologyRelabel(MeshState & state, const LocalSampling & sizing, double radiusEdgeBound, double minimumDihedralAngle)
    : m_State(state)
    , m_Sizing(sizing)
    , m_RadiusEdgeBound(radiusEdgeBound)
    , m_DihedralBound(minimumDihedralAngle)
  {}

  /** Relabels at the non-manifold places while a move removes some (the extracted mesh lists the tetrahedra that
   * took another label), starting from `found`, what the search for them found with the labels as they are now
   * (ManifoldRepair, in insertion order; its answers are every vertex's until a move changes the vertex's star,
   * so the link tests are not made again); only feature vertices are worked on. Returns how many tetrahedra it
   * relabelled (0: nothing changed). */
  std::size_t
  Relabel(const NonManifoldPlaces & found)
  {
    const std::size_t changesBefore = m_Changes.size();
    m_Stars.clear();
    m_NonManifoldLabels.clear();
    for (std::size_t index = 0; index < found.vertices.size(); ++index)
    {
      m_NonManifoldLabels[&*found.vertices[index]] = { true, found.LabelsOf(index) };
    }
    std::vector<VertexHandle> candidates;
    std::copy_if(found.vertices.begin(), found.vertices.end(), std::back_inserter(candidates), [](VertexHandle vertex) {
      return vertex->info().kind == VertexKind::Feature;
    });
    while (!candidates.empty())
    {
      std::vector<VertexHandle> touched;
      for (const VertexHandle vertex : candidates)
      {
        if (!CurrentNonManifoldLabelsAt(vertex).empty())
        {
          RelabelBestAround(vertex, touched);
        }
      }
      // Only the corners of changed tetrahedra have a new star: the next pass looks at those still offending.
      std::sort(touched.begin(), touched.end(), ById);
      touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
      candidates.clear();
      for (const VertexHandle vertex : touched)
      {
        if (vertex->info().kind == VertexKind::Feature && !CurrentNonManifoldLabelsAt(vertex).empty())
        {
          candidates.push_back(vertex);
        }
      }
    }
    UnmarkCellsBackToTheirLabel();
    m_Stars.clear();
    m_NonManifoldLabels.clear();
    return m_Changes.size() - changesBefore;
  }

  /** Applies again, in their order, the moves undone by Revert() whose tetrahedra and face neighbours are all as
   * they were when the move was made (same cells, same labels before it, same neighbours with the same labels
   * after it): their new boundary facets, shapes and isolation are then what was checked, without the link tests
   * that make the relabelling's cost. The refinement between a Revert() and a Replay() changes the mesh near the
   * regularised places only, so most moves come back and Relabel() works on what is left. Returns how many
   * tetrahedra it relabelled. A tetrahedron that ends with the label it had before the Revert() leaves its
   * corners' manifold test as it was (the refinement marks the corners of the tetrahedra it makes): after a
   * replay that brings most moves back, the next search looks at the regularised places only. */
  std::size_t
  Replay()
  {
    const std::size_t         changesBefore = m_Changes.size();
    std::vector<MoveMade>     made;
    std::vector<VertexHandle> touched; // unused: Relabel() starts from the places found after the replay
    std::swap(made, m_MovesMade);
    for (const MoveMade & move : made)
    {
      const bool cellsAsBefore = std::all_of(move.cells.begin(), move.cells.end(), [this](const CellState & state) {
        return m_State.IsCurrent(state.cell, state.stamp) && state.cell->cache.label == state.label;
      });
      if (cellsAsBefore && NeighborsAsAfter(move))
      {
        for (const CellState & state : move.cells)
        {
          m_LabelsBeforeRevert.try_emplace(&*state.cell, state);
        }
        Apply(move.cells, move.label, touched);
        m_MovesMade.push_back(move);
      }
    }
    UnmarkCellsBackToTheirLabel();
    MarkCellsWhoseLabelChangedSinceRevert();
    return m_Changes.size() - changesBefore;
  }

  /** Gives every relabelled tetrahedron that still exists its label back (the oracle's at its circumcentre); the
   * moves are remembered for Replay(), which also marks the corners of the tetrahedra whose label this changed for
   * good. */
  void
  Revert()
  {
    MarkCellsWhoseLabelChangedSinceRevert();
    for (const Change & change : m_Changes)
    {
      if (change.cell->cache.stamp == change.stamp && change.cell->cache.relabelledForTopology)
      {
        m_LabelsBeforeRevert.try_emplace(&*change.cell,
                                         CellState{ change.cell, change.stamp, change.cell->cache.label });
        change.cell->cache.label = change.originalLabel;
        change.cell->cache.relabelledForTopology = false;
      }
    }
    m_Changes.clear();
  }

private:
  struct Change
  {
    CellHandle cell;
    uint64_t   stamp;
    Label      originalLabel;
  };

  /** A cell as it was: its handle, its cache's stamp, and a label. */
  struct CellState
  {
    CellHandle cell;
    uint64_t   stamp;
    Label      label;
  };

  /** A move made: its cells with their labels before it, its label, and the face neighbours of its cells with
   * their labels just after it (the move's own cells included, with the move's label). */
  struct MoveMade
  {
    std::vector<CellState> cells;
    Label                  label;
    std::vector<CellState> neighbors;
  };

  /** Whether each face neighbour of the move's cells is the cell it was, with the label it had, just after the move
   * (the move's own cells counting with the move's label). */
  bool
  NeighborsAsAfter(const MoveMade & move) const
  {
    const Triangulation & triangulation = m_State.GetTriangulation();
    std::size_t           next = 0;
    for (const CellState & state : move.cells)
    {
      for (int facet = 0; facet < 4; ++facet, ++next)
      {
        const CellHandle  neighbor = state.cell->neighbor(facet);
        const CellState & then = move.neighbors[next];
        const bool        inMove = std::any_of(
          move.cells.begin(), move.cells.end(), [neighbor](const CellState & cell) { return cell.cell == neighbor; });
        if (neighbor != then.cell || (inMove ? move.label : LabelOf(neighbor)) != then.label ||
            (!triangulation.is_infinite(neighbor) && neighbor->cache.stamp != then.stamp))
        {
          return false;
        }
      }
    }
    return true;
  }

  /** The cells take `label`; each is marked and its original label kept for Revert(); their corners go to
   * `touched`. Their corners' manifold test is the caller's to mark due. */
  void
  Apply(const std::vector<CellState> & cells, Label label, std::vector<VertexHandle> & touched)
  {
    for (const CellState & state : cells)
    {
      const CellHandle cell = state.cell;
      if (!cell->cache.relabelledForTopology)
      {
        m_Changes.push_back({ cell, cell->cache.stamp, cell->cache.label });
        cell->cache.relabelledForTopology = true;
      }
      cell->cache.label = label;
      for (int corner = 0; corner < 4; ++corner)
      {
        touched.push_back(cell->vertex(corner));
        m_NonManifoldLabels[&*cell->vertex(corner)].known = false;
      }
    }
  }

  /** The tetrahedra that Revert() and Replay() changed, still as they were then, whose label now differs from
   * the one before the Revert(): their corners' stars changed. */
  void
  MarkCellsWhoseLabelChangedSinceRevert()
  {
    for (const auto & entry : m_LabelsBeforeRevert)
    {
      const CellState & before = entry.second;
      if (m_State.IsCurrent(before.cell, before.stamp) && before.cell->cache.label != before.label)
      {
        MarkManifoldCheckDue(before.cell);
      }
    }
    m_LabelsBeforeRevert.clear();
  }

  /** The cell's label changed: its corners' stars did. */
  static void
  MarkManifoldCheckDue(CellHandle cell)
  {
    for (int corner = 0; corner < 4; ++corner)
    {
      cell->vertex(corner)->info().manifoldCheckDue = true;
    }
  }

  /** A tetrahedron moved back to its own label by a later move is not relabelled. */
  void
  UnmarkCellsBackToTheirLabel()
  {
    for (const Change & change : m_Changes)
    {
      if (change.cell->cache.label == change.originalLabel)
      {
        change.cell->cache.relabelledForTopology = false;
      }
    }
  }

  static bool
  ById(VertexHandle a, VertexHandle b)
  {
    return a->info().id < b->info().id;
  }

  /** The labels whose boundaries are not a manifold at the vertex (VertexLinks), with the labels as they are (no
   * move being tried), in increasing order. They depend on the labels of the vertex's star only: a vertex that the
   * search did not list has none until a move relabels a cell of its star, and a vertex's labels, once tested, stay
   * until then (Apply() forgets the corners of the cells it relabels). */
  const std::vector<Label> &
  CurrentNonManifoldLabelsAt(VertexHandle vertex) const
  {
    static const std::vector<Label> none;
    const auto                      found = m_NonManifoldLabels.find(&*vertex);
    if (found == m_NonManifoldLabels.end())
    {
      return none;
    }
    KnownLabels & known = found->second;
    if (!known.known)
    {
      known.labels = m_Links.ListNonManifoldLabelsAt(m_State.GetTriangulation(), vertex, StarOf(vertex));
      known.known = true;
    }
    return known.labels;
  }

  /** The vertex's incident cells. A relabelling pass changes labels only, never the triangulation, and tries many
   * moves around each vertex, each asking for the stars of the same corners: they are collected once per pass. */
  const std::vector<CellHandle> &
  StarOf(VertexHandle vertex) const
  {
    const auto [entry, isNew] = m_Stars.try_emplace(&*vertex);
    if (isNew)
    {
      m_State.GetTriangulation().incident_cells(vertex, std::back_inserter(entry->second));
    }
    return entry->second;
  }

  Label
  LabelOf(CellHandle cell) const
  {
    return m_State.GetTriangulation().is_infinite(cell) ? BackgroundLabel : cell->cache.label;
  }

  /** A change: the cells all take `label`. */
  struct Move
  {
    std::vector<CellHandle> cells;
    Label                   label{ BackgroundLabel };
  };

  /** Whether every facet that the move puts on a boundary has its corners on the surface and its angles above
   * 30°; with the move applied. */
  bool
  NewBoundaryFacetsAreGood(const Move & move, const std::vector<Label> & oldLabels) const
  {
    for (std::size_t index = 0; index < move.cells.size(); ++index)
    {
      const CellHandle cell = move.cells[index];
      for (int facet = 0; facet < 4; ++facet)
      {
        const CellHandle neighbor = cell->neighbor(facet);
        const auto       inMove = std::find(move.cells.begin(), move.cells.end(), neighbor);
        const Label      beyondBefore = inMove == move.cells.end()
                                          ? LabelOf(neighbor)
                                          : oldLabels[static_cast<std::size_t>(inMove - move.cells.begin())];
        const bool       boundaryBefore = beyondBefore != oldLabels[index];
        const bool       boundaryAfter = LabelOf(neighbor) != cell->cache.label;
        if (boundaryBefore || !boundaryAfter)
        {
          continue;
        }
        std::array<Vector3, 3> corners;
        for (int corner = 0; corner < 3; ++corner)
        {
          const VertexHandle vertex = cell->vertex(Triangulation::vertex_triple_index(facet, corner));
          if (vertex->info().kind != VertexKind::Feature)
          {
            return false;
          }
          corners[corner] = m_State.PointOf(vertex);
        }
        if (!HasPlanarAnglesAbove30Degrees(corners[0], corners[1], corners[2]))
        {
          return false;
        }
        if (!m_Sizing.KeepsBoundaryFacetBound(corners[0], corners[1], corners[2]))
        {
          return false;
        }
      }
    }
    return true;
  }

  /** A move's corners with their non-manifold labels now, the labels it moves cells between, and the bound on its
   * gain that these give (GainOf can remove no pair of a label the move leaves alone). */
  struct MoveBound
  {
    struct Corner
    {
      VertexHandle               vertex;
      const std::vector<Label> * nonManifoldLabels;
    };
    /** The corners non-manifold now first: a move that does not mend them is rejected after the fewest link tests. */
    std::vector<Corner> corners;
    std::vector<Label>  changing;
    /** The non-manifold pairs at the corners, and those of the labels the move leaves alone. */
    int before{ 0 };
    int unchanging{ 0 };

    int
    Bound() const
    {
      return before - unchanging;
    }
  };

  MoveBound
  BoundOf(const Move & move) const
  {
    MoveBound                 bound;
    std::vector<VertexHandle> cornerHandles;
    for (const CellHandle cell : move.cells)
    {
      for (int corner = 0; corner < 4; ++corner)
      {
        cornerHandles.push_back(cell->vertex(corner));
      }
    }
    std::sort(cornerHandles.begin(), cornerHandles.end());
    cornerHandles.erase(std::unique(cornerHandles.begin(), cornerHandles.end()), cornerHandles.end());
    // Each corner's non-manifold labels, looked up once: the counts ask for them three times.
    bound.corners.reserve(cornerHandles.size());
    for (const VertexHandle vertex : cornerHandles)
    {
      bound.corners.push_back({ vertex, &CurrentNonManifoldLabelsAt(vertex) });
      bound.before += static_cast<int>(bound.corners.back().nonManifoldLabels->size());
    }
    std::stable_partition(bound.corners.begin(), bound.corners.end(), [](const MoveBound::Corner & corner) {
      return !corner.nonManifoldLabels->empty();
    });
    // Only the links of the labels the move takes cells from or gives them are tested again at its corners: the
    // others stay as they are (VertexLinks::NonManifoldLabelsAmong).
    bound.changing.push_back(move.label);
    for (const CellHandle cell : move.cells)
    {
      bound.changing.push_back(cell->cache.label);
    }
    std::sort(bound.changing.begin(), bound.changing.end());
    bound.changing.erase(std::unique(bound.changing.begin(), bound.changing.end()), bound.changing.end());
    // The non-manifold pairs of the labels the move leaves alone stay whatever it does: it gains at most the others,
    // and one that cannot gain what it needs is rejected before its checks and link tests (k-means tissues at 4 mm:
    // 13 % of the moves that passed the checks, 10 % of the link tests).
    for (const MoveBound::Corner & corner : bound.corners)
    {
      const std::vector<Label> & labels = *corner.nonManifoldLabels;
      bound.unchanging += static_cast<int>(std::count_if(labels.begin(), labels.end(), [&bound](Label label) {
        return !std::binary_search(bound.changing.begin(), bound.changing.end(), label);
      }));
    }
    return bound;
  }

  /** How many non-manifold (vertex, label) pairs the move removes (its corners and labels are `bound`'s); below 1
   * when it is not allowed, and below `needed` when it removes fewer than that (the count is then not finished: the
   * caller rejects the move either way, and the corners' link tests are most of the relabelling's time). The move
   * is undone before returning. */
  int
  GainOf(const Move & move, const MoveBound & bound, int needed) const
  {
    const int before = bound.before;
    const int unchanging = bound.unchanging;
    if (bound.Bound() < needed)
    {
      return bound.Bound();
    }
    // The cells whose face neighbours change: the move's and their neighbours.
    std::vector<CellHandle> near = move.cells;
    for (const CellHandle cell : move.cells)
    {
      for (int facet = 0; facet < 4; ++facet)
      {
        near.push_back(cell->neighbor(facet));
      }
    }
    std::sort(near.begin(), near.end());
    near.erase(std::unique(near.begin(), near.end()), near.end());
    const std::vector<bool>       isolatedBefore = Isolated(near);
    const std::vector<CellHandle> sliverCaps = SliverCapsOnBackground(near, move.cells);
    std::vector<Label>            oldLabels;
    for (const CellHandle cell : move.cells)
    {
      oldLabels.push_back(cell->cache.label);
      cell->cache.label = move.label;
    }
    int gain = 0;
    if ((move.label == BackgroundLabel || AreWellShaped(move.cells)) && IsolatesNone(near, isolatedBefore) &&
        AreStillCapsOnBackground(sliverCaps) && NewBoundaryFacetsAreGood(move, oldLabels))
    {
      const Triangulation & triangulation = m_State.GetTriangulation();
      int                   after = unchanging;
      for (std::size_t index = 0; index < bound.corners.size() && before - after >= needed; ++index)
      {
        const VertexHandle vertex = bound.corners[index].vertex;
        after += m_Links.NonManifoldLabelsAmong(triangulation, vertex, StarOf(vertex), bound.changing);
      }
      gain = before - after;
    }
    for (std::size_t index = 0; index < move.cells.size(); ++index)
    {
      move.cells[index]->cache.label = oldLabels[index];
    }
    return gain;
  }

  /** Whether every cell's radius-edge ratio is below ρ, no cell is flat to rounding and, when σ > 0, every dihedral
   * angle is at least σ: a background tetrahedron was never split for its shape, and one that takes a tissue's label
   * is an output tetrahedron, which must keep the bounds (R4's and R4′'s tests, the first on the cached
   * circumradius). A flat one has a small radius-edge ratio when its corners are nearly co-circular, so only the
   * flatness test keeps it out (found by a wider randomized search: SaltAndPepper 2001483 at σ = 0 had three). */
  bool
  AreWellShaped(const std::vector<CellHandle> & cells) const
  {
    return std::none_of(cells.begin(), cells.end(), [this](CellHandle cell) {
      const std::array<Vector3, 4> corners = m_State.CornersOf(cell);
      return ReachesRadiusEdgeBound(cell->cache.squaredRadius, corners, m_RadiusEdgeBound) ||
             IsFlatToRounding(corners) || m_DihedralBound.IsSliver(corners);
    });
  }

  /** With σ > 0, the cells among `near` (not among `moved`) that are slivers R4′ leaves to the flat-cap step, as caps
   * on the background (FlatCaps::IsCapOnBackground). A move must leave each a cap there: a neighbour relabelled
   * from the background would make it part of the boundary that nothing peels or splits any more, an output
   * tetrahedron below σ (found by the randomized suite once R4′ ran after the other rules). */
  std::vector<CellHandle>
  SliverCapsOnBackground(const std::vector<CellHandle> & near, const std::vector<CellHandle> & moved) const
  {
    std::vector<CellHandle> caps;
    if (!m_DihedralBound.IsOn())
    {
      return caps; // no sliver, so none left to the flat-cap step; this runs for every move tried
    }
    const Triangulation & triangulation = m_State.GetTriangulation();
    for (const CellHandle cell : near)
    {
      if (!triangulation.is_infinite(cell) && cell->cache.label != BackgroundLabel &&
          m_DihedralBound.IsSliver(m_State.CornersOf(cell)) &&
          std::find(moved.begin(), moved.end(), cell) == moved.end() &&
          FlatCaps::IsCapOnBackground(m_State, m_Sizing, cell))
      {
        caps.push_back(cell);
      }
    }
    return caps;
  }

  bool
  AreStillCapsOnBackground(const std::vector<CellHandle> & caps) const
  {
    return std::all_of(caps.begin(), caps.end(), [this](CellHandle cell) {
      return FlatCaps::IsCapOnBackground(m_State, m_Sizing, cell);
    });
  }

  /** Whether the cell carries a tissue's label that none of its face neighbours carries: a one-tetrahedron
   * component. */
  bool
  IsIsolated(CellHandle cell) const
  {
    const Label label = LabelOf(cell);
    if (label == BackgroundLabel)
    {
      return false;
    }
    for (int facet = 0; facet < 4; ++facet)
    {
      if (LabelOf(cell->neighbor(facet)) == label)
      {
        return false;
      }
    }
    return true;
  }

  /** IsIsolated() of each cell. */
  std::vector<bool>
  Isolated(const std::vector<CellHandle> & cells) const
  {
    std::vector<bool> isolated;
    isolated.reserve(cells.size());
    for (const CellHandle cell : cells)
    {
      isolated.push_back(IsIsolated(cell));
    }
    return isolated;
  }

  /** Whether every cell isolated now (IsIsolated) was isolated before the move: a move makes no one-tetrahedron
   * component, and leaves no relabelled tetrahedron alone with its new label. Comparing counts is not enough: a
   * move that joined one isolated cell to a neighbour while isolating another would pass (found by a wider
   * randomized search, SaltAndPepper 2002799: a relabelled tetrahedron with no neighbour of its label). */
  bool
  IsolatesNone(const std::vector<CellHandle> & cells, const std::vector<bool> & isolatedBefore) const
  {
    for (std::size_t index = 0; index < cells.size(); ++index)
    {
      if (!isolatedBefore[index] && IsIsolated(cells[index]))
      {
        return false;
      }
    }
    return true;
  }

  /** The moves tried at a vertex: each finite cell of the star taking a neighbour's label; and, for each label
   * whose boundary is not a manifold there, each group of the star's cells on one side of it (connected through
   * facets at the vertex) taking the other side's label: a cone cut off, or a gap filled. */
  std::vector<Move>
  MovesAround(VertexHandle vertex, const std::vector<CellHandle> & star) const
  {
    const Triangulation & triangulation = m_State.GetTriangulation();
    const StarAdjacency   adjacency = AdjacencyOf(vertex, star);
    std::vector<Move>     moves;
    std::vector<Label>    labelsHere{ UnionKey };
    for (std::size_t index = 0; index < star.size(); ++index)
    {
      const CellHandle cell = star[index];
      labelsHere.push_back(adjacency.labels[index]);
      if (triangulation.is_infinite(cell))
      {
        continue;
      }
      std::array<Label, 4> candidates{};
      for (int facet = 0; facet < 4; ++facet)
      {
        candidates[facet] = LabelOf(cell->neighbor(facet));
      }
      std::sort(candidates.begin(), candidates.end());
      const auto last = std::unique(candidates.begin(), candidates.end());
      for (auto candidate = candidates.begin(); candidate != last; ++candidate)
      {
        if (*candidate != cell->cache.label)
        {
          moves.push_back({ { cell }, *candidate });
        }
      }
    }
    std::sort(labelsHere.begin(), labelsHere.end());
    labelsHere.erase(std::unique(labelsHere.begin(), labelsHere.end()), labelsHere.end());
    std::vector<bool> inside(star.size());
    for (const Label key : labelsHere)
    {
      const auto isInside = [key](Label label) { return key == UnionKey ? label != BackgroundLabel : label == key; };
      for (std::size_t index = 0; index < star.size(); ++index)
      {
        inside[index] = isInside(adjacency.labels[index]);
      }
      for (const std::vector<std::size_t> & group : GroupsAround(adjacency, inside))
      {
        if (std::any_of(
              group.begin(), group.end(), [&](std::size_t index) { return triangulation.is_infinite(star[index]); }))
        {
          continue;
        }
        const bool groupInside = inside[group.front()];
        Label      label = key;
        if (groupInside || key == UnionKey)
        {
          // The most frequent label beyond the group on the other side; ties to the smallest label.
          std::vector<Label> beyond;
          for (const std::size_t index : group)
          {
            for (int facet = 0; facet < 4; ++facet)
            {
              const Label neighborLabel = LabelOf(star[index]->neighbor(facet));
              if (isInside(neighborLabel) != groupInside)
              {
                beyond.push_back(neighborLabel);
              }
            }
          }
          if (beyond.empty())
          {
            continue;
          }
          label = MostFrequent(beyond);
        }
        std::vector<CellHandle> cells;
        cells.reserve(group.size());
        for (const std::size_t index : group)
        {
          cells.push_back(star[index]);
        }
        moves.push_back({ std::move(cells), label });
      }
    }
    return moves;
  }

  /** The most frequent of the labels; ties to the smallest. */
  static Label
  MostFrequent(std::vector<Label> & labels)
  {
    std::sort(labels.begin(), labels.end());
    Label       best = labels.front();
    std::size_t bestCount = 0;
    for (auto first = labels.begin(); first != labels.end();)
    {
      const auto last = std::upper_bound(first, labels.end(), *first);
      if (static_cast<std::size_t>(last - first) > bestCount)
      {
        best = *first;
        bestCount = static_cast<std::size_t>(last - first);
      }
      first = last;
    }
    return best;
  }

  /** A vertex's star as indices: each cell's label, and the star indices of its neighbours through its three
   * facets at the vertex (NoNeighbor through the facet opposite the vertex). Built once per vertex, for the group
   * searches of every label (GroupsAround). */
  struct StarAdjacency
  {
    static constexpr std::size_t            NoNeighbor = std::numeric_limits<std::size_t>::max();
    std::vector<Label>                      labels;
    std::vector<std::array<std::size_t, 4>> neighbors;
  };

  StarAdjacency
  AdjacencyOf(VertexHandle vertex, const std::vector<CellHandle> & star) const
  {
    std::vector<std::pair<CellHandle, std::size_t>> byHandle;
    byHandle.reserve(star.size());
    for (std::size_t index = 0; index < star.size(); ++index)
    {
      byHandle.emplace_back(star[index], index);
    }
    std::sort(byHandle.begin(), byHandle.end());
    StarAdjacency adjacency;
    adjacency.labels.reserve(star.size());
    adjacency.neighbors.reserve(star.size());
    for (const CellHandle cell : star)
    {
      adjacency.labels.push_back(LabelOf(cell));
      std::array<std::size_t, 4> neighbors{};
      const int                  own = cell->index(vertex);
      for (int facet = 0; facet < 4; ++facet)
      {
        neighbors[facet] = StarAdjacency::NoNeighbor;
        if (facet != own)
        {
          // A neighbour through a facet at the vertex has the vertex too: it is in the star.
          const auto found = std::lower_bound(byHandle.begin(),
                                              byHandle.end(),
                                              std::make_pair(cell->neighbor(facet), std::size_t{ 0 }),
                                              [](const auto & a, const auto & b) { return a.first < b.first; });
          neighbors[facet] = found->second;
        }
      }
      adjacency.neighbors.push_back(neighbors);
    }
    return adjacency;
  }

  /** The star's cells (indices) on each side of `inside`, in groups connected through the facets at the vertex;
   * only when one side has more than one group (the vertex is a pinch of that side). */
  static std::vector<std::vector<std::size_t>>
  GroupsAround(const StarAdjacency & adjacency, const std::vector<bool> & inside)
  {
    const std::size_t                     size = inside.size();
    std::vector<int>                      groupOf(size, -1);
    std::vector<std::vector<std::size_t>> groups;
    int                                   insideGroups = 0;
    for (std::size_t seed = 0; seed < size; ++seed)
    {
      if (groupOf[seed] >= 0)
      {
        continue;
      }
      const bool side = inside[seed];
      insideGroups += side ? 1 : 0;
      groupOf[seed] = static_cast<int>(groups.size());
      groups.push_back({ seed });
      for (std::size_t next = 0; next < groups.back().size(); ++next)
      {
        for (const std::size_t neighbor : adjacency.neighbors[groups.back()[next]])
        {
          if (neighbor == StarAdjacency::NoNeighbor || inside[neighbor] != side || groupOf[neighbor] >= 0)
          {
            continue;
          }
          groupOf[neighbor] = groupOf[seed];
          groups.back().push_back(neighbor);
        }
      }
    }
    const int outsideGroups = static_cast<int>(groups.size()) - insideGroups;
    if (insideGroups <= 1 && outsideGroups <= 1)
    {
      return {};
    }
    return groups;
  }

  /** Applies the move at the vertex that removes the most non-manifold pairs (ties: the fewest tetrahedra, then
   * the first in a fixed order); the corners of its tetrahedra go to `touched`. False when no move removes any. */
  bool
  RelabelBestAround(VertexHandle vertex, std::vector<VertexHandle> & touched)
  {
    const Triangulation &   triangulation = m_State.GetTriangulation();
    std::vector<CellHandle> star;
    triangulation.incident_cells(vertex, std::back_inserter(star));
    // Handles are addresses: the order comes from the vertices' insertion ids, so that the result does not.
    std::sort(star.begin(), star.end(), [&triangulation](CellHandle a, CellHandle b) {
      const bool aInfinite = triangulation.is_infinite(a);
      const bool bInfinite = triangulation.is_infinite(b);
      if (aInfinite || bInfinite)
      {
        return !aInfinite && bInfinite;
      }
      return MeshState::SortedVertexIds(a) < MeshState::SortedVertexIds(b);
    });
    const std::vector<Move> moves = MovesAround(vertex, star);
    // The best move removes the most pairs, then has the fewest tetrahedra, then comes first. The moves are weighed
    // from the largest bound on their gain down, so that a good move found early lets the others stop at their bound
    // or early in their link tests (GainOf); the answer is the one a scan in their order would give.
    std::vector<MoveBound>   bounds;
    std::vector<std::size_t> order(moves.size());
    bounds.reserve(moves.size());
    for (std::size_t index = 0; index < moves.size(); ++index)
    {
      bounds.push_back(BoundOf(moves[index]));
      order[index] = index;
    }
    std::stable_sort(order.begin(), order.end(), [&bounds](std::size_t a, std::size_t b) {
      return bounds[a].Bound() > bounds[b].Bound();
    });
    int                        bestGain = 0;
    std::optional<std::size_t> bestIndex;
    for (const std::size_t index : order)
    {
      if (bounds[index].Bound() < std::max(bestGain, 1))
      {
        break; // neither this move nor one after it can even tie
      }
      // A tie on the gain goes to the fewest tetrahedra, then to the first in the scan's order.
      const bool winsTies = bestIndex && std::make_pair(moves[index].cells.size(), index) <
                                           std::make_pair(moves[*bestIndex].cells.size(), *bestIndex);
      const int needed = winsTies ? bestGain : bestGain + 1;
      const int gain = GainOf(moves[index], bounds[index], needed);
      if (gain >= needed)
      {
        bestGain = gain;
        bestIndex = index;
      }
    }
    if (!bestIndex)
    {
      return false;
    }
    const Move & best = moves[*bestIndex];
    MoveMade     made{ {}, best.label, {} };
    for (const CellHandle cell : best.cells)
    {
      made.cells.push_back({ cell, cell->cache.stamp, cell->cache.label });
    }
    Apply(made.cells, best.label, touched);
    for (const CellState & state : made.cells)
    {
      MarkManifoldCheckDue(state.cell);
    }
    for (const CellState & state : made.cells)
    {
      for (int facet = 0; facet < 4; ++facet)
      {
        const CellHandle neighbor = state.cell->neighbor(facet);
        made.neighbors.push_back({ neighbor, neighbor->cache.stamp, LabelOf(neighbor) });
      }
    }
    m_MovesMade.push_back(std::move(made));
    return true;
  }

  static constexpr Label UnionKey = VertexLinks::UnionKey;

  MeshState &              m_State;
  const LocalSampling &    m_Sizing;
  const double             m_RadiusEdgeBound;
  const DihedralAngleBound m_DihedralBound;
  std::vector<Change>      m_Changes;
  // The cells Revert() and Replay() relabelled since the last Revert(), with their labels before it.
  std::unordered_map<const void *, CellState> m_LabelsBeforeRevert;
  // The moves made since the relabelling began, in order, for Replay().
  std::vector<MoveMade> m_MovesMade;
  // The stars collected in the current pass (StarOf()), keyed by the vertex's address.
  mutable std::unordered_map<const void *, std::vector<CellHandle>> m_Stars;
  /** A vertex's non-manifold labels with the current labels, when `known`; to be tested again when not. */
  struct KnownLabels
  {
    bool               known{ false };
    std::vector<Label> labels;
  };
  // The vertices the search listed or a move changed the star of (CurrentNonManifoldLabelsAt()).
  mutable std::unordered_map<const void *, KnownLabels> m_NonManifoldLabels;
  VertexLinks                                           m_Links;
};

} // namespace detail
} // namespace delaunay_refinement

#endif
