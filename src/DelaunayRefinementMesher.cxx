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

// The driver of the refinement (docs/algorithm.md): it chains the levels the other files implement, as CGAL
// Mesh_3's Mesher_3::refine_mesh chains its levels. Where each part lives:
// - DelaunayRefinementTriangulation.h: the CGAL triangulation, vertex data and cell caches;
// - DelaunayRefinementMeshState.h: the mesh under refinement, insertion and deletion;
// - DelaunayRefinementQueue.h: the two-level work list;
// - DelaunayRefinementSizing.h: the local δ;
// - DelaunayRefinementRules.h: R1-R4 and R4';
// - DelaunayRefinementSliverSplit.h: where R4' splits a sliver;
// - DelaunayRefinementSliverPerturbation.h: R4' moving a vertex, for slivers and flat tetrahedra;
// - DelaunayRefinementVertexLinks.h: the local manifold test;
// - DelaunayRefinementBoxProtection.h: the bounding box and E1-E3;
// - DelaunayRefinementManifoldRepair.h: local refinement where a tissue's boundary is not a manifold;
// - DelaunayRefinementTopologyRelabel.h: tetrahedra relabelled where a boundary is not a manifold;
// - DelaunayRefinementFlatCaps.h: tetrahedra flat to rounding on a boundary;
// - DelaunayRefinementFlatTetrahedronRemoval.h: those inside a tissue that no move removes, by an edge removal;
// - DelaunayRefinementExtraction.h: the output mesh.
// This is the only translation unit that includes CGAL's triangulation: one slow compile.

#include "DelaunayRefinementMesher.h"
#include "DelaunayRefinementBoxProtection.h"
#include "DelaunayRefinementExtraction.h"
#include "DelaunayRefinementFlatCaps.h"
#include "DelaunayRefinementFlatTetrahedronRemoval.h"
#include "DelaunayRefinementTopologyRelabel.h"
#include "DelaunayRefinementManifoldRepair.h"
#include "DelaunayRefinementMeshState.h"
#include "DelaunayRefinementQueue.h"
#include "DelaunayRefinementRules.h"
#include "DelaunayRefinementSizing.h"
#include "DelaunayRefinementSliverPerturbation.h"
#include "DelaunayRefinementSliverSplit.h"
#include "DelaunayRefinementTestHooks.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{
namespace
{

/** Runs the rules until none applies, then the manifold repair, then extracts the mesh. */
class Refiner
{
public:
  Refiner(const LabelOracle & oracle, const RefinementParameters & parameters, const ProgressObserver & observer,
          TopologyRegularizer * regularizer, const LabelPartCensus * census, const RefinementTestHooks & hooks)
    : m_Oracle(oracle)
    , m_Parameters(parameters)
    , m_Observer(observer)
    , m_Regularizer(regularizer)
    , m_Census(census)
    , m_State(oracle, parameters)
    , m_Sizing(parameters.surfaceSamplingDistance)
    , m_BoxProtection(m_State, parameters.surfaceSamplingDistance, m_Statistics)
    , m_Rules(oracle, parameters, m_State, m_Sizing, m_BoxProtection.Box(), hooks)
    , m_SliverSplit(oracle, m_State, m_BoxProtection, m_Rules, parameters.radiusEdgeBound,
                    parameters.minimumDihedralAngle)
    , m_Extraction(m_State)
    , m_Repair(m_State, m_Extraction, m_Sizing, parameters)
  {
    m_State.SetNewCellsHook([this](const std::vector<CellHandle> & cells) {
      for (CellHandle cell : cells)
      {
        if (!m_State.GetTriangulation().is_infinite(cell))
        {
          Enqueue(cell);
        }
      }
    });
  }

  TetrahedralMesh
  Run(RefinementStatistics & statistics)
  {
    const AxisAlignedBox objectBounds = m_Oracle.ObjectBounds();
    if (objectBounds.IsEmpty())
    {
      return {};
    }
    const auto refinementStart = std::chrono::steady_clock::now();
    m_BoxProtection.CreateBox(objectBounds);
    SampleThinPartsFinely();
    RefineAndPerturbFlatTetrahedra();
    RepairTopology();
    PeelFlatCaps();
    m_Queue.ReleaseEmptyLevels();
    const auto      extractionStart = std::chrono::steady_clock::now();
    TetrahedralMesh mesh = WithEveryThickPart(ExtractWithoutFlatTetrahedra());
    m_Statistics.topologyRelabelledTetrahedra = mesh.topologyRelabelledTetrahedra.size();
    const auto end = std::chrono::steady_clock::now();

    m_Statistics.deletedVertices = m_State.NumberOfDeletedVertices();
    m_Statistics.triangulationVertices = m_State.GetTriangulation().number_of_vertices();
    m_Statistics.refinementSeconds = std::chrono::duration<double>(extractionStart - refinementStart).count();
    m_Statistics.extractionSeconds = std::chrono::duration<double>(end - extractionStart).count();
    statistics = m_Statistics;
    return mesh;
  }

private:
  void
  Enqueue(CellHandle cell)
  {
    const std::optional<QueueLevel> level = m_Rules.Classify(cell);
    if (level)
    {
      m_Queue.Push(*level, { cell->cache.squaredRadius, cell, cell->cache.stamp, MeshState::SortedVertexIds(cell) });
    }
  }

  /** A vertex at `point` beside a zone's short edges honours only `spacing`, less than the δ there: the exported
   * sizing says so (LocalSampling::NoteFinerSample). Not below every zone's δ: shorter edges come from R4′'s points
   * only (σ > 0), which give Lemma 2's spacing up and are not exported. */
  void
  NoteSpacingBesideAZone(const Vector3 & point, double spacing)
  {
    if (spacing >= m_Sizing.FinestDelta())
    {
      m_Sizing.NoteFinerSample(point, spacing);
    }
  }

