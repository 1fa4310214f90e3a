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

// Unit tests of itk::DelaunayImageToMeshFilter. Every guarantee is measured on the filter's ITK outputs with
// the measures of DelaunayRefinementMeshQuality.h. Every bound is justified in the comment next to it, from the
// algorithm's rules and the image's geometry where a proof exists and from a stated argument where not; none
// is fitted to a measured value.

#include "itkDelaunayImageToMeshFilter.h"
#include "itkImageLabelOracle.h"
#include "itkLabelVolume.h"
#include "itkDelaunayImageToMeshFilterTestHelpers.h"
#include "itkTetrahedralMeshVoxelizer.h"

#include "DelaunayImageToMeshQualityReport.h"
#include "DelaunayRefinementBoundaryVertexChecks.h"
#include "DelaunayRefinementLocalSizingChecks.h"
#include "DelaunayRefinementTestHooks.h"

#include "itkCommand.h"
#include "itkImageFileReader.h"
#include "itkImageRegionConstIterator.h"
#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkLabelImageGaussianInterpolateImageFunction.h"
#include "itkNearestNeighborInterpolateImageFunction.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <iterator>
#include <limits>
#include <memory>
#include <set>

namespace
{

using namespace itk::delaunay_image_to_mesh_test;
using FilterType = itk::DelaunayImageToMeshFilter<LabelImageType, MeshType>;
using FloatImageType = itk::Image<float, 3>;
using FloatFilterType = itk::DelaunayImageToMeshFilter<FloatImageType, MeshType>;
using Clock = std::chrono::steady_clock;

constexpr double Pi = 3.14159265358979323846;

/** Only rounding may eat into a bound that the theory gives exactly. */
constexpr double RoundingSlack = 1e-9;

/** Feature vertices are bisected onto the oracle's surface to 1e-4 × the smallest spacing (ImageLabelOracle);
 * a thousandth of a millimetre covers that for every image here (spacings up to 3 mm). */
constexpr double SurfacePointTolerance = 1e-3;

double
Seconds(Clock::time_point since)
{
  return std::chrono::duration<double>(Clock::now() - since).count();
}

// ---- Running the filter and measuring what it produced ---------------------------------------------------

/** A filter run and the measures every test looks at, taken on the filter's ITK outputs. */
template <typename TFilter>
struct Meshed
{
  typename TFilter::Pointer filter;
  dr::TetrahedralMesh       mesh;
  double                    seconds{ 0.0 };
  dr::TetrahedronQuality    quality;
  dr::SurfaceTopology       boundary;
  BoundaryConsistency       consistency;
};

template <typename TFilter>
std::unique_ptr<Meshed<TFilter>>
RunFilter(const typename TFilter::Pointer & filter)
{
  auto       meshed = std::make_unique<Meshed<TFilter>>();
  const auto start = Clock::now();
  filter->Update();
  meshed->seconds = Seconds(start);
  meshed->filter = filter;
  meshed->mesh = TetrahedralMeshFromOutputs(*filter);
  meshed->quality = dr::ComputeTetrahedronQuality(meshed->mesh);
  meshed->boundary = dr::ComputeBoundaryTopology(meshed->mesh);
  meshed->consistency = CheckBoundaryAgainstTetrahedra(meshed->mesh);
  return meshed;
}

template <typename TImage>
typename itk::DelaunayImageToMeshFilter<TImage, MeshType>::Pointer
FilterFor(const TImage * image, double delta)
{
  auto filter = itk::DelaunayImageToMeshFilter<TImage, MeshType>::New();
  filter->SetInput(image);
  filter->SetSurfaceSamplingDistance(delta);
  return filter;
}

/** R4′'s promise, the one bound it adds: every dihedral angle at least σ (to rounding). */
void
ExpectDihedralAnglesReach(const dr::TetrahedronQuality & quality, double sigma)
{
  EXPECT_GE(quality.minimumDihedralAngle, sigma * (1.0 - RoundingSlack)) << "sigma " << sigma;
}

/** The same for the σ the filter ran with. */
template <typename TFilter>
void
ExpectDihedralAnglesReachSigma(const Meshed<TFilter> & meshed)
{
  ExpectDihedralAnglesReach(meshed.quality, meshed.filter->GetMinimumDihedralAngle());
}

/** The guarantees of docs/algorithm.md that hold for any object with ρ >= 1 and σ = 0: well-formed tetrahedra,
 * radius-edge < ρ, boundary planar angles > 30°, Lemma 2's shortest edges, every boundary triangle inside
 * its surface ball (radius < δ by R3, so circumradius < δ), with ρ >= 2 only feature vertices on the
 * boundary (Lemma 5, where δ is uniform), and a boundary that is exactly the facets between different labels.
 * With σ > 0 (the default), R4′ inserts free points that may come closer than δ to others, so Lemma 2's edges are
 * not asserted, nor Lemma 5, which rests on them (a free vertex may reach a boundary, still a corner of triangles
 * inside their surface balls: docs/algorithm.md, "Guarantees"); dihedral angles >= σ are, with every other bound. */
template <typename TFilter>
void
ExpectGuarantees(const Meshed<TFilter> & meshed)
{
  const double delta = meshed.filter->GetEffectiveSurfaceSamplingDistance();
  const double rho = meshed.filter->GetRadiusEdgeBound();
  ASSERT_FALSE(meshed.mesh.tetrahedra.empty());
  ASSERT_FALSE(meshed.mesh.boundaryTriangles.empty());
  EXPECT_EQ(meshed.quality.malformedTetrahedra, 0u);
  EXPECT_EQ(meshed.quality.duplicateTetrahedra, 0u);
  EXPECT_EQ(meshed.quality.unusedPoints, 0u);
  EXPECT_EQ(meshed.quality.invertedTetrahedra, 0u) << "smallest signed volume " << meshed.quality.minimumVolume;
  EXPECT_GT(meshed.quality.minimumVolume, 0.0);
  EXPECT_LT(meshed.quality.maximumRadiusEdgeRatio, rho);
  EXPECT_GT(meshed.boundary.minimumPlanarAngle, 30.0);
  EXPECT_TRUE(meshed.consistency.IsConsistent())
    << "missing " << meshed.consistency.missingTriangles << ", extra " << meshed.consistency.extraTriangles
    << ", wrong labels " << meshed.consistency.wrongLabels << ", wrong orientation "
    << meshed.consistency.wrongOrientation << ", over-shared facets " << meshed.consistency.overSharedFacets;
  // R3's surface balls, so the triangles' circumradii, stay below δ with its lattice tie margin.
  EXPECT_LT(LargestBoundaryCircumradius(meshed.mesh), delta * (1.0 + dr::LatticeTieMargin));
  const double sigma = meshed.filter->GetMinimumDihedralAngle();
  const auto & statistics = meshed.filter->GetRefinementStatistics();
  if (sigma > 0.0)
  {
    ExpectDihedralAnglesReachSigma(meshed);
  }
  // Lemma 2 edge by edge (feature and free edges with σ = 0 only), against the sampling distance the refinement
  // exported at each point, which must be δ, or δ halved no more often than the zones allow: not against the finest δ
  // the refinement reports about itself, which a refinement that halved δ everywhere would report as well.
  const dr::LocalSizingReport sizing =
    dr::CheckEdgesAgainstTheRefinementsSizing(meshed.filter->GetRefinedMesh(),
                                              delta,
                                              rho,
                                              sigma,
                                              meshed.filter->GetManifoldRefinementLevels(),
                                              statistics.thickPartRounds,
                                              RoundingSlack);
  for (const std::string & problem : sizing.problems)
  {
    ADD_FAILURE() << problem;
  }
  EXPECT_EQ(CountFlatTetrahedra(meshed.mesh), 0u);
  std::size_t backgroundTetrahedra = 0;
  for (const dr::Label label : meshed.mesh.tetrahedronLabels)
  {
    backgroundTetrahedra += label == dr::BackgroundLabel;
  }
  EXPECT_EQ(backgroundTetrahedra, 0u);
  // Lemma 5 needs Lemma 2 and a uniform δ (a free vertex's edges >= 2δ put any facet through it above R3's
  // threshold); where the manifold refinement or a part's zone (docs/algorithm.md, "Local sampling distance") made δ
  // smaller locally, a feature vertex there clears free vertices within twice the finer δ only, and the transition
  // may leave a free vertex on the boundary (the k-means tissues at 6 mm, which have one such zone: a free corner
  // 1.2δ from the nearest feature vertex; none without the zone), and so may R4′ (σ > 0), so the lemma is checked
  // where its hypotheses hold, as the randomized suite does: a uniform δ read from the sizing the mesh exports, not
  // from the refinement's account of its zones.
  if (rho >= 2.0 && !sizing.refinedLocally && !(sigma > 0.0))
  {
    EXPECT_EQ(dr::NonFeatureBoundaryCorners(meshed.mesh).size(), 0u);
  }
}

/** The first few edges in other than two of `triangles`, with their end points and number of triangles. */
std::string
DescribeNonManifoldEdges(const dr::TetrahedralMesh & mesh, const std::vector<std::array<uint32_t, 3>> & triangles,
                         std::size_t atMost = 5)
{
  std::map<std::pair<uint32_t, uint32_t>, int> trianglesOfEdge;
  for (const auto & triangle : triangles)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      const uint32_t a = triangle[corner];
      const uint32_t b = triangle[(corner + 1) % 3];
      ++trianglesOfEdge[{ std::min(a, b), std::max(a, b) }];
    }
  }
  std::ostringstream text;
  std::size_t        described = 0;
  for (const auto & entry : trianglesOfEdge)
  {
    if (entry.second != 2 && described++ < atMost)
    {
      const dr::Vector3 & a = mesh.points[entry.first.first];
      const dr::Vector3 & b = mesh.points[entry.first.second];
      text << "edge (" << a[0] << ", " << a[1] << ", " << a[2] << ")-(" << b[0] << ", " << b[1] << ", " << b[2]
           << ") in " << entry.second << " triangles; ";
    }
  }
  return text.str();
}

/** A boundary that is a closed 2-manifold: every edge in exactly two triangles, every vertex link one cycle. */
void
ExpectClosedManifold(const dr::SurfaceTopology & topology, const dr::TetrahedralMesh & mesh,
                     const std::vector<std::array<uint32_t, 3>> & triangles)
{
  EXPECT_GT(topology.numberOfTriangles, 0u);
  EXPECT_EQ(topology.nonManifoldEdges, 0u) << DescribeNonManifoldEdges(mesh, triangles);
  EXPECT_EQ(topology.nonManifoldVertices, 0u);
}

template <typename TFilter>
void
ExpectClosedManifoldBoundary(const Meshed<TFilter> & meshed)
{
  ExpectClosedManifold(meshed.boundary, meshed.mesh, meshed.mesh.boundaryTriangles);
}

/** Runs the filter and expects an itk::ExceptionObject whose description names `problem` (case-insensitive). */
template <typename TFilter>
void
ExpectExceptionNaming(TFilter & filter, const std::string & problem)
{
  const auto lower = [](std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
    return text;
  };
  try
  {
    filter.Update();
    ADD_FAILURE() << "no exception; expected one naming '" << problem << "'";
  }
  catch (const itk::ExceptionObject & error)
  {
    const std::string description = error.GetDescription();
    EXPECT_NE(lower(description).find(lower(problem)), std::string::npos)
      << "the description '" << description << "' does not name '" << problem << "'";
  }
  catch (const std::exception & error)
  {
    ADD_FAILURE() << "a std::exception instead of an itk::ExceptionObject: " << error.what();
  }
}

// ---- Images ----------------------------------------------------------------------------------------------

LabelImageType::DirectionType
ObliqueDirection()
{
  // Rz(25°) Ry(-35°) Rx(15°): a proper rotation with no zero entry, so that no axis is left in place.
  const auto rotation = [](int axis, double degrees) {
    const double                  c = std::cos(degrees * Pi / 180.0);
    const double                  s = std::sin(degrees * Pi / 180.0);
    LabelImageType::DirectionType r;
    r.SetIdentity();
    const int i = (axis + 1) % 3;
    const int j = (axis + 2) % 3;
    r[i][i] = c;
    r[i][j] = -s;
    r[j][i] = s;
    r[j][j] = c;
    return r;
  };
  return rotation(2, 25.0) * rotation(1, -35.0) * rotation(0, 15.0);
}

LabelImageType::DirectionType
IdentityDirection()
{
  LabelImageType::DirectionType identity;
  identity.SetIdentity();
  return identity;
}

/** Half the diagonal of a voxel: every point of a voxel's cell is this close to its centre. */
template <typename TImage>
double
HalfVoxelDiagonal(const TImage & image)
{
  const auto & spacing = image.GetSpacing();
  return 0.5 * std::sqrt(spacing[0] * spacing[0] + spacing[1] * spacing[1] + spacing[2] * spacing[2]);
}

/** A ball of radius 15 mm in an anisotropic, oblique, off-origin grid; its centre is at a fractional index so
 * that the voxel pattern has no symmetry to hide an error. */
struct BallInGrid
{
  static constexpr double Radius = 15.0;
  LabelImageType::Pointer image;
  dr::Vector3             center;
};

BallInGrid
MakeBallInGrid(const LabelImageType::DirectionType & direction)
{
  const LabelImageType::SizeType size{ { 50, 40, 25 } };
  LabelImageType::SpacingType    spacing;
  LabelImageType::PointType      origin;
  const double                   centerIndex[3] = { 24.3, 19.6, 11.7 };
  const double                   spacings[3] = { 0.7, 0.9, 1.6 };
  const double                   origins[3] = { -12.5, 7.25, 30.0 };
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    spacing[axis] = spacings[axis];
    origin[axis] = origins[axis];
  }
  dr::Vector3 center;
  for (unsigned int row = 0; row < 3; ++row)
  {
    center[row] = origin[row];
    for (unsigned int column = 0; column < 3; ++column)
    {
      center[row] += direction[row][column] * spacing[column] * centerIndex[column];
    }
  }
  return { MakeBallImage(size, spacing, origin, direction, center, BallInGrid::Radius), center };
}

// ---- Distances to an analytic sphere ---------------------------------------------------------------------

/** Bound on the two-sided distance between a sphere of radius r and a closed boundary around its centre whose
 * vertices lie within `vertexOffset` of it and whose triangles have circumradius < δ. Outwards: a triangle lies
 * in the ball around the centre through its farthest vertex, so within r + vertexOffset. Inwards: for a point x
 * of a triangle with circumcentre m and circumradius R, |x - c|^2 = Σ λi |vi - c|^2 - (R^2 - |x - m|^2)
 * >= r'^2 - R^2 with r' = r - vertexOffset, so the shortfall is at most vertexOffset + r' - sqrt(r'^2 - δ^2).
 * The same band bounds the sphere-to-mesh side: the ray from the centre through a sphere point leaves the
 * enclosed volume through the boundary, inside the band. */
double
ChordalDistanceBound(double radius, double vertexOffset, double delta)
{
  const double inner = radius - vertexOffset;
  return vertexOffset + inner - std::sqrt(inner * inner - delta * delta);
}

double
DistanceToSphere(const dr::Vector3 & point, const dr::Vector3 & center, double radius)
{
  return std::abs(dr::Distance(point, center) - radius);
}

/** The largest distance to the sphere of the boundary's feature vertices, and of its other vertices (counted, with
 * multiplicity). */
struct BoundaryVertexOffsets
{
  double      feature{ 0.0 };
  double      other{ 0.0 };
  std::size_t others{ 0 };
};

