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
#include "DelaunayRefinementMesher.h"
#include "DelaunayRefinementGeometry.h"
#include "DelaunayRefinementMeshQuality.h"
#include "DelaunayRefinementSpatialGrid.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Robust_weighted_circumcenter_filtered_traits_3.h>
#include <CGAL/Triangulation_data_structure_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <unordered_map>

namespace delaunay_refinement
{
namespace
{

/** Exact predicates; circumcentres in floating point with an exact fallback when the floating-point
 * denominator vanishes, which nearly flat tetrahedra of symmetric surface samples do produce. */
using Kernel = CGAL::Robust_circumcenter_filtered_traits_3<CGAL::Exact_predicates_inexact_constructions_kernel>;
using CgalPoint = Kernel::Point_3;

/** A vertex not (yet) numbered in an output. */
constexpr uint32_t NoOutputIndex = std::numeric_limits<uint32_t>::max();

/** Vertex ids are insertion counters of 32 bits: they keep vertices and queue entries small. */
using VertexId = uint32_t;

struct VertexData
{
  VertexKind kind{ VertexKind::Free };
  /** Insertion order: sorts vertices deterministically where a container's order would not. */
  VertexId id{ 0 };
  /** Index in the output mesh, assigned during extraction. */
  uint32_t outputIndex{ NoOutputIndex };
};

/** What every rule asks of a tetrahedron, computed once when the tetrahedron is created. */
struct CellCache
{
  static constexpr double NotYetComputed = -1.0;
  Vector3                 circumcenter{ { 0.0, 0.0, 0.0 } };
  double                  squaredRadius{ 0.0 };
  /** Distance from the circumcentre to the surface, or the bound on it that decided IsIntersecting(); NotYetComputed
   * until a rule asks (most cells are destroyed before that: the oracle's distance query is the refinement's most
   * expensive per-cell step). */
  double surfaceDistance{ NotYetComputed };
  Label  label{ BackgroundLabel };
  /** Unique per evaluated cell. CGAL recycles freed cells, so a queue entry is current only while its cell
   * is in use and still carries the stamp it was queued with. (CGAL's erase counters would do, but GCC's
   * lifetime dead-store elimination drops the counter's stores made before a slot is reconstructed.) */
  uint64_t stamp{ 0 };
};

/** A Delaunay cell that carries the rules' cache. */
template <class GeometricTraits, class CellBase = CGAL::Delaunay_triangulation_cell_base_3<GeometricTraits>>
class RefinementCellBase : public CellBase
{
public:
  template <class Tds>
  struct Rebind_TDS
  {
    using OtherCellBase = typename CellBase::template Rebind_TDS<Tds>::Other;
    using Other = RefinementCellBase<GeometricTraits, OtherCellBase>;
  };

  using CellBase::CellBase;

  CellCache cache;
};

using VertexBase = CGAL::Triangulation_vertex_base_with_info_3<VertexData, Kernel>;
using CellBase = RefinementCellBase<Kernel>;
using DataStructure = CGAL::Triangulation_data_structure_3<VertexBase, CellBase>;
using Triangulation = CGAL::Delaunay_triangulation_3<Kernel, DataStructure>;
using VertexHandle = Triangulation::Vertex_handle;
using CellHandle = Triangulation::Cell_handle;

Vector3
ToVector(const CgalPoint & point)
{
  return { point.x(), point.y(), point.z() };
}

CgalPoint
ToCgal(const Vector3 & point)
{
  return { point[0], point[1], point[2] };
}

std::string
DescribeValue(double value)
{
  std::ostringstream stream;
  stream.precision(17);
  stream << value;
  return stream.str();
}

/** Rules, in the order ALGORITHM.md checks them. */
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
};

/** Queue levels: surface work first (its feature insertions delete nearby free vertices, so quality work
 * done before it would be wasted), then quality work. */
enum class QueueLevel : int
{
  Surface = 0,
  Quality = 1
};

/** 40 bytes: popping sifts entries through a heap of hundreds of thousands of them. */
struct QueueEntry
{
  double     squaredRadius;
  CellHandle cell;
  uint64_t   stamp;
  /** The cell's vertex ids, sorted: a tie-break that depends on the geometry and the (canonical) insertion
   * order only, never on memory addresses, which CGAL's vertex removal lets leak into container orders. */
  std::array<VertexId, 4> vertexIds;
};

/** Largest tetrahedra first; equal sizes (co-spherical cells) by vertex ids, for determinism. */
struct QueueEntryOrder
{
  bool
  operator()(const QueueEntry & a, const QueueEntry & b) const
  {
    if (a.squaredRadius != b.squaredRadius)
    {
      return a.squaredRadius < b.squaredRadius;
    }
    return a.vertexIds > b.vertexIds;
  }
};

/** A max-heap with four children per node: half the depth of a binary heap, and a node's children share a cache
 * line or two, so popping from hundreds of thousands of entries misses the cache about half as often. */
class FourAryHeap
{
public:
  bool
  Empty() const
  {
    return m_Entries.empty();
  }

  std::size_t
  Size() const
  {
    return m_Entries.size();
  }

  void
  Push(const QueueEntry & entry)
  {
    std::size_t position = m_Entries.size();
    m_Entries.push_back(entry);
    while (position > 0)
    {
      const std::size_t parent = (position - 1) / Arity;
      if (!m_Before(m_Entries[parent], entry))
      {
        break;
      }
      m_Entries[position] = m_Entries[parent];
      position = parent;
    }
    m_Entries[position] = entry;
  }

  /** Removes and returns the greatest entry; the heap must not be empty. */
  QueueEntry
  Pop()
  {
    const QueueEntry top = m_Entries.front();
    const QueueEntry last = m_Entries.back();
    m_Entries.pop_back();
    if (!m_Entries.empty())
    {
      SiftDown(last);
    }
    return top;
  }

private:
  static constexpr std::size_t Arity = 4;

  /** Places `entry` from the root down, moving greater children up. */
  void
  SiftDown(const QueueEntry & entry)
  {
    const std::size_t size = m_Entries.size();
    std::size_t       position = 0;
    for (;;)
    {
      const std::size_t firstChild = Arity * position + 1;
      if (firstChild >= size)
      {
        break;
      }
      std::size_t greatest = firstChild;
      for (std::size_t child = firstChild + 1; child < std::min(firstChild + Arity, size); ++child)
      {
        if (m_Before(m_Entries[greatest], m_Entries[child]))
        {
          greatest = child;
        }
      }
      if (!m_Before(entry, m_Entries[greatest]))
      {
        break;
      }
      m_Entries[position] = m_Entries[greatest];
      position = greatest;
    }
    m_Entries[position] = entry;
  }

