// The insertion's worker pool (private header): every task runs once per round, on any thread
// count from round to round, and a task's exception reaches the caller without breaking the pool.
#include <gtest/gtest.h>

#include <stdexcept>
#include <thread>
#include <vector>

#include "support/parallel.h"

namespace {

TEST(WorkerPool, EveryTaskRunsOncePerRoundWhateverTheThreadCount) {
  ndtom::WorkerPool pool;
  const std::vector<size_t> counts{2, 3, 1, 4, 2, 1, 3};
  for (int round = 0; round < 300; ++round) {
    const size_t threads = counts[size_t(round) % counts.size()];
    std::vector<int> runs(threads, 0);
    std::vector<std::thread::id> ids(threads);
    pool.run(threads, [&](size_t t) {
      ++runs[t];
      ids[t] = std::this_thread::get_id();
    });
    for (size_t t = 0; t < threads; ++t)
      EXPECT_EQ(runs[t], 1) << "round " << round << " task " << t;
    EXPECT_EQ(ids[0], std::this_thread::get_id());  // task 0 on the caller
    for (size_t t = 1; t < threads; ++t) EXPECT_NE(ids[t], ids[0]);
    if (HasFailure()) return;
  }
}

TEST(WorkerPool, ExceptionsReachTheCallerAndThePoolGoesOn) {
  ndtom::WorkerPool pool;
  for (const size_t thrower : {size_t(0), size_t(2)}) {
    std::vector<int> runs(3, 0);
    EXPECT_THROW(pool.run(3,
                          [&](size_t t) {
                            ++runs[t];
                            if (t == thrower) throw std::runtime_error("task failed");
                          }),
                 std::runtime_error);
    EXPECT_EQ(runs, (std::vector<int>{1, 1, 1}));  // the others still ran to the end
  }
  std::vector<int> runs(3, 0);
  pool.run(3, [&](size_t t) { ++runs[t]; });
  EXPECT_EQ(runs, (std::vector<int>{1, 1, 1}));
}

}  // namespace