BoundaryVertexOffsets
LargestBoundaryVertexOffsets(const dr::TetrahedralMesh & mesh, const dr::Vector3 & center, double radius)
{
  BoundaryVertexOffsets largest;
  for (const auto & triangle : mesh.boundaryTriangles)
  {
    for (const uint32_t vertex : triangle)
    {
      const bool isFeature = mesh.pointKinds.at(vertex) == dr::VertexKind::Feature;
      largest.others += !isFeature;
      double & offset = isFeature ? largest.feature : largest.other;
      offset = std::max(offset, DistanceToSphere(mesh.points[vertex], center, radius));
    }
  }
  return largest;
}

/** Points spread evenly over the sphere (a Fibonacci lattice). */
std::vector<dr::Vector3>
SphereSamples(const dr::Vector3 & center, double radius, std::size_t count)
{
  std::vector<dr::Vector3> samples;
  const double             goldenAngle = Pi * (3.0 - std::sqrt(5.0));
  for (std::size_t i = 0; i < count; ++i)
  {
    const double z = 1.0 - 2.0 * (static_cast<double>(i) + 0.5) / static_cast<double>(count);
    const double ring = std::sqrt(1.0 - z * z);
    const double angle = goldenAngle * static_cast<double>(i);
    samples.push_back(center + radius * dr::Vector3{ { ring * std::cos(angle), ring * std::sin(angle), z } });
  }
  return samples;
}

struct SphereFidelity
{
  BoundaryVertexOffsets largestVertexOffsets;
  /** Samples of the boundary triangles (every δ/10) to the sphere. */
  dr::DistanceStatistics meshToSphere;
  /** 20,000 sphere samples to the boundary triangles. */
  dr::DistanceStatistics sphereToMesh;
};

SphereFidelity
MeasureAgainstSphere(const dr::TetrahedralMesh & mesh, const dr::Vector3 & center, double radius, double delta)
{
  SphereFidelity      fidelity;
  std::vector<double> distances;
  fidelity.largestVertexOffsets = LargestBoundaryVertexOffsets(mesh, center, radius);
  for (const dr::Vector3 & sample : dr::SampleTriangles(mesh.points, mesh.boundaryTriangles, delta / 10.0))
  {
    distances.push_back(DistanceToSphere(sample, center, radius));
  }
  fidelity.meshToSphere = dr::SummarizeDistances(distances);
  distances.clear();
  const dr::TriangleSurfaceDistance boundary(mesh.points, mesh.boundaryTriangles);
  for (const dr::Vector3 & sample : SphereSamples(center, radius, 20000))
  {
    distances.push_back(boundary.Distance(sample));
  }
  fidelity.sphereToMesh = dr::SummarizeDistances(distances);
  return fidelity;
}

/** The analytic-sphere checks shared by the label and gray-value tests: boundary feature vertices within
 * `vertexOffsetBound` of the sphere, the two-sided sampled distance within the chordal bound, and a closed
 * genus-0 surface of one component. Other vertices reach the boundary only with σ > 0 (Lemma 5, which
 * ExpectGuarantees asserts with σ = 0): such a vertex is a corner of boundary triangles that lie in their surface
 * balls, of radius < δ around a point of the oracle's surface, so it is within δ + `vertexOffsetBound` of the
 * sphere, and where the mesh has one the chordal bound is taken with that offset. */
template <typename TFilter>
void
ExpectFaithfulSphere(const Meshed<TFilter> & meshed, const dr::Vector3 & center, double radius,
                     double vertexOffsetBound)
{
  const double         delta = meshed.filter->GetEffectiveSurfaceSamplingDistance();
  const SphereFidelity fidelity = MeasureAgainstSphere(meshed.mesh, center, radius, delta);
  const bool           freeVertexMayBeOnTheBoundary = meshed.filter->GetMinimumDihedralAngle() > 0.0;
  const double         offsetBound = freeVertexMayBeOnTheBoundary ? delta + vertexOffsetBound : vertexOffsetBound;
  const double         bound =
    ChordalDistanceBound(radius, fidelity.largestVertexOffsets.others > 0 ? offsetBound : vertexOffsetBound, delta);
  std::cout << "sphere r=" << radius << " delta=" << delta << ": " << meshed.mesh.tetrahedra.size()
            << " tetrahedra, largest vertex offset " << fidelity.largestVertexOffsets.feature << " (bound "
            << vertexOffsetBound << "), of other boundary vertices " << fidelity.largestVertexOffsets.other
            << ", mesh->sphere mean " << fidelity.meshToSphere.mean << " max " << fidelity.meshToSphere.maximum
            << ", sphere->mesh mean " << fidelity.sphereToMesh.mean << " max " << fidelity.sphereToMesh.maximum
            << " (bound " << bound << ")\n";
  EXPECT_LE(fidelity.largestVertexOffsets.feature, vertexOffsetBound);
  EXPECT_LE(fidelity.largestVertexOffsets.other, offsetBound);
  EXPECT_LE(fidelity.meshToSphere.maximum, bound);
  EXPECT_LE(fidelity.sphereToMesh.maximum, bound);
  ExpectClosedManifoldBoundary(meshed);
  EXPECT_EQ(meshed.boundary.numberOfComponents, 1);
  EXPECT_EQ(meshed.boundary.totalGenus, 0);
}

// ---- Physical space ----------------------------------------------------------------------------------------

/** δ = 2 mm against a 15 mm ball: the chordal part of the bound stays near 0.15 mm. */
constexpr double BallDelta = 2.0;

const BallInGrid &
ObliqueBall()
{
  static const BallInGrid ball = MakeBallInGrid(ObliqueDirection());
  return ball;
}

const Meshed<FilterType> &
MeshedObliqueBall()
{
  static const auto meshed = RunFilter<FilterType>(FilterFor(ObliqueBall().image.GetPointer(), BallDelta));
  return *meshed;
}

TEST(PhysicalSpace, ObliqueAnisotropicBallGuarantees)
{
  ExpectGuarantees(MeshedObliqueBall());
}

// The quality report reads the selected labels through ViewLabelVolume: the image's own buffer, not a copy, in the
// image's physical space. It must be the segmentation a copy made voxel by voxel is (the test helpers' own
// LabelVolumeOf), and the report made from it the same: here the oblique, anisotropic ball's, whose selected labels
// are a cropped region.
TEST(PhysicalSpace, ViewLabelVolumeIsTheSelectedLabelsWithoutACopy)
{
  const auto & filter = MeshedObliqueBall().filter;
  const auto * selected = filter->GetSelectedLabelImage();
  ASSERT_NE(selected->GetBufferedRegion().GetIndex(), ObliqueBall().image->GetBufferedRegion().GetIndex())
    << "the case no longer has a cropped region";
  const dr::LabelVolume view = itk::ViewLabelVolume(selected);
  const dr::LabelVolume copy = LabelVolumeOf(*selected, [](double value) { return static_cast<dr::Label>(value); });
  EXPECT_EQ(view.borrowedLabels, selected->GetBufferPointer());
  EXPECT_TRUE(view.labels.empty());
  ASSERT_EQ(view.size, copy.size);
  ASSERT_EQ(view.NumberOfVoxels(), copy.labels.size());
  EXPECT_TRUE(std::equal(copy.labels.begin(), copy.labels.end(), view.Labels()));
  for (int axis = 0; axis < 3; ++axis)
  {
    EXPECT_NEAR(view.origin[axis], copy.origin[axis], 1e-9) << "axis " << axis;
    EXPECT_EQ(view.spacing[axis], copy.spacing[axis]) << "axis " << axis;
    for (int column = 0; column < 3; ++column)
    {
      EXPECT_EQ(view.direction[axis][column], copy.direction[axis][column]) << "axis " << axis;
    }
  }
  const auto json = [&filter](const dr::LabelVolume & segmentation) {
    std::ostringstream out;
    dr::WriteQualityReportJson(dr::ComputeQualityReport(filter->GetRefinedMesh(), segmentation), out);
    return out.str();
  };
  EXPECT_EQ(json(view), json(copy));
}

// A voxel is inside when its centre is within r of c. The nearest-neighbour surface runs along the faces
// between an inside voxel a and an outside voxel b, and a point p there is within half a voxel diagonal h
// of both centres, so r - h < |p - c| <= r + h: feature vertices lie within h (plus the bisection tolerance)
// of the sphere, and ChordalDistanceBound() carries that to the whole boundary.
TEST(PhysicalSpace, ObliqueAnisotropicBallMatchesTheAnalyticSphere)
{
  const BallInGrid & ball = ObliqueBall();
  ExpectFaithfulSphere(
    MeshedObliqueBall(), ball.center, BallInGrid::Radius, HalfVoxelDiagonal(*ball.image) + SurfacePointTolerance);
}

// The rigorous band of ChordalDistanceBound() allows ±22 % of volume; the requirement is a few %. The
// voxelised ball's own volume error and the chords' shrinkage (about 3 R^2 / (4 r^2) < 1.4 % for R < δ) are
// each far below 3 %.
TEST(PhysicalSpace, ObliqueAnisotropicBallVolume)
{
  const double ballVolume = 4.0 / 3.0 * Pi * std::pow(BallInGrid::Radius, 3);
  const double meshVolume = MeshedObliqueBall().quality.totalVolume;
  const auto & image = *ObliqueBall().image;
  const auto & spacing = image.GetSpacing();
  std::size_t  ballVoxels = 0;
  for (itk::ImageRegionConstIteratorWithIndex<LabelImageType> it(&image, image.GetBufferedRegion()); !it.IsAtEnd();
       ++it)
  {
    ballVoxels += it.Get() != 0;
  }
  const double voxelVolume = static_cast<double>(ballVoxels) * spacing[0] * spacing[1] * spacing[2];
  std::cout << "mesh volume " << meshVolume << " mm^3, voxels " << voxelVolume << " mm^3, ball " << ballVolume
            << " mm^3; relative error of the mesh " << (meshVolume - ballVolume) / ballVolume << ", of the voxels "
            << (voxelVolume - ballVolume) / ballVolume << "\n";
  EXPECT_NEAR(meshVolume / ballVolume, 1.0, 0.03);
}

// The same voxels with the identity direction: that mesh must follow its own analytic sphere, and mapping it
// by x -> origin + D (x - origin) must put it onto the oblique mesh. Both lie within the chordal bound B of
// spheres that the map carries onto each other, so the mapped meshes are within 2B (triangle inequality); the
// unmapped one is about 20 mm off, so a filter that ignored the direction could not pass.
TEST(PhysicalSpace, MeshFollowsTheDirectionMatrix)
{
  const BallInGrid & oblique = ObliqueBall();
  auto               identityImage = LabelImageType::New();
  identityImage->Graft(oblique.image);
  identityImage->SetDirection(IdentityDirection());
  const auto & origin = oblique.image->GetOrigin();
  const auto & direction = oblique.image->GetDirection();
  // c = origin + D v with v the centre's offset in the grid's own axes; with the identity, origin + v.
  dr::Vector3 offsetInGrid{ { 0.0, 0.0, 0.0 } };
  for (unsigned int row = 0; row < 3; ++row)
  {
    for (unsigned int column = 0; column < 3; ++column)
    {
      offsetInGrid[row] += direction[column][row] * (oblique.center[column] - origin[column]);
    }
  }
  const dr::Vector3 identityCenter{
    { origin[0] + offsetInGrid[0], origin[1] + offsetInGrid[1], origin[2] + offsetInGrid[2] }
  };
  const double halfDiagonal = HalfVoxelDiagonal(*oblique.image);
  const double bound = ChordalDistanceBound(BallInGrid::Radius, halfDiagonal + SurfacePointTolerance, BallDelta);
  ASSERT_GT(dr::Distance(identityCenter, oblique.center), 4.0 * bound) << "the test could not tell the two apart";

  const auto identityMeshed = RunFilter<FilterType>(FilterFor(identityImage.GetPointer(), BallDelta));
  ExpectGuarantees(*identityMeshed);
  ExpectFaithfulSphere(*identityMeshed, identityCenter, BallInGrid::Radius, halfDiagonal + SurfacePointTolerance);

  dr::TetrahedralMesh mapped = identityMeshed->mesh;
  for (dr::Vector3 & point : mapped.points)
  {
    dr::Vector3 rotated{ { origin[0], origin[1], origin[2] } };
    for (unsigned int row = 0; row < 3; ++row)
    {
      for (unsigned int column = 0; column < 3; ++column)
      {
        rotated[row] += direction[row][column] * (point[column] - origin[column]);
      }
    }
    point = rotated;
  }
  const dr::TetrahedralMesh & obliqueMesh = MeshedObliqueBall().mesh;
  const dr::TwoSidedDistance  distance = dr::ComputeTwoSidedDistance(
    mapped.points, mapped.boundaryTriangles, obliqueMesh.points, obliqueMesh.boundaryTriangles, BallDelta / 10.0);
  std::cout << "mapped identity-direction mesh to oblique mesh: mean " << distance.combined.mean << " max "
            << distance.combined.maximum << " (bound " << 2.0 * bound << ")\n";
  EXPECT_LE(distance.combined.maximum, 2.0 * bound);
}

// The same ball with its buffered region starting at index (5, -3, 7) and the origin moved so that every voxel
// keeps its physical place: the mesh must stay on the same sphere.
TEST(PhysicalSpace, RegionWithANonZeroStartIndex)
{
  const BallInGrid &              ball = ObliqueBall();
  const LabelImageType::IndexType start{ { 5, -3, 7 } };
  LabelImageType::PointType       firstVoxel;
  ball.image->TransformIndexToPhysicalPoint({ { 0, 0, 0 } }, firstVoxel);
  auto moved = LabelImageType::New();
  moved->Graft(ball.image);
  moved->SetRegions(LabelImageType::RegionType(start, ball.image->GetBufferedRegion().GetSize()));
  LabelImageType::PointType origin = firstVoxel;
  for (unsigned int row = 0; row < 3; ++row)
  {
    for (unsigned int column = 0; column < 3; ++column)
    {
      origin[row] -= ball.image->GetDirection()[row][column] * ball.image->GetSpacing()[column] * start[column];
    }
  }
  moved->SetOrigin(origin);
  LabelImageType::PointType movedFirstVoxel;
  moved->TransformIndexToPhysicalPoint(start, movedFirstVoxel);
  ASSERT_LT(movedFirstVoxel.EuclideanDistanceTo(firstVoxel), 1e-9);

  const auto meshed = RunFilter<FilterType>(FilterFor(moved.GetPointer(), BallDelta));
  ExpectGuarantees(*meshed);
  ExpectFaithfulSphere(
    *meshed, ball.center, BallInGrid::Radius, HalfVoxelDiagonal(*ball.image) + SurfacePointTolerance);
}

// ---- The real brain mask ---------------------------------------------------------------------------------

LabelImageType::Pointer
ReadExampleImage(const std::string & fileName)
{
  return itk::ReadImage<LabelImageType>(ExamplesDataDirectory() + fileName);
}

/** KmeansTest_T1RawSkullStrip (labels 0/4/5/6) as one object: every non-zero voxel is 1. */
const LabelImageType *
BrainMaskImage()
{
  static const LabelImageType::Pointer mask =
    MapLabels(*ReadExampleImage("KmeansTest_T1RawSkullStrip.nii.gz"), NonZeroToOne);
  return mask;
}

/** Each δ is meshed once per process: the guarantees, the distances and the table share the run. */
const Meshed<FilterType> &
MeshedBrainMask(double delta)
{
  static std::map<double, std::unique_ptr<Meshed<FilterType>>> cache;
  auto &                                                       entry = cache[delta];
  if (!entry)
  {
    entry = RunFilter<FilterType>(FilterFor(BrainMaskImage(), delta));
  }
  return *entry;
}

