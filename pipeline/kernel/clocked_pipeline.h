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
#include <type_traits>
#include <utility>
#include <vector>

#include "blocks/base/timing_spec.h"

namespace texsim {

struct StageConfig {
  std::string name;
  TimingSpec timing;        // latency, ii, lanes
  uint32_t fifo_depth = 4;  // capacity of the FIFO in front of this stage (>= 1)
  // Items that may be inside the stage at once (issued, not yet passed on). 0 = enough for
  // full pipelining: lanes * ceil(latency / ii). A memory stage sets it to its miss-queue depth.
  uint32_t max_inflight = 0;
};

// Per-item variable cost in one stage (e.g. a cache miss, or a row set-up).
struct ItemCost {
  uint64_t extra_latency = 0;  // added to the stage latency for this item (non-blocking)
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
  uint64_t issue_with(uint64_t ready, CostFn&& cost_at) {
    // Common stage counts get the stage sequence unrolled at compile time, so cost_at sees a
    // constant stage index and the per-stage addresses are fixed offsets.
    switch (stages_.size()) {
      case 3:
        return issue_unrolled(ready, cost_at, std::make_index_sequence<3>{});
      case 4:
        return issue_unrolled(ready, cost_at, std::make_index_sequence<4>{});
      default: {
        const ItemCtx c = item_ctx();
        uint64_t arrival = ready;
        for (size_t s = 0; s < stages_.size(); ++s) arrival = step(c, s, arrival, cost_at);
        return retire(arrival);
      }
    }
  }

  // As issue_with() for a pipeline of exactly kStages stages (the caller knows the count from
  // construction; checked on entry): the stage sequence is unrolled and cost_at receives the
  // stage as std::integral_constant<int, s>, so a caller's per-stage cost is chosen at compile
  // time and inlined into the stage's step.
  template <int kStages, class CostFn>
  [[gnu::always_inline]] uint64_t issue_fixed(uint64_t ready, CostFn&& cost_at) {
    if (stages_.size() != static_cast<size_t>(kStages))
      throw std::logic_error("ClockedPipeline::issue_fixed: wrong stage count");
    const ItemCtx c = item_ctx();
    uint64_t arrival = ready;
    [&]<int... kStage>(std::integer_sequence<int, kStage...>) __attribute__((always_inline)) {
      ((arrival = step(
            c, static_cast<size_t>(kStage), arrival,
            [&](int, uint64_t start) __attribute__((always_inline)) {
              return cost_at(std::integral_constant<int, kStage>{}, start);
            })),
       ...);
    }
    (std::make_integer_sequence<int, kStages>{});
    return retire(arrival);
  }

  // issue_fixed for n items in a row, item k's costs cost_at(k, stage, start): the same times
  // and counters, with the stages' running state (last start and leave, counters) held in
  // locals across the items instead of stored and reloaded per item, which put a store and
  // its reload on the chain from one item to the next.
  template <int kStages, class CostFn>
  void issue_run(size_t n, CostFn&& cost_at) {
    if (stages_.size() != static_cast<size_t>(kStages))
      throw std::logic_error("ClockedPipeline::issue_run: wrong stage count");
    bool one_lane = true;
    for (const Hot& h : hot_) one_lane = one_lane && h.lanes == 1;
    if (one_lane) {
      run_items<kStages, true>(n, cost_at);
    } else {
      run_items<kStages, false>(n, cost_at);
    }
  }