  /** What each rule's action does to the mesh: R1 and R3 insert a feature vertex and delete the free vertices
   * near it; R2 inserts its circumcentre, or applies a box rule when that lies on or outside the box; R4 inserts
   * its circumcentre, R4' the best point near it (SliverSplit). Returns whether a vertex was inserted. */
  bool
  Perform(const Action & action, CellHandle cell)
  {
    switch (action.rule)
    {
      case Rule::R1:
        ++m_Statistics.insertionsR1;
        return m_State.InsertFeatureVertex(action.point, action.localDelta, cell);
      case Rule::R2:
        if (!m_BoxProtection.IsStrictlyInsideBox(action.point))
        {
          return m_BoxProtection.ProtectBox(action.point, cell);
        }
        ++m_Statistics.insertionsR2;
        if (!m_State.InsertVertex(action.point, VertexKind::Free, cell))
        {
          return false;
        }
        m_Sizing.NoteFinerSample(action.point, action.localDelta);
        return true;
      case Rule::R3:
        ++m_Statistics.insertionsR3;
        if (!m_State.InsertFeatureVertex(action.point, action.localDelta, cell))
        {
          return false;
        }
        // Beside a zone, a facet's shortest edge can be R3's threshold, and the ball it splits smaller than the δ
        // at its centre: the new vertex honours the ball's radius.
        NoteSpacingBesideAZone(action.point, action.ballRadius);
        return true;
      case Rule::R4: {
        ++m_Statistics.insertionsR4;
        // R4's point is its circumradius from every vertex, and that is ρ × the tetrahedron's shortest edge or more:
        // beside a zone's short edges, with ρ < 2, it can be below the δ there (Lemma 2's ρδ), even once the zone's
        // own points are gone (the randomized SheetsAndLines 3330698, ρ = 1: an R4 point 0.98 δ from a feature
        // vertex, every output point at δ).
        const double honoured = std::sqrt(cell->cache.squaredRadius) / std::min(m_Parameters.radiusEdgeBound, 2.0);
        if (!m_State.InsertVertex(action.point, VertexKind::Free, cell))
        {
          return false;
        }
        NoteSpacingBesideAZone(action.point, honoured);
        return true;
      }
      case Rule::R4Dihedral:
        return SplitSliver(cell, action.point);
    }
    return false;
  }

  /** R4': the point SliverSplit chooses, free or on the surface. A sliver for which no point passes its acceptance
   * test is left for FlatCaps to peel off when it is a cap on the background, unless that step could not peel it
   * before (PeelFlatCaps); otherwise one of its corners is moved
   * (SliverPerturbation); when no move passes either, it is split at the least bad point. An accepted point that R3
   * would split again (a boundary triangle at its new tetrahedra gets a surface ball reaching δ) also tries the
   * moves first, since a move is kept only when no rule but R4′ applies to its tetrahedra: the split and R3's
   * insertion after it, with the deletions around that, made many of σ = 15°'s tetrahedra (docs/algorithm.md,
   * "R4′ moves a vertex"). A tetrahedron that is
   * only flat to rounding (its angles reach σ, or σ = 0) is never split, since a split point would come closer
   * than δ to its corners (Lemma 2): a corner is moved, or it is left. */
  bool
  SplitSliver(CellHandle cell, const Vector3 & center)
  {
    if (!m_DihedralBound.IsSliver(m_State.CornersOf(cell)))
    {
      return Perturb(cell) == SliverPerturbation::Outcome::Moved;
    }
    const SliverSplit::Split split = m_SliverSplit.Choose(cell, center, cell->cache.squaredRadius);
    if (!split.accepted && FlatCaps::IsCapOnBackground(m_State, m_Sizing, cell) &&
        m_SliversThatCannotBePeeled.count(m_State.SortedCornersOf(cell)) == 0)
    {
      ++m_Statistics.sliverCapsLeftToPeel;
      m_SliversLeftToPeel.push_back(
        { cell->cache.squaredRadius, cell, cell->cache.stamp, MeshState::SortedVertexIds(cell) });
      return false;
    }
    // The cell to locate the split point from: the sliver's, or none after moves that were undone, which gave the
    // sliver a new cell. Undoing restores the triangulation exactly (MeshState::MoveVertex), so the split chosen
    // before is still the one Choose would choose, and it is made now instead of choosing it again.
    CellHandle hint = cell;
    if (!split.accepted || split.splitByR3)
    {
      switch (Perturb(cell))
      {
        case SliverPerturbation::Outcome::Moved:
          return true;
        case SliverPerturbation::Outcome::Undone:
          hint = CellHandle();
          break;
        case SliverPerturbation::Outcome::NotTried:
          break;
      }
    }
    ++m_Statistics.insertionsR4Dihedral;
    m_Statistics.sliverSplitsOnSurface += split.kind == VertexKind::Feature;
    m_Statistics.sliverSplitsChangingBoundary += split.changesBoundary;
    m_Statistics.sliverSplitsFailingAcceptance += !split.accepted;
    return m_State.InsertVertex(split.point, split.kind, hint).has_value();
  }

  SliverPerturbation::Outcome
  Perturb(CellHandle cell, SliverPerturbation::Acceptance lastResort = SliverPerturbation::Acceptance::EveryRule)
  {
    const SliverPerturbation::Outcome outcome = m_SliverPerturbation.Perturb(cell, lastResort);
    m_Statistics.sliverPerturbations += outcome == SliverPerturbation::Outcome::Moved;
    return outcome;
  }

  bool
  IsAlive(const QueueEntry & entry) const
  {
    return m_State.IsCurrent(entry.cell, entry.stamp);
  }

