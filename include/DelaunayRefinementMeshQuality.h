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
#ifndef DelaunayRefinementMeshQuality_h
#define DelaunayRefinementMeshQuality_h

#include "DelaunayRefinementTypes.h"

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace delaunay_refinement
{

/** Shape measures of the tetrahedra, computed from the mesh alone. Angles in degrees. */
struct TetrahedronQuality
{
  std::size_t numberOfTetrahedra{ 0 };
  /** Largest circumradius / shortest edge over all tetrahedra. */
  double maximumRadiusEdgeRatio{ 0.0 };
  double minimumDihedralAngle{ 180.0 };
  double maximumDihedralAngle{ 0.0 };
  /** Smallest signed volume (negative = inverted). */
  double minimumVolume{ 0.0 };
  double totalVolume{ 0.0 };
  /** Tetrahedra whose orientation, decided exactly, is not positive (negative or flat). A tetrahedron flat to
   * rounding but positively oriented is not counted: its floating-point volume may still be <= 0. */
  std::size_t invertedTetrahedra{ 0 };
  /** Tetrahedra sharing their vertex set with another tetrahedron. */
  std::size_t duplicateTetrahedra{ 0 };
  /** Points not used by any tetrahedron. */
  std::size_t unusedPoints{ 0 };
  /** Tetrahedra with a vertex index out of range or a repeated vertex. */
  std::size_t malformedTetrahedra{ 0 };
  /** Smallest dihedral angle of each tetrahedron, for histograms. */
  std::vector<double> minimumDihedralAngles;
};

DelaunayImageToMesh_EXPORT TetrahedronQuality
ComputeTetrahedronQuality(const TetrahedralMesh & mesh);

/** Topology and angles of a closed triangle surface. */
struct SurfaceTopology
{
  std::size_t numberOfTriangles{ 0 };
  std::size_t numberOfVertices{ 0 };
  std::size_t numberOfEdges{ 0 };
  /** Edges in a number of triangles other than two. */
  std::size_t nonManifoldEdges{ 0 };
  /** Vertices whose link (the triangles around them) is not a single cycle. */
  std::size_t nonManifoldVertices{ 0 };
  /** Edge-connected components. */
  int numberOfComponents{ 0 };
  /** Sum over components of the genus g = (2 - χ) / 2; meaningful only when the surface is a closed manifold. */
  int totalGenus{ 0 };
  /** Genus of each component, in no particular order. */
  std::vector<int> componentGenera;
  /** Smallest planar angle of any triangle, degrees. */
  double minimumPlanarAngle{ 180.0 };

  bool
  IsClosedManifold() const
  {
    return nonManifoldEdges == 0 && nonManifoldVertices == 0;
  }
};

/** Topology of the triangles `triangles` over `points` (indices into points). */
DelaunayImageToMesh_EXPORT SurfaceTopology
ComputeSurfaceTopology(const std::vector<Vector3> & points, const std::vector<std::array<uint32_t, 3>> & triangles);

/** The vertices where the triangles do not form a 2-manifold: a vertex whose link is not a single cycle, or an
 * endpoint of an edge in a number of triangles other than two. Sorted, without repeats. */
DelaunayImageToMesh_EXPORT std::vector<uint32_t>
                           FindNonManifoldVertices(const std::vector<std::array<uint32_t, 3>> & triangles);

/** Topology of every boundary triangle of the mesh (all labels together). */
DelaunayImageToMesh_EXPORT SurfaceTopology
ComputeBoundaryTopology(const TetrahedralMesh & mesh);

/** The boundary triangles with `label` on one of their sides: the boundary of the tetrahedra so labelled. */
DelaunayImageToMesh_EXPORT std::vector<std::array<uint32_t, 3>>
                           LabelBoundaryTriangles(const TetrahedralMesh & mesh, Label label);

/** LabelBoundaryTriangles() of every label on a side of a boundary triangle, in one pass over the triangles: the
 * quality report's per-label topology scanned every triangle once per label, a cost that grew with the number of
 * labels times the mesh (an atlas of hundreds of labels). */
DelaunayImageToMesh_EXPORT std::map<Label, std::vector<std::array<uint32_t, 3>>>
                           BoundaryTrianglesByLabel(const TetrahedralMesh & mesh);

/** Topology of the boundary of the tetrahedra labelled `label`: every boundary triangle with `label` on
 * one of its sides. */
DelaunayImageToMesh_EXPORT SurfaceTopology
ComputeLabelBoundaryTopology(const TetrahedralMesh & mesh, Label label);

/** Largest circumradius of the boundary triangles. Each boundary triangle lies in its surface ball, whose radius
 * R3 keeps below δ, so this is below δ (Theorem 2). A degenerate triangle (collinear or coincident corners) has
 * no circumcircle and counts as +infinity; 0 without boundary triangles. Throws std::invalid_argument for a
 * vertex index out of range. */
DelaunayImageToMesh_EXPORT double
LargestBoundaryCircumradius(const TetrahedralMesh & mesh);

/** The boundary that the tetrahedra and their labels imply, compared with the mesh's boundary triangles. */
struct BoundaryConsistency
{
  /** Facets between different labels (or on the hull of the mesh) that are not boundary triangles. */
  std::size_t missingTriangles{ 0 };
  /** Boundary triangles that are no such facet, or that appear twice. */
  std::size_t extraTriangles{ 0 };
  /** Boundary triangles whose label pair is not {label of its tetrahedron, label on the other side}. */
  std::size_t wrongLabels{ 0 };
  /** Boundary triangles whose normal does not point away from the tetrahedron carrying the first label. */
  std::size_t wrongOrientation{ 0 };
  /** Facets of more than two tetrahedra: the tetrahedra overlap. */
  std::size_t overSharedFacets{ 0 };
  /** The first wrongly oriented triangle and the tetrahedron it faces into (corners, kinds, label), for a
   * report; empty when every triangle is oriented right. */
  std::string firstWronglyOriented;

  bool
  IsConsistent() const
  {
    return missingTriangles == 0 && extraTriangles == 0 && wrongLabels == 0 && wrongOrientation == 0 &&
           overSharedFacets == 0;
  }
};

/** TetrahedralMesh's promise about its boundary, checked facet by facet against the tetrahedra: every facet
 * between different labels (a facet on the hull of the mesh has the background on its other side) is a
 * boundary triangle, once; a tissue/background facet has the tissue first, a tissue/tissue facet the smaller
 * label first; its normal points away from the tetrahedron carrying the first label. The orientation is
 * decided with exact predicates, as the mesher decides the orientation of its tetrahedra: voxel data make
 * tetrahedra flat to rounding, on which a floating-point sign is a coin toss. Throws std::invalid_argument for
 * a vertex index out of range or a label array whose size is not that of the cells it labels. */
DelaunayImageToMesh_EXPORT BoundaryConsistency
CheckBoundaryAgainstTetrahedra(const TetrahedralMesh & mesh);

/** The name of a vertex kind for reports: "box-face", "box-edge", "feature" or "free". */
DelaunayImageToMesh_EXPORT const char *
VertexKindName(VertexKind kind);

/** Point-to-triangle-surface distance queries (an AABB tree over the triangles). */
class DelaunayImageToMesh_EXPORT TriangleSurfaceDistance
{
public:
  TriangleSurfaceDistance(const std::vector<Vector3> & points, const std::vector<std::array<uint32_t, 3>> & triangles);
  ~TriangleSurfaceDistance();
  TriangleSurfaceDistance(const TriangleSurfaceDistance &) = delete;
  TriangleSurfaceDistance &
  operator=(const TriangleSurfaceDistance &) = delete;

  /** Distance from `query` to the nearest triangle; +infinity if there is no triangle. */
  double
  Distance(const Vector3 & query) const;

private:
  struct Tree;
  std::unique_ptr<Tree> m_Tree;
};

/** Points on every triangle, about `spacing` apart (vertices, edge points and interior points). */
DelaunayImageToMesh_EXPORT std::vector<Vector3>
SampleTriangles(const std::vector<Vector3> & points, const std::vector<std::array<uint32_t, 3>> & triangles,
                double spacing);

/** Summary of a set of distances. */
struct DistanceStatistics
{
  std::size_t count{ 0 };
  double      mean{ 0.0 };
  double      percentile95{ 0.0 };
  double      maximum{ 0.0 };
};

DelaunayImageToMesh_EXPORT DistanceStatistics
SummarizeDistances(std::vector<double> distances);

/** Two-sided distance between two triangle surfaces, each sampled at `spacing` and measured against the
 * other's AABB tree. `fromFirst` holds first-to-second distances, `fromSecond` second-to-first. */
struct TwoSidedDistance
{
  DistanceStatistics fromFirst;
  DistanceStatistics fromSecond;
  /** Statistics of both directions pooled; its maximum is the sampled two-sided Hausdorff distance. */
  DistanceStatistics combined;
};

/** Told the fraction of the samples measured so far, in [0, 1], from the calling thread only: on a speckled
 * segmentation's marching-cubes surface the measurement takes minutes. */
using DistanceProgress = std::function<void(double)>;

/** `progress`, when given, is told how far the measurement is (after the search trees are built, which is about a
 * sixth of the time), ending with 1. */
DelaunayImageToMesh_EXPORT TwoSidedDistance
ComputeTwoSidedDistance(const std::vector<Vector3> &                 firstPoints,
                        const std::vector<std::array<uint32_t, 3>> & firstTriangles,
                        const std::vector<Vector3> &                 secondPoints,
                        const std::vector<std::array<uint32_t, 3>> & secondTriangles, double spacing,
                        const DistanceProgress & progress = {});

/** Shortest edge from a vertex of each kind, for Lemma 2 (feature >= δ, free >= ρδ, box >= 2δ). Only edges
 * of the mesh's tetrahedra are seen; +infinity for a kind with no vertex. */
struct ShortestEdgesByKind
{
  std::map<VertexKind, double> shortestEdge;
};

DelaunayImageToMesh_EXPORT ShortestEdgesByKind
ComputeShortestEdgesByKind(const TetrahedralMesh & mesh);

} // namespace delaunay_refinement

#endif
