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

// The refinement's work list (src/DelaunayRefinementQueue.h, docs/algorithm.md, "Order of work"): the live entries
// come out in the same order whether or not the dead ones are removed on the way, since that order makes the mesh.
// The entries stand for no tetrahedron (a null cell); the stamp names each, and a set of dead stamps plays the
// triangulation's part.

#include "DelaunayRefinementQueue.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <unordered_set>
#include <vector>

namespace dr = delaunay_refinement;
using dr::detail::FourAryHeap;
using dr::detail::QueueEntry;
using dr::detail::QueueEntryOrder;
using dr::detail::QueueLevel;
using dr::detail::RefinementQueue;

namespace
{

/** A stamped entry with a size from a few values and three of its vertex ids from a few, so that many entries tie
 * on their size and some on their first vertex ids as well (co-spherical cells sharing corners). */
QueueEntry
RandomEntry(std::mt19937 & random, uint64_t stamp)
{
  std::uniform_int_distribution<int>      size(1, 40);
  std::uniform_int_distribution<uint32_t> vertex(0, 30);
  QueueEntry                              entry{};
  entry.squaredRadius = 0.25 * size(random);
  entry.stamp = stamp;
  for (std::size_t corner = 0; corner < 3; ++corner)
  {
    entry.vertexIds[corner] = vertex(random);
  }
  // The last corner is the entry's own: two entries with the same corners would be the same tetrahedron, which
  // the refinement never has twice alive, and whose copies no order could tell apart.
  entry.vertexIds[3] = 100 + static_cast<uint32_t>(stamp);
  std::sort(entry.vertexIds.begin(), entry.vertexIds.end());
  return entry;
}

/** Pops `queue` until it is empty or a live entry comes out; the live entry's stamp and level, or none. */
bool
PopLive(RefinementQueue & queue, const std::unordered_set<uint64_t> & dead, uint64_t & stamp, QueueLevel & level)
{
  while (!queue.Empty())
  {
    const QueueEntry entry = queue.Pop(level);
    if (dead.count(entry.stamp) == 0)
    {
      stamp = entry.stamp;
      return true;
    }
  }
  return false;
}

} // namespace

TEST(RefinementQueue, RemovingDeadEntriesKeepsTheOrderOfTheLiveOnes)
{
  std::mt19937                       random(20261129);
  std::uniform_int_distribution<int> levelOf(0, 2);
  std::uniform_int_distribution<int> pushesPerStep(0, 6);
  std::bernoulli_distribution        dies(0.6);
  RefinementQueue                    removing;
  RefinementQueue                    keeping;
  std::unordered_set<uint64_t>       dead;
  std::vector<uint64_t>              waiting;
  uint64_t                           nextStamp = 1;
  std::size_t                        removed = 0;
  std::size_t                        popped = 0;
  const auto isAlive = [&dead](const QueueEntry & entry) { return dead.count(entry.stamp) == 0; };
  for (int step = 0; step < 60000; ++step)
  {
    // As an insertion does: new entries, and some of those waiting die (most entries do, as in the refinement).
    for (int push = pushesPerStep(random); push > 0; --push)
    {
      const QueueEntry entry = RandomEntry(random, nextStamp++);
      const auto       level = static_cast<QueueLevel>(levelOf(random));
      removing.Push(level, entry);
      keeping.Push(level, entry);
      waiting.push_back(entry.stamp);
    }
    for (int death = 0; death < 3; ++death)
    {
      if (!waiting.empty() && dies(random))
      {
        std::uniform_int_distribution<std::size_t> which(0, waiting.size() - 1);
        const std::size_t                          index = which(random);
        dead.insert(waiting[index]);
        waiting[index] = waiting.back();
        waiting.pop_back();
      }
    }
    removed += removing.RemoveDeadWhenDue(isAlive);
    uint64_t   fromRemoving = 0;
    uint64_t   fromKeeping = 0;
    QueueLevel levelRemoving = QueueLevel::Surface;
    QueueLevel levelKeeping = QueueLevel::Surface;
    const bool liveRemoving = PopLive(removing, dead, fromRemoving, levelRemoving);
    const bool liveKeeping = PopLive(keeping, dead, fromKeeping, levelKeeping);
    ASSERT_EQ(liveRemoving, liveKeeping) << "step " << step;
    if (liveRemoving)
    {
      ASSERT_EQ(fromRemoving, fromKeeping) << "step " << step;
      ASSERT_EQ(levelRemoving, levelKeeping) << "step " << step;
      ++popped;
      // A popped entry is done with; it dies, as its tetrahedron is refined.
      dead.insert(fromRemoving);
      waiting.erase(std::find(waiting.begin(), waiting.end(), fromRemoving));
    }
  }
  // The removal took place, and often: otherwise the comparison above says nothing about it.
  EXPECT_GT(removed, 10000U);
  EXPECT_GT(popped, 10000U);
  EXPECT_LT(removing.Size(), keeping.Size());
  // Then the rest of both, in the same order.
  uint64_t   fromRemoving = 0;
  uint64_t   fromKeeping = 0;
  QueueLevel levelRemoving = QueueLevel::Surface;
  QueueLevel levelKeeping = QueueLevel::Surface;
  while (PopLive(keeping, dead, fromKeeping, levelKeeping))
  {
    ASSERT_TRUE(PopLive(removing, dead, fromRemoving, levelRemoving));
    ASSERT_EQ(fromRemoving, fromKeeping);
  }
  EXPECT_FALSE(PopLive(removing, dead, fromRemoving, levelRemoving));
}