const dr::TriangleSurface &
BrainMaskMarchingCubes()
{
  static const dr::TriangleSurface surface = dr::ExtractLabelSurfaces(LabelVolumeOf(*BrainMaskImage(), NonZeroToOne));
  return surface;
}

/** Both directions sampled every millimetre, half the smallest voxel spacing. */
constexpr double MarchingCubesSampleSpacing = 1.0;

const dr::TwoSidedDistance &
BrainMaskDistance(double delta)
{
  static std::map<double, dr::TwoSidedDistance> cache;
  if (!cache.count(delta))
  {
    const dr::TetrahedralMesh & mesh = MeshedBrainMask(delta).mesh;
    const dr::TriangleSurface & reference = BrainMaskMarchingCubes();
    cache[delta] = dr::ComputeTwoSidedDistance(
      mesh.points, mesh.boundaryTriangles, reference.points, reference.triangles, MarchingCubesSampleSpacing);
  }
  return cache.at(delta);
}

/** Half the diagonal of the largest voxel face (2 × 3 mm for the brain images). The nearest-neighbour surface
 * is made of voxel faces, and discrete marching cubes puts a vertex at the centre of each of them, so every
 * point of the oracle's surface is within this distance of the marching-cubes surface. */
template <typename TImage>
double
HalfLargestFaceDiagonal(const TImage & image)
{
  const auto & s = image.GetSpacing();
  const double largestSquaredFaceDiagonal =
    std::max({ s[0] * s[0] + s[1] * s[1], s[1] * s[1] + s[2] * s[2], s[0] * s[0] + s[2] * s[2] });
  return 0.5 * std::sqrt(largestSquaredFaceDiagonal);
}

class BrainMask : public testing::TestWithParam<double>
{};

TEST_P(BrainMask, GuaranteesHold)
{
  ExpectGuarantees(MeshedBrainMask(GetParam()));
}

// The defaults remove slivers (σ = 10°), which gives up Lemma 2's edges; the paper's method, whose bounds are
// proven, is held to all of them on the same image.
TEST_P(BrainMask, ProvenGuaranteesHoldWithoutSliverRemoval)
{
  const auto filter = FilterFor(BrainMaskImage(), GetParam());
  filter->SetMinimumDihedralAngle(0.0);
  ExpectGuarantees(*RunFilter<FilterType>(filter));
}

// The paper's isotopy guarantee needs δ small against the local feature size; a brain mask has features of a
// voxel, so this is where the guarantee is put to the test rather than assumed.
TEST_P(BrainMask, BoundaryIsAClosedManifold)
{
  const Meshed<FilterType> & meshed = MeshedBrainMask(GetParam());
  ExpectClosedManifoldBoundary(meshed);
  std::cout << "delta " << GetParam() << ": boundary components " << meshed.boundary.numberOfComponents << ", genus "
            << meshed.boundary.totalGenus << "\n";
}

// Mesh -> marching cubes, proven: each boundary triangle lies in its surface ball, centred on the oracle's
// surface with radius < δ (R3), and that surface is within HalfLargestFaceDiagonal() of marching cubes.
// Marching cubes -> mesh: the paper's fidelity (two-sided Hausdorff distance to the surface <= δ, which the
// core tests assert on analytic shapes) plus the same face term; not a theorem for voxel-sized features.
// Mean: a triangle's vertices lie on the surface and its worst point within δ of it; δ/2 is what a boundary
// as far off on average as the surface balls allow at their worst would give.
TEST_P(BrainMask, CloseToTheMarchingCubesSurface)
{
  const double                 delta = GetParam();
  const dr::TwoSidedDistance & distance = BrainMaskDistance(delta);
  const double                 bound = delta + HalfLargestFaceDiagonal(*BrainMaskImage()) + SurfacePointTolerance;
  std::cout << "delta " << delta << ": mesh->MC mean " << distance.fromFirst.mean << " p95 "
            << distance.fromFirst.percentile95 << " max " << distance.fromFirst.maximum << "; MC->mesh mean "
            << distance.fromSecond.mean << " p95 " << distance.fromSecond.percentile95 << " max "
            << distance.fromSecond.maximum << "; bound on max " << bound << "\n";
  EXPECT_LE(distance.fromFirst.maximum, bound);
  EXPECT_LE(distance.fromSecond.maximum, bound);
  EXPECT_LE(distance.combined.mean, delta / 2.0);
}

// 3 mm is where four nearly co-circular surface points made two flat caps before they were relabelled.
INSTANTIATE_TEST_SUITE_P(Delta, BrainMask, testing::Values(2.0, 3.0, 4.0, 6.0),
                         [](const testing::TestParamInfo<double> & info) {
                           return "delta" + std::to_string(static_cast<int>(info.param)) + "mm";
                         });

/** The defaults' mesh must follow δ, not its last bits (a tie that falls the other way moves the cascade of the
 * refinement, and sliver removal adds choices that ties decide). Measured when σ = 10° became the default: the brain
 * mask at 2 mm moves by 1.0 % at most over these perturbations (1.9 % before R4′ tried the surface points near its
 * candidates), the atlas phantom at 1 mm by 1.7 % (before that as well), the k-means tissues at 4 mm by 0.4 %;
 * the random families' small meshes move more (the randomized suite's stability tests). The bound keeps a margin
 * over what was measured. With R3's lattice tie margin: 0.5 % at 2 mm, 0.9 % at 2.5 mm (6.1 % without it). */
TEST(BrainMask, TheDefaultsFollowDeltaNotItsLastBits)
{
  constexpr double largestRelativeChange = 0.04;
  // 2.5 mm on the mask's 2 x 3 x 2 mm voxels makes surface balls of radius delta exactly: before R3's lattice tie
  // margin, 43,591 tetrahedra at delta and 41,336 at delta (1 + 1e-9).
  for (const double delta : { 2.0, 2.5 })
  {
    const double reference = static_cast<double>(MeshedBrainMask(delta).mesh.tetrahedra.size());
    for (const double perturbation : { 1e-12, -1e-12, 1e-9, -1e-9, 1e-6 })
    {
      const auto   meshed = RunFilter<FilterType>(FilterFor(BrainMaskImage(), delta * (1.0 + perturbation)));
      const double tetrahedra = static_cast<double>(meshed->mesh.tetrahedra.size());
      std::cout << "delta " << delta << " x (1 + " << perturbation << "): " << tetrahedra << " tetrahedra, "
                << reference << " at delta\n";
      EXPECT_LE(std::abs(tetrahedra - reference) / reference, largestRelativeChange)
        << "delta " << delta << ", perturbation " << perturbation;
    }
  }
}

TEST(BrainMaskReport, Table)
{
  std::cout << std::fixed << std::setprecision(3);
  std::cout
    << "\nBrain mask (KmeansTest_T1RawSkullStrip, non-zero = object), the defaults (rho = 2, sigma = "
    << dr::RefinementParameters{}.minimumDihedralAngle << " deg):\n"
    << "| delta (mm) | tetrahedra | boundary triangles | seconds | max radius-edge | min boundary planar angle | "
       "min dihedral | MC distance mean (mm) | MC distance max (mm) | components | genus | non-manifold "
       "edges/vertices |\n";
  for (const double delta : { 2.0, 4.0, 6.0 })
  {
    const Meshed<FilterType> &   meshed = MeshedBrainMask(delta);
    const dr::TwoSidedDistance & distance = BrainMaskDistance(delta);
    std::cout << "| " << delta << " | " << meshed.mesh.tetrahedra.size() << " | "
              << meshed.mesh.boundaryTriangles.size() << " | " << meshed.seconds << " | "
              << meshed.quality.maximumRadiusEdgeRatio << " | " << meshed.boundary.minimumPlanarAngle << " | "
              << std::setprecision(5) << meshed.quality.minimumDihedralAngle << std::setprecision(3) << " | "
              << distance.combined.mean << " | " << distance.combined.maximum << " | "
              << meshed.boundary.numberOfComponents << " | " << meshed.boundary.totalGenus << " | "
              << meshed.boundary.nonManifoldEdges << "/" << meshed.boundary.nonManifoldVertices << " |\n";
  }
  const dr::SurfaceTopology reference =
    dr::ComputeSurfaceTopology(BrainMaskMarchingCubes().points, BrainMaskMarchingCubes().triangles);
  std::cout << "marching cubes: " << reference.numberOfTriangles << " triangles, " << reference.numberOfComponents
            << " components, genus " << reference.totalGenus << ", non-manifold edges/vertices "
            << reference.nonManifoldEdges << "/" << reference.nonManifoldVertices << "\n";
  std::cout << std::defaultfloat;

  // The mesh's topology against the voxels' (marching cubes): one closed manifold component, as the mask is. At
  // δ = 2 mm (one voxel diagonal of a face) the mask's one-voxel tunnel is resolved: the genus is the voxels' own. From
  // δ = 4 mm the regularisation at the scale of δ closes it (docs/algorithm.md, "Topology"; test/Baseline/README.md):
  // a coarser mesh may lose handles thinner than δ, never gain one.
  ASSERT_EQ(reference.nonManifoldEdges, 0u);
  ASSERT_EQ(reference.nonManifoldVertices, 0u);
  for (const double delta : { 2.0, 4.0, 6.0 })
  {
    SCOPED_TRACE("delta " + std::to_string(delta) + " mm");
    const dr::SurfaceTopology & boundary = MeshedBrainMask(delta).boundary;
    EXPECT_EQ(boundary.nonManifoldEdges, 0u);
    EXPECT_EQ(boundary.nonManifoldVertices, 0u);
    EXPECT_EQ(boundary.numberOfComponents, reference.numberOfComponents);
    EXPECT_LE(boundary.totalGenus, reference.totalGenus);
  }
  EXPECT_EQ(MeshedBrainMask(2.0).boundary.totalGenus, reference.totalGenus);
}

TEST(FilterOutputs, MatchTheRefinedMesh)
{
  const Meshed<FilterType> &  meshed = MeshedBrainMask(4.0);
  const dr::TetrahedralMesh & refined = meshed.filter->GetRefinedMesh();
  EXPECT_EQ(meshed.mesh.points, refined.points);
  EXPECT_EQ(meshed.mesh.tetrahedra, refined.tetrahedra);
  EXPECT_EQ(meshed.mesh.tetrahedronLabels, refined.tetrahedronLabels);
  EXPECT_EQ(meshed.mesh.boundaryTriangles, refined.boundaryTriangles);
  EXPECT_EQ(meshed.mesh.boundaryTriangleLabels, refined.boundaryTriangleLabels);
  const MeshType * interfaces = meshed.filter->GetInterfaceMesh();
  ASSERT_EQ(interfaces->GetNumberOfCells(), refined.boundaryTriangles.size());
  for (std::size_t i = 0; i < refined.boundaryTriangles.size(); ++i)
  {
    MeshType::CellPixelType label = 0;
    ASSERT_TRUE(interfaces->GetCellData(i, &label));
    ASSERT_EQ(label, refined.boundaryTriangleLabels[i][0]);
    // The accessor ITK Python has (GetInterfaceLabels() is not wrapped): the inside, then the other side.
    ASSERT_EQ(meshed.filter->GetInterfaceLabel(i, 0), refined.boundaryTriangleLabels[i][0]);
    ASSERT_EQ(meshed.filter->GetInterfaceLabel(i, 1), refined.boundaryTriangleLabels[i][1]);
  }
  EXPECT_THROW(meshed.filter->GetInterfaceLabel(refined.boundaryTriangles.size(), 0), itk::ExceptionObject);
  EXPECT_THROW(meshed.filter->GetInterfaceLabel(0, 2), itk::ExceptionObject);
}

// The check that the guarantees rest on must see each kind of corruption.
TEST(TestHelpers, BoundaryCheckSeesCorruptedBoundaries)
{
  const dr::TetrahedralMesh & intact = MeshedObliqueBall().mesh;
  ASSERT_TRUE(CheckBoundaryAgainstTetrahedra(intact).IsConsistent());
  dr::TetrahedralMesh flipped = intact;
  std::swap(flipped.boundaryTriangles[0][1], flipped.boundaryTriangles[0][2]);
  EXPECT_EQ(CheckBoundaryAgainstTetrahedra(flipped).wrongOrientation, 1u);
  dr::TetrahedralMesh missing = intact;
  missing.boundaryTriangles.pop_back();
  missing.boundaryTriangleLabels.pop_back();
  EXPECT_EQ(CheckBoundaryAgainstTetrahedra(missing).missingTriangles, 1u);
  dr::TetrahedralMesh duplicated = intact;
  duplicated.boundaryTriangles.push_back(duplicated.boundaryTriangles[0]);
  duplicated.boundaryTriangleLabels.push_back(duplicated.boundaryTriangleLabels[0]);
  EXPECT_EQ(CheckBoundaryAgainstTetrahedra(duplicated).extraTriangles, 1u);
  dr::TetrahedralMesh relabelled = intact;
  relabelled.boundaryTriangleLabels[0][1] = 7;
  EXPECT_EQ(CheckBoundaryAgainstTetrahedra(relabelled).wrongLabels, 1u);
  dr::TetrahedralMesh relabelledTetrahedron = intact;
  relabelledTetrahedron.tetrahedronLabels[0] = 2;
  EXPECT_FALSE(CheckBoundaryAgainstTetrahedra(relabelledTetrahedron).IsConsistent());
}

/** Voxels where two label images differ. */
std::size_t
CountDifferingVoxels(const LabelImageType & a, const LabelImageType & b)
{
  std::size_t                                            differing = 0;
  itk::ImageRegionConstIteratorWithIndex<LabelImageType> it(&a, a.GetBufferedRegion());
  for (; !it.IsAtEnd(); ++it)
  {
    differing += it.Get() != b.GetPixel(it.GetIndex());
  }
  return differing;
}

/** Voxels where the mask differs from itself shifted by one voxel along the axis where that is fewest. */
std::size_t
SmallestOneVoxelShiftDifference(const LabelImageType & mask)
{
  const auto & region = mask.GetBufferedRegion();
  std::size_t  smallest = std::numeric_limits<std::size_t>::max();
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    std::size_t                                            differing = 0;
    itk::ImageRegionConstIteratorWithIndex<LabelImageType> it(&mask, region);
    for (; !it.IsAtEnd(); ++it)
    {
      auto neighbor = it.GetIndex();
      ++neighbor[axis];
      differing += it.Get() != (region.IsInside(neighbor) ? mask.GetPixel(neighbor) : 0);
    }
    smallest = std::min(smallest, differing);
  }
  return smallest;
}

// The voxelised mesh against the mask it came from, on the δ = 2 mm mesh (about 80,000 tetrahedra, the size
// the voxeliser must handle well under a second). The mesh must be closer to the mask than the mask is to
// itself moved by one voxel: a mesh off by a voxel, mirrored or rotated could not be.
TEST(Voxelizer, BrainMaskMeshIsCloserToTheMaskThanAOneVoxelShift)
{
  for (const double delta : { 2.0, 4.0 })
  {
    const Meshed<FilterType> & meshed = MeshedBrainMask(delta);
    const auto                 start = Clock::now();
    const auto voxelized = itk::VoxelizeTetrahedralMesh<LabelImageType>(*meshed.filter->GetOutput(), *BrainMaskImage());
    const double      seconds = Seconds(start);
    const std::size_t differing = CountDifferingVoxels(*BrainMaskImage(), *voxelized);
    const std::size_t shifted = SmallestOneVoxelShiftDifference(*BrainMaskImage());
    std::cout << "delta " << delta << ": voxelised " << meshed.mesh.tetrahedra.size() << " tetrahedra in " << seconds
              << " s; " << differing << " voxels differ from the mask, a one-voxel shift of the mask " << shifted
              << "\n";
    EXPECT_LT(seconds, 1.0);
    EXPECT_LT(differing, shifted);
  }
}