  std::vector<QueueEntry> m_Entries;
  QueueEntryOrder         m_Before;
};

/** One heap per level, the surface level's emptied first: the level is then never compared. */
class RefinementQueue
{
public:
  void
  Push(QueueLevel level, const QueueEntry & entry)
  {
    m_Levels[static_cast<int>(level)].Push(entry);
  }

  bool
  Empty() const
  {
    return m_Levels[0].Empty() && m_Levels[1].Empty();
  }

  std::size_t
  Size() const
  {
    return m_Levels[0].Size() + m_Levels[1].Size();
  }

  /** The next entry to process; the queue must not be empty. */
  QueueEntry
  Pop()
  {
    return (m_Levels[0].Empty() ? m_Levels[1] : m_Levels[0]).Pop();
  }

private:
  std::array<FourAryHeap, 2> m_Levels;
};

/** One of the 12 edges of the bounding box, with the positions of the box-edge vertices along it. */
struct BoxEdge
{
  int     axis{ 0 };
  Vector3 origin{ { 0.0, 0.0, 0.0 } };
  /** Sorted coordinates, along `axis`, of the vertices on this edge (its two corners included). */
  std::vector<double> stations;

  Vector3
  PointAt(double station) const
  {
    Vector3 point = origin;
    point[axis] = station;
    return point;
  }
};

/** A box-edge subsegment: the part of a box edge between two consecutive vertices on it. */
struct BoxSubsegment
{
  std::size_t edgeIndex;
  Vector3     midpoint;
  double      squaredRadius;
};

/** The local surface sampling distance: δ everywhere, except in balls around places where the restricted
 * surface was not a 2-manifold, where it is halved once per refinement level. */
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
    double delta = m_Delta;
    if (m_Zones.empty())
    {
      return delta;
    }
    m_ZoneCenters.ForEachWithin(point, ZoneRadiusFactor * m_Delta, [&](std::size_t zone) {
      if (SquaredNorm(point - m_Zones[zone].center) < m_Zones[zone].squaredRadius)
      {
        delta = std::min(delta, m_Zones[zone].delta);
      }
    });
    return delta;
  }

  /** Samples at `delta` around `point` (where that is finer than elsewhere); the zone covers the facets around
   * it. Returns the zone's radius: outside it nothing changed. */
  double
  AddZone(const Vector3 & point, double delta)
  {
    const double radius = ZoneRadiusFactor * 2.0 * delta;
    m_ZoneCenters.Insert(point, m_Zones.size());
    m_Zones.push_back({ point, radius * radius, delta });
    return radius;
  }

  std::size_t
  NumberOfZones() const
  {
    return m_Zones.size();
  }

  double
  FinestDelta() const
  {
    double finest = m_Delta;
    for (const Zone & zone : m_Zones)
    {
      finest = std::min(finest, zone.delta);
    }
    return finest;
  }

private:
  /** Zone radius in units of the sampling distance it refines: wide enough to hold the restricted facets
   * (circumradius < δ) around the offending vertex. */
  static constexpr double ZoneRadiusFactor = 3.0;

  struct Zone
  {
    Vector3 center;
    double  squaredRadius;
    double  delta;
  };

  double                   m_Delta;
  std::vector<Zone>        m_Zones;
  SpatialGrid<std::size_t> m_ZoneCenters;
};

class Refiner
{
public:
  Refiner(const LabelOracle & oracle, const RefinementParameters & parameters, const ProgressObserver & observer)
    : m_Oracle(oracle)
    , m_Parameters(parameters)
    , m_Observer(observer)
    , m_Delta(parameters.surfaceSamplingDistance)
    // Cells twice the largest query radius: a query then looks at 2 x 2 x 2 cells.
    , m_FeatureVertices(2.0 * parameters.surfaceSamplingDistance)
    , m_FreeVertices(4.0 * parameters.surfaceSamplingDistance)
    , m_Sizing(parameters.surfaceSamplingDistance)
  {}

  TetrahedralMesh
  Run(RefinementStatistics & statistics)
  {
    const AxisAlignedBox objectBounds = m_Oracle.ObjectBounds();
    if (objectBounds.IsEmpty())
    {
      return {};
    }
    const auto refinementStart = std::chrono::steady_clock::now();
    CreateBoundingBox(objectBounds);
    RefineUntilNoRuleApplies();
    RefineUntilManifold();
    const auto      extractionStart = std::chrono::steady_clock::now();
    TetrahedralMesh mesh = ExtractMesh();
    const auto      end = std::chrono::steady_clock::now();

    m_Statistics.triangulationVertices = m_Triangulation.number_of_vertices();
    m_Statistics.refinementSeconds = std::chrono::duration<double>(extractionStart - refinementStart).count();
    m_Statistics.extractionSeconds = std::chrono::duration<double>(end - extractionStart).count();
    statistics = m_Statistics;
    return mesh;
  }

private:
  // ---- Set-up -------------------------------------------------------------------------------------------

  /** A box no point of which is closer than 2√2·δ to the surface: the object's bounds grown by 3δ. */
  void
  CreateBoundingBox(const AxisAlignedBox & objectBounds)
  {
    const double margin = 3.0 * m_Delta;
    for (int axis = 0; axis < 3; ++axis)
    {
      m_Box.lower[axis] = objectBounds.lower[axis] - margin;
      m_Box.upper[axis] = objectBounds.upper[axis] + margin;
    }
    for (int axis = 0; axis < 3; ++axis)
    {
      for (int corner = 0; corner < 4; ++corner)
      {
        BoxEdge edge;
        edge.axis = axis;
        const int firstOther = (axis + 1) % 3;
        const int secondOther = (axis + 2) % 3;
        edge.origin[axis] = m_Box.lower[axis];
        edge.origin[firstOther] = (corner & 1) ? m_Box.upper[firstOther] : m_Box.lower[firstOther];
        edge.origin[secondOther] = (corner & 2) ? m_Box.upper[secondOther] : m_Box.lower[secondOther];
        edge.stations = { m_Box.lower[axis], m_Box.upper[axis] };
        m_BoxEdges.push_back(edge);
      }
    }
    std::vector<CgalPoint> corners;
    for (int corner = 0; corner < 8; ++corner)
    {
      corners.emplace_back((corner & 1) ? m_Box.upper[0] : m_Box.lower[0],
                           (corner & 2) ? m_Box.upper[1] : m_Box.lower[1],
                           (corner & 4) ? m_Box.upper[2] : m_Box.lower[2]);
    }
    CellHandle hint;
    for (const CgalPoint & corner : corners)
    {
      VertexHandle vertex = m_Triangulation.insert(corner, hint);
      vertex->info().kind = VertexKind::BoxEdge;
      vertex->info().id = m_NextVertexId++;
      hint = vertex->cell();
    }
    std::vector<CellHandle> cells;
    for (auto cell = m_Triangulation.finite_cells_begin(); cell != m_Triangulation.finite_cells_end(); ++cell)
    {
      cells.push_back(cell);
    }
    EnqueueNewCells(cells);
  }

