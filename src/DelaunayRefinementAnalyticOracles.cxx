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
#include "DelaunayRefinementAnalyticOracles.h"

#include <algorithm>
#include <random>
#include <stdexcept>
#include <string>

namespace delaunay_refinement
{
namespace
{

/** Below this length, relative to the offset, the direction from a core point to a query is rounding noise:
 * the query sits on the core, where any normal direction of the core is right. */
constexpr double DegenerateRelativeLength = 1e-12;

/** The point at distance `offset` from `corePoint` in the direction of `query`: the closest point of the
 * offset surface {x : dist(x, core) = offset} when `corePoint` is the core point closest to `query`. Both are
 * in the shape's local frame, so that a query on the core gives an exactly zero difference, not rounding
 * noise that would be normalised into a wrong direction. */
SurfacePoint
OffsetSurfacePoint(const Vector3 & query, const Vector3 & corePoint, double offset, const Vector3 & fallbackDirection)
{
  const Vector3 toQuery = query - corePoint;
  const double  length = Norm(toQuery);
  const Vector3 direction = length > DegenerateRelativeLength * offset ? (1.0 / length) * toQuery : fallbackDirection;
  return { corePoint + offset * direction, std::abs(length - offset) };
}

/** A surface point computed in a shape's local frame, moved back to physical space. */
SurfacePoint
FromLocal(SurfacePoint local, const Vector3 & center)
{
  local.point = center + local.point;
  return local;
}

SurfacePoint
Closer(const SurfacePoint & a, const SurfacePoint & b)
{
  return b.distance < a.distance ? b : a;
}

AxisAlignedBox
BoxAround(const Vector3 & center, const Vector3 & halfExtent)
{
  return { center - halfExtent, center + halfExtent };
}

AxisAlignedBox
Union(const AxisAlignedBox & a, const AxisAlignedBox & b)
{
  AxisAlignedBox result;
  for (int axis = 0; axis < 3; ++axis)
  {
    result.lower[axis] = std::min(a.lower[axis], b.lower[axis]);
    result.upper[axis] = std::max(a.upper[axis], b.upper[axis]);
  }
  return result;
}

void
RequirePositive(double value, const char * name)
{
  if (!(value > 0.0) || !std::isfinite(value))
  {
    throw std::invalid_argument(std::string(name) + " = " + std::to_string(value) + " must be finite and > 0");
  }
}

const Vector3 UnitZ{ { 0.0, 0.0, 1.0 } };

} // namespace

double
AnalyticOracle::SurfaceTolerance() const
{
  const AxisAlignedBox bounds = ObjectBounds();
  return 1e-10 * Distance(bounds.lower, bounds.upper);
}

std::vector<Vector3>
AnalyticOracle::SampleSurface(std::size_t count, uint32_t seed) const
{
  const AxisAlignedBox                                bounds = ObjectBounds();
  const Vector3                                       margin = 0.1 * (bounds.upper - bounds.lower);
  std::mt19937                                        generator(seed);
  std::vector<std::uniform_real_distribution<double>> coordinate;
  for (int axis = 0; axis < 3; ++axis)
  {
    coordinate.emplace_back(bounds.lower[axis] - margin[axis], bounds.upper[axis] + margin[axis]);
  }
  std::vector<Vector3> samples;
  samples.reserve(count);
  for (std::size_t i = 0; i < count; ++i)
  {
    const Vector3 point{ { coordinate[0](generator), coordinate[1](generator), coordinate[2](generator) } };
    samples.push_back(ClosestSurfacePoint(point).point);
  }
  return samples;
}

SphereOracle::SphereOracle(const Vector3 & center, double radius, Label label)
  : m_Center(center)
  , m_Radius(radius)
  , m_Label(label)
{
  RequirePositive(radius, "radius");
}

Label
SphereOracle::LabelAt(const Vector3 & point) const
{
  return SquaredNorm(point - m_Center) < m_Radius * m_Radius ? m_Label : BackgroundLabel;
}

AxisAlignedBox
SphereOracle::ObjectBounds() const
{
  return BoxAround(m_Center, { { m_Radius, m_Radius, m_Radius } });
}

SurfacePoint
SphereOracle::ClosestSurfacePoint(const Vector3 & query) const
{
  return FromLocal(OffsetSurfacePoint(query - m_Center, Vector3{ { 0.0, 0.0, 0.0 } }, m_Radius, UnitZ), m_Center);
}

TorusOracle::TorusOracle(const Vector3 & center, double majorRadius, double minorRadius)
  : m_Center(center)
  , m_MajorRadius(majorRadius)
  , m_MinorRadius(minorRadius)
{
  RequirePositive(minorRadius, "minorRadius");
  RequirePositive(majorRadius - minorRadius, "majorRadius - minorRadius");
}

Label
TorusOracle::LabelAt(const Vector3 & point) const
{
  const Vector3 local = point - m_Center;
  const double  radial = std::hypot(local[0], local[1]) - m_MajorRadius;
  return radial * radial + local[2] * local[2] < m_MinorRadius * m_MinorRadius ? 1 : BackgroundLabel;
}

AxisAlignedBox
TorusOracle::ObjectBounds() const
{
  const double outer = m_MajorRadius + m_MinorRadius;
  return BoxAround(m_Center, { { outer, outer, m_MinorRadius } });
}

SurfacePoint
TorusOracle::ClosestSurfacePoint(const Vector3 & query) const
{
  const Vector3 local = query - m_Center;
  const double  radial = std::hypot(local[0], local[1]);
  // On the axis every point of the core circle is closest; take the one on the +x side.
  const Vector3 radialDirection = radial > DegenerateRelativeLength * m_MajorRadius
                                    ? Vector3{ { local[0] / radial, local[1] / radial, 0.0 } }
                                    : Vector3{ { 1.0, 0.0, 0.0 } };
  const Vector3 corePoint = m_MajorRadius * radialDirection;
  return FromLocal(OffsetSurfacePoint(local, corePoint, m_MinorRadius, radialDirection), m_Center);
}

double
TorusOracle::MinimumLocalFeatureSize() const
{
  return std::min(m_MinorRadius, m_MajorRadius - m_MinorRadius);
}

TwoSpheresOracle::TwoSpheresOracle(const Vector3 & firstCenter, double firstRadius, const Vector3 & secondCenter,
                                   double secondRadius)
  : m_First(firstCenter, firstRadius)
  , m_Second(secondCenter, secondRadius)
  , m_HalfGap(0.5 * (Distance(firstCenter, secondCenter) - firstRadius - secondRadius))
{
  RequirePositive(m_HalfGap, "gap between the spheres");
}

Label
TwoSpheresOracle::LabelAt(const Vector3 & point) const
{
  return std::max(m_First.LabelAt(point), m_Second.LabelAt(point));
}

AxisAlignedBox
TwoSpheresOracle::ObjectBounds() const
{
  return Union(m_First.ObjectBounds(), m_Second.ObjectBounds());
}

SurfacePoint
TwoSpheresOracle::ClosestSurfacePoint(const Vector3 & query) const
{
  return Closer(m_First.ClosestSurfacePoint(query), m_Second.ClosestSurfacePoint(query));
}

double
TwoSpheresOracle::MinimumLocalFeatureSize() const
{
  return std::min({ m_First.MinimumLocalFeatureSize(), m_Second.MinimumLocalFeatureSize(), m_HalfGap });
}

Genus2Oracle::Genus2Oracle(const Vector3 & center, double halfLength, double plateRadius, double holeRadius,
                           double thickness)
  : m_Center(center)
  , m_HalfLength(halfLength)
  , m_PlateRadius(plateRadius)
  , m_HoleRadius(holeRadius)
  , m_Thickness(thickness)
{
  RequirePositive(thickness, "thickness");
  RequirePositive(holeRadius - thickness, "holeRadius - thickness");
  RequirePositive(plateRadius - holeRadius - thickness, "plateRadius - holeRadius - thickness");
  RequirePositive(halfLength - holeRadius, "halfLength - holeRadius");
}

Vector3
Genus2Oracle::ClosestPlatePoint(const Vector3 & query) const
{
  const Vector3 local = query - m_Center;
  const Vector3 inPlane{ { local[0], local[1], 0.0 } };
  const Vector3 onSegment{ { std::clamp(local[0], -m_HalfLength, m_HalfLength), 0.0, 0.0 } };
  const Vector3 fromSegment = inPlane - onSegment;
  const double  distanceToSegment = Norm(fromSegment);
  if (distanceToSegment > m_PlateRadius)
  {
    return onSegment + (m_PlateRadius / distanceToSegment) * fromSegment;
  }
  for (const double holeX : { -m_HalfLength, m_HalfLength })
  {
    const Vector3 fromHole{ { local[0] - holeX, local[1], 0.0 } };
    const double  distanceToHoleCenter = Norm(fromHole);
    if (distanceToHoleCenter < m_HoleRadius)
    {
      const Vector3 direction = distanceToHoleCenter > DegenerateRelativeLength * m_HoleRadius
                                  ? (1.0 / distanceToHoleCenter) * fromHole
                                  : Vector3{ { 1.0, 0.0, 0.0 } };
      return Vector3{ { holeX, 0.0, 0.0 } } + m_HoleRadius * direction;
    }
  }
  return inPlane;
}

Label
Genus2Oracle::LabelAt(const Vector3 & point) const
{
  return SquaredNorm(point - m_Center - ClosestPlatePoint(point)) < m_Thickness * m_Thickness ? 1 : BackgroundLabel;
}

AxisAlignedBox
Genus2Oracle::ObjectBounds() const
{
  const double outer = m_PlateRadius + m_Thickness;
  return BoxAround(m_Center, { { m_HalfLength + outer, outer, m_Thickness } });
}

SurfacePoint
Genus2Oracle::ClosestSurfacePoint(const Vector3 & query) const
{
  return FromLocal(OffsetSurfacePoint(query - m_Center, ClosestPlatePoint(query), m_Thickness, UnitZ), m_Center);
}

double
Genus2Oracle::MinimumLocalFeatureSize() const
{
  return std::min(m_Thickness, m_HoleRadius - m_Thickness);
}

NestedSpheresOracle::NestedSpheresOracle(const Vector3 & center, double innerRadius, double outerRadius)
  : m_Inner(center, innerRadius, 2)
  , m_Outer(center, outerRadius, 1)
{
  RequirePositive(outerRadius - innerRadius, "outerRadius - innerRadius");
}

Label
NestedSpheresOracle::LabelAt(const Vector3 & point) const
{
  return std::max(m_Inner.LabelAt(point), m_Outer.LabelAt(point));
}

AxisAlignedBox
NestedSpheresOracle::ObjectBounds() const
{
  return m_Outer.ObjectBounds();
}

SurfacePoint
NestedSpheresOracle::ClosestSurfacePoint(const Vector3 & query) const
{
  return Closer(m_Inner.ClosestSurfacePoint(query), m_Outer.ClosestSurfacePoint(query));
}

double
NestedSpheresOracle::MinimumLocalFeatureSize() const
{
  const double shellHalfThickness = 0.5 * (m_Outer.MinimumLocalFeatureSize() - m_Inner.MinimumLocalFeatureSize());
  return std::min(m_Inner.MinimumLocalFeatureSize(), shellHalfThickness);
}

} // namespace delaunay_refinement