  void
  RefineUntilNoRuleApplies()
  {
    std::size_t processed = 0;
    // Slivers wait until no other rule applies anywhere (below), so every vertex this pass makes once the first
    // one is popped is the sliver removal's doing: RequireSliverRemovalWithinBudget.
    std::optional<std::size_t> verticesBeforeSliverRemoval;
    while (!m_Queue.Empty() || RequeueSliversNoLongerCaps())
    {
      m_Statistics.staleQueueEntries +=
        m_Queue.RemoveDeadWhenDue([this](const QueueEntry & entry) { return IsAlive(entry); });
      if (m_Queue.Empty())
      {
        continue;
      }
      QueueLevel       level = QueueLevel::Surface;
      const QueueEntry entry = m_Queue.Pop(level);
      if (level == QueueLevel::Sliver && !verticesBeforeSliverRemoval)
      {
        verticesBeforeSliverRemoval = m_State.GetTriangulation().number_of_vertices();
      }
      if (!IsAlive(entry))
      {
        ++m_Statistics.staleQueueEntries;
        continue;
      }
      if (++processed % ProgressInterval == 0)
      {
        ReportProgress(processed);
      }
      const std::optional<Action> action = m_Rules.FindApplicableRule(entry.cell);
      if (!action)
      {
        continue;
      }
      // A sliver on a boundary waits, like the interior ones, until no other rule applies anywhere: split while
      // the surface was still being sampled, its free vertex was mostly deleted again by a feature insertion nearby
      // (measured with σ = 15°: the atlas phantom at 4 mm made 1,358 R4′ splits and deleted 830 vertices, 588 and
      // 138 when they wait).
      if (action->rule == Rule::R4Dihedral && level != QueueLevel::Sliver)
      {
        m_Queue.Push(QueueLevel::Sliver, entry);
        continue;
      }
      const bool inserted = PerformCountingTheSliverRemoval(*action, entry.cell, verticesBeforeSliverRemoval);
      if (verticesBeforeSliverRemoval)
      {
        RequireSliverRemovalWithinBudget(*verticesBeforeSliverRemoval);
      }
      // A tetrahedron that survives its own refinement (the new point fell on its circumsphere) is looked at
      // again; one whose point could not be inserted is given up, or it would be retried forever.
      if (inserted && IsAlive(entry))
      {
        Enqueue(entry.cell);
      }
    }
    ReportProgress(processed);
  }

  /** Perform(), where a vertex cap reached once this pass has taken its first sliver (`verticesBeforeSliverRemoval`)
   * says so: every vertex made since is the sliver removal's doing, so the user should lower σ or raise ρ rather
   * than raise the cap. The budget (RequireSliverRemovalWithinBudget) is relative, and a pass that starts large can
   * reach a cap below it: the randomized Mixed 8067665 (ρ = 1, σ = 16.6°) took its first sliver at 18,244 vertices
   * and ran to the suite's cap of 100,000 in 27 s, under its budget of 183,440. */
  bool
  PerformCountingTheSliverRemoval(const Action & action, CellHandle cell,
                                  const std::optional<std::size_t> & verticesBeforeSliverRemoval)
  {
    try
    {
      return Perform(action, cell);
    }
    catch (const VertexLimitExceeded & error)
    {
      if (!verticesBeforeSliverRemoval)
      {
        throw;
      }
      throw VertexLimitExceeded(std::string(error.what()) + "; the limit was reached by the sliver removal (" +
                                SliverRemovalGrowth(*verticesBeforeSliverRemoval) + ")");
    }
  }

  /** How the sliver removal grew this pass, from `verticesBefore`, for the exceptions that stop it. */
  std::string
  SliverRemovalGrowth(std::size_t verticesBefore) const
  {
    return "it took the mesh from " + std::to_string(verticesBefore) +
           " vertices, where every other rule was met, to " +
           std::to_string(m_State.GetTriangulation().number_of_vertices());
  }

  /** Throws SliverRemovalWithoutEnd when the sliver removal has made this pass of the refinement grow from
   * `verticesBefore` vertices beyond SliverRemovalGrowthBudget (docs/algorithm.md, "When sliver removal does not
   * end"). */
  void
  RequireSliverRemovalWithinBudget(std::size_t verticesBefore) const
  {
    const std::size_t vertices = m_State.GetTriangulation().number_of_vertices();
    if (vertices <= SliverRemovalGrowthBudget * verticesBefore + SliverRemovalVertexAllowance)
    {
      return;
    }
    throw SliverRemovalWithoutEnd(
      "Sliver removal did not end: with minimumDihedralAngle sigma = " +
      DescribeValue(m_Parameters.minimumDihedralAngle) +
      " degrees and radiusEdgeBound rho = " + DescribeValue(m_Parameters.radiusEdgeBound) + ", " +
      SliverRemovalGrowth(verticesBefore) + ", more than " + std::to_string(SliverRemovalGrowthBudget) +
      " times as many plus " + std::to_string(SliverRemovalVertexAllowance) +
      "; where it ends it needs far less (at most 4 times measured, with rho = 1). Nothing proves that it ends, and "
      "below rho = 2 R4 and R4' can keep making work for each other: a smaller sigma or a larger rho may let it end");
  }

  /** Queues again the slivers that R4′ left to the flat-cap step as caps on the background (SplitSliver) and that
   * are caps there no more: the refinement around them replaced a neighbour on the background by cells of a
   * tissue, without changing the sliver itself, so nothing looked at it again (found on the k-means tissues on the
   * 1 mm grid at 2 mm, σ = 15°: one tetrahedron of 4.6° left). Called with the queue empty; returns whether it is
   * not empty any more. */
  bool
  RequeueSliversNoLongerCaps()
  {
    std::vector<QueueEntry> stillCaps;
    for (const QueueEntry & entry : m_SliversLeftToPeel)
    {
      if (!IsAlive(entry))
      {
        continue;
      }
      if (FlatCaps::IsCapOnBackground(m_State, m_Sizing, entry.cell))
      {
        stillCaps.push_back(entry);
        continue;
      }
      Enqueue(entry.cell);
    }
    m_SliversLeftToPeel = std::move(stillCaps);
    return !m_Queue.Empty();
  }

