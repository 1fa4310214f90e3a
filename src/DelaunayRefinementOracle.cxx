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
#include "DelaunayRefinementOracle.h"

namespace delaunay_refinement
{

LabelOracle::~LabelOracle() = default;

TopologyRegularizer::~TopologyRegularizer() = default;
LabelPartCensus::~LabelPartCensus() = default;

SurfaceDistanceBounds
LabelOracle::BoundSurfaceDistance(const Vector3 &) const
{
  return {};
}

Vector3
LabelOracle::SurfaceCrossing(const Vector3 & a, const Vector3 & b) const
{
  return BisectLabelChange(*this, a, b, SurfaceTolerance());
}

Vector3
BisectLabelChange(const LabelOracle & oracle, Vector3 a, Vector3 b, double tolerance)
{
  const Label labelAtA = oracle.LabelAt(a);
  // The bracket halves every step; 200 steps reach any tolerance representable in double precision, which
  // bounds the loop even for a tolerance of 0.
  for (int step = 0; step < 200 && SquaredNorm(b - a) > tolerance * tolerance; ++step)
  {
    const Vector3 middle = 0.5 * (a + b);
    if (oracle.LabelAt(middle) == labelAtA)
    {
      a = middle;
    }
    else
    {
      b = middle;
    }
  }
  return 0.5 * (a + b);
}

} // namespace delaunay_refinement