  // Split issue, for a scheduler that orders several pipelines' memory requests by cycle
  // (docs/timing-model.md#several-units): issue_head runs the item through stages [0, k) and
  // returns its arrival at stage k; start_at(k, arrival) is the cycle it will start there;
  // issue_tail runs stages [k, n) and retires it. issue_head then issue_tail give the same
  // times as issue_with with the same costs; no other item may be issued in between.
  template <class CostFn>
  uint64_t issue_head(uint64_t ready, int k, CostFn&& cost_at) {
    const ItemCtx c = item_ctx();
    uint64_t arrival = ready;
    for (size_t s = 0; s < static_cast<size_t>(k); ++s) arrival = step(c, s, arrival, cost_at);
    return arrival;
  }
  uint64_t start_at(int k, uint64_t arrival) const {
    // step()'s start, without its side effects (inline: once per item of a unit of several).
    const uint64_t p = ring_mask_ + 1, iw = items_ * kEntry, mask = ring_mask_ * kEntry;
    const Hot& st = hot_[static_cast<size_t>(k)];
    const uint64_t* const e = ring_.data() + static_cast<uint64_t>(k) * p * kEntry;
    const uint64_t free_at = e[((iw - st.lanes_w) & mask) + kLaneFree];
    const uint64_t slot_free = e[((iw - st.cap_w) & mask) + kLeave];
    return std::max({free_at, arrival, slot_free, st.last_start});
  }
  // issue_head(ready, kHead, ..) and issue_tail(kHead, ..) for a pipeline of exactly kStages
  // stages, unrolled as issue_fixed (cost_at gets the stage as std::integral_constant).
  template <int kHead, class CostFn>
  [[gnu::always_inline]] uint64_t issue_head_fixed(uint64_t ready, CostFn&& cost_at) {
    return steps_fixed<0>(item_ctx(), ready, cost_at, std::make_integer_sequence<int, kHead>{});
  }
  template <int kHead, int kStages, class CostFn>
  [[gnu::always_inline]] uint64_t issue_tail_fixed(uint64_t arrival, CostFn&& cost_at) {
    if (stages_.size() != static_cast<size_t>(kStages))
      throw std::logic_error("ClockedPipeline::issue_tail_fixed: wrong stage count");
    return retire(steps_fixed<kHead>(item_ctx(), arrival, cost_at,
                                     std::make_integer_sequence<int, kStages - kHead>{}));
  }
  template <class CostFn>
  uint64_t issue_tail(int k, uint64_t arrival, CostFn&& cost_at) {
    const ItemCtx c = item_ctx();
    for (size_t s = static_cast<size_t>(k); s < stages_.size(); ++s)
      arrival = step(c, s, arrival, cost_at);
    return retire(arrival);
  }

  // Total cycles: when the last item left the last stage.
  // Cycle at which the last item left the pipeline.
  uint64_t cycles() const { return cycles_; }
  // End of the run: the last exit, or later if a stage's last issue slot (extra cycles charged
  // after an item, e.g. a set-up) outlasts it. Utilisation is measured against this.
  uint64_t run_end() const;
  uint64_t items() const { return items_; }
  int stage_count() const { return static_cast<int>(stages_.size()); }
  const StageConfig& config(int s) const { return stages_[s].cfg; }
  // A snapshot of stage s's counters, refreshed by each call.
  const StageStats& stats(int s) const;
  // When stage s's issue slots end: its lanes' last free cycle. The last items' slots (ii plus
  // extra_ii) may end after cycles().
  uint64_t issue_end(int s) const;
  // Busy issue slots ÷ (cycles × lanes).
  double utilisation(int s) const;

  // Stage s's cycles of the last item issued: when it started there, when its result was
  // ready and when it left. Read only by optional tracing (stage_timeline.h), after an issue.
  struct ItemTimes {
    uint64_t start, finish, leave;
  };
  ItemTimes last_item(int s) const;

  // Cycles one item may wait in one stage before the run is declared stuck.
  void set_watchdog(uint64_t cycles) { watchdog_ = cycles; }
  // Writes each stage's state (last start/leave times, FIFO occupancy) for a deadlock report.
  void dump_state(std::ostream& os) const;

