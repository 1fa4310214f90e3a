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
#ifndef DelaunayRefinementBoxProtection_h
#define DelaunayRefinementBoxProtection_h

// The bounding box and its protection (docs/algorithm.md, "Set-up" and "Box rules E1-E3"): the box around the
// object whose eight corners are the whole initial mesh, and what R2 does instead when the circumcentre it wants
// lies on or outside the box: split an encroached box-edge subsegment (E1, E3) or a box facet (E2), as TetGen's
// refinement refuses an insertion that would encroach a lower-dimensional element and splits that element instead.

#include "DelaunayRefinementMeshState.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{

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

/** The bounding box, its edges' vertices, and the box rules E1-E3. */
class BoxProtection
{
public:
  BoxProtection(MeshState & state, double delta, RefinementStatistics & statistics)
    : m_State(state)
    , m_Delta(delta)
    , m_Statistics(statistics)
  {}

  /** A box no point of which is closer than 2√2·δ to the surface: the object's bounds grown by 3δ. Its corners
   * go into the mesh. */
  void
  CreateBox(const AxisAlignedBox & objectBounds)
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
    std::array<Vector3, 8> corners;
    for (int corner = 0; corner < 8; ++corner)
    {
      corners[corner] = { (corner & 1) ? m_Box.upper[0] : m_Box.lower[0],
                          (corner & 2) ? m_Box.upper[1] : m_Box.lower[1],
                          (corner & 4) ? m_Box.upper[2] : m_Box.lower[2] };
    }
    m_State.InsertBoxCorners(corners);
  }

  /** The bounding box; empty until CreateBox(). */
  const AxisAlignedBox &
  Box() const
  {
    return m_Box;
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
    m_State.EmptyBall(facetCenter, std::sqrt(facet->second), false);
    return m_State.InsertVertex(facetCenter, VertexKind::BoxFace, CellHandle()).has_value();
  }

private:
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
    const std::array<Vector3, 4> corners = m_State.CornersOf(cell);
    const Vector3                centroid = 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
    const Vector3                exit = BoxExitPoint(centroid, point);
    Triangulation::Locate_type   locateType;
    int                          facetIndex = 0;
    int                          unusedIndex = 0;
    const CellHandle             located =
      m_State.GetTriangulation().locate(ToCgal(exit), locateType, facetIndex, unusedIndex, cell);
    if (locateType != Triangulation::FACET)
    {
      // The exit point is on an edge or a vertex of the hull's triangulation (a measure-zero case).
      return std::nullopt;
    }
    const CgalPoint & a = located->vertex((facetIndex + 1) & 3)->point();
    const CgalPoint & b = located->vertex((facetIndex + 2) & 3)->point();
    const CgalPoint & c = located->vertex((facetIndex + 3) & 3)->point();
    Vector3           center = m_State.TriangleCircumcenter(a, b, c);
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
    m_State.EmptyBall(subsegment.midpoint, std::sqrt(subsegment.squaredRadius), true);
    BoxEdge &    edge = m_BoxEdges[subsegment.edgeIndex];
    const double station = subsegment.midpoint[edge.axis];
    edge.stations.insert(std::upper_bound(edge.stations.begin(), edge.stations.end(), station), station);
    return m_State.InsertVertex(subsegment.midpoint, VertexKind::BoxEdge, CellHandle()).has_value();
  }

  MeshState &            m_State;
  const double           m_Delta;
  RefinementStatistics & m_Statistics;
  AxisAlignedBox         m_Box;
  std::vector<BoxEdge>   m_BoxEdges;
};

} // namespace detail
} // namespace delaunay_refinement

#endif
