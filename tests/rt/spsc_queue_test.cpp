// The SPSC queue: FIFO order, full and empty edges, taking a batch, wrap-around, two threads
// passing a million sequence numbers, and no allocation.
#include "core/rt/spsc_queue.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <thread>
#include <vector>

#include "tests/support/alloc_guard.h"

namespace enact::rt {
namespace {

TEST(SpscQueue, KeepsFifoOrder) {
  SpscQueue<int, 8> q;
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(q.try_push(i));
  EXPECT_EQ(q.size_approx(), 5u);
  for (int i = 0; i < 5; ++i) {
    int out = -1;
    ASSERT_TRUE(q.try_pop(out));
    EXPECT_EQ(out, i);
  }
  EXPECT_EQ(q.size_approx(), 0u);
}

TEST(SpscQueue, FullAndEmptyEdges) {
  SpscQueue<int, 4> q;
  int out = -1;
  EXPECT_FALSE(q.try_pop(out));
  EXPECT_EQ(out, -1);
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(q.try_push(i));
  EXPECT_EQ(q.size_approx(), q.capacity());
  // full: the push is refused and the contents are untouched
  EXPECT_FALSE(q.try_push(99));
  EXPECT_TRUE(q.try_pop(out));
  EXPECT_EQ(out, 0);
  EXPECT_TRUE(q.try_push(4));
  for (int want = 1; want <= 4; ++want) {
    ASSERT_TRUE(q.try_pop(out));
    EXPECT_EQ(out, want);
  }
  EXPECT_FALSE(q.try_pop(out));
}

TEST(SpscQueue, TakeFillsAnArrayInOrderAndLeavesTheRest) {
  SpscQueue<int, 8> q;
  for (int i = 0; i < 6; ++i) ASSERT_TRUE(q.try_push(i));
  std::array<int, 4> out{-1, -1, -1, -1};
  // as many as the array holds, oldest first; the others stay queued
  ASSERT_EQ(q.take(out), 4u);
  EXPECT_EQ(out, (std::array<int, 4>{0, 1, 2, 3}));
  EXPECT_EQ(q.size_approx(), 2u);
  out.fill(-1);
  // fewer queued than room: only those, the rest of the array untouched
  ASSERT_EQ(q.take(out), 2u);
  EXPECT_EQ(out, (std::array<int, 4>{4, 5, -1, -1}));
  EXPECT_EQ(q.take(out), 0u);
}

TEST(SpscQueue, WrapsAroundManyTimes) {
  SpscQueue<std::uint64_t, 4> q;
  std::uint64_t next_in = 0, next_out = 0;
  // uneven batches so the indices cross the ring's end at every offset
  for (int round = 0; round < 1000; ++round) {
    const int batch = 1 + round % 4;
    for (int i = 0; i < batch; ++i) ASSERT_TRUE(q.try_push(next_in++));
    for (int i = 0; i < batch; ++i) {
      std::uint64_t out = 0;
      ASSERT_TRUE(q.try_pop(out));
      ASSERT_EQ(out, next_out++);
    }
  }
  EXPECT_EQ(q.size_approx(), 0u);
}

TEST(SpscQueue, TwoThreadsPassAMillionNumbersInOrder) {
  constexpr std::uint64_t kCount = 1'000'000;
  SpscQueue<std::uint64_t, 64> q;
  std::uint64_t retries = 0;
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kCount; ++i) {
      while (!q.try_push(i)) {
        ++retries;
        std::this_thread::yield();
      }
    }
  });
  // the consumer checks every number arrives once, in order
  std::uint64_t expected = 0, out_of_order = 0;
  while (expected < kCount) {
    std::uint64_t v = 0;
    if (!q.try_pop(v)) {
      std::this_thread::yield();
      continue;
    }
    out_of_order += v != expected;
    ++expected;
  }
  producer.join();
  std::uint64_t extra = 0;
  EXPECT_EQ(out_of_order, 0u);
  EXPECT_FALSE(q.try_pop(extra));
  RecordProperty("full_queue_retries", std::to_string(retries));
}

TEST(SpscQueue, PushAndPopAllocateNothing) {
  SpscQueue<std::uint64_t, 64> q;
  std::vector<int> v;
  std::size_t queue_allocations = 0, vector_allocations = 0;
  {
    enact::test::AllocGuard guard;
    for (std::uint64_t i = 0; i < 1000; ++i) {
      q.try_push(i);
      std::uint64_t out = 0;
      if (i % 2) q.try_pop(out);
    }
    queue_allocations = guard.allocations();
    // the guard is not vacuous: a vector's first push_back counts
    v.push_back(1);
    vector_allocations = guard.allocations() - queue_allocations;
  }
  EXPECT_EQ(queue_allocations, 0u);
  EXPECT_GT(vector_allocations, 0u);
}

}  // namespace
}  // namespace enact::rt