// The voxeliser on its own: a ball meshed in an oblique grid, voxelised onto that grid, gives back the ball's
// voxels except along the boundary (where mesh and voxel surface part by less than a voxel).
TEST(Voxelizer, ObliqueBallComesBackOnItsOwnGrid)
{
  const BallInGrid & ball = ObliqueBall();
  const auto         voxelized =
    itk::VoxelizeTetrahedralMesh<LabelImageType>(*MeshedObliqueBall().filter->GetOutput(), *ball.image);
  EXPECT_EQ(voxelized->GetDirection(), ball.image->GetDirection());
  EXPECT_EQ(voxelized->GetOrigin(), ball.image->GetOrigin());
  EXPECT_EQ(voxelized->GetSpacing(), ball.image->GetSpacing());
  const std::size_t differing = CountDifferingVoxels(*ball.image, *voxelized);
  const std::size_t shifted = SmallestOneVoxelShiftDifference(*ball.image);
  std::cout << differing << " voxels differ, a one-voxel shift " << shifted << "\n";
  EXPECT_LT(differing, shifted);
}

/** "A centre on a facet shared by two tetrahedra takes the label of the one that comes first in the mesh's cell
 * order" (itkTetrahedralMeshVoxelizer.h). Two tetrahedra on either side of the triangle (0, 0, 0), (4, 0, 0),
 * (0, 4, 0) in the plane z = 0 of a unit grid: the voxel centres (i, j, 0) with i, j >= 0 and i + j <= 4 lie on
 * that facet, exactly (integer coordinates, an axis-aligned facet). They take the first cell's label whichever of
 * the two tetrahedra comes first; the centres off the facet take their own tetrahedron's. */
TEST(Voxelizer, ACentreOnASharedFacetTakesTheFirstCellsLabel)
{
  auto grid = LabelImageType::New();
  grid->SetRegions(LabelImageType::RegionType({ { -1, -1, -5 } }, { { 7, 7, 11 } }));
  for (const bool upperFirst : { true, false })
  {
    SCOPED_TRACE(upperFirst ? "the tetrahedron above the facet first" : "the tetrahedron below the facet first");
    auto mesh = MeshType::New();
    for (const auto & [id, x, y, z] : std::vector<std::array<double, 4>>{ { 0, 0.0, 0.0, 0.0 },
                                                                          { 1, 4.0, 0.0, 0.0 },
                                                                          { 2, 0.0, 4.0, 0.0 },
                                                                          { 3, 0.0, 0.0, 4.0 },
                                                                          { 4, 0.0, 0.0, -4.0 } })
    {
      MeshType::PointType point;
      point[0] = x;
      point[1] = y;
      point[2] = z;
      mesh->SetPoint(static_cast<MeshType::PointIdentifier>(id), point);
    }
    const std::array<MeshType::PointIdentifier, 2> apexes =
      upperFirst ? std::array<MeshType::PointIdentifier, 2>{ 3, 4 } : std::array<MeshType::PointIdentifier, 2>{ 4, 3 };
    for (unsigned int cellId = 0; cellId < 2; ++cellId)
    {
      MeshType::CellAutoPointer cell;
      cell.TakeOwnership(new itk::TetrahedronCell<MeshType::CellType>);
      const MeshType::PointIdentifier corners[4] = { 0, 1, 2, apexes[cellId] };
      for (unsigned int corner = 0; corner < 4; ++corner)
      {
        cell->SetPointId(corner, corners[corner]);
      }
      mesh->SetCell(cellId, cell);
      mesh->SetCellData(cellId, static_cast<MeshType::CellPixelType>(10 + cellId));
    }
    const auto  voxelized = itk::VoxelizeTetrahedralMesh<LabelImageType>(*mesh, *grid);
    std::size_t onTheFacet = 0;
    for (itk::ImageRegionConstIteratorWithIndex<LabelImageType> it(voxelized, voxelized->GetBufferedRegion());
         !it.IsAtEnd();
         ++it)
    {
      const auto & index = it.GetIndex();
      const bool   inTriangle = index[0] >= 0 && index[1] >= 0 && index[0] + index[1] + std::abs(index[2]) <= 4;
      int          expected = 0;
      if (inTriangle && index[2] == 0)
      {
        expected = 10; // the first cell's
        ++onTheFacet;
      }
      else if (inTriangle)
      {
        expected = (index[2] > 0) == upperFirst ? 10 : 11;
      }
      ASSERT_EQ(int{ it.Get() }, expected) << "at " << index;
    }
    EXPECT_EQ(onTheFacet, 15u);
  }
}

// ---- The k-means segmentation: five tissues -------------------------------------------------------------

/** Label 1 is the background class: 729,202 of the 1,015,808 voxels and 92 % of the border voxels. Labels 2..6
 * are the tissues; label 0 (126 voxels) is not a class of the k-means and stays background. */
const std::vector<FilterType::LabelType> KmeansTissues{ 2, 3, 4, 5, 6 };

/** 6 mm: the driver's regression test covers 4 mm, and the unit tests stay quick. */
constexpr double KmeansDelta = 6.0;

const Meshed<FilterType> &
MeshedKmeans()
{
  static const auto meshed = [] {
    static const LabelImageType::Pointer image = ReadExampleImage("KmeansTest_T1KmeansPrelimSegmentation.nii.gz");
    auto                                 filter = FilterFor(image.GetPointer(), KmeansDelta);
    filter->SetLabels(KmeansTissues);
    return RunFilter<FilterType>(filter);
  }();
  return *meshed;
}

TEST(KmeansTissues, GuaranteesHold)
{
  ExpectGuarantees(MeshedKmeans());
}

TEST(KmeansTissues, ProvenGuaranteesHoldWithoutSliverRemoval)
{
  static const LabelImageType::Pointer image = ReadExampleImage("KmeansTest_T1KmeansPrelimSegmentation.nii.gz");
  const auto                           filter = FilterFor(image.GetPointer(), KmeansDelta);
  filter->SetLabels(KmeansTissues);
  filter->SetMinimumDihedralAngle(0.0);
  ExpectGuarantees(*RunFilter<FilterType>(filter));
}

/** At δ = 5 mm the default scale gives the opening a radius of 2 mm, and its erosion a reach of 3 mm: the voxels'
 * spacing along one axis. Which side of the reach those neighbours fell on followed δ's last bits, and took the mesh
 * with it (57,695 tetrahedra at δ, 67,339 at δ (1 − 10⁻¹²)), until the reaches got LatticeTieMargin:
 * now the regularisation is the same voxel for voxel, and the mesh moves by what the refinement's own ties move it. */
TEST(KmeansTissues, TheRegularisationFollowsDeltaNotItsLastBits)
{
  constexpr double                     delta = 5.0;
  constexpr double                     largestRelativeChange = 0.04;
  static const LabelImageType::Pointer image = ReadExampleImage("KmeansTest_T1KmeansPrelimSegmentation.nii.gz");
  const auto                           meshAt = [](double atDelta) {
    auto filter = FilterFor(image.GetPointer(), atDelta);
    filter->SetLabels(KmeansTissues);
    return RunFilter<FilterType>(filter);
  };
  const auto                            reference = meshAt(delta);
  const dr::LabelRegularizationReport & regularised = reference->filter->GetRegularizationReport();
  ASSERT_GT(regularised.changedVoxels, 0U) << "the regularisation should change voxels at this delta";
  const double tetrahedra = static_cast<double>(reference->mesh.tetrahedra.size());
  for (const double perturbation : { -1e-12, 1e-12, -1e-9 })
  {
    const auto                            perturbed = meshAt(delta * (1.0 + perturbation));
    const dr::LabelRegularizationReport & report = perturbed->filter->GetRegularizationReport();
    EXPECT_EQ(report.changedVoxels, regularised.changedVoxels) << "perturbation " << perturbation;
    ASSERT_EQ(report.labels.size(), regularised.labels.size());
    for (std::size_t i = 0; i < report.labels.size(); ++i)
    {
      EXPECT_EQ(report.labels[i].voxelsRemoved, regularised.labels[i].voxelsRemoved)
        << "label " << report.labels[i].label << ", perturbation " << perturbation;
      EXPECT_EQ(report.labels[i].componentsRemoved, regularised.labels[i].componentsRemoved)
        << "label " << report.labels[i].label << ", perturbation " << perturbation;
    }
    const double change = std::abs(static_cast<double>(perturbed->mesh.tetrahedra.size()) - tetrahedra) / tetrahedra;
    std::cout << "delta " << delta << " x (1 + " << perturbation << "): " << perturbed->mesh.tetrahedra.size()
              << " tetrahedra, " << tetrahedra << " at delta\n";
    EXPECT_LE(change, largestRelativeChange) << "perturbation " << perturbation;
  }
}

TEST(KmeansTissues, InterfaceTrianglesSeparateTwoDifferentLabels)
{
  const dr::TetrahedralMesh & mesh = MeshedKmeans().mesh;
  const auto                  isTissue = [](dr::Label label) {
    return std::find(KmeansTissues.begin(), KmeansTissues.end(), label) != KmeansTissues.end();
  };
  std::map<std::array<dr::Label, 2>, std::size_t> trianglesOfPair;
  for (const auto & labels : mesh.boundaryTriangleLabels)
  {
    EXPECT_TRUE(isTissue(labels[0])) << labels[0];
    EXPECT_TRUE(isTissue(labels[1]) || labels[1] == dr::BackgroundLabel) << labels[1];
    EXPECT_NE(labels[0], labels[1]);
    ++trianglesOfPair[labels];
  }
  for (const dr::Label label : mesh.tetrahedronLabels)
  {
    ASSERT_TRUE(isTissue(label)) << label;
  }
  std::cout << "interface triangles per label pair:";
  for (const auto & entry : trianglesOfPair)
  {
    std::cout << " " << entry.first[0] << "|" << entry.first[1] << ": " << entry.second;
  }
  std::cout << "\n";
}

/** The labels on both sides of every boundary triangle at each edge. */
std::map<std::pair<uint32_t, uint32_t>, std::set<dr::Label>>
LabelsAroundBoundaryEdges(const dr::TetrahedralMesh & mesh)
{
  std::map<std::pair<uint32_t, uint32_t>, std::set<dr::Label>> labels;
  for (std::size_t i = 0; i < mesh.boundaryTriangles.size(); ++i)
  {
    const auto & triangle = mesh.boundaryTriangles[i];
    for (int corner = 0; corner < 3; ++corner)
    {
      const uint32_t a = triangle[corner];
      const uint32_t b = triangle[(corner + 1) % 3];
      auto &         around = labels[{ std::min(a, b), std::max(a, b) }];
      around.insert(mesh.boundaryTriangleLabels[i].begin(), mesh.boundaryTriangleLabels[i].end());
    }
  }
  return labels;
}

std::map<std::pair<uint32_t, uint32_t>, int>
TrianglesPerEdge(const std::vector<std::array<uint32_t, 3>> & triangles)
{
  std::map<std::pair<uint32_t, uint32_t>, int> count;
  for (const auto & triangle : triangles)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      const uint32_t a = triangle[corner];
      const uint32_t b = triangle[(corner + 1) % 3];
      ++count[{ std::min(a, b), std::max(a, b) }];
    }
  }
  return count;
}

/** Voxel edges around which `inside` holds at exactly two diagonally opposite voxels of the four: there the
 * voxels' own surface (the nearest-neighbour oracle's) is not a manifold. Outside the volume is background. */
std::size_t
CountDiagonalVoxelContacts(const dr::LabelVolume & volume, const std::function<bool(dr::Label)> & inside)
{
  const auto isInside = [&](std::array<long, 3> index) {
    for (unsigned int axis = 0; axis < 3; ++axis)
    {
      if (index[axis] < 0 || index[axis] >= static_cast<long>(volume.size[axis]))
      {
        return false;
      }
    }
    return inside(volume.labels[index[0] + volume.size[0] * (index[1] + volume.size[1] * index[2])]);
  };
  std::size_t contacts = 0;
  for (unsigned int along = 0; along < 3; ++along)
  {
    const unsigned int  first = (along + 1) % 3;
    const unsigned int  second = (along + 2) % 3;
    std::array<long, 3> corner;
    for (corner[along] = 0; corner[along] < static_cast<long>(volume.size[along]); ++corner[along])
    {
      for (corner[first] = -1; corner[first] < static_cast<long>(volume.size[first]); ++corner[first])
      {
        for (corner[second] = -1; corner[second] < static_cast<long>(volume.size[second]); ++corner[second])
        {
          auto step = [&](long d1, long d2) {
            auto index = corner;
            index[first] += d1;
            index[second] += d2;
            return isInside(index);
          };
          const bool a = step(0, 0);
          const bool b = step(1, 0);
          const bool c = step(1, 1);
          const bool d = step(0, 1);
          contacts += (a == c && b == d && a != b) ? 1 : 0;
        }
      }
    }
  }
  return contacts;
}

const dr::LabelVolume &
KmeansTissueVolume()
{
  static const dr::LabelVolume volume =
    LabelVolumeOf(*ReadExampleImage("KmeansTest_T1KmeansPrelimSegmentation.nii.gz"), KeepLabels(KmeansTissues));
  return volume;
}

/** Closedness (an even number of triangles at every edge) holds for any union of tetrahedra; what the topology
 * mechanism of issue #14 buys is manifoldness: at δ = 6 mm every tissue's boundary and the union's are closed
 * 2-manifolds, against thousands of voxel pinches in the input (the pinch removal, the regularisation, and the
 * relabelling at non-manifold places; without the relabelling 63 edges stay pinched). */
void
ExpectManifold(const dr::SurfaceTopology & topology, std::size_t voxelPinches, const std::string & what)
{
  EXPECT_GT(topology.numberOfTriangles, 0u) << what;
  EXPECT_GT(voxelPinches, 1000u) << what << ": the input is meant to be speckle";
  EXPECT_EQ(topology.nonManifoldEdges, 0u) << what;
  EXPECT_EQ(topology.nonManifoldVertices, 0u) << what;
}

// A tissue's boundary bounds a union of tetrahedra, so each of its edges lies in an even number of its triangles:
// closed, always. A manifold it is only where the tissue does not touch itself across an edge, and the
// k-means segmentation is speckle: its own voxel surface pinches at thousands of edges per tissue (printed as
// "voxel pinches"), most of them where only two labels meet. The mesh represents the labels regularised at the
// scale of δ: closedness and manifoldness are asserted, and the places where a tissue would touch itself are
// reported, classified by the number of labels meeting at the edge, next to the input's own pinches.
TEST(KmeansTissues, EachTissueBoundaryIsAClosedManifold)
{
  const dr::TetrahedralMesh & mesh = MeshedKmeans().mesh;
  const auto                  labelsAround = LabelsAroundBoundaryEdges(mesh);
  std::cout << "| tissue | tetrahedra | boundary triangles | components | genus | non-manifold edges (2 labels / >= 3 "
               "labels) | non-manifold vertices | voxel pinches of the input |\n";
  for (const dr::Label tissue : KmeansTissues)
  {
    const auto triangles = BoundaryTrianglesWhere(
      mesh, [tissue](const std::array<dr::Label, 2> & labels) { return labels[0] == tissue || labels[1] == tissue; });
    std::size_t oddEdges = 0;
    std::size_t twoLabelPinches = 0;
    std::size_t junctionPinches = 0;
    for (const auto & entry : TrianglesPerEdge(triangles))
    {
      oddEdges += entry.second % 2;
      if (entry.second > 2)
      {
        (labelsAround.at(entry.first).size() <= 2 ? twoLabelPinches : junctionPinches) += 1;
      }
    }
    const dr::SurfaceTopology topology = dr::ComputeLabelBoundaryTopology(mesh, tissue);
    const auto tetrahedra = std::count(mesh.tetrahedronLabels.begin(), mesh.tetrahedronLabels.end(), tissue);
    const auto voxelPinches =
      CountDiagonalVoxelContacts(KmeansTissueVolume(), [tissue](dr::Label label) { return label == tissue; });
    std::cout << "| " << tissue << " | " << tetrahedra << " | " << topology.numberOfTriangles << " | "
              << topology.numberOfComponents << " | " << topology.totalGenus << " | " << topology.nonManifoldEdges
              << " (" << twoLabelPinches << " / " << junctionPinches << ") | " << topology.nonManifoldVertices << " | "
              << voxelPinches << " |\n";
    EXPECT_EQ(oddEdges, 0u) << "tissue " << tissue << " has a boundary with holes";
    ExpectManifold(topology, voxelPinches, "tissue " + std::to_string(tissue));
  }
}

