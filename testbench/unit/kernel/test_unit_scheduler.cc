// Several clocked units sharing a memory level, on one global clock: the timestamp kernel with
// the UnitScheduler's cycle order against a naive simulation that steps every unit through
// every cycle (units in index order within a cycle) and makes each memory request at the cycle
// its item starts the memory stage. Every item's leave time must agree exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <memory>
#include <random>
#include <vector>

#include "blocks/texture/memory/banked_dram.h"
#include "blocks/texture/memory/dram_model.h"
#include "blocks/texture/memory/l2_cache.h"
#include "pipeline/kernel/clocked_pipeline.h"
#include "pipeline/kernel/unit_scheduler.h"
#include "testbench/lib/stepped_pipeline.h"

namespace texsim {
namespace {

struct Item {
  std::vector<ItemCost> cost;  // per stage; the memory stage's extra_latency comes from memory
  std::vector<uint64_t> lines;
};
struct UnitSpec {
  std::vector<StageConfig> cfg;
  int mem_stage = 0;
  std::vector<Item> items;
};
using MemoryFactory = std::function<std::unique_ptr<LineMemory>()>;

// The memory stage's wait: the last of the item's lines to arrive, after the start cycle.
uint64_t memory_wait(LineMemory& m, const Item& it, uint64_t t, int unit) {
  uint64_t ready = t;
  for (uint64_t line : it.lines) ready = std::max(ready, m.read_line(t, line * 64, 64, unit));
  return ready - t;
}

// The kernel: issue_head to the memory stage, the scheduler picks the earliest, issue_tail.
struct Kernel {
  std::vector<UnitSpec>& units;
  LineMemory& mem;
  std::vector<std::unique_ptr<ClockedPipeline>> pipes;
  std::vector<std::vector<uint64_t>> leave;
  std::vector<uint64_t> arrival;
  std::vector<std::vector<ItemCost>> cost;

