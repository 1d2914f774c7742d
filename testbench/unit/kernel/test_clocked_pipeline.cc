// The timestamp pipeline kernel against (1) closed-form cases and (2) a naive cycle-stepped
// simulation with explicit FIFOs, on random configurations: leave times must agree exactly.
#include <gtest/gtest.h>

#include <random>

#include "pipeline/kernel/clocked_pipeline.h"
#include "testbench/lib/stepped_pipeline.h"

namespace texsim {
namespace {

StageConfig stage(const char* name, uint32_t lat, uint32_t ii, uint32_t depth = 4,
                  uint32_t lanes = 1, uint32_t inflight = 0) {
  StageConfig c;
  c.name = name;
  c.timing.latency = lat;
  c.timing.ii = ii;
  c.timing.lanes = lanes;
  c.fifo_depth = depth;
  c.max_inflight = inflight;
  return c;
}

TEST(ClockedPipeline, SingleStageClosedForm) {
  ClockedPipeline p({stage("a", 5, 1)});
  for (int i = 0; i < 100; ++i) p.issue();
  EXPECT_EQ(p.cycles(), 5u + 99u);
  EXPECT_EQ(p.stats(0).busy, 100u);
  ClockedPipeline q({stage("a", 5, 3)});
  for (int i = 0; i < 100; ++i) q.issue();
  EXPECT_EQ(q.cycles(), 5u + 3u * 99u);
}

TEST(ClockedPipeline, SlowStageBackPressuresUpstream) {
  ClockedPipeline p({stage("fast", 2, 1), stage("slow", 4, 3, 2)});
  for (int i = 0; i < 50; ++i) p.issue();
  EXPECT_EQ(p.cycles(), 2u + 4u + 3u * 49u);
  EXPECT_GT(p.stats(0).stall_blocked, 0u);  // the fast stage waits for FIFO space
  EXPECT_GT(p.stats(1).stall_starved, 0u);  // only before the first item arrives
  EXPECT_NEAR(p.utilisation(1), 3.0 * 50 / static_cast<double>(p.cycles()), 1e-12);
}

TEST(ClockedPipeline, LanesMultiplyThroughput) {
  ClockedPipeline p({stage("lanes", 8, 4, 4, 4)});
  for (int i = 0; i < 400; ++i) p.issue();
  EXPECT_EQ(p.cycles(), 8u + 99u * 4u);  // 4 lanes, each one item per 4 cycles
}

TEST(ClockedPipeline, InflightLimitStallsOnLongLatency) {
  ClockedPipeline p({stage("mem", 2, 1, 4, 1, 4), stage("out", 1, 1)});
  std::vector<ItemCost> miss(2);
  miss[0].extra_latency = 100;
  for (int i = 0; i < 40; ++i) p.issue(0, i % 10 == 0 ? miss.data() : nullptr);
  EXPECT_GT(p.stats(0).stall_full, 300u);  // 4 misses, each hides at most 4 items
  EXPECT_GE(p.cycles(), 4u * 100u);
}

TEST(ClockedPipeline, StructuralDeadlockAndWatchdog) {
  EXPECT_THROW(ClockedPipeline({stage("a", 1, 1, 0)}), std::invalid_argument);
  EXPECT_THROW(ClockedPipeline({stage("a", 1, 0)}), std::invalid_argument);
  ClockedPipeline p({stage("a", 1, 1), stage("b", 1, 1)});
  p.set_watchdog(1000);
  std::vector<ItemCost> stuck(2);
  stuck[0].extra_latency = 5000;
  EXPECT_THROW(p.issue(0, stuck.data()), DeadlockError);
}

TEST(ClockedPipeline, MatchesCycleSteppedReferenceOnRandomConfigs) {
  std::mt19937 rng_engine(11);
  auto rng = [&] { return static_cast<uint32_t>(rng_engine()); };
  for (int trial = 0; trial < 200; ++trial) {
    const size_t n = 1 + rng() % 4;
    std::vector<StageConfig> cfg;
    for (size_t s = 0; s < n; ++s) {
      cfg.push_back(stage("s", 1 + rng() % 6, 1 + rng() % 3, 1 + rng() % 4, 1 + rng() % 3,
                          rng() % 3 == 0 ? 1 + rng() % 5 : 0));
    }
    const size_t items = 1 + rng() % 60;
    std::vector<uint64_t> ready(items);
    std::vector<std::vector<ItemCost>> cost(items, std::vector<ItemCost>(n));
    uint64_t r = 0;
    for (size_t i = 0; i < items; ++i) {
      r += rng() % 3;
      ready[i] = r;
      for (size_t s = 0; s < n; ++s) {
        if (rng() % 5 == 0) cost[i][s].extra_latency = rng() % 20;
        if (rng() % 7 == 0) cost[i][s].extra_ii = rng() % 4;
      }
    }
    ClockedPipeline p(cfg);
    std::vector<uint64_t> got(items);
    for (size_t i = 0; i < items; ++i) got[i] = p.issue(ready[i], cost[i].data());
    const auto want = stepped_reference(cfg, ready, cost);
    ASSERT_EQ(got, want) << "trial " << trial;
    EXPECT_EQ(p.cycles(), want.back());
    for (int s = 0; s < p.stage_count(); ++s) {
      const StageStats& st = p.stats(s);
      // Issue-slot accounting never exceeds the cycles available (a last slot may run past the
      // end by its ii (<= 3 + extra_ii <= 3) when ii > latency).
      const uint64_t lanes = p.config(s).timing.lanes;
      EXPECT_LE(st.busy + st.stall_starved + st.stall_blocked + st.stall_full,
                p.cycles() * lanes + 6 * lanes)
          << "trial " << trial << " stage " << s;
    }
  }
}

// A last item whose issue slots (ii + extra_ii) outlast its latency: cycles() is when it left,
// issue_end() when the stage could issue again, and the busy slots fit up to the latter.
TEST(ClockedPipeline, IssueEndCoversSlotsThatRunPastTheLastLeave) {
  ClockedPipeline p({stage("a", 2, 1, 2, 4, 0)});
  ItemCost heavy;
  heavy.extra_ii = 100;
  p.issue(0);
  p.issue(0, &heavy);
  EXPECT_EQ(p.cycles(), 2u);
  EXPECT_EQ(p.issue_end(0), 101u);  // issued at 0 on lane 1: 0 + ii 1 + 100
  EXPECT_GT(p.stats(0).busy / 4, p.cycles());
  EXPECT_GE(p.issue_end(0), p.stats(0).busy / 4);
  // The run ends with that slot: utilisation never exceeds 1.
  EXPECT_EQ(p.run_end(), 101u);
  EXPECT_LE(p.utilisation(0), 1.0);
}

}  // namespace
}  // namespace texsim