  // ---- Cell evaluation ----------------------------------------------------------------------------------

  Vector3
  PointOf(VertexHandle vertex) const
  {
    return ToVector(vertex->point());
  }

  std::array<Vector3, 4>
  CornersOf(CellHandle cell) const
  {
    return { PointOf(cell->vertex(0)), PointOf(cell->vertex(1)), PointOf(cell->vertex(2)), PointOf(cell->vertex(3)) };
  }

  /** CGAL's filtered construction accepts its floating-point circumcentre as soon as that point lies inside the
   * circumsphere, which almost any point near a nearly flat tetrahedron does: for the nearly flat, nearly
   * co-spherical tetrahedra that voxel-derived points produce, it can be far from the centre, and every rule
   * built on it (Voronoi edges, surface balls, labels) goes wrong. A centre whose corners are not equidistant
   * is recomputed exactly, and so is the centre of a nearly flat tetrahedron: there every point of a whole line
   * is nearly equidistant from the corners, so equidistance cannot vouch for the centre (the fuzzer found an R3
   * surface ball, on a Voronoi edge ending at such a centre, that held a feature vertex 0.88 δ from its centre). */
  Vector3
  CircumcenterOf(CellHandle cell, const std::array<Vector3, 4> & corners) const
  {
    const CgalPoint & p = cell->vertex(0)->point();
    const CgalPoint & q = cell->vertex(1)->point();
    const CgalPoint & r = cell->vertex(2)->point();
    const CgalPoint & s = cell->vertex(3)->point();
    if (IsNearlyFlat(corners))
    {
      return ToVector(m_Circumcenter(p, q, r, s, true));
    }
    const Vector3 center = ToVector(m_Circumcenter(p, q, r, s));
    const double  squaredRadius = SquaredNorm(center - corners[0]);
    for (int corner = 1; corner < 4; ++corner)
    {
      if (std::abs(SquaredNorm(center - corners[corner]) - squaredRadius) > EquidistanceTolerance * squaredRadius)
      {
        return ToVector(m_Circumcenter(p, q, r, s, true));
      }
    }
    return center;
  }

  /** Whether six times the volume is below FlatnessTolerance times the cube of the longest edge: then the
   * floating-point circumcentre's error along the nearly degenerate direction can reach rounding / flatness. */
  static bool
  IsNearlyFlat(const std::array<Vector3, 4> & corners)
  {
    double longestSquaredEdge = 0.0;
    for (int i = 0; i < 4; ++i)
    {
      for (int j = i + 1; j < 4; ++j)
      {
        longestSquaredEdge = std::max(longestSquaredEdge, SquaredNorm(corners[i] - corners[j]));
      }
    }
    const double sixVolume = Dot(corners[1] - corners[0], Cross(corners[2] - corners[0], corners[3] - corners[0]));
    return std::abs(sixVolume) < FlatnessTolerance * longestSquaredEdge * std::sqrt(longestSquaredEdge);
  }

  /** Keeps the floating-point circumcentre's error below about 1e-7 of the longest edge (rounding 1e-16 over a
   * flatness above 1e-9). */
  static constexpr double FlatnessTolerance = 1e-9;

  /** Relative disagreement of the squared distances from a floating-point circumcentre to the corners beyond
   * which it is not trusted: far above rounding (1e-16) for any tetrahedron CGAL's floating-point construction
   * handles well, far below any error that would move a Voronoi edge by a fraction of δ. */
  static constexpr double EquidistanceTolerance = 1e-10;

  void
  ComputeCache(CellHandle cell)
  {
    CellCache &                  cache = cell->cache;
    const std::array<Vector3, 4> corners = CornersOf(cell);
    cache.circumcenter = CircumcenterOf(cell, corners);
    cache.squaredRadius = SquaredNorm(cache.circumcenter - corners[0]);
    cache.label = m_Oracle.LabelAt(cache.circumcenter);
    cache.surfaceDistance = CellCache::NotYetComputed;
    cache.stamp = ++m_LastStamp;
  }

