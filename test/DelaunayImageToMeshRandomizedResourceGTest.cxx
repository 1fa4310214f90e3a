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

// Resource safety of itk::DelaunayImageToMeshFilter (issue #5): the vertex cap stops a refinement with an
// exception that names MaximumNumberOfVertices; an abort requested by a progress observer is honoured within a
// second; the same input gives the same mesh every time; two filters in two threads do not disturb each other.

#include "DelaunayImageToMeshRandomizedChecks.h"

#include <gtest/gtest.h>

#include <atomic>
#include <random>
#include <string>
#include <thread>

#include <time.h>

namespace
{

using namespace itk::delaunay_image_to_mesh_randomized;
using ImageType = itk::Image<short, 3>;
using FilterType = itk::DelaunayImageToMeshFilter<ImageType, MeshType>;
using Clock = std::chrono::steady_clock;

/** The longest an abort may take, from the request to the exception leaving Update(), in CPU time of the
 * process: the work the filter still does after the request, which a loaded machine (CI runs several builds at
 * once) does not inflate as it does wall time. Instrumented builds run several times slower. */
#if defined(__SANITIZE_ADDRESS__)
constexpr double AbortLatencyLimitSeconds = 5.0;
#else
constexpr double AbortLatencyLimitSeconds = 1.0;
#endif

double
SecondsBetween(Clock::time_point from, Clock::time_point to)
{
  return std::chrono::duration<double>(to - from).count();
}

/** CPU time of the whole process (every thread: ITK's distance map runs on a pool), in seconds. */
double
ProcessCpuSeconds()
{
  timespec time{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &time);
  return static_cast<double>(time.tv_sec) + 1e-9 * static_cast<double>(time.tv_nsec);
}

struct Ellipsoid
{
  dr::Vector3 center;
  dr::Vector3 radii;
  short       label;
};

/** Ellipsoids (physical space, later ones painted over earlier ones) on an oblique, anisotropic grid. */
ImageType::Pointer
MakeEllipsoidImage(unsigned int sideInVoxels, const std::vector<Ellipsoid> & ellipsoids, double rotationDegrees = 20.0)
{
  auto                image = ImageType::New();
  ImageType::SizeType size;
  size.Fill(sideInVoxels);
  image->SetRegions(size);
  ImageType::SpacingType spacing;
  spacing[0] = 1.0;
  spacing[1] = 0.8;
  spacing[2] = 1.3;
  image->SetSpacing(spacing);
  ImageType::PointType origin;
  origin[0] = -12.5;
  origin[1] = 40.0;
  origin[2] = 3.0;
  image->SetOrigin(origin);
  const double             angle = rotationDegrees * 3.14159265358979323846 / 180.0;
  ImageType::DirectionType direction;
  direction.SetIdentity();
  direction[0][0] = std::cos(angle);
  direction[0][1] = -std::sin(angle);
  direction[1][0] = std::sin(angle);
  direction[1][1] = std::cos(angle);
  image->SetDirection(direction);
  image->Allocate();
  image->FillBuffer(0);
  // The ellipsoids are given relative to the image centre, in physical units.
  ImageType::IndexType centerIndex;
  centerIndex.Fill(sideInVoxels / 2);
  ImageType::PointType imageCenter;
  image->TransformIndexToPhysicalPoint(centerIndex, imageCenter);
  for (itk::ImageRegionIteratorWithIndex<ImageType> it(image, image->GetBufferedRegion()); !it.IsAtEnd(); ++it)
  {
    ImageType::PointType point;
    image->TransformIndexToPhysicalPoint(it.GetIndex(), point);
    for (const Ellipsoid & ellipsoid : ellipsoids)
    {
      double sum = 0.0;
      for (unsigned int axis = 0; axis < 3; ++axis)
      {
        const double offset = (point[axis] - imageCenter[axis] - ellipsoid.center[axis]) / ellipsoid.radii[axis];
        sum += offset * offset;
      }
      if (sum <= 1.0)
      {
        it.Set(ellipsoid.label);
      }
    }
  }
  return image;
}

/** Two touching tissues and a separate third one: interfaces, several components, an oblique frame. */
ImageType::Pointer
MakeThreeTissueImage()
{
  return MakeEllipsoidImage(24,
                            { { { { -3.0, 0.0, 0.0 } }, { { 7.0, 6.0, 8.0 } }, 1 },
                              { { { 2.0, 1.0, 0.0 } }, { { 5.0, 4.0, 6.0 } }, 2 },
                              { { { 6.0, -6.0, 7.0 } }, { { 3.0, 3.0, 3.0 } }, 3 } });
}

ImageType::Pointer
MakeBallImage(unsigned int sideInVoxels)
{
  const double radius = 0.4 * sideInVoxels;
  return MakeEllipsoidImage(sideInVoxels, { { { { 0.0, 0.0, 0.0 } }, { { radius, radius, radius } }, 1 } });
}

FilterType::Pointer
MakeFilter(const ImageType * image, double delta)
{
  auto filter = FilterType::New();
  filter->SetInput(image);
  filter->SetSurfaceSamplingDistance(delta);
  return filter;
}

dr::TetrahedralMesh
MeshOf(const ImageType * image, double delta)
{
  auto filter = MakeFilter(image, delta);
  filter->Update();
  return filter->GetRefinedMesh();
}

/** Bit-for-bit equality of everything the refinement returns. */
void
ExpectIdentical(const dr::TetrahedralMesh & expected, const dr::TetrahedralMesh & actual, const std::string & what)
{
  EXPECT_FALSE(expected.tetrahedra.empty()) << what;
  EXPECT_EQ(expected.points, actual.points) << what;
  EXPECT_EQ(expected.pointKinds, actual.pointKinds) << what;
  EXPECT_EQ(expected.tetrahedra, actual.tetrahedra) << what;
  EXPECT_EQ(expected.tetrahedronLabels, actual.tetrahedronLabels) << what;
  EXPECT_EQ(expected.boundaryTriangles, actual.boundaryTriangles) << what;
  EXPECT_EQ(expected.boundaryTriangleLabels, actual.boundaryTriangleLabels) << what;
}

// ---- The vertex cap -------------------------------------------------------------------------------------

/** Expects Update() to throw the vertex-limit exception, naming the filter's parameter and its value. */
void
ExpectVertexLimitException(FilterType & filter)
{
  const itk::SizeValueType cap = filter.GetMaximumNumberOfVertices();
  try
  {
    filter.Update();
    ADD_FAILURE() << "no exception with MaximumNumberOfVertices = " << cap;
  }
  catch (const itk::ProcessAborted & aborted)
  {
    ADD_FAILURE() << "ProcessAborted instead of the vertex-limit exception: " << aborted.GetDescription();
  }
  catch (const itk::ExceptionObject & error)
  {
    const std::string description = error.GetDescription();
    EXPECT_EQ(ClassifyExceptionDescription(description), Outcome::VertexLimit) << description;
    EXPECT_NE(description.find("MaximumNumberOfVertices = " + std::to_string(cap)), std::string::npos) << description;
  }
}

TEST(VertexCap, OneBelowTheFinalCountStopsTheRefinement)
{
  const auto image = MakeBallImage(24);
  auto       filter = MakeFilter(image, 1.0);
  filter->Update();
  const std::size_t finalVertices = filter->GetRefinementStatistics().triangulationVertices;
  ASSERT_GT(finalVertices, 100u);

  // The triangulation held at least finalVertices at the end, so one fewer can never be enough.
  auto capped = MakeFilter(image, 1.0);
  capped->SetMaximumNumberOfVertices(finalVertices - 1);
  ExpectVertexLimitException(*capped);
}

TEST(VertexCap, SmallCapStopsQuicklyAndTheFilterRecovers)
{
  const auto image = MakeBallImage(24);
  auto       filter = MakeFilter(image, 0.6);
  filter->SetMaximumNumberOfVertices(50);
  const auto start = Clock::now();
  ExpectVertexLimitException(*filter);
  EXPECT_LT(SecondsBetween(start, Clock::now()), 1.0);

  // The same filter, with the cap lifted, gives what a fresh filter gives: the failure left nothing behind.
  filter->SetMaximumNumberOfVertices(10000000);
  filter->Update();
  ExpectIdentical(MeshOf(image, 0.6), filter->GetRefinedMesh(), "after a vertex-limit exception");
}

TEST(VertexCap, BelowTheBoxCornersIsAnInvalidParameter)
{
  const auto image = MakeBallImage(12);
  auto       filter = MakeFilter(image, 1.0);
  filter->SetMaximumNumberOfVertices(7);
  try
  {
    filter->Update();
    ADD_FAILURE() << "no exception with MaximumNumberOfVertices = 7";
  }
  catch (const itk::ExceptionObject & error)
  {
    std::string description = error.GetDescription();
    EXPECT_EQ(ClassifyExceptionDescription(description), Outcome::InvalidParameter) << description;
    std::transform(description.begin(), description.end(), description.begin(), [](unsigned char c) {
      return static_cast<char>(std::tolower(c));
    });
    EXPECT_NE(description.find("maximumnumberofvertices"), std::string::npos) << description;
  }
}

// ---- Aborting -------------------------------------------------------------------------------------------

struct AbortMeasurement
{
  bool   aborted{ false };
  bool   requested{ false };
  double latencyCpuSeconds{ 0.0 };
  double latencyWallSeconds{ 0.0 };
  float  progressAtRequest{ 0.0f };
};

/** Runs `filter`, and from its progress observer requests an abort once `shouldAbort(progress, seconds)` says
 * so; measures the time from that request to the ProcessAborted exception. */
AbortMeasurement
RunAndAbort(FilterType & filter, const std::function<bool(float, double)> & shouldAbort)
{
  AbortMeasurement  measurement;
  const auto        start = Clock::now();
  Clock::time_point requestTime;
  double            requestCpuSeconds = 0.0;
  filter.AddObserver(itk::ProgressEvent(), [&](const itk::EventObject &) {
    if (!measurement.requested && shouldAbort(filter.GetProgress(), SecondsBetween(start, Clock::now())))
    {
      measurement.requested = true;
      measurement.progressAtRequest = filter.GetProgress();
      requestTime = Clock::now();
      requestCpuSeconds = ProcessCpuSeconds();
      filter.AbortGenerateDataOn();
    }
  });
  try
  {
    filter.Update();
  }
  catch (const itk::ProcessAborted &)
  {
    measurement.aborted = true;
  }
  if (measurement.requested)
  {
    measurement.latencyCpuSeconds = ProcessCpuSeconds() - requestCpuSeconds;
    measurement.latencyWallSeconds = SecondsBetween(requestTime, Clock::now());
  }
  filter.RemoveAllObservers();
  return measurement;
}

/** A run long enough (several seconds in Release) that an abort in its middle is an abort. */
ImageType::Pointer
MakeLongRunImage()
{
  return MakeBallImage(48);
}
constexpr double LongRunDelta = 0.45;

TEST(Abort, DuringRefinementStopsWithinASecond)
{
  const auto             image = MakeLongRunImage();
  auto                   filter = MakeFilter(image, LongRunDelta);
  const AbortMeasurement measurement =
    RunAndAbort(*filter, [](float progress, double seconds) { return progress > 0.1f && seconds > 0.5; });
  ASSERT_TRUE(measurement.requested) << "the run ended before the abort was requested: make it longer";
  EXPECT_TRUE(measurement.aborted);
  EXPECT_LT(measurement.latencyCpuSeconds, AbortLatencyLimitSeconds);
  std::cout << "abort during refinement (progress " << measurement.progressAtRequest << "): stopped after "
            << measurement.latencyCpuSeconds << " s of CPU time (" << measurement.latencyWallSeconds << " s wall)"
            << std::endl;
}

TEST(Abort, AtTheFirstProgressEventStopsWithinASecond)
{
  const auto             image = MakeLongRunImage();
  auto                   filter = MakeFilter(image, LongRunDelta);
  const AbortMeasurement measurement = RunAndAbort(*filter, [](float, double) { return true; });
  ASSERT_TRUE(measurement.requested);
  EXPECT_TRUE(measurement.aborted);
  EXPECT_LT(measurement.latencyCpuSeconds, AbortLatencyLimitSeconds);
  std::cout << "abort at the first progress event: stopped after " << measurement.latencyCpuSeconds
            << " s of CPU time (" << measurement.latencyWallSeconds << " s wall)" << std::endl;
}

/** A large image (160³ voxels, as CT and MR volumes are): its set-up (the label image and the feature transform
 * of 4 M voxels) is the longest stretch before the refinement's own progress events start. */
ImageType::Pointer
MakeLargeImage()
{
  return MakeBallImage(160);
}
constexpr double LargeImageDelta = 4.0;

TEST(Abort, DuringTheSetUpOfALargeImageStopsWithinASecond)
{
  const auto             image = MakeLargeImage();
  auto                   filter = MakeFilter(image, LargeImageDelta);
  const AbortMeasurement measurement = RunAndAbort(*filter, [](float, double) { return true; });
  ASSERT_TRUE(measurement.requested);
  EXPECT_TRUE(measurement.aborted);
  EXPECT_LT(measurement.latencyCpuSeconds, AbortLatencyLimitSeconds);
  std::cout << "abort at the start of a 160^3 image's set-up: stopped after " << measurement.latencyCpuSeconds
            << " s of CPU time (" << measurement.latencyWallSeconds << " s wall)" << std::endl;
}

TEST(Abort, TheFilterRunsNormallyAfterAnAbort)
{
  const auto             image = MakeThreeTissueImage();
  auto                   filter = MakeFilter(image, 1.5);
  const AbortMeasurement measurement = RunAndAbort(*filter, [](float progress, double) { return progress >= 0.1f; });
  ASSERT_TRUE(measurement.aborted);
  filter->Update();
  ExpectIdentical(MeshOf(image, 1.5), filter->GetRefinedMesh(), "after an abort");
}

/** The longest stretch of CPU time between two progress events of a run, and after the last one. */
struct ProgressGaps
{
  std::size_t events{ 0 };
  double      longest{ 0.0 };
  float       progressAfterLongest{ 0.0f };
  double      afterLast{ 0.0 };
};

ProgressGaps
MeasureProgressGaps(FilterType & filter)
{
  ProgressGaps gaps;
  double       last = ProcessCpuSeconds();
  filter.AddObserver(itk::ProgressEvent(), [&](const itk::EventObject &) {
    const double now = ProcessCpuSeconds();
    if (now - last > gaps.longest)
    {
      gaps.longest = now - last;
      gaps.progressAfterLongest = filter.GetProgress();
    }
    last = now;
    ++gaps.events;
  });
  filter.Update();
  gaps.afterLast = ProcessCpuSeconds() - last;
  filter.RemoveAllObservers();
  return gaps;
}

/** An abort requested at any moment (a GUI's cancel button) is seen at the next progress event: no stretch of
 * a run, set-up and extraction included, may take a second of CPU time without one. A long refinement, then the
 * set-up of a large image. */
TEST(Abort, ProgressEventsAreNeverASecondApart)
{
  for (const auto & [image, delta] :
       { std::make_pair(MakeLongRunImage(), LongRunDelta), std::make_pair(MakeLargeImage(), LargeImageDelta) })
  {
    auto               filter = MakeFilter(image, delta);
    const ProgressGaps gaps = MeasureProgressGaps(*filter);
    std::cout << image->GetLargestPossibleRegion().GetSize() << " voxels: " << gaps.events
              << " progress events; longest gap " << gaps.longest << " s of CPU time (ending at progress "
              << gaps.progressAfterLongest << "), after the last event " << gaps.afterLast << " s" << std::endl;
    EXPECT_GT(gaps.events, 3u);
    EXPECT_LT(gaps.longest, AbortLatencyLimitSeconds) << "ending at progress " << gaps.progressAfterLongest;
    EXPECT_LT(gaps.afterLast, AbortLatencyLimitSeconds);
  }
}

// ---- Determinism and independence ------------------------------------------------------------------------

/** Fine enough for thousands of tetrahedra and every kind of vertex on the three-tissue image. */
constexpr double DeterminismDelta = 1.6;

TEST(Determinism, TheSameFilterTwiceGivesTheSameMesh)
{
  const auto image = MakeThreeTissueImage();
  auto       filter = MakeFilter(image, DeterminismDelta);
  filter->Update();
  const dr::TetrahedralMesh first = filter->GetRefinedMesh();
  filter->Modified();
  filter->Update();
  ExpectIdentical(first, filter->GetRefinedMesh(), "second Update() of the same filter");
  ExpectIdentical(first, MeshOf(image, DeterminismDelta), "a fresh filter");
}

/** The set-up's passes over every voxel (the nearest-interface map, the regularisation's distance transform) are
 * shared among the filter's work units: on 64³ voxels with a slab of speckle to regularise, one work unit and
 * several must give the same mesh. */
TEST(Determinism, TheNumberOfWorkUnitsDoesNotChangeTheMesh)
{
  const auto   image = MakeEllipsoidImage(64,
                                        { { { { -8.0, 0.0, 0.0 } }, { { 18.0, 16.0, 20.0 } }, 1 },
                                            { { { 5.0, 3.0, 0.0 } }, { { 13.0, 11.0, 16.0 } }, 2 },
                                            { { { 16.0, -16.0, 18.0 } }, { { 8.0, 8.0, 8.0 } }, 3 } });
  std::mt19937 random(64);
  for (itk::ImageRegionIteratorWithIndex<ImageType> it(image, image->GetBufferedRegion()); !it.IsAtEnd(); ++it)
  {
    if (it.GetIndex()[2] >= 40 && it.GetIndex()[2] < 50)
    {
      it.Set(static_cast<ImageType::PixelType>(random() % 4));
    }
  }
  auto reference = MakeFilter(image, 4.0);
  reference->SetNumberOfWorkUnits(1);
  reference->Update();
  EXPECT_GT(reference->GetRegularizationReport().changedVoxels, 0U);
  for (const itk::ThreadIdType workUnits : { 2U, 5U })
  {
    auto filter = MakeFilter(image, 4.0);
    filter->SetNumberOfWorkUnits(workUnits);
    filter->Update();
    ExpectIdentical(reference->GetRefinedMesh(), filter->GetRefinedMesh(), std::to_string(workUnits) + " work units");
  }
}

TEST(Determinism, TwoFiltersInTwoThreadsGiveTheSequentialMeshes)
{
  const std::array<ImageType::Pointer, 2>  images{ MakeThreeTissueImage(), MakeBallImage(24) };
  const std::array<double, 2>              deltas{ DeterminismDelta, 1.0 };
  const std::array<dr::TetrahedralMesh, 2> sequential{ MeshOf(images[0], deltas[0]), MeshOf(images[1], deltas[1]) };
  for (int round = 0; round < 3; ++round)
  {
    std::array<dr::TetrahedralMesh, 2> concurrent;
    std::array<std::string, 2>         errors;
    std::vector<std::thread>           threads;
    for (std::size_t i = 0; i < 2; ++i)
    {
      threads.emplace_back([&, i] {
        try
        {
          concurrent[i] = MeshOf(images[i], deltas[i]);
        }
        catch (const std::exception & error)
        {
          errors[i] = error.what();
        }
      });
    }
    for (std::thread & thread : threads)
    {
      thread.join();
    }
    for (std::size_t i = 0; i < 2; ++i)
    {
      EXPECT_EQ(errors[i], "") << "thread " << i;
      ExpectIdentical(sequential[i], concurrent[i], "image " + std::to_string(i) + ", round " + std::to_string(round));
    }
  }
}

TEST(Determinism, TwoFiltersOnTheSameImageInTwoThreads)
{
  // The input image is shared, read-only, by both pipelines: a common situation in a GUI.
  const auto                         image = MakeThreeTissueImage();
  const dr::TetrahedralMesh          sequential = MeshOf(image, DeterminismDelta);
  std::array<dr::TetrahedralMesh, 2> concurrent;
  std::string                        otherError;
  std::thread                        other([&] {
    try
    {
      concurrent[1] = MeshOf(image, DeterminismDelta);
    }
    catch (const std::exception & error)
    {
      otherError = error.what();
    }
  });
  concurrent[0] = MeshOf(image, DeterminismDelta);
  other.join();
  EXPECT_EQ(otherError, "");
  ExpectIdentical(sequential, concurrent[0], "this thread");
  ExpectIdentical(sequential, concurrent[1], "the other thread");
}

} // namespace
