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
#ifndef DelaunayRefinementParallel_h
#define DelaunayRefinementParallel_h

// Work over independent ranges or pieces on several threads, for the passes over every voxel (the regularisation's
// opening and distance transform) and the report's distances: each piece's results are its own, so they do not
// depend on how many threads there are.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace delaunay_refinement
{
namespace detail
{

/** Calls work(begin, end) on consecutive ranges that cover [0, count), one per thread, on at most `threads`
 * threads and with no range shorter than `minimumPerThread` (below that a thread costs more than it saves); the
 * calling thread takes the first range. The calls must not depend on each other. Rethrows the first range's
 * exception, if any, after every thread has ended. */
template <typename TWork>
void
ForEachRangeInParallel(std::size_t count, std::size_t threads, std::size_t minimumPerThread, const TWork & work)
{
  const std::size_t used =
    std::max<std::size_t>(1, std::min(threads, count / std::max<std::size_t>(minimumPerThread, 1)));
  const std::size_t               chunk = (count + used - 1) / used;
  std::vector<std::exception_ptr> errors(used);
  const auto                      run = [&](std::size_t range) {
    try
    {
      work(std::min(range * chunk, count), std::min((range + 1) * chunk, count));
    }
    catch (...)
    {
      errors[range] = std::current_exception();
    }
  };
  std::vector<std::thread> workers;
  for (std::size_t range = 1; range < used; ++range)
  {
    workers.emplace_back(run, range);
  }
  run(0);
  for (std::thread & worker : workers)
  {
    worker.join();
  }
  for (const std::exception_ptr & error : errors)
  {
    if (error)
    {
      std::rethrow_exception(error);
    }
  }
}

/** How often the calling thread of ForEachIndexInParallel, once no index is left for it, calls `onCallingThread()`
 * while the other threads finish theirs: often enough for a progress bar to move and an abort to be seen at once
 * by a user, rarely enough to cost nothing. */
constexpr std::chrono::milliseconds CallingThreadWaitCheckInterval{ 20 };

/** Calls work(index) for every index in [0, count), on up to `threads` threads that each take the next index when
 * they finish one (for pieces of work of very different sizes); the calling thread takes part, index 0 always among
 * its pieces (the first, the largest where the caller sorts them), and calls `onCallingThread()` before each index it
 * takes, and then every CallingThreadWaitCheckInterval until the other threads have ended (a progress report and a
 * check for an abort, which must not run elsewhere: without the checks while it waits, an abort asked for while
 * another thread opened the largest piece was seen only after it).
 * When that or a call of work throws, no index is started any more (an abort inside one piece stops the others'
 * queue too) and the exception is rethrown once every thread has ended. The calls of work must not depend on each
 * other. */
template <typename TWork, typename TOnCallingThread>
void
ForEachIndexInParallel(std::size_t count, std::size_t threads, const TWork & work,
                       const TOnCallingThread & onCallingThread)
{
  // Index 0 is the calling thread's, whenever it starts: were the other threads to take every index first (the
  // calling thread held up on a loaded machine), it would check nothing until they all ended.
  std::atomic<std::size_t> next{ 1 };
  const std::size_t        used = std::max<std::size_t>(1, std::min(threads, count));
  std::mutex               othersMutex;
  std::condition_variable  othersEnded;
  std::size_t              othersRunning = used - 1;
  const auto               workOn = [&](std::size_t index, bool onTheCallingThread) {
    try
    {
      if (onTheCallingThread)
      {
        onCallingThread();
      }
      work(index);
    }
    catch (...)
    {
      next = count;
      throw;
    }
  };
  const auto takeIndices = [&](bool onTheCallingThread) {
    for (std::size_t index = next++; index < count; index = next++)
    {
      workOn(index, onTheCallingThread);
    }
  };
  ForEachRangeInParallel(used, used, 1, [&](std::size_t range, std::size_t) {
    if (range != 0)
    {
      // The count of running threads goes down however the work ends, or the calling thread would wait forever.
      struct Ended
      {
        std::mutex &              mutex;
        std::condition_variable & ended;
        std::size_t &             running;
        ~Ended()
        {
          {
            const std::lock_guard<std::mutex> lock(mutex);
            --running;
          }
          ended.notify_one();
        }
      } ended{ othersMutex, othersEnded, othersRunning };
      takeIndices(false);
      return;
    }
    if (count > 0)
    {
      workOn(0, true);
    }
    takeIndices(true);
    std::unique_lock<std::mutex> lock(othersMutex);
    while (!othersEnded.wait_for(lock, CallingThreadWaitCheckInterval, [&othersRunning] { return othersRunning == 0; }))
    {
      lock.unlock();
      try
      {
        onCallingThread();
      }
      catch (...)
      {
        next = count;
        throw;
      }
      lock.lock();
    }
  });
}

} // namespace detail
} // namespace delaunay_refinement

#endif
