#pragma once
// Clocked pipeline kernel: in-order stages with latency, initiation interval and lanes, joined
// by bounded FIFOs with back-pressure. Items carry timestamps through the stages
// (start = max(arrival, stage free, FIFO space)), so no work is spent on idle cycles; the
// model and its equivalence to a cycle-stepped simulation are in docs/timing-model.md.
#include <algorithm>
#include <cstdint>
#include <iosfwd>
#include <stdexcept>
#include <string>
#include <vector>

#include "blocks/timing_spec.h"

namespace texsim {

struct StageConfig {
  std::string name;
  TimingSpec timing;         // latency, ii, lanes
  uint32_t fifo_depth = 4;   // capacity of the FIFO in front of this stage (>= 1)
  // Items that may be inside the stage at once (issued, not yet passed on). 0 = enough for
  // full pipelining: lanes * ceil(latency / ii). A memory stage sets it to its miss-queue depth.
  uint32_t max_inflight = 0;
};

// Per-item variable cost in one stage (e.g. a cache miss, or a row set-up).
struct ItemCost {
  uint32_t extra_latency = 0;  // added to the stage latency for this item (non-blocking)
  uint32_t extra_ii = 0;       // added to the stage's initiation interval (blocks the lane)
};

struct StageStats {
  uint64_t items = 0;
  // Issue-slot accounting: every cycle of every lane up to the stage's last issue is busy or
  // one of the stall causes, so busy + stalls <= cycles × lanes.
  uint64_t busy = 0;           // issue-slot cycles occupied (sum of ii per item, over lanes)
  uint64_t stall_starved = 0;  // a lane was free but no item had arrived (input FIFO empty)
  uint64_t stall_blocked = 0;  // stage full because finished results could not leave
                               // (downstream FIFO full: back-pressure)
  uint64_t stall_full = 0;     // stage full because results were not ready yet (in-flight
                               // limit reached waiting on latency, e.g. DRAM misses)
  uint64_t stall_extra = 0;    // part of busy: cycles added by ItemCost::extra_ii
  uint64_t last_done = 0;      // cycle the last item left this stage
};

class ClockedPipeline {
 public:
  // Throws std::invalid_argument if a configuration could never make progress
  // (zero FIFO depth, zero lanes, zero ii or in-flight limit): the structural deadlock check.
  explicit ClockedPipeline(std::vector<StageConfig> stages);

  // Sends the next item in program order. `ready` is the cycle it is available at the input;
  // `costs` is null or points at one ItemCost per stage. Returns the cycle it leaves the last
  // stage. Throws DeadlockError if an item's progress stalls beyond the watchdog.
  uint64_t issue(uint64_t ready = 0, const ItemCost* costs = nullptr) {
    return issue_with(ready, [costs](int s, uint64_t) { return costs ? costs[s] : ItemCost{}; });
  }
  // As issue(), but a stage's cost may depend on the cycle the item starts there (a cache
  // miss is sent to DRAM at that cycle): `cost_at(stage, start_cycle) -> ItemCost`.
  template <class CostFn>
  uint64_t issue_with(uint64_t ready, CostFn&& cost_at);

  // Total cycles: when the last item left the last stage.
  uint64_t cycles() const { return cycles_; }
  uint64_t items() const { return items_; }
  int stage_count() const { return static_cast<int>(stages_.size()); }
  const StageConfig& config(int s) const { return stages_[s].cfg; }
  const StageStats& stats(int s) const { return stages_[s].stats; }
  // Busy issue slots ÷ (cycles × lanes).
  double utilisation(int s) const;

  // Cycles one item may wait in one stage before the run is declared stuck.
  void set_watchdog(uint64_t cycles) { watchdog_ = cycles; }
  // Writes each stage's state (last start/leave times, FIFO occupancy) for a deadlock report.
  void dump_state(std::ostream& os) const;

 private:
  struct Stage {
    StageConfig cfg;
    StageStats stats;
    uint32_t inflight_cap = 1;
    std::vector<uint64_t> lane_free;  // next cycle each lane can issue
    std::vector<uint64_t> starts;     // ring: start cycle of the last fifo_depth items
    std::vector<uint64_t> leaves;     // ring: leave cycle of the last inflight_cap items
    std::vector<uint64_t> finishes;   // ring: finish cycle of the same items
    uint64_t last_leave = 0;
    uint64_t last_start = 0;
    uint32_t fifo_pos = 0, slot_pos = 0, lane_pos = 0;  // item index modulo each ring size
  };
  [[noreturn]] void report_stuck(uint64_t item, int stage) const;

  std::vector<Stage> stages_;
  uint64_t items_ = 0;
  uint64_t cycles_ = 0;
  uint64_t watchdog_ = uint64_t{1} << 40;
};

class DeadlockError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

template <class CostFn>
uint64_t ClockedPipeline::issue_with(uint64_t ready, CostFn&& cost_at) {
  const uint64_t i = items_;
  uint64_t arrival = ready;
  const size_t n = stages_.size();
  for (size_t s = 0; s < n; ++s) {
    Stage& st = stages_[s];
    const TimingSpec& t = st.cfg.timing;
    // Ring positions are kept as wrapping counters: no divisions on the hot path.
    uint64_t& lane_free = st.lane_free[st.lane_pos];
    const uint32_t slot = st.slot_pos;
    // The item i - inflight_cap must have left before this one can enter.
    const uint64_t slot_free = i >= st.inflight_cap ? st.leaves[slot] : 0;
    // Items issue in order from the FIFO head, so never before the previous item issued.
    const uint64_t own_free = std::max(lane_free, slot_free);
    const uint64_t start = std::max({arrival, own_free, st.last_start});
    if (arrival > lane_free) st.stats.stall_starved += std::min(arrival, start) - lane_free;
    if (slot_free > std::max(lane_free, arrival)) {
      // Waiting for item i - cap to leave: back-pressure if it had finished, else latency.
      const uint64_t wait = slot_free - std::max(lane_free, arrival);
      const uint64_t blocked = std::min(wait, st.leaves[slot] - st.finishes[slot]);
      st.stats.stall_blocked += blocked;
      st.stats.stall_full += wait - blocked;
    }
    const ItemCost cost = cost_at(static_cast<int>(s), start);
    const uint64_t ii = uint64_t{t.ii} + cost.extra_ii;
    lane_free = start + ii;
    st.stats.busy += ii;
    st.stats.stall_extra += cost.extra_ii;
    const uint64_t finish = start + t.latency + cost.extra_latency;
    uint64_t leave = std::max(finish, st.last_leave);  // results retire in order
    if (s + 1 < n) {
      // Back-pressure: item i - depth must have left the next stage's input FIFO.
      const Stage& next = stages_[s + 1];
      if (i >= next.cfg.fifo_depth) leave = std::max(leave, next.starts[next.fifo_pos]);
    }
    if (leave - arrival > watchdog_) report_stuck(i, static_cast<int>(s));
    st.starts[st.fifo_pos] = start;
    if (++st.fifo_pos == st.cfg.fifo_depth) st.fifo_pos = 0;
    if (++st.slot_pos == st.inflight_cap) st.slot_pos = 0;
    if (++st.lane_pos == st.cfg.timing.lanes) st.lane_pos = 0;
    st.leaves[slot] = leave;
    st.finishes[slot] = finish;
    st.last_leave = leave;
    st.last_start = start;
    st.stats.last_done = leave;
    ++st.stats.items;
    arrival = leave;
  }
  ++items_;
  cycles_ = std::max(cycles_, arrival);
  return arrival;
}

}  // namespace texsim