TEST(FourAryHeap, RemovingEntriesLeavesAHeapOfTheOthers)
{
  // Small heaps, each emptied after one removal: the entries the removal moves are then often those whose order
  // the rebuild must restore, down to the last entry with children.
  std::mt19937                           random(20261129);
  std::uniform_real_distribution<double> share(0.0, 1.0);
  for (uint64_t size = 0; size < 400; ++size)
  {
    FourAryHeap heap;
    for (uint64_t stamp = 1; stamp <= size; ++stamp)
    {
      heap.Push(RandomEntry(random, stamp));
    }
    const double                 deadShare = share(random);
    std::unordered_set<uint64_t> dead;
    for (uint64_t stamp = 1; stamp <= size; ++stamp)
    {
      if (share(random) < deadShare)
      {
        dead.insert(stamp);
      }
    }
    EXPECT_EQ(heap.RemoveDead([&dead](const QueueEntry & entry) { return dead.count(entry.stamp) == 0; }), dead.size());
    ASSERT_EQ(heap.Size(), size - dead.size());
    QueueEntry previous{};
    for (std::size_t popped = 0; !heap.Empty(); ++popped)
    {
      const QueueEntry entry = heap.Pop();
      EXPECT_EQ(dead.count(entry.stamp), 0U);
      if (popped > 0)
      {
        ASSERT_FALSE(QueueEntryOrder()(previous, entry)) << "heap of " << size << ", entry " << popped;
      }
      previous = entry;
    }
  }
}

TEST(RefinementQueue, PopsLevelByLevelLargestFirstTiesByVertexIds)
{
  RefinementQueue queue;
  const auto      entry = [](double squaredRadius, uint64_t stamp, std::array<uint32_t, 4> ids) {
    QueueEntry made{};
    made.squaredRadius = squaredRadius;
    made.stamp = stamp;
    made.vertexIds = ids;
    return made;
  };
  queue.Push(QueueLevel::Sliver, entry(9.0, 1, { 0, 1, 2, 3 }));
  queue.Push(QueueLevel::Quality, entry(1.0, 2, { 0, 1, 2, 3 }));
  queue.Push(QueueLevel::Quality, entry(4.0, 3, { 2, 3, 4, 5 }));
  queue.Push(QueueLevel::Quality, entry(4.0, 4, { 1, 3, 4, 5 }));
  queue.Push(QueueLevel::Surface, entry(0.5, 5, { 7, 8, 9, 10 }));
  const std::vector<std::pair<uint64_t, QueueLevel>> expected{ { 5, QueueLevel::Surface },
                                                               { 4, QueueLevel::Quality },
                                                               { 3, QueueLevel::Quality },
                                                               { 2, QueueLevel::Quality },
                                                               { 1, QueueLevel::Sliver } };
  for (const auto & [stamp, level] : expected)
  {
    ASSERT_FALSE(queue.Empty());
    QueueLevel poppedLevel = QueueLevel::Surface;
    EXPECT_EQ(queue.Pop(poppedLevel).stamp, stamp);
    EXPECT_EQ(poppedLevel, level);
  }
  EXPECT_TRUE(queue.Empty());
}