/** The boundary triangles with the background on their far side: the boundary of the union of the tissues. */
std::vector<std::array<uint32_t, 3>>
TrianglesAgainstTheBackground(const dr::TetrahedralMesh & mesh)
{
  return BoundaryTrianglesWhere(
    mesh, [](const std::array<dr::Label, 2> & labels) { return labels[1] == dr::BackgroundLabel; });
}

// The tissues together against the background: the triangles with background on their far side bound the
// union of the tissues, which must again be a closed manifold.
TEST(KmeansTissues, UnionBoundaryIsAClosedManifold)
{
  const dr::TetrahedralMesh & mesh = MeshedKmeans().mesh;
  const auto                  outer = TrianglesAgainstTheBackground(mesh);
  const dr::SurfaceTopology   topology = dr::ComputeSurfaceTopology(mesh.points, outer);
  std::size_t                 oddEdges = 0;
  for (const auto & entry : TrianglesPerEdge(outer))
  {
    oddEdges += entry.second % 2;
  }
  const auto voxelPinches =
    CountDiagonalVoxelContacts(KmeansTissueVolume(), [](dr::Label label) { return label != dr::BackgroundLabel; });
  std::cout << "union of tissues: " << topology.numberOfTriangles << " triangles, " << topology.numberOfComponents
            << " components, genus " << topology.totalGenus << ", non-manifold edges/vertices "
            << topology.nonManifoldEdges << "/" << topology.nonManifoldVertices << "; voxel pinches of the input "
            << voxelPinches << "\n";
  EXPECT_EQ(oddEdges, 0u);
  ExpectManifold(topology, voxelPinches, "the union of the tissues");
}

// With σ = 15°, R4′'s forced splits in tissue layers about δ thick make non-manifold places that the later topology
// rounds settle (docs/algorithm.md, "What the forced splits cost"): at 4.5 mm the six rounds that were the default
// left 1 non-manifold edge and 13 non-manifold vertices over the tissues. Every tissue's boundary and the union's must
// be manifolds, as with σ = 0, with every tetrahedron at least σ and the other bounds kept.
TEST(KmeansSlivers, FifteenDegreesKeepEveryBoundaryAManifold)
{
  static const LabelImageType::Pointer image = ReadExampleImage("KmeansTest_T1KmeansPrelimSegmentation.nii.gz");
  auto                                 filter = FilterFor(image.GetPointer(), 4.5);
  filter->SetLabels(KmeansTissues);
  filter->SetMinimumDihedralAngle(15.0);
  const auto meshed = RunFilter<FilterType>(filter);
  ASSERT_FALSE(meshed->mesh.tetrahedra.empty());
  ExpectDihedralAnglesReachSigma(*meshed);
  EXPECT_LT(meshed->quality.maximumRadiusEdgeRatio, 2.0);
  EXPECT_GT(meshed->boundary.minimumPlanarAngle, 30.0);
  EXPECT_EQ(meshed->quality.invertedTetrahedra, 0u);
  EXPECT_EQ(CountFlatTetrahedra(meshed->mesh), 0u);
  EXPECT_TRUE(meshed->consistency.IsConsistent());
  for (const dr::Label tissue : KmeansTissues)
  {
    const dr::SurfaceTopology topology = dr::ComputeLabelBoundaryTopology(meshed->mesh, tissue);
    EXPECT_GT(topology.numberOfTriangles, 0u) << "tissue " << tissue;
    EXPECT_EQ(topology.nonManifoldEdges, 0u) << "tissue " << tissue;
    EXPECT_EQ(topology.nonManifoldVertices, 0u) << "tissue " << tissue;
  }
  const dr::SurfaceTopology unionTopology =
    dr::ComputeSurfaceTopology(meshed->mesh.points, TrianglesAgainstTheBackground(meshed->mesh));
  EXPECT_EQ(unionTopology.nonManifoldEdges, 0u) << "the union of the tissues";
  EXPECT_EQ(unionTopology.nonManifoldVertices, 0u) << "the union of the tissues";
}

/** The test inputs kept with the sources (test/Input). */
std::string
TestInputFile(const std::string & fileName)
{
  return std::string(DelaunayImageToMesh_TEST_INPUT) + "/" + fileName;
}

LabelImageType::Pointer
ReadTestInputImage(const std::string & fileName)
{
  return itk::ReadImage<LabelImageType>(TestInputFile(fileName));
}

/** δ a hair below h/√2 for the 1 mm voxels of the bench's atlas phantom: the surface samples sit on a lattice about δ
 * apart. */
constexpr double DeltaOnTheLattice = 0.70710678;

/** A crop of the atlas phantom (test/Input) meshed at DeltaOnTheLattice with the defaults and σ. */
std::unique_ptr<Meshed<FilterType>>
MeshedAtLatticeDelta(const std::string & fileName, double sigma)
{
  const LabelImageType::Pointer image = ReadTestInputImage(fileName);
  const auto                    filter = FilterFor(image.GetPointer(), DeltaOnTheLattice);
  filter->SetMinimumDihedralAngle(sigma);
  return RunFilter<FilterType>(filter);
}

/** No flat tetrahedron, radius-edge < 2, boundary angles > 30°, boundary triangles within their surface balls, at
 * least `tissues` tissues, each with a manifold boundary, as the union's, and with σ = 0 Lemma 2 as the sizing and
 * the list of points moved below it that the core exported with `refined` say (DelaunayRefinementLocalSizingChecks.h);
 * with σ > 0 dihedral angles >= σ instead (R4′'s free points may come closer than δ). `mesh` is the output as the
 * user gets it. */
void
ExpectLatticeDeltaGuarantees(const dr::TetrahedralMesh & mesh, const dr::TetrahedralMesh & refined, double sigma,
                             std::size_t thickPartRounds, std::size_t tissues)
{
  ASSERT_FALSE(mesh.tetrahedra.empty());
  EXPECT_EQ(CountFlatTetrahedra(mesh), 0u);
  const dr::TetrahedronQuality quality = dr::ComputeTetrahedronQuality(mesh);
  EXPECT_LT(quality.maximumRadiusEdgeRatio, 2.0);
  EXPECT_GT(dr::ComputeBoundaryTopology(mesh).minimumPlanarAngle, 30.0);
  EXPECT_EQ(quality.invertedTetrahedra, 0u);
  EXPECT_TRUE(CheckBoundaryAgainstTetrahedra(mesh).IsConsistent());
  EXPECT_LT(LargestBoundaryCircumradius(mesh), DeltaOnTheLattice * (1.0 + dr::LatticeTieMargin));
  const std::set<dr::Label> labels(mesh.tetrahedronLabels.begin(), mesh.tetrahedronLabels.end());
  EXPECT_GE(labels.size(), tissues);
  for (const dr::Label tissue : labels)
  {
    const dr::SurfaceTopology topology = dr::ComputeLabelBoundaryTopology(mesh, tissue);
    EXPECT_EQ(topology.nonManifoldEdges, 0u) << "tissue " << tissue;
    EXPECT_EQ(topology.nonManifoldVertices, 0u) << "tissue " << tissue;
  }
  const dr::SurfaceTopology unionOfTissues =
    dr::ComputeSurfaceTopology(mesh.points, TrianglesAgainstTheBackground(mesh));
  EXPECT_GT(unionOfTissues.numberOfTriangles, 0u);
  EXPECT_EQ(unionOfTissues.nonManifoldEdges, 0u) << "the union of the tissues";
  EXPECT_EQ(unionOfTissues.nonManifoldVertices, 0u) << "the union of the tissues";
  if (sigma > 0.0)
  {
    ExpectDihedralAnglesReach(quality, sigma);
    return;
  }
  // δ is halved once per round of the sampling of thin parts (single voxels hold a ball of diameter δ here).
  const dr::LocalSizingReport sizing =
    dr::CheckEdgesAgainstLocalSizing(refined, DeltaOnTheLattice, 2.0, static_cast<unsigned int>(thickPartRounds), true);
  EXPECT_TRUE(sizing.problems.empty()) << sizing.problems.front();
}

/** The same of a filter's run: its ITK outputs, and the core's mesh for the sizing they do not carry. */
void
ExpectLatticeDeltaGuarantees(const Meshed<FilterType> & meshed, std::size_t tissues)
{
  ExpectLatticeDeltaGuarantees(meshed.mesh,
                               meshed.filter->GetRefinedMesh(),
                               meshed.filter->GetMinimumDihedralAngle(),
                               meshed.filter->GetRefinementStatistics().thickPartRounds,
                               tissues);
}

// At DeltaOnTheLattice four voxel-face centres around a voxel edge used to make a flat square inside a tissue, its
// edges within rounding of δ: no move of a corner kept Lemma 2's spacing, and the edge removal found no good ring
// (the whole atlas phantom kept 52 flat tetrahedra; this 24³ crop of it kept 2), so a last resort moved a corner
// keeping LastResortSpacingFraction of the spacing. R1 now counts a feature vertex up to LatticeTieMargin beyond δ
// as within δ (src/DelaunayRefinementRules.h): where the face centres are δ apart to within that margin, R1 does not
// put all four in, and where they are farther apart the smallest move of a corner keeps the spacing. So here, as on
// every image the suites mesh, the last resort is not needed: Lemma 2 holds in full, and no point is listed as
// moved below it (the last resort stays, as a safety net, with no case known to need it;
// TheLastResortRemovesTheFlatTetrahedraNothingElseRemoves reaches it without the margin).
TEST(LatticeDelta, FlatSquaresNeedNoMoveBelowTheSpacing)
{
  const auto meshed = MeshedAtLatticeDelta("AtlasPhantomCropWithFlatSquares.nrrd", 0.0);
  ExpectLatticeDeltaGuarantees(*meshed, 9);
  EXPECT_TRUE(meshed->filter->GetRefinedMesh().pointsMovedBelowSpacing.empty());
  EXPECT_EQ(meshed->filter->GetRefinementStatistics().flatTetrahedraMovedBelowSpacing, 0u);
}

// The same flat squares with the defaults, where R4′ removes the slivers as well.
TEST(LatticeDelta, FlatTetrahedraAndSliversAreRemovedWithTheDefaults)
{
  const auto meshed =
    MeshedAtLatticeDelta("AtlasPhantomCropWithFlatSquares.nrrd", dr::RefinementParameters{}.minimumDihedralAngle);
  ExpectLatticeDeltaGuarantees(*meshed, 9);
}

// R1's LatticeTieMargin keeps the flat squares above out, and no input known today reaches the last resort that
// removed them (docs/algorithm.md, "Flat tetrahedra inside a tissue"), so no mesh of the suite showed whether it still
// works. A hook only tests use takes the margin away (src/DelaunayRefinementTestHooks.h) and the flat squares come
// back: the edge removal takes most of them out, the last resort the rest. The mesh must keep every guarantee, with
// Lemma 2 at LastResortSpacingFraction since it lists moved points (as the filter would set the oracle up: voxel
// pinches removed, labels regularised at the default scale).
TEST(LatticeDelta, TheLastResortRemovesTheFlatTetrahedraNothingElseRemoves)
{
  const LabelImageType::Pointer image = ReadTestInputImage("AtlasPhantomCropWithFlatSquares.nrrd");
  using InterpolatorType = itk::NearestNeighborInterpolateImageFunction<LabelImageType, double>;
  auto interpolator = InterpolatorType::New();
  interpolator->SetInputImage(image);
  itk::ImageLabelMapping mapping;
  mapping.joinDiagonalVoxels = true;
  mapping.regularizationRadius = FilterType::DefaultRegularizationScale * DeltaOnTheLattice;
  itk::ImageLabelOracle<LabelImageType> oracle(image, interpolator, mapping);
  dr::RefinementParameters              parameters;
  parameters.surfaceSamplingDistance = DeltaOnTheLattice;
  parameters.minimumDihedralAngle = 0.0;
  dr::detail::RefinementTestHooks hooks;
  hooks.r1TieMargin = 0.0;
  dr::RefinementStatistics  statistics;
  const dr::TetrahedralMesh mesh =
    dr::detail::RefineMeshWithTestHooks(hooks, oracle, parameters, &statistics, &oracle, &oracle);
  ExpectLatticeDeltaGuarantees(mesh, mesh, 0.0, statistics.thickPartRounds, 9);
  // Were the case to stop reaching the last resort, this test would no longer test it.
  EXPECT_GT(statistics.flatTetrahedraRemovedByEdgeRemoval, 0u);
  EXPECT_GT(statistics.flatTetrahedraMovedBelowSpacing, 0u);
  ASSERT_FALSE(mesh.pointsMovedBelowSpacing.empty());
  // The sizing check above holds every edge to the finest δ the mesh exports, below δ here (a thick part was sampled
  // more finely), so each listed point is measured by itself against every point of the mesh: it keeps
  // LastResortSpacingFraction of its δ, and the list says something: some listed point has a neighbour nearer than δ.
  bool anyNearerThanDelta = false;
  for (const uint32_t moved : mesh.pointsMovedBelowSpacing)
  {
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t other = 0; other < mesh.points.size(); ++other)
    {
      if (other != moved)
      {
        nearest = std::min(nearest, dr::Norm(mesh.points[moved] - mesh.points[other]));
      }
    }
    const double local = mesh.pointSamplingDistances[moved];
    EXPECT_GE(nearest, dr::LastResortSpacingFraction * local) << "point " << moved;
    anyNearerThanDelta = anyNearerThanDelta || nearest < local;
  }
  EXPECT_TRUE(anyNearerThanDelta);
}

// The brain mask's own voxel surface, for comparison: one pinch, so there the manifold test above is fair.
TEST(BrainMaskReport, VoxelPinchesOfTheInput)
{
  const auto pinches = CountDiagonalVoxelContacts(LabelVolumeOf(*BrainMaskImage(), NonZeroToOne),
                                                  [](dr::Label label) { return label != dr::BackgroundLabel; });
  std::cout << "brain mask voxel pinches: " << pinches << "\n";
  // bench/README.md's bar status rests on this: the mask's own voxel surface is not a manifold.
  EXPECT_GT(pinches, 0u);
}

// ---- Diagonal voxel contacts ------------------------------------------------------------------------------