  /** The flat-cap step (FlatCaps), and what it cannot do: a sliver that R4′ left to it as a cap on the background
   * stays in its tissue, below σ, when peeling it off makes a boundary non-manifold (found in the randomized
   * suite, Mixed 8005805: 0.0087° with σ = 5.2°). Such slivers are split after all, like any other, with the
   * flat caps' and the topology's relabelling undone first (the rules read labels as the oracle's); the
   * topology repair and the flat-cap step then run again. The rounds are bounded: the refinement around a split
   * may leave new caps that cannot be peeled. */
  void
  PeelFlatCaps()
  {
    const FlatCaps          flatCaps(m_State, m_Sizing, m_Parameters.minimumDihedralAngle);
    FlatCaps::Relabelling & peeled = m_PeeledCaps;
    peeled = flatCaps.Relabel();
    for (int round = 0; !peeled.sliversKept.empty() && round < SliversThatCannotBePeeledRounds; ++round)
    {
      peeled.Undo();
      m_Relabelling.Revert();
      std::sort(peeled.sliversKept.begin(), peeled.sliversKept.end(), [](CellHandle a, CellHandle b) {
        return MeshState::SortedVertexIds(a) < MeshState::SortedVertexIds(b);
      });
      for (const CellHandle cell : peeled.sliversKept)
      {
        m_SliversThatCannotBePeeled.insert(m_State.SortedCornersOf(cell));
        Enqueue(cell);
      }
      m_Statistics.sliverCapsThatCouldNotBePeeled += peeled.sliversKept.size();
      RefineAndPerturbFlatTetrahedra();
      RepairTopology();
      peeled = flatCaps.Relabel();
    }
    m_Statistics.flatCapsRelabelled = peeled.relabelled.size();
  }

  /** The mesh, with its tetrahedra flat to rounding taken out by an edge removal (FlatTetrahedronRemoval). Those
   * it cannot take out get a move of a corner that keeps only part of Lemma 2's spacing (SliverPerturbation, the
   * level SpacingMayBreak), and the refinement, the repairs and the extraction run again, once: the spacing is
   * short only where nothing else removed a flat tetrahedron, and the mesh lists those points. */
  TetrahedralMesh
  ExtractWithoutFlatTetrahedra()
  {
    TetrahedralMesh                        mesh = ExtractAndRemoveFlatTetrahedra();
    const std::set<std::array<Vector3, 4>> left = FlatTissueTetrahedraOf(mesh);
    if (left.empty())
    {
      return mesh;
    }
    // The rules read labels as the oracle's.
    m_PeeledCaps.Undo();
    m_Relabelling.Revert();
    m_SliverPerturbation.ForgetTried();
    for (const FlatCellVertices & corners :
         FindFlatTetrahedra([&](CellHandle cell) { return left.count(m_State.SortedCornersOf(cell)) > 0; }))
    {
      CellHandle cell;
      if (IsStillThere(corners, cell))
      {
        m_Statistics.flatTetrahedraMovedBelowSpacing +=
          Perturb(cell, SliverPerturbation::Acceptance::SpacingMayBreak) == SliverPerturbation::Outcome::Moved;
      }
    }
    RefineAndPerturbFlatTetrahedra();
    RepairTopology();
    PeelFlatCaps();
    mesh = ExtractAndRemoveFlatTetrahedra();
    const std::set<Vector3> & moved = m_SliverPerturbation.MovedBelowSpacing();
    for (uint32_t point = 0; point < mesh.points.size(); ++point)
    {
      if (moved.count(mesh.points[point]) > 0)
      {
        mesh.pointsMovedBelowSpacing.push_back(point);
      }
    }
    return mesh;
  }

  /** Whether a part of the labels holds a ball of diameter δ, up to PartTieMargin. */
  bool
  IsThick(const UnmeshedPart & part) const
  {
    return part.radius >= ThickPartRadius * m_Parameters.surfaceSamplingDistance * (1.0 - PartTieMargin);
  }

  /** Zones of finer sampling around the small parts of the labels (at most SmallPartVolume δ³) that hold a ball of
   * diameter δ but not one of radius WellSampledPartRadius δ (LabelPartCensus): a part that small and thin gets a few
   * surface samples, and the tetrahedra between them may all have their circumcentres outside it (the randomized
   * suite's meshes lost such parts with balls of radius 0.50-0.70 δ, none thicker). A part whose ball has radius r is
   * sampled at r within 2r of the ball's centre, where the part's surface near the ball is (at r /
   * WellSampledPartRadius, the edge of what is meshed surely, whether the zone sufficed followed δ's last bits again,
   * on the case below; within 3r, 2.9 % more tetrahedra on the atlas phantom at 1 mm, 4.4 % on the k-means tissues on
   * the 1 mm grid at 3 mm). Decided from the voxels before the refinement, so that a last-bit change of δ does not
   * decide it: when only the parts found without a tetrahedron were sampled (WithEveryThickPart), a part the
   * refinement happened to mesh at one δ was lost at the next (the randomized SheetsAndLines 3000031: 443 or 502
   * points at δ and δ (1 + 1e-12)). */
  void
  SampleThinPartsFinely()
  {
    if (!m_Census || !m_Parameters.refineThickParts)
    {
      return;
    }
    const double delta = m_Parameters.surfaceSamplingDistance;
    std::size_t  zones = 0;
    for (const UnmeshedPart & part : m_Census->PartsHoldingNone(
           NoLabelledPoints, WellSampledPartRadius * delta, SmallPartVolume * delta * delta * delta))
    {
      if (IsThick(part) && part.radius < WellSampledPartRadius * delta * (1.0 - PartTieMargin))
      {
        m_Sizing.AddZone(part.center, part.radius, 2.0 * part.radius);
        ++m_ThickPartTries[{ part.label, part.center }];
        ++zones;
      }
    }
    if (zones > 0)
    {
      ++m_Statistics.thickPartRounds;
      m_Statistics.thickPartsRefined += zones;
    }
  }

