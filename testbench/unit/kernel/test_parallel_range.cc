// The thread pools: every index runs once for any thread count, and an exception thrown in a
// task reaches the caller (the lowest failing index's) instead of terminating the program.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <vector>

#include "pipeline/kernel/parallel_range.h"

namespace texsim {
namespace {

TEST(ParallelTasks, EveryIndexRunsOnceForAnyThreadCount) {
  for (int threads : {1, 2, 3, 8}) {
    std::vector<int> hits(37, 0);
    parallel_tasks(hits.size(), threads, [&](size_t i) { ++hits[i]; });
    EXPECT_EQ(hits, std::vector<int>(37, 1)) << threads << " threads";
  }
}

TEST(ParallelTasks, ATaskErrorReachesTheCallerAsTheLowestFailingIndex) {
  for (int threads : {1, 2, 4}) {
    try {
      parallel_tasks(100, threads, [](size_t i) {
        if (i == 7 || i == 40) throw std::invalid_argument("task " + std::to_string(i));
      });
      ADD_FAILURE() << "no exception with " << threads << " threads";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()), "task 7") << threads << " threads";
    }
  }
}

TEST(ParallelRange, CoversTheRangeOnceAndPassesErrorsUp) {
  for (int threads : {1, 2, 5}) {
    std::vector<std::atomic<int>> hits(23);
    parallel_range(hits.size(), threads, [&](size_t b, size_t e) {
      for (size_t i = b; i < e; ++i) ++hits[i];
    });
    for (const auto& h : hits) EXPECT_EQ(h.load(), 1) << threads << " threads";
  }
  EXPECT_THROW(parallel_range(10, 3,
                              [](size_t b, size_t) {
                                if (b > 0) throw std::runtime_error("late part");
                              }),
               std::runtime_error);
}

}  // namespace
}  // namespace texsim