TEST(RefinementQueue, RemovesDeadEntriesOnceAsManyPushesAsItHeldAfterTheLastRemoval)
{
  // The removal is due when the pushes since the last one reach the entries left by it, or the minimum
  // (MinimumPushesBetweenRemovals), whichever is larger: its pass over the queue then costs a constant per push. The
  // first removal, after the minimum's pushes into an empty queue, tells the minimum, m. With no entry dead, the
  // second comes m pushes later, over 2m entries; all of them dead, the third 2m later, over 4m, removes 2m; all the
  // rest dead and every new entry with them, the fourth 2m later, over 4m, removes all; the queue then empty, the
  // fifth and sixth come m pushes apart.
  struct Removal
  {
    std::size_t pushes;
    std::size_t looked;
    std::size_t removed;
  };
  RefinementQueue              queue;
  std::unordered_set<uint64_t> dead;
  std::size_t                  looked = 0;
  const auto                   isAlive = [&dead, &looked](const QueueEntry & entry) {
    ++looked;
    return dead.count(entry.stamp) == 0;
  };
  std::vector<Removal> removals;
  std::size_t          minimum = 0;
  bool                 newEntriesDie = false;
  for (uint64_t stamp = 1; minimum == 0 || stamp <= 8 * minimum; ++stamp)
  {
    ASSERT_LT(stamp, 1000000U) << "no removal";
    QueueEntry entry{};
    entry.squaredRadius = 1.0 + static_cast<double>(stamp % 7);
    entry.stamp = stamp;
    entry.vertexIds = { 0, 1, 2, static_cast<uint32_t>(stamp + 2) };
    queue.Push(static_cast<QueueLevel>(stamp % 3), entry);
    if (newEntriesDie)
    {
      dead.insert(stamp);
    }
    const std::size_t lookedBefore = looked;
    const std::size_t removed = queue.RemoveDeadWhenDue(isAlive);
    if (looked == lookedBefore)
    {
      ASSERT_EQ(removed, 0U);
      continue;
    }
    removals.push_back({ static_cast<std::size_t>(stamp), looked - lookedBefore, removed });
    if (removals.size() == 1)
    {
      minimum = stamp;
    }
    if (removals.size() == 2 || removals.size() == 3)
    {
      for (uint64_t killed = 1; killed <= stamp; ++killed)
      {
        dead.insert(killed);
      }
      newEntriesDie = removals.size() == 3;
    }
  }
  const std::size_t m = minimum;
  ASSERT_EQ(removals.size(), 6U);
  const std::array<Removal, 6> expected{ { { m, m, 0 },
                                           { 2 * m, 2 * m, 0 },
                                           { 4 * m, 4 * m, 2 * m },
                                           { 6 * m, 4 * m, 4 * m },
                                           { 7 * m, m, m },
                                           { 8 * m, m, m } } };
  for (std::size_t index = 0; index < expected.size(); ++index)
  {
    EXPECT_EQ(removals[index].pushes, expected[index].pushes) << "removal " << index << ", m = " << m;
    EXPECT_EQ(removals[index].looked, expected[index].looked) << "removal " << index << ", m = " << m;
    EXPECT_EQ(removals[index].removed, expected[index].removed) << "removal " << index << ", m = " << m;
  }
  EXPECT_EQ(queue.Size(), 0U);
}

TEST(RefinementQueue, ReleasingTheEmptyLevelsKeepsTheEntriesOfTheOthers)
{
  RefinementQueue queue;
  const auto      entry = [](double squaredRadius, uint64_t stamp) {
    QueueEntry made{};
    made.squaredRadius = squaredRadius;
    made.stamp = stamp;
    made.vertexIds = { 0, 1, 2, static_cast<uint32_t>(stamp + 2) };
    return made;
  };
  queue.Push(QueueLevel::Surface, entry(5.0, 1));
  queue.Push(QueueLevel::Quality, entry(1.0, 2));
  queue.Push(QueueLevel::Quality, entry(3.0, 3));
  queue.Push(QueueLevel::Quality, entry(2.0, 4));
  QueueLevel level = QueueLevel::Sliver;
  EXPECT_EQ(queue.Pop(level).stamp, 1U);
  EXPECT_EQ(level, QueueLevel::Surface);
  // The surface and sliver levels are empty now; the quality level keeps its three entries, in their order.
  queue.ReleaseEmptyLevels();
  ASSERT_EQ(queue.Size(), 3U);
  for (const uint64_t stamp : { 3U, 4U, 2U })
  {
    ASSERT_FALSE(queue.Empty());
    EXPECT_EQ(queue.Pop(level).stamp, stamp);
    EXPECT_EQ(level, QueueLevel::Quality);
  }
  EXPECT_TRUE(queue.Empty());
  // Released, a level takes entries again.
  queue.ReleaseEmptyLevels();
  queue.Push(QueueLevel::Surface, entry(1.0, 5));
  EXPECT_EQ(queue.Pop(level).stamp, 5U);
  EXPECT_TRUE(queue.Empty());
}
