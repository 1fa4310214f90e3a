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
#ifndef DelaunayRefinementOracle_h
#define DelaunayRefinementOracle_h

#include "DelaunayRefinementTypes.h"

#include <functional>
#include <limits>
#include <vector>

namespace delaunay_refinement
{

/** A point of the surface together with its distance to the query point. */
struct SurfacePoint
{
  Vector3 point{ { 0.0, 0.0, 0.0 } };
  double  distance{ 0.0 };
};

/** An interval that holds ClosestSurfacePoint(query).distance. */
struct SurfaceDistanceBounds
{
  double lower{ 0.0 };
  double upper{ std::numeric_limits<double>::infinity() };
};

/** \class LabelOracle
 * \brief What the refinement knows of the object: a label-valued function of physical space.
 *
 * The surface (written ∂Ω in docs/algorithm.md) is where the label changes: object/background boundaries and
 * tissue/tissue interfaces alike. Implementations must be deterministic and safe to call from one thread
 * at a time. Outside ObjectBounds() every label must be BackgroundLabel. */
class DelaunayImageToMesh_EXPORT LabelOracle
{
public:
  virtual ~LabelOracle();

  /** Label at a physical point; BackgroundLabel (0) outside every object. */
  virtual Label
  LabelAt(const Vector3 & point) const = 0;

  /** A box holding every point with a non-zero label. Empty if there is no object. */
  virtual AxisAlignedBox
  ObjectBounds() const = 0;

  /** The point of the surface closest to `query` and its distance. The point must lie on the surface (to
   * SurfaceTolerance()); the distance may be approximate to the oracle's resolution. */
  virtual SurfacePoint
  ClosestSurfacePoint(const Vector3 & query) const = 0;

  /** Bounds on the distance ClosestSurfacePoint(query) would return, for an oracle that can bound it much faster
   * than it computes it: the refinement classifies every new tetrahedron by whether its circumsphere meets the
   * surface, and most are destroyed before the closest point itself is asked for. The default, [0, +inf),
   * decides nothing. */
  virtual SurfaceDistanceBounds
  BoundSurfaceDistance(const Vector3 & query) const;

  /** A point where the label changes on the segment [a, b], given LabelAt(a) != LabelAt(b). The default
   * bisects on LabelAt() down to SurfaceTolerance() and returns the midpoint of the last bracket. */
  virtual Vector3
  SurfaceCrossing(const Vector3 & a, const Vector3 & b) const;

  /** How far from the true surface a returned surface point may lie, in physical units. */
  virtual double
  SurfaceTolerance() const = 0;

protected:
  LabelOracle() = default;
};

/** A place where the boundary of the region labelled `label` (its facets against every other label) is not a
 * 2-manifold: one of its vertices. BackgroundLabel stands for the union of the tissues against the background. */
struct NonManifoldPlace
{
  Vector3 point{ { 0.0, 0.0, 0.0 } };
  Label   label{ BackgroundLabel };
};

/** \class TopologyRegularizer
 * \brief An oracle whose labels can be regularised further where the mesh's boundaries came out non-manifold
 * (docs/algorithm.md, "Topology").
 *
 * The refinement calls it between rounds only, never while it asks the oracle anything else: an oracle that is
 * also a TopologyRegularizer may change what LabelAt() and the surface queries answer inside the returned balls,
 * and nowhere else. */
class DelaunayImageToMesh_EXPORT TopologyRegularizer
{
public:
  virtual ~TopologyRegularizer();

  /** Changes the labels in a ball of `radius` around each place, in the given order, so that the place's label
   * either fills the ball or leaves it (whichever changes less), and wherever that made the labels pinch. Returns
   * balls that hold every change (a ball may be larger than `radius`, and a pinch mended outside them has a small
   * ball of its own); none when nothing could be changed. */
  virtual std::vector<Ball>
  RegularizeAround(const std::vector<NonManifoldPlace> & places, double radius) = 0;

protected:
  TopologyRegularizer() = default;
};

/** A point and the label of the tetrahedron it stands for (LabelPartCensus). */
struct LabelledPoint
{
  Vector3 point{ { 0.0, 0.0, 0.0 } };
  Label   label{ BackgroundLabel };
};

/** Labelled points given one at a time: points(visit) calls visit() on each, in a fixed order. The census's points are
 * two per tetrahedron of the mesh: as a vector they were 64 bytes a tetrahedron, 4.5 MB of the peak memory on the 1 mm
 * brain mask at δ = 2 mm, made while the triangulation was still there. */
using LabelledPoints = std::function<void(const std::function<void(const LabelledPoint &)> & visit)>;

/** A part of a label that holds no tetrahedron of it (LabelPartCensus). */
struct UnmeshedPart
{
  Label label{ BackgroundLabel };
  /** The centre of the part's largest ball and its radius, measured up to the limit asked for. */
  Vector3 center{ { 0.0, 0.0, 0.0 } };
  double  radius{ 0.0 };
  /** The part's volume, in cubic physical units. */
  double volume{ 0.0 };
};

/** \class LabelPartCensus
 * \brief An oracle whose labels are voxels' (or follow them, as an iso-surface of linear interpolation does), which can
 * say which parts of them a mesh lost (docs/algorithm.md, "Topology"): a part is the face-connected voxels of one
 * label, as LabelAt() answers now (regularised).
 *
 * The refinement asks it between rounds only, with two points of each tetrahedron of the mesh (its circumcentre and
 * its centroid) and the tetrahedron's label. */
class DelaunayImageToMesh_EXPORT LabelPartCensus
{
public:
  virtual ~LabelPartCensus();

  /** The parts (BackgroundLabel's excepted) of at most `maximumVolume` none of whose voxels holds one of `points` of
   * the part's label, in a fixed order, each with its largest ball measured up to `radiusLimit`. */
  virtual std::vector<UnmeshedPart>
  PartsHoldingNone(const LabelledPoints & points, double radiusLimit,
                   double maximumVolume = std::numeric_limits<double>::infinity()) const = 0;

protected:
  LabelPartCensus() = default;
};

/** Bisection of [a, b] on oracle.LabelAt(), down to `tolerance`; the labels at a and b must differ. Returns
 * the midpoint of the final bracket, whose ends still carry LabelAt(a) and a different label. */
DelaunayImageToMesh_EXPORT Vector3
BisectLabelChange(const LabelOracle & oracle, Vector3 a, Vector3 b, double tolerance);

} // namespace delaunay_refinement

#endif