/** Two boxes of 6 x 6 x 6 voxels of label 1 that share only the edge of 6 voxels along z between them. */
LabelImageType::Pointer
BoxesTouchingAlongAnEdge()
{
  auto                        image = LabelImageType::New();
  LabelImageType::SpacingType spacing;
  spacing[0] = 1.0;
  spacing[1] = 1.25;
  spacing[2] = 1.0;
  image->SetRegions(LabelImageType::SizeType{ { 20, 20, 12 } });
  image->SetSpacing(spacing);
  image->Allocate();
  const auto within = [](long value, long first) { return value >= first && value < first + 6; };
  for (itk::ImageRegionIteratorWithIndex<LabelImageType> it(image, image->GetBufferedRegion()); !it.IsAtEnd(); ++it)
  {
    const auto & index = it.GetIndex();
    const bool   first = within(index[0], 3) && within(index[1], 3);
    const bool   second = within(index[0], 9) && within(index[1], 9);
    it.Set((first || second) && within(index[2], 3) ? 1 : 0);
  }
  return image;
}

template <typename TImage>
std::size_t
CountObjectVoxels(const TImage & image)
{
  std::size_t count = 0;
  for (itk::ImageRegionConstIterator<TImage> it(&image, image.GetBufferedRegion()); !it.IsAtEnd(); ++it)
  {
    count += it.Get() != 0;
  }
  return count;
}

/** By default the contact is joined by one voxel per voxel edge (a bar of 6 voxels), and the mesh is one closed
 * manifold with every guarantee; kept apart, nothing is added. */
TEST(DiagonalVoxels, BoxesTouchingAlongAnEdgeAreJoinedIntoOneManifold)
{
  const auto image = BoxesTouchingAlongAnEdge();
  auto       joined = FilterFor(image.GetPointer(), 1.5);
  // The joining alone: the regularisation at δ would also round the boxes' corners.
  joined->SetRegularizationScale(0.0);
  joined->SetTopologyRegularizationRounds(0);
  EXPECT_TRUE(joined->GetJoinDiagonalVoxels());
  const auto meshed = RunFilter<FilterType>(joined);
  EXPECT_EQ(joined->GetNumberOfJoiningVoxels(), 6u);
  EXPECT_EQ(CountObjectVoxels(*joined->GetObjectLabelImage()), 2u * 216u + 6u);
  ExpectGuarantees(*meshed);
  ExpectClosedManifoldBoundary(*meshed);
  EXPECT_EQ(meshed->boundary.numberOfComponents, 1);
  EXPECT_EQ(meshed->boundary.totalGenus, 0);

  auto apart = FilterFor(image.GetPointer(), 1.5);
  apart->SetRegularizationScale(0.0);
  apart->SetTopologyRegularizationRounds(0);
  apart->JoinDiagonalVoxelsOff();
  apart->Update();
  EXPECT_EQ(apart->GetNumberOfJoiningVoxels(), 0u);
  EXPECT_EQ(CountObjectVoxels(*apart->GetObjectLabelImage()), 2u * 216u);
}

/** Kept apart and with every repair off, the contact along the edge stays a non-manifold place, and the filter says
 * so (GetNumberOfRemainingNonManifoldVertices, which Python reads too); with the defaults it leaves none. Neither run
 * comes near the regularisation's budget. */
TEST(DiagonalVoxels, ContactLeftNonManifoldIsCountedByTheFilter)
{
  const auto image = BoxesTouchingAlongAnEdge();
  auto       apart = FilterFor(image.GetPointer(), 1.5);
  apart->SetRegularizationScale(0.0);
  apart->SetTopologyRegularizationRounds(0);
  apart->RelabelNonManifoldPlacesOff();
  apart->JoinDiagonalVoxelsOff();
  const auto left = RunFilter<FilterType>(apart);
  EXPECT_GT(left->boundary.nonManifoldEdges + left->boundary.nonManifoldVertices, 0u);
  EXPECT_GT(apart->GetNumberOfRemainingNonManifoldVertices(), 0u);
  EXPECT_FALSE(apart->GetTopologyRegularizationBudgetReached());

  auto       defaults = FilterFor(image.GetPointer(), 1.5);
  const auto mended = RunFilter<FilterType>(defaults);
  ExpectClosedManifoldBoundary(*mended);
  EXPECT_EQ(defaults->GetNumberOfRemainingNonManifoldVertices(), 0u);
  EXPECT_FALSE(defaults->GetTopologyRegularizationBudgetReached());
}

// ---- Bad input: a valid mesh or an itk::ExceptionObject naming the problem, never a crash or an empty mesh ----

LabelImageType::Pointer
SmallBall()
{
  const LabelImageType::SizeType size{ { 24, 24, 24 } };
  LabelImageType::SpacingType    spacing;
  spacing.Fill(1.0);
  LabelImageType::PointType origin;
  origin.Fill(0.0);
  return MakeBallImage(size, spacing, origin, IdentityDirection(), { { 11.3, 11.6, 11.8 } }, 8.0);
}

/** SetDelta is δ under the paper's name (ITK Python's delta=...): the same parameter, the same mesh. */
TEST(Parameters, DeltaIsTheSurfaceSamplingDistance)
{
  const auto image = SmallBall();
  auto       byDelta = FilterType::New();
  byDelta->SetInput(image);
  byDelta->SetDelta(3.0);
  EXPECT_EQ(byDelta->GetSurfaceSamplingDistance(), 3.0);
  auto byName = FilterType::New();
  byName->SetInput(image);
  byName->SetSurfaceSamplingDistance(3.0);
  EXPECT_EQ(byName->GetDelta(), 3.0);
  byDelta->Update();
  byName->Update();
  EXPECT_EQ(byDelta->GetOutput()->GetNumberOfCells(), byName->GetOutput()->GetNumberOfCells());
  EXPECT_GT(byDelta->GetOutput()->GetNumberOfCells(), 0u);
}

TEST(BadInput, NoVoxelCarriesASelectedLabel)
{
  auto filter = FilterFor(SmallBall().GetPointer(), 2.0);
  filter->SetLabels({ 99 });
  ExpectExceptionNaming(*filter, "no voxel carries a selected label");
}

TEST(BadInput, SingleVoxelObject)
{
  const LabelImageType::SizeType size{ { 16, 16, 16 } };
  LabelImageType::SpacingType    spacing;
  spacing.Fill(1.0);
  LabelImageType::PointType origin;
  origin.Fill(0.0);
  auto image = MakeBallImage(size, spacing, origin, IdentityDirection(), { { 0.0, 0.0, 0.0 } }, -1.0);
  const LabelImageType::IndexType voxel{ { 7, 8, 9 } };
  image->SetPixel(voxel, 1);
  // The automatic δ (4 voxels): the voxel holds no ball of diameter δ, and the regularisation removes it, saying so.
  for (const char * problem : { "thinner than the regularisation scale", "SurfaceSamplingDistance" })
  {
    auto filter = FilterFor(image.GetPointer(), 0.0);
    ExpectExceptionNaming(*filter, problem);
  }
  // δ = 0.25 voxel: the voxel holds a ball of diameter δ, so it is meshed (nothing a δ across is lost), around its
  // centre, with every guarantee.
  auto       filter = FilterFor(image.GetPointer(), 0.25);
  const auto meshed = RunFilter<FilterType>(filter);
  ASSERT_FALSE(meshed->mesh.tetrahedra.empty());
  ExpectGuarantees(*meshed);
  ExpectClosedManifoldBoundary(*meshed);
  EXPECT_TRUE(ATetrahedronOfTheLabelContains(meshed->mesh, 1, PhysicalCenterOf(*image, voxel)));
}

// A ball clipped by all six faces of its image: outside the image everything is background, so the mesh must
// be closed there.
TEST(BadInput, ObjectTouchingEveryBorder)
{
  const LabelImageType::SizeType size{ { 20, 22, 18 } };
  LabelImageType::SpacingType    spacing;
  spacing.Fill(1.0);
  LabelImageType::PointType origin;
  origin.Fill(0.0);
  auto image = MakeBallImage(size, spacing, origin, IdentityDirection(), { { 9.5, 10.5, 8.5 } }, 12.0);
  for (const auto index : { LabelImageType::IndexType{ { 0, 10, 8 } },
                            LabelImageType::IndexType{ { 19, 10, 8 } },
                            LabelImageType::IndexType{ { 9, 0, 8 } },
                            LabelImageType::IndexType{ { 9, 21, 8 } },
                            LabelImageType::IndexType{ { 9, 10, 0 } },
                            LabelImageType::IndexType{ { 9, 10, 17 } } })
  {
    ASSERT_EQ(image->GetPixel(index), 1) << "the ball does not touch the border at " << index;
  }
  const auto meshed = RunFilter<FilterType>(FilterFor(image.GetPointer(), 2.0));
  ExpectGuarantees(*meshed);
  ExpectClosedManifoldBoundary(*meshed);
  EXPECT_EQ(meshed->boundary.numberOfComponents, 1);
  EXPECT_EQ(meshed->boundary.totalGenus, 0);
}

// Every voxel is object: the object is the image's box (voxel centres ± half a voxel). The mesh must be a closed
// genus-0 surface inside that box, its vertices on the box's faces.
TEST(BadInput, WholeImageIsOneLabel)
{
  const LabelImageType::SizeType size{ { 12, 10, 8 } };
  LabelImageType::SpacingType    spacing;
  spacing[0] = 1.0;
  spacing[1] = 1.5;
  spacing[2] = 2.0;
  LabelImageType::PointType origin;
  origin.Fill(-3.0);
  auto       image = MakeBallImage(size, spacing, origin, IdentityDirection(), { { 0.0, 0.0, 0.0 } }, 1e9);
  const auto meshed = RunFilter<FilterType>(FilterFor(image.GetPointer(), 2.0));
  ExpectGuarantees(*meshed);
  ExpectClosedManifoldBoundary(*meshed);
  EXPECT_EQ(meshed->boundary.numberOfComponents, 1);
  EXPECT_EQ(meshed->boundary.totalGenus, 0);
  double boxVolume = 1.0;
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    const double lower = origin[axis] - 0.5 * spacing[axis];
    const double upper = origin[axis] + (size[axis] - 0.5) * spacing[axis];
    boxVolume *= upper - lower;
    for (const dr::Vector3 & point : meshed->mesh.points)
    {
      EXPECT_GE(point[axis], lower - SurfacePointTolerance);
      EXPECT_LE(point[axis], upper + SurfacePointTolerance);
    }
  }
  std::cout << "box " << boxVolume << " mm^3, mesh " << meshed->quality.totalVolume << " mm^3\n";
  EXPECT_LE(meshed->quality.totalVolume, boxVolume * (1.0 + RoundingSlack));
}

FloatImageType::Pointer
FloatBallWith(float specialValue)
{
  const auto ball = SmallBall();
  auto       image = FloatImageType::New();
  image->CopyInformation(ball);
  image->SetRegions(ball->GetBufferedRegion());
  image->Allocate();
  itk::ImageRegionConstIteratorWithIndex<LabelImageType> from(ball, ball->GetBufferedRegion());
  for (; !from.IsAtEnd(); ++from)
  {
    image->SetPixel(from.GetIndex(), from.Get());
  }
  image->SetPixel({ { 3, 4, 5 } }, specialValue);
  return image;
}

TEST(BadInput, FloatImageWithNaN)
{
  auto filter = FilterFor(FloatBallWith(std::numeric_limits<float>::quiet_NaN()).GetPointer(), 2.0);
  ExpectExceptionNaming(*filter, "non-finite");
  ExpectExceptionNaming(*filter, "at index [3, 4, 5]");
}

TEST(BadInput, FloatImageWithInfinity)
{
  auto filter = FilterFor(FloatBallWith(std::numeric_limits<float>::infinity()).GetPointer(), 2.0);
  ExpectExceptionNaming(*filter, "non-finite");
}

TEST(BadInput, FloatImageWithInfinityInIsoValueMode)
{
  auto filter = FilterFor(FloatBallWith(std::numeric_limits<float>::infinity()).GetPointer(), 2.0);
  filter->SetIsoValue(0.5);
  ExpectExceptionNaming(*filter, "non-finite");
}

/** Two balls of radius 4 mm on a 24 x 12 x 12 grid of 1 mm voxels: the left one of value `left`, the right one of
 * `right`; their centres. */
template <typename TPixel>
std::pair<typename itk::Image<TPixel, 3>::Pointer, std::array<dr::Vector3, 2>>
TwoBallsOf(TPixel left, TPixel right)
{
  using ImageType = itk::Image<TPixel, 3>;
  auto image = ImageType::New();
  image->SetRegions(typename ImageType::SizeType{ { 24, 12, 12 } });
  image->Allocate();
  image->FillBuffer(TPixel{ 0 });
  const std::array<dr::Vector3, 2> centers{ { { { 5.5, 5.5, 5.5 } }, { { 17.5, 5.5, 5.5 } } } };
  for (itk::ImageRegionIteratorWithIndex<ImageType> it(image, image->GetBufferedRegion()); !it.IsAtEnd(); ++it)
  {
    for (int ball = 0; ball < 2; ++ball)
    {
      double squared = 0.0;
      for (unsigned int axis = 0; axis < 3; ++axis)
      {
        const double d = static_cast<double>(it.GetIndex()[axis]) - centers[ball][axis];
        squared += d * d;
      }
      if (squared <= 16.0)
      {
        it.Set(ball == 0 ? left : right);
      }
    }
  }
  return { image, centers };
}

// A label is the voxel's value rounded to the nearest integer, and the labels are the 32-bit signed integers but
// the smallest (the output's cell data, delaunay_refinement::Label). A value beyond them was clamped to the largest
// label: two tissues of 3,000,000,000 and 4,000,000,000 would have been one, and a selection of 2147483647 would
// have taken both. Each label being a tissue, such a value is refused, naming it, its index and the range.
TEST(BadInput, ValueBeyondTheLabels)
{
  const auto [image, centers] = TwoBallsOf<uint32_t>(3000000000u, 4000000000u);
  auto filter = FilterFor(image.GetPointer(), 2.0);
  ExpectExceptionNaming(*filter, "holds the value 3000000000 at index [");
  ExpectExceptionNaming(*filter, "the integers in [-2147483647, 2147483647]");

  const auto [smallest, unused] = TwoBallsOf<int32_t>(1, std::numeric_limits<int32_t>::min());
  auto smallestFilter = FilterFor(smallest.GetPointer(), 2.0);
  ExpectExceptionNaming(*smallestFilter, "holds the value -2147483648 at index [");

  // A float a label apart from the largest label, and one within rounding of it.
  const auto [beyond, unusedBeyond] = TwoBallsOf<double>(1.0, 2147483647.5);
  ExpectExceptionNaming(*FilterFor(beyond.GetPointer(), 2.0), "holds the value 2147483647.5 at index [");
  const auto [within, withinCenters] = TwoBallsOf<double>(1.0, 2147483647.4);
  const auto meshed =
    RunFilter<itk::DelaunayImageToMeshFilter<itk::Image<double, 3>, MeshType>>(FilterFor(within.GetPointer(), 2.0));
  EXPECT_TRUE(ATetrahedronOfTheLabelContains(meshed->mesh, 2147483647, withinCenters[1]));
}

