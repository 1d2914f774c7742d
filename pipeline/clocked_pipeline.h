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
  // A snapshot of stage s's counters, refreshed by each call.
  const StageStats& stats(int s) const;
  // Busy issue slots ÷ (cycles × lanes).
  double utilisation(int s) const;

  // Cycles one item may wait in one stage before the run is declared stuck.
  void set_watchdog(uint64_t cycles) { watchdog_ = cycles; }
  // Writes each stage's state (last start/leave times, FIFO occupancy) for a deadlock report.
  void dump_state(std::ostream& os) const;

 private:
  // Per-stage state the kernel touches for every item, kept small and apart from the
  // configuration. The per-item history a stage needs (lane free times, start, leave and
  // finish cycles) is kept in rings of one power-of-two size P >= every lane count, FIFO
  // depth and in-flight limit: item i writes position i mod P and reads item i − k at
  // (i − k) mod P, so no ring position has to be stored or advanced.
  struct Hot {
    uint64_t last_leave = 0;
    uint64_t last_start = 0;
    uint32_t latency = 1, ii = 1;
    uint32_t lanes = 1;       // item i issues on the lane item i − lanes used
    uint32_t cap = 1;         // in-flight limit: item i − cap must have left
    uint32_t next_depth = 1;  // FIFO in front of the next stage: item i − depth left it
    // Counters; busy (= items · ii + extra) and last_done (= last_leave) follow from them.
    uint64_t starved = 0, blocked = 0, full = 0, extra = 0;
  };
  struct Stage {
    StageConfig cfg;
    uint32_t inflight_cap = 1;
    mutable StageStats stats;  // filled from Hot by stats()
  };
  // Ring layout: stage s owns ring_[4Ps .. 4P(s+1)): lane free | start | leave | finish.
  // A sentinel stage n (never written) makes the last stage read "no back-pressure".
  enum Ring : uint64_t { kLane = 0, kStart = 1, kLeave = 2, kFinish = 3, kRings = 4 };
  uint64_t items_of(size_t s) const;
  [[noreturn]] void report_stuck(uint64_t item, int stage);

  std::vector<Stage> stages_;
  std::vector<Hot> hot_;
  std::vector<uint64_t> ring_;
  uint64_t ring_mask_ = 0;  // P − 1
  uint64_t items_ = 0;
  uint64_t cycles_ = 0;
  uint64_t watchdog_ = uint64_t{1} << 40;
  int stuck_stage_ = -1;  // stage that raised DeadlockError (its earlier stages took the item)
};

class DeadlockError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

template <class CostFn>
uint64_t ClockedPipeline::issue_with(uint64_t ready, CostFn&& cost_at) {
  const uint64_t i = items_;
  const uint64_t mask = ring_mask_, p = mask + 1;
  const uint64_t w = i & mask;  // this item's position in every ring
  uint64_t* r = ring_.data();
  Hot* const hot = hot_.data();
  const size_t n = stages_.size();
  const uint64_t watchdog = watchdog_;
  uint64_t arrival = ready;
  // The rings start zeroed and item i − k (k <= P) for i < k reads a cell not yet written,
  // so a predecessor that does not exist reads as cycle 0, which constrains nothing.
  for (size_t s = 0; s < n; ++s, r += kRings * p) {
    Hot& st = hot[s];
    // Everything this stage needs is read before the first store (ring and counters are all
    // uint64_t, so a store would make the compiler reload them).
    const uint64_t free_at = r[kLane * p + ((i - st.lanes) & mask)];
    // The item i − inflight_cap must have left before this one can enter.
    const uint64_t old = (i - st.cap) & mask;
    const uint64_t slot_free = r[kLeave * p + old], slot_finish = r[kFinish * p + old];
    // Back-pressure: item i − depth must have left the next stage's input FIFO.
    const uint64_t next_start = r[(kRings + kStart) * p + ((i - st.next_depth) & mask)];
    const uint64_t last_start = st.last_start, last_leave = st.last_leave;
    // Items issue in order from the FIFO head, so never before the previous item issued.
    const uint64_t avail = std::max(free_at, arrival);
    const uint64_t start = std::max(std::max(avail, slot_free), last_start);
    if (slot_free > avail) {
      // Waiting for item i − cap to leave: back-pressure if it had finished, else latency.
      const uint64_t wait = slot_free - avail;
      const uint64_t blocked = std::min(wait, slot_free - slot_finish);
      st.blocked += blocked;
      st.full += wait - blocked;
    }
    const ItemCost cost = cost_at(static_cast<int>(s), start);
    const uint64_t finish = start + st.latency + cost.extra_latency;
    const uint64_t leave = std::max(std::max(finish, last_leave), next_start);  // in order
    r[kLane * p + w] = start + st.ii + cost.extra_ii;
    if (leave - arrival > watchdog) report_stuck(i, static_cast<int>(s));
    r[kStart * p + w] = start;
    r[kLeave * p + w] = leave;
    r[kFinish * p + w] = finish;
    st.last_leave = leave;
    st.last_start = start;
    st.starved += avail - free_at;  // start >= arrival: a starved lane waited until arrival
    st.extra += cost.extra_ii;
    arrival = leave;
  }
  ++items_;
  cycles_ = std::max(cycles_, arrival);
  return arrival;
}

}  // namespace texsim