  /** `mesh`, or, when a part of the labels that holds a ball of diameter δ has no tetrahedron in it all the same
   * (LabelPartCensus; SampleThinPartsFinely), the mesh made again with that part sampled around its largest ball at
   * the ball's radius, halved in each round after the first (SampleThinPartsFinely's included) up to the
   * ThickPartRounds-th; each part at most ThickPartRounds times, at most LargestThickPartRounds rounds in all. The
   * parts still without a tetrahedron, thick or not, go to the statistics: nothing is lost silently. */
  TetrahedralMesh
  WithEveryThickPart(TetrahedralMesh mesh)
  {
    if (!m_Census)
    {
      return mesh;
    }
    const double delta = m_Parameters.surfaceSamplingDistance;
    while (true)
    {
      const auto                round = static_cast<unsigned int>(m_Statistics.thickPartRounds);
      std::vector<UnmeshedPart> parts = m_Census->PartsHoldingNone(PointsOfTetrahedra(mesh), delta);
      std::vector<Ball>         zones;
      for (const UnmeshedPart & part : parts)
      {
        unsigned int & tries = m_ThickPartTries[{ part.label, part.center }];
        if (m_Parameters.refineThickParts && tries < ThickPartRounds && round < LargestThickPartRounds && IsThick(part))
        {
          // The part's surface near the ball is within its radius of the centre, and the facets there have
          // circumradii below the local δ: a zone of the radius plus twice that holds them.
          const int    halvings = static_cast<int>(std::min(round, ThickPartRounds - 1));
          const double localDelta = std::ldexp(std::min(delta, part.radius), -halvings);
          zones.push_back(
            { part.center,
              m_Sizing.AddZone(part.center, localDelta, part.radius + 2.0 * localDelta, ZoneReach::Circumballs) });
          ++tries;
        }
      }
      if (zones.empty())
      {
        m_Statistics.unmeshedParts = std::move(parts);
        return mesh;
      }
      ++m_Statistics.thickPartRounds;
      m_Statistics.thickPartsRefined += zones.size();
      // The rules read labels as the oracle's.
      m_PeeledCaps.Undo();
      m_Relabelling.Revert();
      for (const CellHandle cell : m_Repair.WithNeighbors(m_Repair.CellsMeeting(zones)))
      {
        Enqueue(cell);
      }
      RefineAndPerturbFlatTetrahedra();
      RepairTopology();
      PeelFlatCaps();
      mesh = ExtractWithoutFlatTetrahedra();
    }
  }

