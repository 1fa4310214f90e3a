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
#include "DelaunayRefinementParameters.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace delaunay_refinement
{
namespace
{

void
RequireInRange(bool inRange, const char * name, double value, const std::string & validRange)
{
  if (!inRange)
  {
    throw std::invalid_argument(std::string("Invalid parameter ") + name + " = " + DescribeValue(value) +
                                ": the valid range is " + validRange);
  }
}

/** A range's end as people write it (1e+30, not the 17 digits of the nearest double). */
std::string
DescribeLimit(double limit)
{
  std::ostringstream stream;
  stream << limit;
  return stream.str();
}

} // namespace

std::string
DescribeValue(double value)
{
  std::ostringstream stream;
  stream.precision(17);
  stream << value;
  return stream.str();
}

void
ValidateParameters(const RefinementParameters & parameters)
{
  using Limits = ParameterLimits;
  const double delta = parameters.surfaceSamplingDistance;
  RequireInRange(delta > 0.0 && delta <= Limits::LargestSurfaceSamplingDistance,
                 "surfaceSamplingDistance (delta)",
                 delta,
                 "(0, " + DescribeLimit(Limits::LargestSurfaceSamplingDistance) + "]");
  const double rho = parameters.radiusEdgeBound;
  RequireInRange(std::isfinite(rho) && rho >= Limits::SmallestRadiusEdgeBound,
                 "radiusEdgeBound (rho)",
                 rho,
                 "[" + DescribeLimit(Limits::SmallestRadiusEdgeBound) + ", +inf)");
  const double sigma = parameters.minimumDihedralAngle;
  RequireInRange(sigma >= 0.0 && sigma <= Limits::LargestMinimumDihedralAngle,
                 "minimumDihedralAngle (sigma, degrees)",
                 sigma,
                 "[0, " + DescribeLimit(Limits::LargestMinimumDihedralAngle) + "]");
  RequireInRange(parameters.maximumNumberOfVertices >= Limits::SmallestMaximumNumberOfVertices,
                 "maximumNumberOfVertices",
                 static_cast<double>(parameters.maximumNumberOfVertices),
                 "[" + std::to_string(Limits::SmallestMaximumNumberOfVertices) +
                   ", +inf) (the bounding box alone has 8)");
  const double floor = parameters.minimumSurfaceSamplingDistance;
  RequireInRange(std::isfinite(floor) && floor >= 0.0, "minimumSurfaceSamplingDistance", floor, "[0, +inf)");
  RequireInRange(parameters.manifoldRefinementLevels <= Limits::LargestManifoldRefinementLevels,
                 "manifoldRefinementLevels",
                 static_cast<double>(parameters.manifoldRefinementLevels),
                 "[0, " + std::to_string(Limits::LargestManifoldRefinementLevels) + "]");
  RequireInRange(parameters.topologyRegularizationRounds <= Limits::LargestTopologyRegularizationRounds,
                 "topologyRegularizationRounds",
                 static_cast<double>(parameters.topologyRegularizationRounds),
                 "[0, " + std::to_string(Limits::LargestTopologyRegularizationRounds) + "]");
}

} // namespace delaunay_refinement