 private:
  // Per-stage state the kernel touches for every item, kept small and apart from the
  // configuration. The per-item history a stage needs (lane free time, start, leave and
  // finish cycles) is kept in a ring of one power-of-two size P >= every lane count, FIFO
  // depth and in-flight limit: item i writes entry i mod P and reads item i − k at
  // (i − k) mod P, so no ring position has to be stored or advanced. An entry is kEntry
  // words; positions and offsets are counted in words (i·kEntry), so an address is one
  // scaled index.
  static constexpr uint64_t kEntry = 4;
  enum Word : uint64_t { kLaneFree, kStart, kLeave, kFinish };  // one item's history in one stage
  struct Hot {
    uint64_t last_leave = 0;
    uint64_t last_start = 0;
    uint64_t last_free = 0;  // the last item's lane-free cycle (its ring entry's kLaneFree)
    // 64-bit, so each is an operand of the arithmetic that uses it.
    uint64_t latency = 1, ii = 1;
    uint64_t lanes = 1;
    uint64_t lanes_w = kEntry;  // item i issues on the lane item i − lanes used (in words)
    uint64_t cap_w = kEntry;    // in-flight limit: item i − cap must have left (in words)
    uint64_t depth_w = kEntry;  // FIFO in front of the next stage: item i − depth left it
    // Counters; busy (= items · ii + extra) and last_done (= last_leave) follow from them.
    uint64_t starved = 0, blocked = 0, full = 0, extra = 0;
  };
  struct Stage {
    StageConfig cfg;
    uint32_t inflight_cap = 1;
    mutable StageStats stats;  // filled from Hot by stats()
  };

