// The step's thread pool and the P2G row plan (engine/src/thread_pool.hpp, scatter_rows.hpp):
// every run calls each thread index once and returns only when all are done, including runs
// that find the threads asleep after a pause; the plan marks the rows that one thread reaches
// alone and those near rows that several reach.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "scatter_rows.hpp"
#include "thread_pool.hpp"

namespace compaction {
namespace {

TEST(ThreadPoolGtest, EveryRunCallsEachThreadOnceAndWaitsForAll) {
  // More threads than cores (3 and 4 on a 2-core machine) take a scheduler's time slice per
  // run whenever a spinning thread holds the core another needs: 20 000 such runs took 65 s in a
  // loaded CI. They get a tenth of the runs, still thousands of hand-overs to lose one in.
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  for (int threads : {1, 2, 3, 4}) {
    ThreadPool pool(threads);
    std::vector<int> calls(threads, 0);
    const int runs = threads <= cores ? 20000 : 2000;
    for (int run = 0; run < runs; ++run) {
      pool.run([&](int t) { ++calls[t]; });  // each index writes its own slot
      for (int t = 0; t < threads; ++t) ASSERT_EQ(calls[t], run + 1) << threads << " " << t;
    }
  }
}

TEST(ThreadPoolGtest, ThreadsThatFellAsleepWakeForTheNextRun) {
  ThreadPool pool(3);
  std::atomic<int> sum{0};
  for (int run = 0; run < 5; ++run) {
    std::this_thread::sleep_for(ThreadPool::kSpin * 5);  // past the spin: the workers sleep
    pool.run([&](int t) { sum += t + 1; });
    ASSERT_EQ(sum.load(), 6 * (run + 1));
  }
}

TEST(ThreadPoolGtest, SharesCoverTheItemsOnceInOrder) {
  ThreadPool pool(3);
  for (std::size_t n : {0u, 1u, 2u, 7u, 100u}) {
    std::size_t next = 0;
    for (int t = 0; t < pool.size(); ++t) {
      ASSERT_EQ(pool.begin(n, t), next);
      next = pool.end(n, t);
    }
    EXPECT_EQ(next, n);
  }
}

// Two threads on rows [10, 40): thread 0 reaches [10, 26), thread 1 [24, 40), so rows 24 and
// 25 are shared; a stencil based at b covers b, b + 1, b + 2.
TEST(ScatterRowsGtest, PlanMarksOwnAndNearRows) {
  ScatterRows rows;
  rows.resize(2, 50);
  rows.lo = {10, 24}, rows.hi = {26, 40};
  rows.plan(10, 40);
  for (int b = 10; b < 38; ++b) {
    const bool touches_shared = b + 2 >= 24 && b <= 25;
    EXPECT_EQ(rows.alone[b] != 0, !touches_shared) << b;
  }
  for (int r = 10; r < 40; ++r) EXPECT_EQ(rows.near[r] != 0, r >= 22 && r <= 27) << r;
  EXPECT_TRUE(rows.reaches(0, 25));
  EXPECT_FALSE(rows.reaches(0, 26));
  EXPECT_TRUE(rows.reaches(1, 24));
}

// A later plan with other ranges forgets the earlier one; an empty share reaches nothing.
TEST(ScatterRowsGtest, PlanStartsAfreshEachStep) {
  ScatterRows rows;
  rows.resize(2, 50);
  rows.lo = {10, 10}, rows.hi = {40, 40};
  rows.plan(10, 40);
  EXPECT_FALSE(rows.alone[20]);
  rows.lo = {10, 0}, rows.hi = {40, 0};
  rows.plan(10, 40);
  for (int r = 10; r < 38; ++r) EXPECT_TRUE(rows.alone[r]) << r;
  for (int r = 10; r < 40; ++r) EXPECT_FALSE(rows.near[r]) << r;
}

}  // namespace
}  // namespace compaction