  /** The circumcentre and the centroid of every tetrahedron, with its label: where the census looks for them. */
  static LabelledPoints
  PointsOfTetrahedra(const TetrahedralMesh & mesh)
  {
    return [&mesh](const std::function<void(const LabelledPoint &)> & visit) {
      for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
      {
        std::array<Vector3, 4> corners{};
        for (int corner = 0; corner < 4; ++corner)
        {
          corners[corner] = mesh.points[mesh.tetrahedra[t][corner]];
        }
        visit({ TetrahedronCircumcenter(corners), mesh.tetrahedronLabels[t] });
        visit({ 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]), mesh.tetrahedronLabels[t] });
      }
    };
  }

  /** No point: the census before there is a mesh (SampleThinPartsFinely). */
  static void
  NoLabelledPoints(const std::function<void(const LabelledPoint &)> &)
  {}

  TetrahedralMesh
  ExtractAndRemoveFlatTetrahedra()
  {
    TetrahedralMesh mesh = m_Extraction.ExtractMesh(m_Sizing);
    m_Statistics.flatTetrahedraRemovedByEdgeRemoval =
      FlatTetrahedronRemoval(m_Oracle, m_Parameters.radiusEdgeBound).Remove(mesh);
    return mesh;
  }

  /** The tissue tetrahedra of the extracted mesh flat to rounding (FlatTetrahedronRemoval::FlatTissueTetrahedra), by
   * their corners in lexicographic order, which name them in the triangulation too. */
  static std::set<std::array<Vector3, 4>>
  FlatTissueTetrahedraOf(const TetrahedralMesh & mesh)
  {
    std::set<std::array<Vector3, 4>> flat;
    for (const uint32_t t : FlatTetrahedronRemoval::FlatTissueTetrahedra(mesh))
    {
      std::array<Vector3, 4> corners = FlatTetrahedronRemoval::CornersOf(mesh, t);
      std::sort(corners.begin(), corners.end());
      flat.insert(corners);
    }
    return flat;
  }

  struct FlatCellVertices
  {
    std::array<VertexHandle, 4> vertices;
    std::array<VertexId, 4>     sortedIds;
  };

  /** The refinement, then more chances for the tetrahedra flat to rounding whose moves all failed while it ran:
   * the acceptance test asks that no rule applies to the new tetrahedra, and during the refinement one often
   * still applied near them, before their neighbourhood was refined (SliverPerturbation). Now that no rule applies
   * elsewhere, a move may also create tetrahedra that the refinement, resumed, splits; its new tetrahedra may be
   * flat again, hence the rounds. */
  void
  RefineAndPerturbFlatTetrahedra()
  {
    RefineUntilNoRuleApplies();
    for (int round = 0; round < FlatTetrahedraRounds; ++round)
    {
      std::vector<FlatCellVertices> flat = FindFlatTissueTetrahedra();
      m_SliverPerturbation.ForgetTried();
      bool moved = false;
      for (const FlatCellVertices & corners : flat)
      {
        CellHandle cell;
        if (IsStillThere(corners, cell))
        {
          moved =
            Perturb(cell, SliverPerturbation::Acceptance::NonManifoldMayFollow) == SliverPerturbation::Outcome::Moved ||
            moved;
        }
      }
      if (!moved)
      {
        return;
      }
      RefineUntilNoRuleApplies();
    }
  }

  /** The tissue tetrahedra flat to rounding, in a fixed order. */
  std::vector<FlatCellVertices>
  FindFlatTissueTetrahedra() const
  {
    return FindFlatTetrahedra([](CellHandle cell) { return cell->cache.label != BackgroundLabel; });
  }

  /** The tetrahedra flat to rounding that `select` keeps, in a fixed order: the cells' container order can follow
   * memory addresses after vertex removals. */
  template <typename TSelect>
  std::vector<FlatCellVertices>
  FindFlatTetrahedra(TSelect && select) const
  {
    const Triangulation &         triangulation = m_State.GetTriangulation();
    std::vector<FlatCellVertices> flat;
    for (auto cell = triangulation.finite_cells_begin(); cell != triangulation.finite_cells_end(); ++cell)
    {
      if (IsFlatToRounding(m_State.CornersOf(cell)) && select(cell))
      {
        flat.push_back(
          { { cell->vertex(0), cell->vertex(1), cell->vertex(2), cell->vertex(3) }, MeshState::SortedVertexIds(cell) });
      }
    }
    std::sort(flat.begin(), flat.end(), [](const FlatCellVertices & a, const FlatCellVertices & b) {
      return a.sortedIds < b.sortedIds;
    });
    return flat;
  }

  /** Whether the four vertices are still vertices and still make a cell (`cell`): a move removes a vertex, and
   * CGAL may reuse its memory for another, which the ids tell apart. */
  bool
  IsStillThere(const FlatCellVertices & corners, CellHandle & cell) const
  {
    const Triangulation & triangulation = m_State.GetTriangulation();
    for (const VertexHandle vertex : corners.vertices)
    {
      if (!triangulation.tds().vertices().is_used(vertex))
      {
        return false;
      }
    }
    const auto & v = corners.vertices;
    return triangulation.is_cell(v[0], v[1], v[2], v[3], cell) && MeshState::SortedVertexIds(cell) == corners.sortedIds;
  }

  void
  ReportProgress(std::size_t processed)
  {
    if (!m_Observer)
    {
      return;
    }
    RefinementProgress progress;
    progress.vertices = m_State.GetTriangulation().number_of_vertices();
    progress.pendingTetrahedra = m_Queue.Size();
    progress.processedTetrahedra = processed;
    const double estimate = static_cast<double>(processed) / static_cast<double>(processed + m_Queue.Size() + 1);
    m_ProgressFraction = std::max(m_ProgressFraction, std::min(estimate, 0.999));
    progress.fraction = m_ProgressFraction;
    if (!m_Observer(progress))
    {
      throw RefinementAborted("Delaunay refinement aborted by the progress observer");
    }
  }

  /** Alternates the manifold check and a repair until every boundary is a manifold or no repair is left: first
   * the relabelling of tetrahedra at the places (TopologyRelabel, when relabelNonManifoldPlaces), then, for the
   * places it could not mend, the regularisation of the oracle's labels around them (when the oracle allows it, at
   * most topologyRegularizationRounds rounds), then, as an opt-in, the local halving of δ (ManifoldRepair). The
   * relabelled tetrahedra get their labels back before the refinement resumes: its rules read labels as the
   * oracle's. */
  void
  RepairTopology()
  {
    NonManifoldPlaces places = RelabelAndFindNonManifoldPlaces();
    const std::size_t placesFound = places.places.size();
    // How far above placesFound a count must be to stand above the start's level (below): a ball's mending may leave a
    // few places beside it, and counts of many places fluctuate by about their square root.
    const double fluctuation =
      std::max(std::sqrt(static_cast<double>(placesFound)), PlacesABallMayLeaveBesideTheOneItMends);
    // Rounds that left more places than the round before and more than the repair began with, since the count was
    // last back at the start's level (below).
    unsigned int risesAboveTheStart = 0;
    std::size_t  placesBefore = placesFound;
    if (!m_RegularizationInsertionBudget)
    {
      m_RegularizationInsertionBudget =
        RegularizationInsertionBudget * m_State.GetTriangulation().number_of_vertices() +
        RegularizationInsertionAllowance;
    }
    while (!places.places.empty())
    {
      m_Relabelling.Revert();
      bool              repaired = false;
      bool              regularized = false;
      const std::size_t insertionsBefore = Insertions();
      if (m_Regularizer && m_Statistics.topologyRegularizationRounds < m_Parameters.topologyRegularizationRounds &&
          !m_Statistics.topologyRegularizationBudgetReached)
      {
        repaired = regularized = RegularizeAround(places);
      }
      // Where the labels could not be regularised (an interpolating oracle's labels are not voxels: a gray image's
      // iso-surface), the opt-in halving of δ is what is left; before, such places ended the repair even when the
      // user had asked for the halving.
      if (!repaired)
      {
        repaired = HalveDeltaAround(places);
      }
      if (repaired)
      {
        RefineAndPerturbFlatTetrahedra();
      }
      if (regularized)
      {
        m_RegularizationInsertions += Insertions() - insertionsBefore;
        m_Statistics.topologyRegularizationBudgetReached =
          m_RegularizationInsertions > *m_RegularizationInsertionBudget;
      }
      places = RelabelAndFindNonManifoldPlaces();
      const bool aboveTheStart = static_cast<double>(places.places.size()) > placesFound + fluctuation;
      if (!aboveTheStart)
      {
        risesAboveTheStart = 0;
      }
      else if (places.places.size() > placesBefore)
      {
        ++risesAboveTheStart;
      }
      placesBefore = places.places.size();
      // Regularisation rounds whose places keep growing beyond the count the repair began with are making things
      // worse: after the second such rise (since the count was last back at the start's level) the rounds stop, and
      // the places left are reported. A count that falls, or holds, is being settled, however high it is: a ball that
      // cuts a pinch can leave smaller ones beside it, which the next rounds' larger balls settle (SheetsAndLines
      // 3029473 of the randomized suite: 2 places, 3 after the δ balls, none after the 2δ balls; SaltAndPepper 2297698:
      // 4, then 10, 7, 7, 1 and 0; the rule before, two rounds in a row above the start's level, stopped it at 7).
      // "Above" is beyond the square root of the count at the start, the scale of its fluctuation, and beyond two at
      // least: a ball that mends a place can leave one or two beside it, which a few places feel and many do not
      // (SaltAndPepper 2075775: 6 places, then 7, 7, 6, 2 and 0; 2164423: 3, then 5, 5 and 0). The budget of
      // insertions bounds what the rounds cost either way. Measured without a stop: Blobs 1000030 (ρ = 1, δ = 0.64
      // voxel) began with 127 places and kept 120 to 260 through all 20 rounds, five times the run's time for a worse
      // mesh; it now goes 112, 95, 115, 106, 134 and 259, and stops there. The bench images' rounds only ever decrease.
      if (!repaired || (regularized && risesAboveTheStart >= RegularizationRisesAboveTheStart))
      {
        break;
      }
      // The regularisation's rounds, over every repair of the run, have a budget of insertions relative to the mesh
      // the first began with (RegularizationInsertionBudget): where the places cover the image, each round made the
      // mesh again.
      if (regularized && m_Statistics.topologyRegularizationBudgetReached)
      {
        break;
      }
    }
    m_Statistics.manifoldRefinementZones = m_Sizing.NumberOfZones() - m_Statistics.thickPartsRefined;
    m_Statistics.finestSurfaceSamplingDistance = m_Sizing.FinestDelta();
    m_Statistics.remainingNonManifoldVertices = places.places.size();
  }

  /** The vertices inserted so far (those deleted since included). */
  std::size_t
  Insertions() const
  {
    return m_State.GetTriangulation().number_of_vertices() + m_State.NumberOfDeletedVertices();
  }

  /** The places found, relabelled where that mends them, and found again when a move was made. The moves of the
   * rounds before that the refinement left untouched are made again first. Each search looks at the vertices whose
   * star changed since the one before, and those it found (ManifoldRepair::FindNonManifoldPlacesWhereChanged). */
  NonManifoldPlaces
  RelabelAndFindNonManifoldPlaces()
  {
    if (m_Parameters.relabelNonManifoldPlaces)
    {
      m_Relabelling.Replay();
    }
    NonManifoldPlaces places = m_Repair.FindNonManifoldPlacesWhereChanged();
    if (m_Parameters.relabelNonManifoldPlaces && !places.vertices.empty() && m_Relabelling.Relabel(places) > 0)
    {
      places = m_Repair.FindNonManifoldPlacesWhereChanged();
    }
    return places;
  }

  /** The oracle's labels change in a ball of radius δ around each place (2δ from the second round on); the surface
   * samples inside go (they are off the new surface), and the cells whose circumball meets a ball are evaluated
   * again. */
  bool
  RegularizeAround(const NonManifoldPlaces & places)
  {
    // A place still there after a round is one the δ ball left as it was (measured: the k-means tissues at 3 mm and
    // the atlas phantom at one voxel kept 4 and 2 vertices through 10 rounds of δ); twice the radius settles them.
    // So does a first round whose δ balls change nothing: a place whose tissue has no voxel within δ of it, its
    // tetrahedra reaching it from voxels farther away (ThinImages 7028533, found by the randomized suite's manifold
    // check), had ended the repair there.
    const double delta = m_Parameters.surfaceSamplingDistance;
    const double radius =
      (m_Statistics.topologyRegularizationRounds == 0 ? RegularizationRadius : LaterRegularizationRadius) * delta;
    std::vector<Ball> balls = m_Regularizer->RegularizeAround(places.places, radius);
    if (balls.empty() && radius < LaterRegularizationRadius * delta)
    {
      balls = m_Regularizer->RegularizeAround(places.places, LaterRegularizationRadius * delta);
    }
    if (balls.empty())
    {
      return false;
    }
    ++m_Statistics.topologyRegularizationRounds;
    m_Statistics.regularizedPlaces += balls.size();
    for (const Ball & ball : balls)
    {
      m_State.RemoveSurfaceSamplesInside(ball.center, ball.radius);
    }
    std::vector<CellHandle> changed = m_Repair.CellsMeeting(balls);
    std::sort(changed.begin(), changed.end());
    // Caches first: the neighbours' classification looks at the changed cells' labels.
    m_State.RefreshCells(changed);
    for (const CellHandle cell : m_Repair.WithNeighbors(changed))
    {
      if (!std::binary_search(changed.begin(), changed.end(), cell))
      {
        Enqueue(cell);
      }
    }
    return true;
  }

  /** The opt-in repair: δ halved around each place (ManifoldRepair::HalveDeltaAround). */
  bool
  HalveDeltaAround(const NonManifoldPlaces & places)
  {
    if (m_Parameters.manifoldRefinementLevels == 0 ||
        !ManifoldRepair::IsRepairable(places, m_Repair.CountBoundaryVertices()))
    {
      return false;
    }
    const std::vector<Ball> newZones = m_Repair.HalveDeltaAround(places);
    if (newZones.empty())
    {
      return false;
    }
    ++m_Statistics.manifoldRefinementRounds;
    for (const CellHandle cell : m_Repair.WithNeighbors(m_Repair.CellsMeeting(newZones)))
    {
      Enqueue(cell);
    }
    return true;
  }

  static constexpr std::size_t ProgressInterval = 4096;
  /** How many times the tetrahedra flat to rounding left after the refinement are moved and the refinement
   * resumed: a bound, so that moves and refinement cannot alternate for ever. In the randomized suite (3,000
   * images) 56 meshes needed a round, 11 a second, 5 a third and 2 a fourth; twice that is allowed. */
  static constexpr int FlatTetrahedraRounds = 8;
  /** How many times the slivers the flat-cap step could not peel off are split and the repairs run again
   * (PeelFlatCaps): a bound, as the refinement around a split may leave new ones. */
  static constexpr int SliversThatCannotBePeeledRounds = 4;
  /** How many times the vertices it starts from a pass of the sliver removal may leave
   * (RequireSliverRemovalWithinBudget), plus a fixed allowance for small meshes. Measured on the bench images
   * (docs/algorithm.md, "When sliver removal does not end"), in runs that end: at most 1.8 times with ρ >= 1.2 and
   * σ <= 20° (the k-means tissues at 4 mm, ρ = 2, σ = 20°), 4.03 times with ρ = 1 (the atlas phantom at 2 mm,
   * σ = 10°); in runs that do not (ρ = 1 in the randomized suite) the mesh grows without bound. */
  static constexpr std::size_t SliverRemovalGrowthBudget = 10;
  static constexpr std::size_t SliverRemovalVertexAllowance = 1000;
  /** The radius of a regularised ball, in units of δ: a pinch filled or cut over a ball this wide becomes a part
   * or a gap about 2δ across, which sampling at δ resolves. */
  static constexpr double RegularizationRadius = 1.0;
  /** The same from the second round on, for the places a ball of δ did not settle. */
  static constexpr double LaterRegularizationRadius = 2.0;
  /** After how many regularisation rounds that leave more non-manifold places than the round before, and more than the
   * repair began with, the rounds stop (counted since the places were last back at the start's level). */
  static constexpr unsigned int RegularizationRisesAboveTheStart = 2;
  /** The least rise in the non-manifold places over the count the repair began with that counts as "more" (the rise
   * is otherwise measured against the square root of that count): a ball that mends a place can leave one or two
   * beside it. */
  static constexpr double PlacesABallMayLeaveBesideTheOneItMends = 2.0;
  /** How many times the vertices of the mesh the first repair began with the regularisation's rounds may insert over
   * the whole run, plus a fixed allowance for small meshes; the round that passes the budget is the last. Measured
   * per repair, as insertions over the vertices at its start: on the bench images at most 0.055 (the k-means tissues
   * at 4 mm, 7 rounds); on 3,200 randomized images (seeds 0-399 of each family) at most 1.95 where the boundary is
   * promised a manifold (δ at least the largest spacing) and 5.56 elsewhere (SaltAndPepper 2000322, 13 rounds, every
   * place mended), the one of them that reaches the budget counted over the run. Where the places cover the image
   * (SaltAndPepper 2061491: ρ = 1, δ = 0.6 of the largest spacing, 1,921 places on 43,203 vertices) a round inserts
   * about 1.5 times the mesh, and 20 rounds took over a minute on 23 x 21 x 19 voxels. */
  static constexpr std::size_t RegularizationInsertionBudget = 4;
  static constexpr std::size_t RegularizationInsertionAllowance = 1000;
  /** A part of the labels holding a ball of this radius, in units of δ (a diameter of δ), must hold a tetrahedron
   * (issue #14's "at least δ thick"); the sampling around such a part is made finer at most ThickPartRounds times. */
  static constexpr double       ThickPartRadius = 0.5;
  static constexpr unsigned int ThickPartRounds = 4;
  /** Each part is sampled more finely at most ThickPartRounds times, but the rounds go on while some part found
   * without a tetrahedron has rounds left: the refinement after a round can leave another part without one (the
   * randomized Blobs 1056639 found a new one-voxel part in each of four rounds, seven in all). At most this many
   * rounds in all, and from the ThickPartRounds-th on δ is no longer halved. */
  static constexpr unsigned int LargestThickPartRounds = 4 * ThickPartRounds;
  /** A part of the labels holding a ball of this radius, in units of δ, is sampled at δ (SampleThinPartsFinely). */
  static constexpr double WellSampledPartRadius = 0.75;
  /** The radii of the parts' balls are distances on the voxel lattice, and users choose round δ: a single voxel at
   * δ = the spacing holds a ball of radius exactly δ / 2. The thresholds above count such a tie, and a radius up to
   * this fraction below, as reaching them, so that δ's last bits do not decide (as R1's LatticeTieMargin). */
  static constexpr double PartTieMargin = 1e-4;
  /** A part of at most this volume, in units of δ³ (a ball of radius δ), has a few surface samples at δ. */
  static constexpr double SmallPartVolume = 4.0 * 3.141592653589793 / 3.0;

  const LabelOracle &          m_Oracle;
  const RefinementParameters & m_Parameters;
  const ProgressObserver &     m_Observer;
  TopologyRegularizer *        m_Regularizer;
  const LabelPartCensus *      m_Census;
  /** How many times each part of the labels (by label and the centre of its largest ball) was sampled more finely
   * (SampleThinPartsFinely, WithEveryThickPart). */
  std::map<std::pair<Label, Vector3>, unsigned int> m_ThickPartTries;
  /** The vertices the regularisation's rounds inserted (their refinement included), and what they may insert: set
   * when the first repair begins (RepairTopology). */
  std::size_t                m_RegularizationInsertions{ 0 };
  std::optional<std::size_t> m_RegularizationInsertionBudget;
  RefinementStatistics       m_Statistics;
  MeshState                  m_State;
  LocalSampling              m_Sizing;
  BoxProtection              m_BoxProtection;
  RefinementRules            m_Rules;
  SliverSplit                m_SliverSplit;
  DihedralAngleBound         m_DihedralBound{ m_Parameters.minimumDihedralAngle };
  SliverPerturbation m_SliverPerturbation{ m_Oracle, m_Parameters, m_State, m_Rules, m_Sizing, m_BoxProtection };
  MeshExtraction     m_Extraction;
  ManifoldRepair     m_Repair;
  TopologyRelabel m_Relabelling{ m_State, m_Sizing, m_Parameters.radiusEdgeBound, m_Parameters.minimumDihedralAngle };
  RefinementQueue m_Queue;
  /** The slivers R4′ left as caps on the background, in the order it left them (RequeueSliversNoLongerCaps). */
  std::vector<QueueEntry> m_SliversLeftToPeel;
  /** The slivers (their corners) the flat-cap step could not peel off: R4′ splits them, caps or not. */
  std::set<std::array<Vector3, 4>> m_SliversThatCannotBePeeled;
  /** The flat caps the last flat-cap step relabelled (PeelFlatCaps), to undo before the refinement resumes. */
  FlatCaps::Relabelling m_PeeledCaps;
  double                m_ProgressFraction{ 0.0 };
};

