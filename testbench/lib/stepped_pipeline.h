#pragma once
// A naive cycle-stepped pipeline with explicit FIFOs: the reference the timestamp kernel
// (ClockedPipeline) and the units' scheduler (UnitScheduler) are checked against. Within a
// cycle it iterates to a fixpoint so an item may leave one stage and start the next in the same
// cycle, as the kernel allows. An item's cost in a stage is asked for at the cycle it starts
// there (a memory stage makes its requests then).
#include <gtest/gtest.h>

#include <cstdint>
#include <deque>
#include <utility>
#include <vector>

#include "pipeline/kernel/clocked_pipeline.h"

namespace texsim {

class SteppedPipeline {
 public:
  // Item i is at the input from cycle ready[i] (non-decreasing).
  SteppedPipeline(std::vector<StageConfig> cfg, std::vector<uint64_t> ready)
      : cfg_(std::move(cfg)), ready_(std::move(ready)) {
    const size_t n = cfg_.size();
    fifo_.resize(n + 1);
    inside_.resize(n);
    lane_free_.resize(n);
    cap_.resize(n);
    for (size_t s = 0; s < n; ++s) {
      const auto& t = cfg_[s].timing;
      lane_free_[s].assign(t.lanes, 0);
      cap_[s] =
          cfg_[s].max_inflight ? cfg_[s].max_inflight : t.lanes * ((t.latency + t.ii - 1) / t.ii);
    }
    done_.assign(ready_.size(), 0);
  }
  // Cycle t (called for t = 0, 1, 2, ...); cost(item, stage, t) -> ItemCost.
  template <class Cost>
  void cycle(uint64_t t, Cost&& cost) {
    const size_t n = cfg_.size();
    while (next_in_ < ready_.size() && ready_[next_in_] <= t) fifo_[0].push_back(next_in_++);
    for (bool changed = true; changed;) {
      changed = false;
      for (size_t s = 0; s < n; ++s) {
        while (!inside_[s].empty() && inside_[s].front().finish <= t &&
               (s + 1 == n || fifo_[s + 1].size() < cfg_[s + 1].fifo_depth)) {
          const size_t it = inside_[s].front().item;
          inside_[s].pop_front();
          if (s + 1 == n) {
            done_[it] = t;
            ++finished_;
          } else {
            fifo_[s + 1].push_back(it);
          }
          changed = true;
        }
        while (!fifo_[s].empty() && inside_[s].size() < cap_[s]) {
          const size_t it = fifo_[s].front();
          uint64_t& lf = lane_free_[s][it % cfg_[s].timing.lanes];
          if (lf > t) break;
          const ItemCost c = cost(it, s, t);
          lf = t + cfg_[s].timing.ii + c.extra_ii;
          inside_[s].push_back({it, t + cfg_[s].timing.latency + c.extra_latency});
          fifo_[s].pop_front();
          changed = true;
        }
      }
    }
  }
  bool finished() const { return finished_ == ready_.size(); }
  // The cycle each item left the last stage.
  const std::vector<uint64_t>& done() const { return done_; }

 private:
  struct InStage {
    size_t item;
    uint64_t finish;
  };
  std::vector<StageConfig> cfg_;
  std::vector<uint64_t> ready_;
  std::vector<std::deque<size_t>> fifo_;  // fifo_[s]: in front of stage s
  std::vector<std::deque<InStage>> inside_;
  std::vector<std::vector<uint64_t>> lane_free_;
  std::vector<uint32_t> cap_;
  std::vector<uint64_t> done_;
  size_t next_in_ = 0, finished_ = 0;
};

// Leave times of items with fixed costs cost[item][stage].
inline std::vector<uint64_t> stepped_reference(const std::vector<StageConfig>& cfg,
                                               const std::vector<uint64_t>& ready,
                                               const std::vector<std::vector<ItemCost>>& cost) {
  SteppedPipeline p(cfg, ready);
  for (uint64_t t = 0; !p.finished(); ++t) {
    if (t > 10'000'000) {
      ADD_FAILURE() << "reference did not finish";
      break;
    }
    p.cycle(t, [&](size_t it, size_t s, uint64_t) { return cost[it][s]; });
  }
  return p.done();
}

}  // namespace texsim
