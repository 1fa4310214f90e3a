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
#ifndef DelaunayRefinementTriangulation_h
#define DelaunayRefinementTriangulation_h

// The triangulation the refinement works on (docs/algorithm.md, "Implementation"): CGAL's 3-D Delaunay
// triangulation with exact predicates, each vertex carrying its kind and insertion id, each cell the cache that
// the rules ask of it. Only the refinement's one translation unit includes this file: no CGAL type reaches a
// public header.

#include "DelaunayRefinementTypes.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Delaunay_triangulation_cell_base_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Robust_weighted_circumcenter_filtered_traits_3.h>
#include <CGAL/Triangulation_data_structure_3.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <cstdint>
#include <limits>

namespace delaunay_refinement
{
namespace detail
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
  /** Whether the manifold test must look at the vertex again (ManifoldRepair::FindNonManifoldPlacesWhereChanged):
   * set for a new vertex, for the corners of every new cell or cell whose label changes, and for the vertices the
   * last search found non-manifold. */
  bool manifoldCheckDue{ true };
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
  /** The label is a neighbour's, given at a non-manifold place (DelaunayRefinementTopologyRelabel.h), not the
   * oracle's at the circumcentre. */
  bool relabelledForTopology{ false };
  /** Scratch for SliverSplit's manifold test, true only while it runs, for the cells of the conflict region it
   * looks at. CGAL's own scratch flag (tds_data) is not free there: incident_cells uses it. */
  mutable bool inConflictRegion{ false };
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

inline Vector3
ToVector(const CgalPoint & point)
{
  return { point.x(), point.y(), point.z() };
}

inline CgalPoint
ToCgal(const Vector3 & point)
{
  return { point[0], point[1], point[2] };
}

} // namespace detail
} // namespace delaunay_refinement

#endif