// Merged labels read every non-zero value as the object, and a selection only the labels it names: there a value
// beyond the labels is no label, neither refused nor clamped into one.
TEST(LabelSelection, ValueBeyondTheLabelsIsObjectWhenMergedAndNeverSelected)
{
  const auto [image, centers] = TwoBallsOf<uint32_t>(1u, 4000000000u);
  auto merged = FilterFor(image.GetPointer(), 2.0);
  merged->MergeLabelsOn();
  const auto meshed = RunFilter<itk::DelaunayImageToMeshFilter<itk::Image<uint32_t, 3>, MeshType>>(merged);
  ExpectGuarantees(*meshed);
  EXPECT_TRUE(ATetrahedronOfTheLabelContains(meshed->mesh, 1, centers[0]));
  EXPECT_TRUE(ATetrahedronOfTheLabelContains(meshed->mesh, 1, centers[1]));
  EXPECT_EQ(meshed->boundary.numberOfComponents, 2);

  auto selected = FilterFor(image.GetPointer(), 2.0);
  selected->AddLabel(1);
  const auto left = RunFilter<itk::DelaunayImageToMeshFilter<itk::Image<uint32_t, 3>, MeshType>>(selected);
  EXPECT_TRUE(ATetrahedronOfTheLabelContains(left->mesh, 1, centers[0]));
  EXPECT_FALSE(ATetrahedronOfTheLabelContains(left->mesh, 1, centers[1]));
  EXPECT_EQ(left->boundary.numberOfComponents, 1);

  auto largest = FilterFor(image.GetPointer(), 2.0);
  largest->AddLabel(std::numeric_limits<int32_t>::max());
  ExpectExceptionNaming(*largest, "no voxel carries a selected label");
}

// A selected label that no voxel carries cannot be meshed, and a selection is how the user said what must be (a
// label mistyped, or a tissue one scan of a series lacks): it is reported, never left out in silence, the same with
// the labels merged. Where no selected label is in the image, the update fails naming them. Each update reads the
// image again: a later selection that is all there reports none.
TEST(LabelSelection, SelectedLabelsNotInTheImageAreReported)
{
  using ImageType = itk::Image<uint16_t, 3>;
  using Filter = itk::DelaunayImageToMeshFilter<ImageType, MeshType>;
  const auto [image, centers] = TwoBallsOf<uint16_t>(3, 7);
  auto filter = FilterFor(image.GetPointer(), 2.0);
  filter->SetLabels({ 7, 99, 3, -4, 99 });
  const auto meshed = RunFilter<Filter>(filter);
  ExpectGuarantees(*meshed);
  EXPECT_TRUE(ATetrahedronOfTheLabelContains(meshed->mesh, 3, centers[0]));
  EXPECT_TRUE(ATetrahedronOfTheLabelContains(meshed->mesh, 7, centers[1]));
  EXPECT_EQ(filter->GetSelectedLabelsNotInImage(), (Filter::LabelListType{ -4, 99 }));

  filter->SetLabels({ 3 });
  filter->Update();
  EXPECT_TRUE(filter->GetSelectedLabelsNotInImage().empty());

  filter->SetLabels({ 12, 7, 3 });
  filter->MergeLabelsOn();
  filter->Update();
  EXPECT_EQ(filter->GetSelectedLabelsNotInImage(), (Filter::LabelListType{ 12 }));

  filter->SetLabels({ 40, 12 });
  ExpectExceptionNaming(*filter, "the selected labels not in the image: 12, 40");
  EXPECT_EQ(filter->GetSelectedLabelsNotInImage(), (Filter::LabelListType{ 12, 40 }));
  // An update refused before it reads the image says nothing of it, not what the last one found.
  filter->SetLabels({ std::numeric_limits<dr::Label>::min() });
  ExpectExceptionNaming(*filter, "Invalid label -2147483648 in Labels");
  EXPECT_TRUE(filter->GetSelectedLabelsNotInImage().empty());
}

// The one 32-bit integer that is no label (a value rounding to it is refused) can never be meshed as a tissue:
// selecting it is refused, naming the label and the valid range, not ignored.
TEST(BadInput, SelectedLabelThatIsNoLabel)
{
  for (const dr::Label label : { std::numeric_limits<dr::Label>::min() })
  {
    auto filter = FilterFor(SmallBall().GetPointer(), 2.0);
    filter->SetLabels({ 1, label });
    ExpectExceptionNaming(*filter, "Invalid label " + std::to_string(label) + " in Labels");
    ExpectExceptionNaming(*filter, "the integers in [-2147483647, 2147483647]");
  }
}

TEST(BadInput, EmptyBufferedRegion)
{
  auto                       image = LabelImageType::New();
  LabelImageType::RegionType empty;
  empty.SetSize({ { 0, 0, 0 } });
  image->SetRegions(empty);
  image->Allocate();
  auto filter = FilterFor(image.GetPointer(), 2.0);
  ExpectExceptionNaming(*filter, "buffered region is empty");
}

// ITK's pipeline says which input is missing (the filter's required input, "Primary"); any other exception would be
// a failure of its own.
TEST(BadInput, NoInput)
{
  auto filter = FilterType::New();
  ExpectExceptionNaming(*filter, "Input Primary is required but not set");
}

TEST(BadInput, SurfaceSamplingDistance)
{
  for (const double delta :
       { -1.0, -1e-12, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity() })
  {
    SCOPED_TRACE("delta " + std::to_string(delta));
    auto filter = FilterFor(SmallBall().GetPointer(), delta);
    ExpectExceptionNaming(*filter, "SurfaceSamplingDistance");
  }
}

TEST(BadInput, ZeroSurfaceSamplingDistanceIsAutomatic)
{
  const auto image = SmallBall();
  auto       filter = FilterFor(image.GetPointer(), 0.0);
  const auto meshed = RunFilter<FilterType>(filter);
  EXPECT_EQ(filter->GetEffectiveSurfaceSamplingDistance(), 4.0 * 1.0);
  ExpectGuarantees(*meshed);
}

TEST(BadInput, RadiusEdgeBound)
{
  for (const double rho :
       { 0.99, 0.0, -2.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity() })
  {
    SCOPED_TRACE("rho " + std::to_string(rho));
    auto filter = FilterFor(SmallBall().GetPointer(), 2.0);
    filter->SetRadiusEdgeBound(rho);
    ExpectExceptionNaming(*filter, "RadiusEdgeBound");
  }
}

TEST(BadInput, MinimumDihedralAngle)
{
  for (const double sigma : { -1.0, 20.5, 30.0, 90.0, std::numeric_limits<double>::quiet_NaN() })
  {
    SCOPED_TRACE("sigma " + std::to_string(sigma));
    auto filter = FilterFor(SmallBall().GetPointer(), 2.0);
    filter->SetMinimumDihedralAngle(sigma);
    ExpectExceptionNaming(*filter, "MinimumDihedralAngle");
  }
}

TEST(BadInput, MaximumNumberOfVertices)
{
  for (const itk::SizeValueType limit : { 0, 7, 8, 50 })
  {
    SCOPED_TRACE("limit " + std::to_string(limit));
    auto filter = FilterFor(SmallBall().GetPointer(), 2.0);
    filter->SetMaximumNumberOfVertices(limit);
    ExpectExceptionNaming(*filter, "MaximumNumberOfVertices");
  }
}

/** The documented range of RegularizationScale is [0, 0.5], both ends included: the filter's own check, which no
 * other test reached (the command line checks its option itself). Just outside either end is refused, naming the
 * parameter; each end meshes. The small ball's radius, 8 voxels, holds the opening's ball at the largest scale
 * (0.5 x 2 = 1 mm), so the ends give a mesh with the guarantees. */
TEST(BadInput, RegularizationScale)
{
  for (const double scale : { -1e-12,
                              std::nextafter(FilterType::LargestRegularizationScale, 1.0),
                              1.0,
                              std::numeric_limits<double>::quiet_NaN(),
                              std::numeric_limits<double>::infinity() })
  {
    SCOPED_TRACE("scale " + std::to_string(scale));
    auto filter = FilterFor(SmallBall().GetPointer(), 2.0);
    filter->SetRegularizationScale(scale);
    ExpectExceptionNaming(*filter, "RegularizationScale");
  }
  EXPECT_EQ(FilterType::LargestRegularizationScale, 0.5);
  for (const double scale : { 0.0, FilterType::LargestRegularizationScale })
  {
    SCOPED_TRACE("scale " + std::to_string(scale));
    auto filter = FilterFor(SmallBall().GetPointer(), 2.0);
    filter->SetRegularizationScale(scale);
    std::unique_ptr<Meshed<FilterType>> meshed;
    ASSERT_NO_THROW(meshed = RunFilter<FilterType>(filter));
    ExpectGuarantees(*meshed);
  }
}

/** ITK's readers give a negative spacing's sign to the direction instead (ImageFileReader); an image made in code can
 * still carry one, which would turn the regularisation's reach and the automatic δ negative: it is refused, naming
 * the spacing. */
TEST(BadInput, SpacingThatIsNotPositive)
{
  for (const auto & values :
       { std::array<double, 3>{ { 1.0, -1.0, 1.0 } }, std::array<double, 3>{ { -2.0, -2.0, -2.0 } } })
  {
    auto image = LabelImageType::New();
    image->Graft(SmallBall());
    LabelImageType::SpacingType spacing;
    std::copy(values.begin(), values.end(), spacing.Begin());
    image->SetSpacing(spacing);
    auto filter = FilterFor(image.GetPointer(), 2.0);
    ExpectExceptionNaming(*filter, "The input image's spacing [");
    ExpectExceptionNaming(*filter, "the valid range is (0, inf)");
  }
}

/** Distances are measured along the voxel axes, so a direction that is not a rotation or a reflection is refused,
 * naming the direction: a shear (a CT gantry tilt), a column that is not a unit vector (ITK itself aborts on a NaN
 * there, in SetDirection()). A rotation written to six decimals, as DICOM files often have it, is accepted and
 * meshes with the guarantees. */
TEST(BadInput, DirectionThatIsNotOrthonormal)
{
  const auto withDirection = [](const LabelImageType::DirectionType & direction) {
    auto image = LabelImageType::New();
    image->Graft(SmallBall());
    image->SetDirection(direction);
    return FilterFor(image.GetPointer(), 2.0);
  };
  LabelImageType::DirectionType sheared = IdentityDirection();
  sheared[0][1] = 0.2;
  LabelImageType::DirectionType stretched = IdentityDirection();
  stretched[1][1] = 1.001;
  for (const auto & direction : { sheared, stretched })
  {
    auto filter = withDirection(direction);
    ExpectExceptionNaming(*filter, "direction (rows) [[");
    ExpectExceptionNaming(*filter, "is not orthonormal");
  }

  LabelImageType::DirectionType rounded = ObliqueDirection();
  for (unsigned int row = 0; row < 3; ++row)
  {
    for (unsigned int column = 0; column < 3; ++column)
    {
      rounded[row][column] = std::round(rounded[row][column] * 1e6) / 1e6;
    }
  }
  ASSERT_NE(rounded, ObliqueDirection()) << "the rounding must leave the rotation";
  std::unique_ptr<Meshed<FilterType>> meshed;
  ASSERT_NO_THROW(meshed = RunFilter<FilterType>(withDirection(rounded)));
  ExpectGuarantees(*meshed);
}

// σ > 0 (R4'): no theorem, but the core promises every output tetrahedron at least σ.
TEST(Parameters, MinimumDihedralAngleIsHonoured)
{
  auto filter = FilterFor(SmallBall().GetPointer(), 2.0);
  filter->SetMinimumDihedralAngle(12.0);
  const auto meshed = RunFilter<FilterType>(filter);
  ASSERT_FALSE(meshed->mesh.tetrahedra.empty());
  ExpectDihedralAnglesReachSigma(*meshed);
  EXPECT_EQ(meshed->quality.invertedTetrahedra, 0u);
  EXPECT_TRUE(meshed->consistency.IsConsistent());
}

// With σ = 15° the same mesh has neither flat tetrahedra nor slivers, and keeps the other bounds (measured: R4'
// proves nothing about boundary angles).
TEST(BrainMaskSlivers, FifteenDegreesRemoveTheFlatCapsAndKeepTheBounds)
{
  auto filter = FilterFor(BrainMaskImage(), 3.0);
  filter->SetMinimumDihedralAngle(15.0);
  const auto meshed = RunFilter<FilterType>(filter);
  EXPECT_EQ(CountFlatTetrahedra(meshed->mesh), 0u);
  ExpectDihedralAnglesReachSigma(*meshed);
  EXPECT_LT(meshed->quality.maximumRadiusEdgeRatio, 2.0);
  EXPECT_GT(meshed->boundary.minimumPlanarAngle, 30.0);
  EXPECT_EQ(meshed->quality.invertedTetrahedra, 0u);
  EXPECT_TRUE(meshed->consistency.IsConsistent());
  ExpectClosedManifoldBoundary(*meshed);
  // The picking region, not the circumcentre: at most 1.3 × the tetrahedra of σ = 0 (the circumcentre made 1.58 ×
  // at 4 mm).
  EXPECT_LE(static_cast<double>(meshed->mesh.tetrahedra.size()),
            1.3 * static_cast<double>(MeshedBrainMask(3.0).mesh.tetrahedra.size()));
}

// ---- Gray image and iso-value -----------------------------------------------------------------------------

// f(x) = r - |x - c| sampled at the voxel centres and interpolated trilinearly; the object is f >= 0. Per cell,
// |I f - f| <= Σ h_i^2 / 8 · max |∂ii f| (tensor-product linear interpolation), and |∂ii f| <= 1 / |x - c|,
// so near the sphere the error is e <= Σ h_i^2 / (8 (r - d)), d a voxel diagonal. f is a signed distance, so
// I f keeps its sign wherever | |x - c| - r | > e: the oracle's surface is within e of the sphere.
TEST(GrayImage, IsoSurfaceOfLinearInterpolationMatchesTheSphere)
{
  constexpr double               radius = 12.0;
  const FloatImageType::SizeType size{ { 30, 28, 26 } };
  FloatImageType::SpacingType    spacing;
  spacing[0] = 1.0;
  spacing[1] = 1.1;
  spacing[2] = 1.25;
  FloatImageType::PointType origin;
  origin[0] = 5.0;
  origin[1] = -3.0;
  origin[2] = 2.0;
  auto image = FloatImageType::New();
  image->SetRegions(size);
  image->SetSpacing(spacing);
  image->SetOrigin(origin);
  image->SetDirection(ObliqueDirection());
  image->Allocate();
  // The centre at a fractional index, so that the voxel values have no symmetry to hide an error.
  itk::ContinuousIndex<double, 3> centerIndex;
  centerIndex[0] = 14.6;
  centerIndex[1] = 13.4;
  centerIndex[2] = 12.8;
  FloatImageType::PointType centerPoint;
  image->TransformContinuousIndexToPhysicalPoint(centerIndex, centerPoint);
  const dr::Vector3 sphereCenter{ { centerPoint[0], centerPoint[1], centerPoint[2] } };
  for (itk::ImageRegionIteratorWithIndex<FloatImageType> it(image, image->GetBufferedRegion()); !it.IsAtEnd(); ++it)
  {
    it.Set(static_cast<float>(radius - dr::Distance(PhysicalCenterOf(*image, it.GetIndex()), sphereCenter)));
  }
  auto filter = FilterFor(image.GetPointer(), 1.5);
  filter->SetIsoValue(0.0);
  const auto meshed = RunFilter<FloatFilterType>(filter);
  ExpectGuarantees(*meshed);

  const double squaredSpacings = spacing[0] * spacing[0] + spacing[1] * spacing[1] + spacing[2] * spacing[2];
  const double interpolationError = squaredSpacings / (8.0 * (radius - 2.0 * HalfVoxelDiagonal(*image)));
  // float storage adds at most a few ulp of values below 20, far under the tolerance.
  ExpectFaithfulSphere(*meshed, sphereCenter, radius, interpolationError + SurfacePointTolerance);
}

// ---- A smooth label interpolator ----------------------------------------------------------------------------