  Label
  LabelBeyondFacet(CellHandle cell, int facet) const
  {
    const CellHandle neighbor = cell->neighbor(facet);
    return m_Triangulation.is_infinite(neighbor) ? BackgroundLabel : neighbor->cache.label;
  }

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
      if (LabelBeyondFacet(cell, facet) != cell->cache.label)
      {
        return true;
      }
    }
    return false;
  }

  bool
  IsBadlyShaped(CellHandle cell) const
  {
    const std::array<Vector3, 4> corners = CornersOf(cell);
    const double                 shortestEdge = ShortestEdgeLength(corners);
    const double                 radius = std::sqrt(cell->cache.squaredRadius);
    if (radius >= m_Parameters.radiusEdgeBound * shortestEdge)
    {
      return true;
    }
    return IsSliver(corners);
  }

  /** Which queue a tetrahedron belongs in, or none when no rule can ever apply to it while it exists. */
  std::optional<QueueLevel>
  Classify(CellHandle cell) const
  {
    // The label test first: it is cheap and often decides without the oracle's distance.
    if (HasLabelChangeAcrossAFacet(cell) || IsIntersecting(cell))
    {
      return QueueLevel::Surface;
    }
    if (cell->cache.label != BackgroundLabel && IsBadlyShaped(cell))
    {
      return QueueLevel::Quality;
    }
    return std::nullopt;
  }

  static std::array<VertexId, 4>
  SortedVertexIds(CellHandle cell)
  {
    std::array<VertexId, 4> ids{
      cell->vertex(0)->info().id, cell->vertex(1)->info().id, cell->vertex(2)->info().id, cell->vertex(3)->info().id
    };
    std::sort(ids.begin(), ids.end());
    return ids;
  }

  void
  Enqueue(CellHandle cell)
  {
    const std::optional<QueueLevel> level = Classify(cell);
    if (level)
    {
      m_Queue.Push(*level, { cell->cache.squaredRadius, cell, cell->cache.stamp, SortedVertexIds(cell) });
    }
  }

  /** Caches first, then classification: classifying looks at the neighbours' labels. */
  void
  EnqueueNewCells(const std::vector<CellHandle> & cells)
  {
    for (CellHandle cell : cells)
    {
      if (!m_Triangulation.is_infinite(cell))
      {
        ComputeCache(cell);
      }
    }
    for (CellHandle cell : cells)
    {
      if (!m_Triangulation.is_infinite(cell))
      {
        Enqueue(cell);
      }
    }
  }

  // ---- Rules --------------------------------------------------------------------------------------------

  /** R1, R2, R3, R4 (and R4'), checked in that order: the first that applies. */
  std::optional<Action>
  FindApplicableRule(CellHandle cell) const
  {
    const CellCache & cache = cell->cache;
    if (IsIntersecting(cell))
    {
      const SurfacePoint closest = ClosestSurfacePointTo(cache.circumcenter);
      const double       deltaAtClosest = m_Sizing.LocalDelta(closest.point);
      if (!m_FeatureVertices.AnyWithin(closest.point, deltaAtClosest))
      {
        return Action{ Rule::R1, closest.point, deltaAtClosest };
      }
      const double deltaAtCenter = m_Sizing.LocalDelta(cache.circumcenter);
      if (cache.squaredRadius >= 4.0 * deltaAtCenter * deltaAtCenter)
      {
        return Action{ Rule::R2, cache.circumcenter, deltaAtCenter };
      }
    }
    if (const std::optional<Action> surfaceBall = LargeSurfaceBall(cell))
    {
      return surfaceBall;
    }
    // R4. ALGORITHM.md calls a tetrahedron skinny only when it is not intersecting; we also split
    // intersecting ones (left here by R1-R3 with r < 2δ), because otherwise an output tetrahedron can have
    // radius-edge ratio up to 2 > ρ when ρ < 2 (the paper's proof of Theorem 2 skips this case). For ρ >= 2
    // nothing changes: such a tetrahedron has r < 2δ and every edge >= δ (Lemma 2), so its ratio is < 2.
    if (cache.label != BackgroundLabel)
    {
      const std::array<Vector3, 4> corners = CornersOf(cell);
      if (std::sqrt(cache.squaredRadius) >= m_Parameters.radiusEdgeBound * ShortestEdgeLength(corners))
      {
        return Action{ Rule::R4, cache.circumcenter, m_Delta };
      }
      if (IsSliver(corners))
      {
        return Action{ Rule::R4Dihedral, cache.circumcenter, m_Delta };
      }
    }
    return std::nullopt;
  }

  /** R4' (the paper's variant, on when σ > 0): a dihedral angle below σ. Like the paper, every such sliver
   * with its circumcentre inside is split, so the output's dihedral angles are >= σ. The paper proves nothing
   * for R4': termination rests on the vertex cap, and its free vertices may come closer than δ to others,
   * so the 30° bound on boundary angles (Theorem 2) is not guaranteed while σ > 0. */
  bool
  IsSliver(const std::array<Vector3, 4> & corners) const
  {
    return m_Parameters.minimumDihedralAngle > 0.0 && MinimumDihedralAngle(corners) < m_Parameters.minimumDihedralAngle;
  }

  double
  ShortestFacetEdge(CellHandle cell, int facet) const
  {
    const Vector3 a = PointOf(cell->vertex((facet + 1) & 3));
    const Vector3 b = PointOf(cell->vertex((facet + 2) & 3));
    const Vector3 c = PointOf(cell->vertex((facet + 3) & 3));
    return std::sqrt(std::min({ SquaredNorm(a - b), SquaredNorm(b - c), SquaredNorm(c - a) }));
  }

  /** The far end of the Voronoi ray dual to a convex-hull facet: beyond the box, so labelled background. */
  Vector3
  FarEndOfVoronoiRay(CellHandle cell, int facet) const
  {
    const Vector3 normal = OutwardFaceNormal(CornersOf(cell), facet);
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
      const Label otherLabel = LabelBeyondFacet(cell, facet);
      if (otherLabel == cell->cache.label)
      {
        continue;
      }
      const CellHandle neighbor = cell->neighbor(facet);
      const Vector3    otherEnd =
        m_Triangulation.is_infinite(neighbor) ? FarEndOfVoronoiRay(cell, facet) : neighbor->cache.circumcenter;
      const Vector3 center = m_Oracle.SurfaceCrossing(cell->cache.circumcenter, otherEnd);
      const double  squaredRadius = SquaredNorm(center - PointOf(cell->vertex((facet + 1) & 3)));
      const double  threshold = std::min(m_Sizing.LocalDelta(center), ShortestFacetEdge(cell, facet));
      if (squaredRadius >= threshold * threshold && squaredRadius > bestSquaredRadius)
      {
        bestSquaredRadius = squaredRadius;
        best = Action{ Rule::R3, center, threshold };
      }
    }
    return best;
  }

  // ---- Insertion and deletion ---------------------------------------------------------------------------

  void
  RequireRoomForAVertex() const
  {
    if (m_NextVertexId == std::numeric_limits<VertexId>::max())
    {
      throw VertexLimitExceeded(
        "Delaunay refinement made 2^32 - 1 vertex insertions, the most its vertex ids can "
        "number, before every rule was satisfied; raise the surface sampling distance (delta = " +
        DescribeValue(m_Delta) + ")");
    }
    if (m_Triangulation.number_of_vertices() >= m_Parameters.maximumNumberOfVertices)
    {
      throw VertexLimitExceeded("Delaunay refinement reached maximumNumberOfVertices = " +
                                std::to_string(m_Parameters.maximumNumberOfVertices) +
                                " vertices before every rule was satisfied; raise the limit or the surface sampling "
                                "distance (delta = " +
                                DescribeValue(m_Delta) + ")");
    }
  }

  /** Inserts `point`; returns no handle when the point is already a vertex. */
  std::optional<VertexHandle>
  InsertVertex(const Vector3 & point, VertexKind kind, CellHandle hint)
  {
    RequireRoomForAVertex();
    const std::size_t  verticesBefore = m_Triangulation.number_of_vertices();
    const VertexHandle vertex = m_Triangulation.insert(ToCgal(point), hint);
    if (m_Triangulation.number_of_vertices() == verticesBefore)
    {
      return std::nullopt;
    }
    vertex->info().kind = kind;
    vertex->info().id = m_NextVertexId++;
    if (kind == VertexKind::Feature)
    {
      m_FeatureVertices.Insert(point, point);
    }
    else if (kind == VertexKind::Free)
    {
      m_FreeVertices.Insert(point, vertex);
    }
    else if (kind == VertexKind::BoxFace)
    {
      m_BoxFaceVertices.push_back(vertex);
    }
    m_NewCells.clear();
    m_Triangulation.incident_cells(vertex, std::back_inserter(m_NewCells));
    EnqueueNewCells(m_NewCells);
    return vertex;
  }

  void
  RemoveVertex(VertexHandle vertex)
  {
    if (vertex->info().kind == VertexKind::Free)
    {
      m_FreeVertices.Remove(PointOf(vertex), vertex);
    }
    else
    {
      m_BoxFaceVertices.erase(std::find(m_BoxFaceVertices.begin(), m_BoxFaceVertices.end(), vertex));
    }
    m_NewCells.clear();
    m_Triangulation.remove_and_give_new_cells(vertex, std::back_inserter(m_NewCells));
    ++m_Statistics.deletedVertices;
    EnqueueNewCells(m_NewCells);
  }

  /** Removes, in insertion order, the vertices of the given kinds strictly inside the ball. */
  void
  EmptyBall(const Vector3 & center, double radius, bool alsoBoxFaceVertices)
  {
    std::vector<VertexHandle> victims;
    m_FreeVertices.ForEachWithin(center, radius, [&](const VertexHandle & vertex) { victims.push_back(vertex); });
    if (alsoBoxFaceVertices)
    {
      for (const VertexHandle & vertex : m_BoxFaceVertices)
      {
        if (SquaredNorm(PointOf(vertex) - center) < radius * radius)
        {
          victims.push_back(vertex);
        }
      }
    }
    std::sort(victims.begin(), victims.end(), [](const VertexHandle & a, const VertexHandle & b) {
      return a->info().id < b->info().id;
    });
    for (const VertexHandle & vertex : victims)
    {
      RemoveVertex(vertex);
    }
  }

  /** R1 and R3: a feature vertex, then deletion of the free vertices closer than 2δ (the local δ) to it. */
  bool
  InsertFeatureVertex(const Vector3 & point, double localDelta, CellHandle hint)
  {
    if (!InsertVertex(point, VertexKind::Feature, hint))
    {
      return false;
    }
    EmptyBall(point, 2.0 * localDelta, false);
    return true;
  }

  bool
  IsStrictlyInsideBox(const Vector3 & point) const
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      if (!(point[axis] > m_Box.lower[axis] && point[axis] < m_Box.upper[axis]))
      {
        return false;
      }
    }
    return true;
  }

  /** The box-edge subsegment whose open diametral ball holds `point`, if any. Only the subsegment over
   * which the point projects can hold it, so each edge needs one binary search. */
  std::optional<BoxSubsegment>
  FindEncroachedBoxSubsegment(const Vector3 & point) const
  {
    for (std::size_t edgeIndex = 0; edgeIndex < m_BoxEdges.size(); ++edgeIndex)
    {
      const BoxEdge &             edge = m_BoxEdges[edgeIndex];
      const std::vector<double> & stations = edge.stations;
      auto                        next = std::upper_bound(stations.begin(), stations.end(), point[edge.axis]);
      if (next == stations.begin() || next == stations.end())
      {
        continue;
      }
      const double  start = *(next - 1);
      const double  halfLength = 0.5 * (*next - start);
      const Vector3 midpoint = edge.PointAt(start + halfLength);
      if (SquaredNorm(point - midpoint) < halfLength * halfLength)
      {
        return BoxSubsegment{ edgeIndex, midpoint, halfLength * halfLength };
      }
    }
    return std::nullopt;
  }

  /** Where the segment from `inside` (strictly inside the box) to `outside` (on or outside it) leaves the
   * box, put exactly onto the face it leaves through. */
  Vector3
  BoxExitPoint(const Vector3 & inside, const Vector3 & outside) const
  {
    const Vector3 direction = outside - inside;
    double        exitParameter = 1.0;
    int           exitAxis = 0;
    double        exitCoordinate = outside[0];
    for (int axis = 0; axis < 3; ++axis)
    {
      const double bound = direction[axis] > 0.0 ? m_Box.upper[axis] : m_Box.lower[axis];
      if (direction[axis] != 0.0 && (bound - inside[axis]) / direction[axis] <= exitParameter)
      {
        exitParameter = (bound - inside[axis]) / direction[axis];
        exitAxis = axis;
        exitCoordinate = bound;
      }
    }
    Vector3 exit = inside + exitParameter * direction;
    exit[exitAxis] = exitCoordinate;
    for (int axis = 0; axis < 3; ++axis)
    {
      exit[axis] = std::clamp(exit[axis], m_Box.lower[axis], m_Box.upper[axis]);
    }
    return exit;
  }

  /** The box facet that stands between the tetrahedron and its circumcentre `point` (on or outside the box):
   * the convex-hull facet holding the point where the segment from the tetrahedron's centroid to `point`
   * leaves the box. Its diametral ball covers the part of the tetrahedron's circumsphere inside the box (the
   * paper's Fig. 1b), although it need not hold `point` itself. Chosen geometrically, not by a walk, so that
   * the choice is deterministic. Returns the facet's circumcentre and squared circumradius. */
  std::optional<std::pair<Vector3, double>>
  FindBoxFacetToward(const Vector3 & point, CellHandle cell) const
  {
    const std::array<Vector3, 4> corners = CornersOf(cell);
    const Vector3                centroid = 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
    const Vector3                exit = BoxExitPoint(centroid, point);
    Triangulation::Locate_type   locateType;
    int                          facetIndex = 0;
    int                          unusedIndex = 0;
    const CellHandle located = m_Triangulation.locate(ToCgal(exit), locateType, facetIndex, unusedIndex, cell);
    if (locateType != Triangulation::FACET)
    {
      // The exit point is on an edge or a vertex of the hull's triangulation (a measure-zero case).
      return std::nullopt;
    }
    const CgalPoint & a = located->vertex((facetIndex + 1) & 3)->point();
    const CgalPoint & b = located->vertex((facetIndex + 2) & 3)->point();
    const CgalPoint & c = located->vertex((facetIndex + 3) & 3)->point();
    Vector3           center = ToVector(m_Circumcenter(a, b, c));
    SnapOntoFacePlane(center, { ToVector(a), ToVector(b), ToVector(c) });
    return std::make_pair(center, SquaredNorm(center - ToVector(a)));
  }

  /** A circumcentre of a triangle on a box face lies on that face: make it so exactly, in the face's
   * coordinate, and keep it within the face. */
  void
  SnapOntoFacePlane(Vector3 & center, const std::array<Vector3, 3> & triangle) const
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      if (triangle[0][axis] == triangle[1][axis] && triangle[1][axis] == triangle[2][axis])
      {
        center[axis] = triangle[0][axis];
      }
      center[axis] = std::clamp(center[axis], m_Box.lower[axis], m_Box.upper[axis]);
    }
  }

  /** The emptied ball may have swallowed any nearby cell, so the insertion locates from scratch. */
  bool
  SplitBoxSubsegment(const BoxSubsegment & subsegment)
  {
    EmptyBall(subsegment.midpoint, std::sqrt(subsegment.squaredRadius), true);
    BoxEdge &    edge = m_BoxEdges[subsegment.edgeIndex];
    const double station = subsegment.midpoint[edge.axis];
    edge.stations.insert(std::upper_bound(edge.stations.begin(), edge.stations.end(), station), station);
    return InsertVertex(subsegment.midpoint, VertexKind::BoxEdge, CellHandle()).has_value();
  }

  /** E1-E3: what R2 does instead when the circumcentre it wants is on or outside the box. */
  bool
  ProtectBox(const Vector3 & circumcenter, CellHandle cell)
  {
    if (const std::optional<BoxSubsegment> subsegment = FindEncroachedBoxSubsegment(circumcenter))
    {
      ++m_Statistics.insertionsE1;
      return SplitBoxSubsegment(*subsegment);
    }
    const std::optional<std::pair<Vector3, double>> facet = FindBoxFacetToward(circumcenter, cell);
    if (!facet)
    {
      ++m_Statistics.unresolvedBoxEncroachments;
      return false;
    }
    const Vector3 & facetCenter = facet->first;
    if (const std::optional<BoxSubsegment> subsegment = FindEncroachedBoxSubsegment(facetCenter))
    {
      ++m_Statistics.insertionsE3;
      return SplitBoxSubsegment(*subsegment);
    }
    ++m_Statistics.insertionsE2;
    EmptyBall(facetCenter, std::sqrt(facet->second), false);
    return InsertVertex(facetCenter, VertexKind::BoxFace, CellHandle()).has_value();
  }

  bool
  Perform(const Action & action, CellHandle cell)
  {
    switch (action.rule)
    {
      case Rule::R1:
        ++m_Statistics.insertionsR1;
        return InsertFeatureVertex(action.point, action.localDelta, cell);
      case Rule::R2:
        if (!IsStrictlyInsideBox(action.point))
        {
          return ProtectBox(action.point, cell);
        }
        ++m_Statistics.insertionsR2;
        return InsertVertex(action.point, VertexKind::Free, cell).has_value();
      case Rule::R3:
        ++m_Statistics.insertionsR3;
        return InsertFeatureVertex(action.point, action.localDelta, cell);
      case Rule::R4:
        ++m_Statistics.insertionsR4;
        return InsertVertex(action.point, VertexKind::Free, cell).has_value();
      case Rule::R4Dihedral:
        ++m_Statistics.insertionsR4Dihedral;
        return InsertVertex(action.point, VertexKind::Free, cell).has_value();
    }
    return false;
  }

  // ---- Main loop ----------------------------------------------------------------------------------------

  bool
  IsAlive(const QueueEntry & entry) const
  {
    return m_Triangulation.tds().cells().is_used(entry.cell) && entry.cell->cache.stamp == entry.stamp;
  }

  void
  RefineUntilNoRuleApplies()
  {
    std::size_t processed = 0;
    while (!m_Queue.Empty())
    {
      const QueueEntry entry = m_Queue.Pop();
      if (!IsAlive(entry))
      {
        ++m_Statistics.staleQueueEntries;
        continue;
      }
      if (++processed % ProgressInterval == 0)
      {
        ReportProgress(processed);
      }
      const std::optional<Action> action = FindApplicableRule(entry.cell);
      if (!action)
      {
        continue;
      }
      const bool inserted = Perform(*action, entry.cell);
      // A tetrahedron that survives its own refinement (the new point fell on its circumsphere) is looked at
      // again; one whose point could not be inserted is given up, or it would be retried forever.
      if (inserted && IsAlive(entry))
      {
        Enqueue(entry.cell);
      }
    }
    ReportProgress(processed);
  }

  void
  ReportProgress(std::size_t processed)
  {
    if (!m_Observer)
    {
      return;
    }
    RefinementProgress progress;
    progress.vertices = m_Triangulation.number_of_vertices();
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

  // ---- Topology -----------------------------------------------------------------------------------------

  /** Where the tissues' boundaries are not 2-manifolds. */
  struct NonManifoldPlaces
  {
    /** The offending boundary vertices. */
    std::vector<Vector3> points;
    /** All boundary vertices. */
    std::size_t numberOfBoundaryVertices{ 0 };
  };

  /** The paper guarantees a manifold only for δ small against the local feature size; a slit or a bridge
   * thinner than δ breaks it. Works on the triangulation's boundary facets directly: a full extraction (every
   * tetrahedron, sorted) costs more than the check itself. */
  NonManifoldPlaces
  FindNonManifoldPlaces() const
  {
    std::vector<VertexHandle>                             boundaryVertices;
    std::map<Label, std::vector<std::array<uint32_t, 3>>> trianglesPerLabel;
    for (auto vertex = m_Triangulation.finite_vertices_begin(); vertex != m_Triangulation.finite_vertices_end();
         ++vertex)
    {
      vertex->info().outputIndex = NoOutputIndex;
    }
    const auto indexOf = [&boundaryVertices](VertexHandle vertex) {
      if (vertex->info().outputIndex == NoOutputIndex)
      {
        vertex->info().outputIndex = static_cast<uint32_t>(boundaryVertices.size());
        boundaryVertices.push_back(vertex);
      }
      return vertex->info().outputIndex;
    };
    ForEachInterfaceFacet(ObjectCells(), [&](CellHandle cell, int facet, Label otherLabel) {
      const std::array<uint32_t, 3> triangle{ indexOf(cell->vertex(Triangulation::vertex_triple_index(facet, 0))),
                                              indexOf(cell->vertex(Triangulation::vertex_triple_index(facet, 1))),
                                              indexOf(cell->vertex(Triangulation::vertex_triple_index(facet, 2))) };
      trianglesPerLabel[cell->cache.label].push_back(triangle);
      if (otherLabel != BackgroundLabel)
      {
        trianglesPerLabel[otherLabel].push_back(triangle);
      }
    });
    std::vector<VertexHandle> offending;
    for (const auto & labelTriangles : trianglesPerLabel)
    {
      for (const uint32_t vertex : FindNonManifoldVertices(labelTriangles.second))
      {
        offending.push_back(boundaryVertices[vertex]);
      }
    }
    // In insertion order, as the extracted mesh numbers its vertices: the zones do not depend on addresses.
    std::sort(offending.begin(), offending.end(), [](const VertexHandle & a, const VertexHandle & b) {
      return a->info().id < b->info().id;
    });
    offending.erase(std::unique(offending.begin(), offending.end()), offending.end());
    NonManifoldPlaces places;
    for (const VertexHandle & vertex : offending)
    {
      places.points.push_back(PointOf(vertex));
    }
    places.numberOfBoundaryVertices = boundaryVertices.size();
    return places;
  }

  /** Halves δ around every non-manifold place and refines again, up to manifoldRefinementLevels times and
   * never below minimumSurfaceSamplingDistance; all rules and guarantees stay as they are, with the local δ
   * (see LocalSampling). It mends isolated defects (a brain mask's one-voxel slit: 0.1 % of its boundary
   * vertices); where most of the boundary is non-manifold (voxel-scale speckle: over half of a k-means
   * segmentation's) refining only resolves more speckle, so it is not tried. It ends because every round
   * halves δ where it refines and δ never goes below the floor. */
  static bool
  IsRepairable(const NonManifoldPlaces & places)
  {
    return static_cast<double>(places.points.size()) <=
           MaximumRepairableFraction * static_cast<double>(places.numberOfBoundaryVertices);
  }

  void
  RefineUntilManifold()
  {
    const double finestDelta =
      std::max(m_Delta / std::pow(2.0, static_cast<double>(m_Parameters.manifoldRefinementLevels)),
               m_Parameters.minimumSurfaceSamplingDistance);
    NonManifoldPlaces places = FindNonManifoldPlaces();
    while (!places.points.empty() && IsRepairable(places))
    {
      // Each place's δ is halved once per round, from its δ before the round: a place inside the zone just made
      // for a nearby one is not halved again (which would refine by how the places happen to be ordered).
      std::vector<std::pair<Vector3, double>> halvings;
      for (const Vector3 & point : places.points)
      {
        const double localDelta = m_Sizing.LocalDelta(point);
        if (localDelta > finestDelta * (1.0 + 1e-12))
        {
          halvings.emplace_back(point, std::max(0.5 * localDelta, finestDelta));
        }
      }
      std::vector<Ball> newZones;
      for (const auto & halving : halvings)
      {
        newZones.push_back({ halving.first, m_Sizing.AddZone(halving.first, halving.second) });
      }
      if (newZones.empty())
      {
        break;
      }
      ++m_Statistics.manifoldRefinementRounds;
      EnqueueCellsAffectedBy(newZones);
      RefineUntilNoRuleApplies();
      places = FindNonManifoldPlaces();
    }
    m_Statistics.manifoldRefinementZones = m_Sizing.NumberOfZones();
    m_Statistics.finestSurfaceSamplingDistance = m_Sizing.FinestDelta();
    m_Statistics.remainingNonManifoldVertices = places.points.size();
  }

  struct Ball
  {
    Vector3 center;
    double  radius;
  };

  /** After the refinement ran out of work, only rules evaluated with a local δ that changed can apply again:
   * R1 at the surface point closest to a circumcentre (inside the circumball), R2 at the circumcentre, R3 at a
   * surface-ball centre on the Voronoi edge between two circumcentres (inside the union of the two
   * circumballs). So the cells whose circumball meets a new zone, and their neighbours, are all that need
   * another look; the rest of the mesh is not walked again. */
  void
  EnqueueCellsAffectedBy(const std::vector<Ball> & zones)
  {
    std::vector<CellHandle> affected;
    for (auto cell = m_Triangulation.finite_cells_begin(); cell != m_Triangulation.finite_cells_end(); ++cell)
    {
      const double radius = std::sqrt(cell->cache.squaredRadius);
      const bool   touched = std::any_of(zones.begin(), zones.end(), [&](const Ball & zone) {
        return Distance(cell->cache.circumcenter, zone.center) < radius + zone.radius;
      });
      if (touched)
      {
        affected.push_back(cell);
        for (int facet = 0; facet < 4; ++facet)
        {
          if (!m_Triangulation.is_infinite(cell->neighbor(facet)))
          {
            affected.push_back(cell->neighbor(facet));
          }
        }
      }
    }
    std::sort(affected.begin(), affected.end());
    affected.erase(std::unique(affected.begin(), affected.end()), affected.end());
    for (const CellHandle cell : affected)
    {
      Enqueue(cell);
    }
  }

  // ---- Output -------------------------------------------------------------------------------------------

  /** The output's vertices: those of the object's tetrahedra, numbered in insertion order, which (unlike
   * the triangulation's container order) does not depend on memory addresses. */
  void
  NumberOutputVertices(const std::vector<CellHandle> & objectCells, TetrahedralMesh & mesh) const
  {
    // Ids are insertion counters: a table indexed by id orders the vertices without a sort.
    std::vector<VertexHandle> verticesById(m_NextVertexId, VertexHandle());
    for (CellHandle cell : objectCells)
    {
      for (int corner = 0; corner < 4; ++corner)
      {
        verticesById[cell->vertex(corner)->info().id] = cell->vertex(corner);
      }
    }
    for (const VertexHandle & vertex : verticesById)
    {
      if (vertex != VertexHandle())
      {
        vertex->info().outputIndex = static_cast<uint32_t>(mesh.points.size());
        mesh.points.push_back(PointOf(vertex));
        mesh.pointKinds.push_back(vertex->info().kind);
      }
    }
  }

  /** Sorted indices, with the last two swapped when sorting was an odd permutation: a canonical form that
   * keeps the orientation. */
  static std::array<uint32_t, 4>
  CanonicalTetrahedron(std::array<uint32_t, 4> indices)
  {
    bool odd = false;
    for (int i = 0; i < 4; ++i)
    {
      for (int j = 0; j + 1 < 4 - i; ++j)
      {
        if (indices[j] > indices[j + 1])
        {
          std::swap(indices[j], indices[j + 1]);
          odd = !odd;
        }
      }
    }
    if (odd)
    {
      std::swap(indices[2], indices[3]);
    }
    return indices;
  }

  /** The facet's vertices ordered so that its normal points away from the cell, smallest index first. CGAL's
   * cells are positively oriented (decided exactly) and vertex_triple_index() lists a facet with its normal
   * pointing into the cell, so the reverse order points out. A floating-point side test would be a coin toss on
   * the tetrahedra flat to rounding that voxel data produce. */
  std::array<uint32_t, 3>
  OutwardFacet(CellHandle cell, int facet) const
  {
    std::array<uint32_t, 3> triangle{ cell->vertex(Triangulation::vertex_triple_index(facet, 0))->info().outputIndex,
                                      cell->vertex(Triangulation::vertex_triple_index(facet, 2))->info().outputIndex,
                                      cell->vertex(Triangulation::vertex_triple_index(facet, 1))->info().outputIndex };
    std::rotate(triangle.begin(), std::min_element(triangle.begin(), triangle.end()), triangle.end());
    return triangle;
  }

  void
  AddTetrahedra(const std::vector<CellHandle> & objectCells, TetrahedralMesh & mesh) const
  {
    std::vector<std::pair<std::array<uint32_t, 4>, Label>> tetrahedra;
    for (CellHandle cell : objectCells)
    {
      tetrahedra.emplace_back(CanonicalTetrahedron({ cell->vertex(0)->info().outputIndex,
                                                     cell->vertex(1)->info().outputIndex,
                                                     cell->vertex(2)->info().outputIndex,
                                                     cell->vertex(3)->info().outputIndex }),
                              cell->cache.label);
    }
    std::sort(tetrahedra.begin(), tetrahedra.end());
    for (const auto & [indices, label] : tetrahedra)
    {
      mesh.tetrahedra.push_back(indices);
      mesh.tetrahedronLabels.push_back(label);
    }
  }

  /** Calls visit(cell, facet, otherLabel) for each interface facet once: from the tissue side when the other
   * side is background, else from the smaller label. */
  template <typename TVisit>
  void
  ForEachInterfaceFacet(const std::vector<CellHandle> & objectCells, TVisit && visit) const
  {
    for (CellHandle cell : objectCells)
    {
      const Label label = cell->cache.label;
      for (int facet = 0; facet < 4; ++facet)
      {
        const Label otherLabel = LabelBeyondFacet(cell, facet);
        if (otherLabel != label && (otherLabel == BackgroundLabel || label < otherLabel))
        {
          visit(cell, facet, otherLabel);
        }
      }
    }
  }

  void
  AddBoundaryTriangles(const std::vector<CellHandle> & objectCells, TetrahedralMesh & mesh) const
  {
    std::vector<std::pair<std::array<uint32_t, 3>, std::array<Label, 2>>> triangles;
    ForEachInterfaceFacet(objectCells, [&](CellHandle cell, int facet, Label otherLabel) {
      triangles.emplace_back(OutwardFacet(cell, facet), std::array<Label, 2>{ cell->cache.label, otherLabel });
    });
    std::sort(triangles.begin(), triangles.end());
    for (const auto & [indices, labels] : triangles)
    {
      mesh.boundaryTriangles.push_back(indices);
      mesh.boundaryTriangleLabels.push_back(labels);
    }
  }

  /** The cells that the output keeps: those whose circumcentre is inside the object. */
  std::vector<CellHandle>
  ObjectCells() const
  {
    std::vector<CellHandle> objectCells;
    for (auto cell = m_Triangulation.finite_cells_begin(); cell != m_Triangulation.finite_cells_end(); ++cell)
    {
      if (cell->cache.label != BackgroundLabel)
      {
        objectCells.push_back(cell);
      }
    }
    return objectCells;
  }

  /** The tetrahedra whose circumcentre is inside the object, in a canonical order. */
  TetrahedralMesh
  ExtractMesh() const
  {
    const std::vector<CellHandle> objectCells = ObjectCells();
    TetrahedralMesh               mesh;
    NumberOutputVertices(objectCells, mesh);
    AddTetrahedra(objectCells, mesh);
    AddBoundaryTriangles(objectCells, mesh);
    return mesh;
  }

  static constexpr std::size_t ProgressInterval = 4096;
  /** Above this fraction of non-manifold boundary vertices the defects are pervasive, not local: see
   * RefineUntilManifold. Measured: brain mask 0.1 %, k-means segmentation 57-69 %. */
  static constexpr double MaximumRepairableFraction = 0.05;

  const LabelOracle &          m_Oracle;
  const RefinementParameters & m_Parameters;
  const ProgressObserver &     m_Observer;
  const double                 m_Delta;

  Triangulation                    m_Triangulation;
  Kernel::Construct_circumcenter_3 m_Circumcenter{ m_Triangulation.geom_traits().construct_circumcenter_3_object() };
  AxisAlignedBox                   m_Box;
  std::vector<BoxEdge>             m_BoxEdges;
  /** Feature vertices never move or go: the grid keeps only their positions, for R1's "any within δ". */
  SpatialGrid<Vector3>      m_FeatureVertices;
  SpatialGrid<VertexHandle> m_FreeVertices;
  std::vector<VertexHandle> m_BoxFaceVertices;
  LocalSampling             m_Sizing;

  RefinementQueue         m_Queue;
  VertexId                m_NextVertexId{ 0 };
  uint64_t                m_LastStamp{ 0 };
  std::vector<CellHandle> m_NewCells;
  double                  m_ProgressFraction{ 0.0 };
  mutable Vector3         m_LastSurfaceQuery{};
  mutable SurfacePoint    m_LastSurfacePoint{};
  mutable bool            m_LastSurfaceQueryValid{ false };
  RefinementStatistics    m_Statistics;
};