  // Stage s of the current item, arriving at `arrival`; returns when it leaves. Stage s owns
  // ring_[s·W .. (s + 1)·W), W = P·kEntry words; a sentinel stage n (never written) makes the
  // last stage read "no back-pressure". The rings start zeroed and item i − k (k <= P) for
  // i < k reads an entry not yet written, so a predecessor that does not exist reads as cycle 0.
  // What every stage of one item needs, loaded once per item (held in registers: reloading
  // members after each uint64_t store would be needed otherwise).
  struct ItemCtx {
    uint64_t iw, mask_w, stage_w, watchdog;  // item position, (P − 1)·kEntry, W, in words
    uint64_t* ring;
    Hot* hot;
  };
  ItemCtx item_ctx() {
    const uint64_t p = ring_mask_ + 1;
    return {items_ * kEntry, ring_mask_ * kEntry, p * kEntry, watchdog_, ring_.data(), hot_.data()};
  }
  template <class CostFn>
  [[gnu::always_inline]] uint64_t step(const ItemCtx& c, size_t s, uint64_t arrival,
                                       CostFn&& cost_at) {
    Hot& st = c.hot[s];
    return step_on<false>(c, st, st.last_start, st.last_leave, st.last_free, s, arrival, cost_at,
                          [&](uint64_t item) { report_stuck(item, static_cast<int>(s)); });
  }
  // step() with stage s's state in `st` (hot_[s], or issue_run's copy) and the last item's
  // start, leave and lane-free cycles in the last three (st's own, or issue_run's locals);
  // `stuck(item)` throws. kOneLane: the stage has one lane (free at last_free).
  template <bool kOneLane, class CostFn, class StuckFn>
  [[gnu::always_inline]] uint64_t step_on(const ItemCtx& c, Hot& st, uint64_t& last_start_at,
                                          uint64_t& last_leave_at, uint64_t& last_free_at, size_t s,
                                          uint64_t arrival, CostFn&& cost_at, StuckFn&& stuck) {
    const uint64_t iw = c.iw, mask = c.mask_w;
    uint64_t* const e = c.ring + s * c.stage_w;
    // Everything this stage needs is read before the first store (ring and counters are all
    // uint64_t, so a store would make the compiler reload them).
    uint64_t free_at;
    if constexpr (kOneLane) {
      free_at = last_free_at;
    } else {
      free_at = e[((iw - st.lanes_w) & mask) + kLaneFree];
    }
    // The item i − inflight_cap must have left before this one can enter.
    const uint64_t* const old = e + ((iw - st.cap_w) & mask);
    const uint64_t slot_free = old[kLeave], slot_finish = old[kFinish];
    // Back-pressure: item i − depth must have left the next stage's input FIFO.
    const uint64_t next_start = e[c.stage_w + ((iw - st.depth_w) & mask) + kStart];
    const uint64_t last_start = last_start_at, last_leave = last_leave_at;
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
    uint64_t* const me = e + (iw & mask);
    const uint64_t lane_free = start + st.ii + cost.extra_ii;
    me[kLaneFree] = lane_free;
    if (leave - arrival > c.watchdog) stuck(iw / kEntry);
    me[kStart] = start;
    me[kLeave] = leave;
    me[kFinish] = finish;
    last_leave_at = leave;
    last_start_at = start;
    last_free_at = lane_free;
    st.starved += avail - free_at;  // start >= arrival: a starved lane waited until arrival
    st.extra += cost.extra_ii;
    return leave;
  }
  // issue_run's loop; kOneLane: every stage has one lane, so an item's lane is free when the
  // previous item's issue slot ends (Hot::last_free), read from a local, not the ring.
  template <int kStages, bool kOneLane, class CostFn>
  [[gnu::always_inline]] void run_items(size_t n, CostFn& cost_at) {
    // The chain from item to item (each stage's last start, leave and lane-free cycle) in
    // scalars the compiler keeps in registers; constants and counters in a copy of hot_.
    Hot h[kStages];
    uint64_t starts[kStages], leaves[kStages], frees[kStages];
    for (int s = 0; s < kStages; ++s) {
      h[s] = hot_[static_cast<size_t>(s)];
      starts[s] = h[s].last_start;
      leaves[s] = h[s].last_leave;
      frees[s] = h[s].last_free;
    }
    ItemCtx c = item_ctx();
    uint64_t cycles = cycles_;
    const auto save = [&](uint64_t item) __attribute__((always_inline)) {
      for (int s = 0; s < kStages; ++s) {
        Hot& to = hot_[static_cast<size_t>(s)];
        to = h[s];
        to.last_start = starts[s];
        to.last_leave = leaves[s];
        to.last_free = frees[s];
      }
      items_ = item;
      cycles_ = cycles;
    };
    for (size_t k = 0; k < n; ++k) {
      uint64_t arrival = 0;
      [&]<int... kStage>(std::integer_sequence<int, kStage...>) __attribute__((always_inline)) {
        ((arrival = step_on<kOneLane>(
              c, h[kStage], starts[kStage], leaves[kStage], frees[kStage],
              static_cast<size_t>(kStage), arrival,
              [&](int, uint64_t at) __attribute__((always_inline)) {
                return cost_at(k, std::integral_constant<int, kStage>{}, at);
              },
              [&](uint64_t item) __attribute__((always_inline)) {
                save(item);
                report_stuck(item, kStage);
              })),
         ...);
      }
      (std::make_integer_sequence<int, kStages>{});
      cycles = std::max(cycles, arrival);
      c.iw += kEntry;
    }
    save(c.iw / kEntry);
  }
  template <class CostFn, size_t... kStage>
  uint64_t issue_unrolled(uint64_t ready, CostFn& cost_at, std::index_sequence<kStage...>) {
    const ItemCtx c = item_ctx();
    uint64_t arrival = ready;
    ((arrival = step(c, kStage, arrival, cost_at)), ...);
    return retire(arrival);
  }
  // Stages kFirst + i, i in kI..., unrolled.
  template <int kFirst, class CostFn, int... kI>
  [[gnu::always_inline]] uint64_t steps_fixed(const ItemCtx& c, uint64_t arrival, CostFn& cost_at,
                                              std::integer_sequence<int, kI...>) {
    ((arrival = step(
          c, static_cast<size_t>(kFirst + kI), arrival,
          [&](int, uint64_t start) __attribute__((always_inline)) {
            return cost_at(std::integral_constant<int, kFirst + kI>{}, start);
          })),
     ...);
    return arrival;
  }
  uint64_t retire(uint64_t leave) {
    ++items_;
    cycles_ = std::max(cycles_, leave);
    return leave;
  }
  uint64_t items_of(size_t s) const;
  [[noreturn]] void report_stuck(uint64_t item, int stage);

  std::vector<Stage> stages_;
  std::vector<Hot> hot_;
  std::vector<uint64_t> ring_;  // kEntry words per entry, P entries per stage
  uint64_t ring_mask_ = 0;      // P − 1
  uint64_t items_ = 0;
  uint64_t cycles_ = 0;
  uint64_t watchdog_ = uint64_t{1} << 40;
  int stuck_stage_ = -1;  // stage that raised DeadlockError (its earlier stages took the item)
};

class DeadlockError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace texsim