  Kernel(std::vector<UnitSpec>& u, LineMemory& m) : units(u), mem(m) {
    for (auto& s : units) {
      pipes.push_back(std::make_unique<ClockedPipeline>(s.cfg));
      leave.emplace_back();
    }
    arrival.resize(units.size());
    cost.resize(units.size());
  }
  uint64_t begin(int u, size_t& i) {
    UnitSpec& s = units[static_cast<size_t>(u)];
    cost[static_cast<size_t>(u)] = s.items[i].cost;
    const auto& c = cost[static_cast<size_t>(u)];
    ClockedPipeline& p = *pipes[static_cast<size_t>(u)];
    arrival[static_cast<size_t>(u)] =
        p.issue_head(0, s.mem_stage, [&](int st, uint64_t) { return c[static_cast<size_t>(st)]; });
    return p.start_at(s.mem_stage, arrival[static_cast<size_t>(u)]);
  }
  void commit(int u, size_t& i) {
    UnitSpec& s = units[static_cast<size_t>(u)];
    ClockedPipeline& p = *pipes[static_cast<size_t>(u)];
    auto& c = cost[static_cast<size_t>(u)];
    const uint64_t start = p.start_at(s.mem_stage, arrival[static_cast<size_t>(u)]);
    c[static_cast<size_t>(s.mem_stage)].extra_latency = memory_wait(mem, s.items[i], start, u);
    leave[static_cast<size_t>(u)].push_back(
        p.issue_tail(s.mem_stage, arrival[static_cast<size_t>(u)],
                     [&](int st, uint64_t) { return c[static_cast<size_t>(st)]; }));
  }
};

// The same kernel saying which begun items stay in their unit (no lines to read): the
// scheduler commits those at once, out of the global order.
struct LocalKernel : Kernel {
  using Kernel::Kernel;
  std::vector<size_t> begun = std::vector<size_t>(units.size());
  uint64_t begin(int u, size_t& i) {
    begun[static_cast<size_t>(u)] = i;
    return Kernel::begin(u, i);
  }
  bool local(int u) const {
    const UnitSpec& s = units[static_cast<size_t>(u)];
    return s.items[begun[static_cast<size_t>(u)]].lines.empty();
  }
};

// Either kernel also saying how early each unit's next item can start the memory stage (its
// stages take items in order): a begun item may then commit before every unit has one.
template <class K>
struct BoundKernel : K {
  using K::K;
  uint64_t next_start_bound(int u) const {
    const UnitSpec& s = this->units[static_cast<size_t>(u)];
    return this->pipes[static_cast<size_t>(u)]->start_at(s.mem_stage, 0);
  }
};

// Items handed to the scheduler interleaved as a stream (unit order shuffled). `early`: items
// committed before finish().
template <class K = Kernel>
std::vector<std::vector<uint64_t>> run_kernel(std::vector<UnitSpec>& units, LineMemory& mem,
                                              std::mt19937& rng, size_t window,
                                              uint64_t* forced = nullptr, uint64_t* late = nullptr,
                                              uint64_t* local = nullptr,
                                              uint64_t* early = nullptr) {
  K k(units, mem);
  UnitScheduler<size_t, K> sched(static_cast<int>(units.size()), k, window);
  std::vector<int> order;
  for (size_t u = 0; u < units.size(); ++u)
    order.insert(order.end(), units[u].items.size(), static_cast<int>(u));
  std::shuffle(order.begin(), order.end(), rng);
  std::vector<size_t> next(units.size(), 0);
  for (int u : order) sched.add(u, next[static_cast<size_t>(u)]++);
  if (early) *early = sched.committed() - sched.local_commits();
  sched.finish();
  if (forced) *forced = sched.forced_commits();
  if (late) *late = sched.late_items();
  if (local) *local = sched.local_commits();
  return k.leave;
}

// Every unit stepped through every cycle; memory requests made as items start the stage.
std::vector<std::vector<uint64_t>> run_stepped(const std::vector<UnitSpec>& units,
                                               LineMemory& mem) {
  std::vector<SteppedPipeline> pipes;
  pipes.reserve(units.size());
  for (const auto& s : units) pipes.emplace_back(s.cfg, std::vector<uint64_t>(s.items.size(), 0));
  auto all_done = [&] {
    return std::all_of(pipes.begin(), pipes.end(), [](const auto& p) { return p.finished(); });
  };
  for (uint64_t t = 0; !all_done(); ++t) {
    if (t > 10'000'000) {
      ADD_FAILURE() << "stepped model did not finish";
      break;
    }
    for (size_t u = 0; u < units.size(); ++u) {
      const UnitSpec& s = units[u];
      pipes[u].cycle(t, [&](size_t it, size_t st, uint64_t now) {
        ItemCost c = s.items[it].cost[st];
        if (static_cast<int>(st) == s.mem_stage)
          c.extra_latency = memory_wait(mem, s.items[it], now, static_cast<int>(u));
        return c;
      });
    }
  }
  std::vector<std::vector<uint64_t>> out;
  out.reserve(pipes.size());
  for (const auto& p : pipes) out.push_back(p.done());
  return out;
}

std::vector<UnitSpec> random_units(std::mt19937& rng, int n_units, int max_items) {
  auto r = [&](uint32_t n) { return static_cast<uint32_t>(rng() % n); };
  std::vector<UnitSpec> units(static_cast<size_t>(n_units));
  for (auto& u : units) {
    const size_t n = 2 + r(3);
    for (size_t s = 0; s < n; ++s) {
      StageConfig c;
      c.name = "s";
      c.timing.latency = 1 + r(6);
      c.timing.ii = 1 + r(3);
      c.timing.lanes = 1 + r(3);
      c.fifo_depth = 1 + r(4);
      c.max_inflight = r(3) == 0 ? 1 + r(5) : 0;
      u.cfg.push_back(c);
    }
    u.mem_stage = static_cast<int>(r(static_cast<uint32_t>(n)));
    const uint32_t items = r(static_cast<uint32_t>(max_items) + 1);
    for (uint32_t i = 0; i < items; ++i) {
      Item it;
      it.cost.resize(n);
      for (size_t s = 0; s < n; ++s) {
        if (r(5) == 0) it.cost[s].extra_latency = r(20);
        if (r(7) == 0) it.cost[s].extra_ii = r(4);
      }
      it.cost[static_cast<size_t>(u.mem_stage)].extra_latency = 0;
      for (uint32_t l = r(4); l > 0; --l) it.lines.push_back(r(24));
      u.items.push_back(it);
    }
  }
  return units;
}

std::unique_ptr<LineMemory> random_dram(std::mt19937& rng) {
  DramModel::Config c;
  c.latency = static_cast<uint32_t>(1 + rng() % 30);
  c.bytes_per_cycle = 4.0 * static_cast<double>(1 + rng() % 16);
  return std::make_unique<DramModel>(c);
}

// Returns the items committed at once (LocalKernel); `early`: items with requests committed
// before the last item was handed over.
template <class K = Kernel>
uint64_t expect_same_as_stepped(const MemoryFactory& make, uint32_t seed, int trials,
                                uint64_t* early = nullptr) {
  std::mt19937 rng(seed);
  uint64_t local_commits = 0;
  for (int trial = 0; trial < trials; ++trial) {
    const int n_units = 1 + static_cast<int>(rng() % 4);
    std::vector<UnitSpec> units = random_units(rng, n_units, 30);
    std::mt19937 mem_rng(rng());
    std::mt19937 mem_rng2 = mem_rng;
    const std::unique_ptr<LineMemory> a = make ? make() : random_dram(mem_rng);
    const std::unique_ptr<LineMemory> b = make ? make() : random_dram(mem_rng2);
    uint64_t forced = 0, local = 0, before_end = 0;
    const auto got =
        run_kernel<K>(units, *a, rng, size_t{1} << 20, &forced, nullptr, &local, &before_end);
    const auto want = run_stepped(units, *b);
    local_commits += local;
    if (early) *early += before_end;
    EXPECT_EQ(forced, 0u);
    EXPECT_EQ(got, want) << "trial " << trial << ", " << n_units << " units";
    if (got != want) break;
  }
  return local_commits;
}

TEST(UnitScheduler, SeveralUnitsOnAFlatDramMatchTheCycleSteppedModel) {
  EXPECT_EQ(expect_same_as_stepped(nullptr, 5, 250), 0u);
}

// A shared L2 (small, with few MSHRs and ports so that conflicts and stalls happen) over a
// banked DRAM, as one level.
class L2OverBankedDram : public LineMemory {
 public:
  explicit L2OverBankedDram(uint32_t seed)
      : dram_(dram_config(seed)), l2_(l2_config(seed), dram_) {}
  uint64_t read_line(uint64_t now, uint64_t addr, uint32_t bytes, int unit) override {
    return l2_.read_line(now, addr, bytes, unit);
  }
  const L2Cache& l2() const { return l2_; }