/** Beyond it the bounding box (the object's bounds grown by 3δ) makes the fourth powers of its coordinates in the
 * circumcentre constructions overflow double precision (NaN circumcentres follow); and no object could be meshed
 * at such a δ anyway. */
constexpr double LargestSurfaceSamplingDistance = 1e30;

void
RequireInRange(bool inRange, const char * name, double value, const char * validRange)
{
  if (!inRange)
  {
    throw std::invalid_argument(std::string("Invalid parameter ") + name + " = " + DescribeValue(value) +
                                ": the valid range is " + validRange);
  }
}

} // namespace

void
ValidateParameters(const RefinementParameters & parameters)
{
  const double delta = parameters.surfaceSamplingDistance;
  RequireInRange(
    delta > 0.0 && delta <= LargestSurfaceSamplingDistance, "surfaceSamplingDistance (delta)", delta, "(0, 1e30]");
  const double rho = parameters.radiusEdgeBound;
  RequireInRange(std::isfinite(rho) && rho >= 1.0, "radiusEdgeBound (rho)", rho, "[1, +inf)");
  const double sigma = parameters.minimumDihedralAngle;
  RequireInRange(sigma >= 0.0 && sigma <= 30.0, "minimumDihedralAngle (sigma, degrees)", sigma, "[0, 30]");
  const auto maximumVertices = static_cast<double>(parameters.maximumNumberOfVertices);
  RequireInRange(parameters.maximumNumberOfVertices >= 8,
                 "maximumNumberOfVertices",
                 maximumVertices,
                 "[8, +inf) (the bounding box alone has 8)");
  const double floor = parameters.minimumSurfaceSamplingDistance;
  RequireInRange(std::isfinite(floor) && floor >= 0.0, "minimumSurfaceSamplingDistance", floor, "[0, +inf)");
  RequireInRange(parameters.manifoldRefinementLevels <= 10,
                 "manifoldRefinementLevels",
                 static_cast<double>(parameters.manifoldRefinementLevels),
                 "[0, 10]");
}

TetrahedralMesh
RefineMesh(const LabelOracle & oracle, const RefinementParameters & parameters, RefinementStatistics * statistics,
           const ProgressObserver & observer)
{
  ValidateParameters(parameters);
  RefinementStatistics localStatistics;
  Refiner              refiner(oracle, parameters, observer);
  TetrahedralMesh      mesh = refiner.Run(localStatistics);
  if (statistics)
  {
    *statistics = localStatistics;
  }
  return mesh;
}

} // namespace delaunay_refinement
