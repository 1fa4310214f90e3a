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
#ifndef DelaunayRefinementAnalyticOracles_h
#define DelaunayRefinementAnalyticOracles_h

#include "DelaunayRefinementOracle.h"

#include <cstdint>
#include <vector>

namespace delaunay_refinement
{

/** \class AnalyticOracle
 * \brief A shape known in closed form: exact labels, exact closest surface points, known topology.
 *
 * Every shape here is the set of points within a distance r of a simple "core" set (a point, a circle, a
 * flat plate with holes), whose closest-point map is exact; this keeps the surfaces smooth (C^1,1) and the
 * distance to them exact, which the tests need to measure Hausdorff distances. */
class DelaunayImageToMesh_EXPORT AnalyticOracle : public LabelOracle
{
public:
  double
  SurfaceTolerance() const override;

  /** About `count` points on the surface, deterministic for a given seed: pseudo-random points of the
   * bounding box projected onto the surface. Dense enough to measure the surface-to-mesh distance. */
  std::vector<Vector3>
  SampleSurface(std::size_t count, uint32_t seed = 1) const;

  /** Number of connected components of the surface. */
  virtual int
  NumberOfSurfaceComponents() const = 0;

  /** Sum of the genera of the surface components. */
  virtual int
  TotalGenus() const = 0;

  /** A lower bound of the local feature size (distance from the surface to its medial axis). */
  virtual double
  MinimumLocalFeatureSize() const = 0;
};

/** A ball; label `label` inside. */
class DelaunayImageToMesh_EXPORT SphereOracle : public AnalyticOracle
{
public:
  SphereOracle(const Vector3 & center, double radius, Label label = 1);
  Label
  LabelAt(const Vector3 & point) const override;
  AxisAlignedBox
  ObjectBounds() const override;
  SurfacePoint
  ClosestSurfacePoint(const Vector3 & query) const override;
  int
  NumberOfSurfaceComponents() const override
  {
    return 1;
  }
  int
  TotalGenus() const override
  {
    return 0;
  }
  double
  MinimumLocalFeatureSize() const override
  {
    return m_Radius;
  }

private:
  Vector3 m_Center;
  double  m_Radius;
  Label   m_Label;
};

/** A solid torus around the z axis through `center`: points within `minorRadius` of the circle of radius
 * `majorRadius`. Label 1 inside. */
class DelaunayImageToMesh_EXPORT TorusOracle : public AnalyticOracle
{
public:
  TorusOracle(const Vector3 & center, double majorRadius, double minorRadius);
  Label
  LabelAt(const Vector3 & point) const override;
  AxisAlignedBox
  ObjectBounds() const override;
  SurfacePoint
  ClosestSurfacePoint(const Vector3 & query) const override;
  int
  NumberOfSurfaceComponents() const override
  {
    return 1;
  }
  int
  TotalGenus() const override
  {
    return 1;
  }
  double
  MinimumLocalFeatureSize() const override;

private:
  Vector3 m_Center;
  double  m_MajorRadius;
  double  m_MinorRadius;
};

/** Two disjoint balls, both labelled 1. */
class DelaunayImageToMesh_EXPORT TwoSpheresOracle : public AnalyticOracle
{
public:
  TwoSpheresOracle(const Vector3 & firstCenter, double firstRadius, const Vector3 & secondCenter, double secondRadius);
  Label
  LabelAt(const Vector3 & point) const override;
  AxisAlignedBox
  ObjectBounds() const override;
  SurfacePoint
  ClosestSurfacePoint(const Vector3 & query) const override;
  int
  NumberOfSurfaceComponents() const override
  {
    return 2;
  }
  int
  TotalGenus() const override
  {
    return 0;
  }
  double
  MinimumLocalFeatureSize() const override;

private:
  SphereOracle m_First;
  SphereOracle m_Second;
  double       m_HalfGap;
};

/** A genus-2 solid: the points within `thickness` of a flat plate in the z = center plane. The plate is a
 * stadium (points within `plateRadius` of the segment from center - (halfLength, 0, 0) to center +
 * (halfLength, 0, 0)) with two round holes of radius `holeRadius` centred on the segment's ends. Needs
 * thickness < holeRadius < plateRadius - thickness, so each hole stays open. Label 1 inside. */
class DelaunayImageToMesh_EXPORT Genus2Oracle : public AnalyticOracle
{
public:
  Genus2Oracle(const Vector3 & center, double halfLength, double plateRadius, double holeRadius, double thickness);
  Label
  LabelAt(const Vector3 & point) const override;
  AxisAlignedBox
  ObjectBounds() const override;
  SurfacePoint
  ClosestSurfacePoint(const Vector3 & query) const override;
  int
  NumberOfSurfaceComponents() const override
  {
    return 1;
  }
  int
  TotalGenus() const override
  {
    return 2;
  }
  double
  MinimumLocalFeatureSize() const override;

private:
  /** Closest point of the flat plate to `query`, relative to the centre. */
  Vector3
  ClosestPlatePoint(const Vector3 & query) const;

  Vector3 m_Center;
  double  m_HalfLength;
  double  m_PlateRadius;
  double  m_HoleRadius;
  double  m_Thickness;
};

/** Two tissues: a ball of radius `innerRadius` labelled 2 inside a ball of radius `outerRadius` labelled 1
 * (a shell around a core). The surface has two components: the interface sphere and the outer sphere. */
class DelaunayImageToMesh_EXPORT NestedSpheresOracle : public AnalyticOracle
{
public:
  NestedSpheresOracle(const Vector3 & center, double innerRadius, double outerRadius);
  Label
  LabelAt(const Vector3 & point) const override;
  AxisAlignedBox
  ObjectBounds() const override;
  SurfacePoint
  ClosestSurfacePoint(const Vector3 & query) const override;
  int
  NumberOfSurfaceComponents() const override
  {
    return 2;
  }
  int
  TotalGenus() const override
  {
    return 0;
  }
  double
  MinimumLocalFeatureSize() const override;

private:
  SphereOracle m_Inner;
  SphereOracle m_Outer;
};

} // namespace delaunay_refinement

#endif
