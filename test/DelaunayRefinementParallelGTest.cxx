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

// The work over pieces on several threads (DelaunayRefinementParallel.h): every index is worked once, and the
// calling thread, once no piece is left for it, keeps calling its check while the other threads finish, so that a
// progress bar moves and an abort is seen while another thread works on a long piece.

#include "DelaunayRefinementParallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

namespace delaunay_refinement
{
namespace
{

/** How long a piece on another thread waits for what the calling thread does before the test gives up: far longer
 * than CallingThreadWaitCheckInterval, so that it is reached only when the calling thread does not check. */
constexpr std::chrono::seconds GiveUpAfter{ 10 };

/** Waits on this thread until `reached()` or GiveUpAfter; whether it was reached. */
template <typename TReached>
bool
WaitUntil(const TReached & reached)
{
  const auto start = std::chrono::steady_clock::now();
  while (!reached())
  {
    if (std::chrono::steady_clock::now() - start > GiveUpAfter)
    {
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

TEST(ParallelPieces, EveryIndexIsWorkedOnce)
{
  for (const std::size_t count : { 0, 1, 2, 37 })
  {
    for (const std::size_t threads : { 1, 2, 3, 8 })
    {
      std::vector<std::atomic<int>> worked(count);
      detail::ForEachIndexInParallel(
        worked.size(), threads, [&worked](std::size_t index) { ++worked[index]; }, [] {});
      for (std::size_t index = 0; index < worked.size(); ++index)
      {
        EXPECT_EQ(worked[index].load(), 1) << "index " << index << " of " << count << " on " << threads << " threads";
      }
    }
  }
}

// The first index is the calling thread's, whichever thread starts first: the calling thread alone reports progress
// and sees an abort, and were the other threads to take every piece before it started (a loaded machine), it would do
// neither until they all ended (the regularisation's openings, LabelRegularization.ReportsItsProgressAndStopsWithin-
// TheOpenings, failed so with the calling thread held up for 200 ms).
TEST(ParallelPieces, TheFirstIndexIsWorkedOnTheCallingThread)
{
  const std::thread::id callingThread = std::this_thread::get_id();
  for (const std::size_t threads : { 2, 3, 8 })
  {
    for (int round = 0; round < 200; ++round)
    {
      std::atomic<bool> firstOnTheCallingThread{ false };
      detail::ForEachIndexInParallel(
        threads,
        threads,
        [&](std::size_t index) {
          if (index == 0)
          {
            firstOnTheCallingThread = std::this_thread::get_id() == callingThread;
          }
        },
        [] {});
      ASSERT_TRUE(firstOnTheCallingThread) << "round " << round << " on " << threads << " threads";
    }
  }
}

/** Pieces for two threads: the calling thread's end once the other thread holds one (or the calling thread could
 * take them all before the other starts), the other thread's last until `released()`. Remembers whether a wait gave
 * up. */
struct PiecesOnTwoThreads
{
  const std::thread::id callingThread = std::this_thread::get_id();
  std::atomic<bool>     otherThreadStarted{ false };
  std::atomic<int>      piecesOnTheCallingThread{ 0 };
  std::atomic<bool>     gaveUp{ false };

  template <typename TReleased>
  auto
  Work(const TReleased & released)
  {
    return [this, &released](std::size_t) {
      if (std::this_thread::get_id() == callingThread)
      {
        gaveUp = gaveUp || !WaitUntil([this] { return otherThreadStarted.load(); });
        ++piecesOnTheCallingThread;
        return;
      }
      otherThreadStarted = true;
      gaveUp = gaveUp || !WaitUntil(released);
    };
  }
};

// Every piece on another thread lasts until the calling thread has made more checks than there are pieces (it checks
// once before each of its own): it ends only if the calling thread checks while it waits.
TEST(ParallelPieces, TheCallingThreadChecksWhileTheOthersWork)
{
  const std::size_t  count = 4;
  std::atomic<int>   checks{ 0 };
  PiecesOnTwoThreads pieces;
  const auto         released = [&checks] { return checks.load() > static_cast<int>(count) + 2; };
  detail::ForEachIndexInParallel(count, 2, pieces.Work(released), [&checks] { ++checks; });
  EXPECT_FALSE(pieces.gaveUp) << "the calling thread made " << checks.load() << " checks while the other thread worked";
  EXPECT_GT(checks.load(), pieces.piecesOnTheCallingThread.load());
}

// An abort seen by the calling thread's check while it waits, its own piece done and the other thread's running, is
// rethrown once that thread has ended: without the checks while it waits, the calling thread would wait for a piece
// that lasts until the abort.
TEST(ParallelPieces, AnAbortSeenWhileWaitingIsRethrown)
{
  std::atomic<bool>  abortSeen{ false };
  PiecesOnTwoThreads pieces;
  const auto         released = [&abortSeen] { return abortSeen.load(); };
  EXPECT_THROW(detail::ForEachIndexInParallel(2,
                                              2,
                                              pieces.Work(released),
                                              [&] {
                                                if (pieces.piecesOnTheCallingThread > 0 && pieces.otherThreadStarted)
                                                {
                                                  abortSeen = true;
                                                  throw std::runtime_error("aborted");
                                                }
                                              }),
               std::runtime_error);
  EXPECT_FALSE(pieces.gaveUp);
  EXPECT_EQ(pieces.piecesOnTheCallingThread.load(), 1);
}

} // namespace
} // namespace delaunay_refinement