 private:
  static BankedDram::Config dram_config(uint32_t seed) {
    BankedDram::Config c = BankedDram::Config::preset(seed % 2 ? "lpddr4" : "gddr6");
    c.channels = 1u << (seed % 3);
    c.banks = 2;
    c.page_policy = seed % 5 == 0 ? BankedDram::PagePolicy::Closed : BankedDram::PagePolicy::Open;
    return c;
  }
  static L2Cache::Config l2_config(uint32_t seed) {
    L2Cache::Config c;
    c.size_bytes = 1024;
    c.ways = 2;
    c.line_bytes = 128;
    c.slices = 1u << (seed % 3);
    c.mshrs = 1 + seed % 3;
    c.hit_latency = 1 + seed % 7;
    c.prefetch = seed % 2 ? L2Cache::Prefetch::NextLine : L2Cache::Prefetch::None;
    return c;
  }
  BankedDram dram_;
  L2Cache l2_;
};

TEST(UnitScheduler, SeveralUnitsOnAnL2AndBankedDramMatchTheCycleSteppedModel) {
  uint32_t seed = 0;
  uint64_t merges = 0, conflicts = 0;
  for (int round = 0; round < 25; ++round) {
    ++seed;
    L2OverBankedDram* last = nullptr;
    expect_same_as_stepped(
        [&]() -> std::unique_ptr<LineMemory> {
          auto m = std::make_unique<L2OverBankedDram>(seed);
          last = m.get();
          return m;
        },
        100 + seed, 10);
    merges += last->l2().stats().mshr_merges;
    conflicts += last->l2().stats().bank_conflicts;
  }
  // The configurations exercised the shared level's contention, not only its hits.
  EXPECT_GT(merges, 0u);
  EXPECT_GT(conflicts, 0u);
}

// Items that read no line (a quarter of them) committed at once, out of the global order: the
// memory still sees every request in cycle order, so every leave time is the stepped model's.
TEST(UnitScheduler, ItemsThatStayInTheirUnitCommitAtOnceWithTheSameTimes) {
  EXPECT_GT(expect_same_as_stepped<LocalKernel>(nullptr, 5, 250), 500u);
  for (uint32_t seed = 1; seed <= 10; ++seed) {
    EXPECT_GT(expect_same_as_stepped<LocalKernel>(
                  [seed] { return std::make_unique<L2OverBankedDram>(seed); }, 300 + seed, 10),
              0u);
  }
}

// With the units' bounds a begun item commits as soon as no other unit can have an earlier
// one, not only once every unit has begun one: the same times, and items committed early.
TEST(UnitScheduler, ItemsCommitBeforeEveryUnitHasOneWhenTheOthersCannotComeFirst) {
  uint64_t early = 0, early_without = 0;
  expect_same_as_stepped<BoundKernel<Kernel>>(nullptr, 5, 250, &early);
  expect_same_as_stepped<Kernel>(nullptr, 5, 250, &early_without);
  EXPECT_GT(early, early_without);
  uint64_t early_local = 0;
  EXPECT_GT(expect_same_as_stepped<BoundKernel<LocalKernel>>(nullptr, 7, 250, &early_local), 500u);
  EXPECT_GT(early_local, 0u);
  for (uint32_t seed = 1; seed <= 10; ++seed) {
    expect_same_as_stepped<BoundKernel<LocalKernel>>(
        [seed] { return std::make_unique<L2OverBankedDram>(seed); }, 400 + seed, 10);
  }
}

TEST(UnitScheduler, OneUnitIsTheKernelAlone) {
  // One unit: the split issue gives the same times as issue_with with the same costs.
  std::mt19937 rng(9);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<UnitSpec> units = random_units(rng, 1, 40);
    DramModel a, b;
    const auto got = run_kernel(units, a, rng, 1 << 20);
    ClockedPipeline p(units[0].cfg);
    std::vector<uint64_t> want;
    for (const Item& it : units[0].items) {
      want.push_back(p.issue_with(0, [&](int s, uint64_t t) {
        ItemCost c = it.cost[static_cast<size_t>(s)];
        if (s == units[0].mem_stage) c.extra_latency = memory_wait(b, it, t, 0);
        return c;
      }));
    }
    ASSERT_EQ(got[0], want) << "trial " << trial;
  }
}

TEST(UnitScheduler, AFullWindowForcesCommitsAndCountsLateItems) {
  // Unit 1 gets its items only after unit 0's 40: with a window of 8, unit 0's items are
  // committed before unit 1 has any, and unit 1's first items start earlier than them.
  std::mt19937 rng(3);
  std::vector<UnitSpec> units = random_units(rng, 2, 0);
  for (auto& u : units) {
    u.cfg.assign(2, StageConfig{"s", {}, 4, 0});
    u.mem_stage = 1;
    for (int i = 0; i < 40; ++i) u.items.push_back({{ItemCost{}, ItemCost{}}, {uint64_t(i)}});
  }
  DramModel mem;
  Kernel k(units, mem);
  UnitScheduler<size_t, Kernel> sched(2, k, 8);
  for (size_t i = 0; i < 40; ++i) sched.add(0, i);
  for (size_t i = 0; i < 40; ++i) sched.add(1, i);
  sched.finish();
  EXPECT_EQ(sched.committed(), 80u);
  // At least unit 0's items beyond the 8 the window holds; later also unit 1's, once unit 0
  // has nothing begun (the scheduler cannot know that unit 0 has no more).
  EXPECT_GE(sched.forced_commits(), 32u);
  EXPECT_GT(sched.late_items(), 0u);
  DramModel mem2;
  Kernel k2(units, mem2);
  UnitScheduler<size_t, Kernel> exact(2, k2, 1 << 20);
  for (size_t i = 0; i < 40; ++i) exact.add(0, i);
  for (size_t i = 0; i < 40; ++i) exact.add(1, i);
  exact.finish();
  EXPECT_EQ(exact.forced_commits(), 0u);
  EXPECT_EQ(exact.late_items(), 0u);
}

}  // namespace
}  // namespace texsim