/** RefineMesh() with `hooks`. */
TetrahedralMesh
Refine(const LabelOracle & oracle, const RefinementParameters & parameters, RefinementStatistics * statistics,
       const ProgressObserver & observer, TopologyRegularizer * regularizer, const LabelPartCensus * census,
       const RefinementTestHooks & hooks)
{
  ValidateParameters(parameters);
  RefinementStatistics localStatistics;
  Refiner              refiner(oracle, parameters, observer, regularizer, census, hooks);
  TetrahedralMesh      mesh = refiner.Run(localStatistics);
  if (statistics)
  {
    *statistics = localStatistics;
  }
  return mesh;
}

} // namespace

TetrahedralMesh
RefineMeshWithTestHooks(const RefinementTestHooks & hooks, const LabelOracle & oracle,
                        const RefinementParameters & parameters, RefinementStatistics * statistics,
                        TopologyRegularizer * regularizer, const LabelPartCensus * census)
{
  return Refine(oracle, parameters, statistics, {}, regularizer, census, hooks);
}

} // namespace detail

TetrahedralMesh
RefineMesh(const LabelOracle & oracle, const RefinementParameters & parameters, RefinementStatistics * statistics,
           const ProgressObserver & observer, TopologyRegularizer * regularizer, const LabelPartCensus * census)
{
  return detail::Refine(oracle, parameters, statistics, observer, regularizer, census, detail::RefinementTestHooks{});
}

} // namespace delaunay_refinement