TEST(Interpolator, LabelImageGaussianInterpolatorGivesAValidMesh)
{
  using GaussianInterpolatorType = itk::LabelImageGaussianInterpolateImageFunction<LabelImageType, double>;
  const BallInGrid & ball = ObliqueBall();
  auto               interpolator = GaussianInterpolatorType::New();
  const double       sigma[3] = { 0.7, 0.9, 1.6 };
  interpolator->SetSigma(sigma);
  interpolator->SetAlpha(2.0);
  auto filter = FilterFor(ball.image.GetPointer(), BallDelta);
  filter->SetInterpolator(interpolator);
  EXPECT_EQ(filter->GetInterpolator(), interpolator.GetPointer());
  const auto meshed = RunFilter<FilterType>(filter);
  ExpectGuarantees(*meshed);
  ExpectClosedManifoldBoundary(*meshed);
  EXPECT_EQ(meshed->boundary.numberOfComponents, 1);
  EXPECT_EQ(meshed->boundary.totalGenus, 0);
  // The Gaussian vote between the labels near a point switches where the weights of the two sides balance, which for a
  // surface flat at the scale of the kernel is the surface of the voxels' labels itself: the nearest-neighbour band
  // (half a voxel diagonal, 0.98 mm here) holds it too. Measured: vertex offset 0.79 mm, mesh -> sphere 0.79 mm,
  // sphere -> mesh 0.62 mm, against a chordal bound of about 1.1 mm.
  ExpectFaithfulSphere(
    *meshed, ball.center, BallInGrid::Radius, HalfVoxelDiagonal(*ball.image) + SurfacePointTolerance);
}

// ---- Progress and abort -------------------------------------------------------------------------------------

/** Records every progress value the filter reports; with `abortAbove` set, requests the abort at the first value
 * above it. */
struct ProgressRecord
{
  std::vector<float> values;
  float              abortAbove{ std::numeric_limits<float>::infinity() };
  bool               requested{ false };

  void
  Watch(itk::ProcessObject & filter)
  {
    filter.AddObserver(itk::ProgressEvent(), [this, &filter](const itk::EventObject &) {
      values.push_back(filter.GetProgress());
      if (!requested && values.back() > abortAbove)
      {
        requested = true;
        filter.AbortGenerateDataOn();
      }
    });
  }
};

TEST(Progress, MonotoneAndEndsAtOne)
{
  auto           filter = FilterFor(BrainMaskImage(), 4.0);
  ProgressRecord record;
  record.Watch(*filter);
  filter->Update();
  const std::vector<float> & progress = record.values;
  ASSERT_GE(progress.size(), 3u);
  EXPECT_GE(progress.front(), 0.0f);
  EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end()));
  EXPECT_EQ(progress.back(), 1.0f);
  const auto inBetween = std::count_if(progress.begin(), progress.end(), [](float p) { return p > 0.1f && p < 0.99f; });
  EXPECT_GT(inBetween, 0) << "no progress reported during the refinement";
  std::cout << progress.size() << " progress events\n";
}

/** Requests the abort once the progress passes a threshold, and remembers when. */
class AbortWhenProgressPasses : public itk::Command
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(AbortWhenProgressPasses);
  using Self = AbortWhenProgressPasses;
  using Pointer = itk::SmartPointer<Self>;
  itkNewMacro(Self);

  float             threshold{ 0.3f };
  bool              requested{ false };
  Clock::time_point requestTime;

  void
  Execute(itk::Object * caller, const itk::EventObject & event) override
  {
    auto * filter = static_cast<itk::ProcessObject *>(caller);
    if (!requested && itk::ProgressEvent().CheckEvent(&event) && filter->GetProgress() > threshold)
    {
      requested = true;
      requestTime = Clock::now();
      filter->AbortGenerateDataOn();
    }
  }

  void
  Execute(const itk::Object *, const itk::EventObject &) override
  {}

protected:
  AbortWhenProgressPasses() = default;
};

TEST(Progress, AbortThrowsProcessAbortedPromptly)
{
  auto filter = FilterFor(BrainMaskImage(), 2.0);
  auto aborter = AbortWhenProgressPasses::New();
  filter->AddObserver(itk::ProgressEvent(), aborter);
  double latency = -1.0;
  try
  {
    filter->Update();
    ADD_FAILURE() << "Update() finished despite the abort request";
  }
  catch (const itk::ProcessAborted &)
  {
    latency = Seconds(aborter->requestTime);
  }
  ASSERT_TRUE(aborter->requested);
  std::cout << "aborted " << latency << " s after the request\n";
  EXPECT_GE(latency, 0.0);
  EXPECT_LT(latency, 1.0);
}

/** A ball of label 1 of `radius` mm near the middle of a grid of `size` voxels of 1 mm at the origin: large enough
 * that the set-up's passes over its voxels take rounds and its steps report progress. */
LabelImageType::Pointer
BallOnAMillimetreGrid(const LabelImageType::SizeType & size, double radius)
{
  LabelImageType::SpacingType spacing;
  spacing.Fill(1.0);
  LabelImageType::PointType origin;
  origin.Fill(0.0);
  const std::array<double, 3> offCentre{ { 0.5, 0.8, 0.3 } };
  std::array<double, 3>       centre{};
  for (unsigned int axis = 0; axis < 3; ++axis)
  {
    centre[axis] = 0.5 * static_cast<double>(size[axis]) - offCentre[axis];
  }
  return MakeBallImage(size, spacing, origin, IdentityDirection(), centre, radius);
}

/** The distinct progress values a whole run of the filter on `image` at δ = `delta` reports strictly between `low`
 * and `high`; the run's values must never decrease. */
std::vector<float>
DistinctProgressBetween(const LabelImageType * image, double delta, float low, float high)
{
  auto           meshing = FilterFor(image, delta);
  ProgressRecord all;
  all.Watch(*meshing);
  meshing->Update();
  EXPECT_TRUE(std::is_sorted(all.values.begin(), all.values.end()));
  std::vector<float> between;
  std::copy_if(all.values.begin(), all.values.end(), std::back_inserter(between), [=](float value) {
    return value > low && value < high;
  });
  between.erase(std::unique(between.begin(), between.end()), between.end());
  return between;
}

/** The last progress value of a run on `image` at δ = `delta` that asks for an abort as soon as the progress passes
 * `abortAbove`; the run must end with ProcessAborted, and report a value past the threshold. */
float
LastProgressOfARunAbortedAbove(const LabelImageType * image, double delta, float abortAbove)
{
  auto           aborted = FilterFor(image, delta);
  ProgressRecord untilAbort;
  untilAbort.abortAbove = abortAbove;
  untilAbort.Watch(*aborted);
  EXPECT_THROW(aborted->Update(), itk::ProcessAborted);
  EXPECT_TRUE(untilAbort.requested) << "no progress reported past " << abortAbove;
  return untilAbort.values.empty() ? 0.0f : *std::max_element(untilAbort.values.begin(), untilAbort.values.end());
}

// The oracle's set-up (label image, regularisation, pinch removal, nearest-interface map) is most of the run when a
// large image is meshed coarsely (bench/README.md, "At 1e3134b": 3.4 of 4 s on 38 M voxels at 8 mm). It reports
// progress within the first tenth of the range, in steps that follow its passes and the rounds of a few million
// voxels of the map's passes, and an abort requested there ends the run before the refinement starts.
TEST(Progress, SetUpReportsProgressAndHonoursAbort)
{
  constexpr float setUpShare = 0.1f;
  const auto      image = BallOnAMillimetreGrid({ { 200, 190, 180 } }, 80.0);
  // The steps: the object's bounds, the selection, the regularisation, the pinch removal, and the map's marking and
  // three passes over the ball's box (162^3 = 4.25 M voxels), each in three rounds of at most 2 M voxels.
  const std::vector<float> setUp = DistinctProgressBetween(image.GetPointer(), 24.0, 0.0f, setUpShare);
  EXPECT_GE(setUp.size(), 12u) << "the set-up reported " << setUp.size() << " distinct progress values";
  // Past the pinch removal (0.048 of the range): within the nearest-interface map's passes.
  EXPECT_LT(LastProgressOfARunAbortedAbove(image.GetPointer(), 24.0, 0.06f), setUpShare)
    << "the run went on to the refinement after the abort request";
}

// The regularisation's share of the set-up (0.006 to 0.04 of the range, SetUpProgressAfter) moves while the labels
// are opened, and an abort asked for there ends the run before the regularisation does. Before, the regularisation
// reported the selection's fraction at each of its checks and the command-line bar sat still through it (0.3 s on
// the CT-like probe of bench/README.md, "At 1161bcd").
TEST(Progress, RegularisationMovesTheProgressAndHonoursAbort)
{
  constexpr float regularisationStart = 0.006f;
  constexpr float regularisationEnd = 0.04f;
  const auto      image = BallOnAMillimetreGrid({ { 160, 150, 140 } }, 62.0);
  // The component count, and the steps of the labels' openings that run on the calling thread.
  const std::vector<float> regularisation =
    DistinctProgressBetween(image.GetPointer(), 24.0, regularisationStart, regularisationEnd);
  EXPECT_GE(regularisation.size(), 4u) << "the regularisation reported " << regularisation.size()
                                       << " distinct progress values";
  EXPECT_LT(LastProgressOfARunAbortedAbove(image.GetPointer(), 24.0, 0.008f), regularisationEnd)
    << "the regularisation ran to its end after the abort request";
}

// An aborted filter must be usable again: the next Update() meshes normally.
TEST(Progress, FilterRunsAgainAfterAnAbort)
{
  const auto image = SmallBall();
  auto       filter = FilterFor(image.GetPointer(), 1.0);
  auto       aborter = AbortWhenProgressPasses::New();
  aborter->threshold = 0.0f;
  const auto tag = filter->AddObserver(itk::ProgressEvent(), aborter);
  EXPECT_THROW(filter->Update(), itk::ProcessAborted);
  filter->RemoveObserver(tag);
  const auto meshed = RunFilter<FilterType>(filter);
  ExpectGuarantees(*meshed);
}

// ---- Pipeline ------------------------------------------------------------------------------------------------

/** ITK's pipeline runs a filter again only when something changed: a second Update(), or a downstream filter pulling
 * the outputs (ITK's FEM registration pulls the mesh it is given), must not mesh again. The outputs are point sets,
 * out of date for the pipeline until their buffered region is the requested one. */
TEST(Pipeline, UpdateRunsTheFilterOnlyWhenSomethingChanged)
{
  const auto image = SmallBall();
  auto       filter = FilterFor(image.GetPointer(), 1.0);
  int        runs = 0;
  filter->AddObserver(itk::StartEvent(), [&runs](const itk::EventObject &) { ++runs; });
  filter->Update();
  ASSERT_EQ(runs, 1);
  filter->Update();
  filter->GetOutput()->Update();
  filter->GetInterfaceMesh()->Update();
  EXPECT_EQ(runs, 1) << "Update() meshed again although nothing changed";
  filter->SetSurfaceSamplingDistance(1.5);
  filter->GetOutput()->Update();
  EXPECT_EQ(runs, 2) << "a changed parameter did not mesh again";
}

// ---- Determinism ---------------------------------------------------------------------------------------------

void
ExpectIdentical(const dr::TetrahedralMesh & a, const dr::TetrahedralMesh & b)
{
  EXPECT_TRUE(a.points == b.points) << "point coordinates differ";
  EXPECT_TRUE(a.tetrahedra == b.tetrahedra) << "tetrahedra differ";
  EXPECT_TRUE(a.tetrahedronLabels == b.tetrahedronLabels) << "labels differ";
  EXPECT_TRUE(a.boundaryTriangles == b.boundaryTriangles) << "boundary triangles differ";
  EXPECT_TRUE(a.boundaryTriangleLabels == b.boundaryTriangleLabels) << "interface labels differ";
}

TEST(Determinism, SameFilterTwiceAndTwoFilters)
{
  const Meshed<FilterType> & first = MeshedBrainMask(4.0);
  first.filter->Modified();
  const auto again = RunFilter<FilterType>(first.filter);
  const auto other = RunFilter<FilterType>(FilterFor(BrainMaskImage(), 4.0));
  ExpectIdentical(first.mesh, again->mesh);
  ExpectIdentical(first.mesh, other->mesh);
}

/** The label image is stored in one, two or four bytes a voxel, by the labels it must hold
 * (ImageLabelSelection::BytesPerVoxelLabel): the k-means tissues as they are (one byte), moved to 1002-1006 in 16-bit
 * pixels (two bytes) and to 100002-100006 in 32-bit pixels (four) give the same mesh with its labels moved alike, and
 * the same object and selected label images. */
TEST(Determinism, TheLabelImagesStorageDoesNotChangeTheMesh)
{
  const Meshed<FilterType> & oneByte = MeshedKmeans();
  EXPECT_EQ(oneByte.filter->GetBytesPerVoxelLabel(), 1u);
  const LabelImageType * input = oneByte.filter->GetInput();
  const auto             expectTheSameMeshMoved = [&](auto pixel, FilterType::LabelType offset) {
    using PixelType = decltype(pixel);
    using ImageType = itk::Image<PixelType, 3>;
    const auto moveLabel = [offset](FilterType::LabelType label) {
      return label == dr::BackgroundLabel ? label : label + offset;
    };
    auto moved = ImageType::New();
    moved->CopyInformation(input);
    moved->SetRegions(input->GetBufferedRegion());
    moved->Allocate();
    std::transform(input->GetBufferPointer(),
                   input->GetBufferPointer() + input->GetBufferedRegion().GetNumberOfPixels(),
                   moved->GetBufferPointer(),
                   [&](uint8_t value) { return static_cast<PixelType>(moveLabel(value)); });
    auto                               filter = FilterFor(moved.GetPointer(), KmeansDelta);
    std::vector<FilterType::LabelType> tissues(KmeansTissues);
    std::transform(tissues.begin(), tissues.end(), tissues.begin(), moveLabel);
    filter->SetLabels(tissues);
    const auto          meshed = RunFilter<itk::DelaunayImageToMeshFilter<ImageType, MeshType>>(filter);
    dr::TetrahedralMesh expected = oneByte.mesh;
    std::transform(expected.tetrahedronLabels.begin(),
                   expected.tetrahedronLabels.end(),
                   expected.tetrahedronLabels.begin(),
                   moveLabel);
    for (auto & pair : expected.boundaryTriangleLabels)
    {
      pair = { moveLabel(pair[0]), moveLabel(pair[1]) };
    }
    SCOPED_TRACE("labels moved by " + std::to_string(offset));
    EXPECT_EQ(filter->GetBytesPerVoxelLabel(), sizeof(PixelType));
    ExpectIdentical(expected, meshed->mesh);
    const auto expectTheSameLabelsMoved = [&](const auto * expectedLabels, const auto * labels, const char * what) {
      ASSERT_EQ(labels->GetBufferedRegion(), expectedLabels->GetBufferedRegion()) << what;
      const auto count = labels->GetBufferedRegion().GetNumberOfPixels();
      EXPECT_TRUE(std::equal(expectedLabels->GetBufferPointer(),
                             expectedLabels->GetBufferPointer() + count,
                             labels->GetBufferPointer(),
                             [&](FilterType::LabelType a, FilterType::LabelType b) { return moveLabel(a) == b; }))
        << what;
    };
    expectTheSameLabelsMoved(oneByte.filter->GetObjectLabelImage(), meshed->filter->GetObjectLabelImage(), "object");
    expectTheSameLabelsMoved(
      oneByte.filter->GetSelectedLabelImage(), meshed->filter->GetSelectedLabelImage(), "selected");
  };
  expectTheSameMeshMoved(uint16_t{}, 1000);
  expectTheSameMeshMoved(int32_t{}, 100000);
}

} // namespace
