#include "pipeline/clocked_pipeline.h"

#include <algorithm>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace texsim {

ClockedPipeline::ClockedPipeline(std::vector<StageConfig> stages) {
  if (stages.empty()) throw std::invalid_argument("pipeline: no stages");
  for (auto& cfg : stages) {
    const auto& t = cfg.timing;
    if (t.ii == 0 || t.lanes == 0 || cfg.fifo_depth == 0) {
      throw std::invalid_argument("pipeline stage '" + cfg.name +
                                  "': ii, lanes and fifo_depth must be >= 1 "
                                  "(a zero would deadlock the pipeline)");
    }
    Stage st;
    st.inflight_cap = cfg.max_inflight ? cfg.max_inflight
                                       : t.lanes * std::max<uint32_t>(1, (t.latency + t.ii - 1) / t.ii);
    st.cfg = std::move(cfg);
    st.lane_free.assign(st.cfg.timing.lanes, 0);
    st.starts.assign(st.cfg.fifo_depth, 0);
    st.leaves.assign(st.inflight_cap, 0);
    stages_.push_back(std::move(st));
  }
}

uint64_t ClockedPipeline::issue(uint64_t ready, const ItemCost* costs) {
  const uint64_t i = items_;
  uint64_t arrival = ready;
  const size_t n = stages_.size();
  for (size_t s = 0; s < n; ++s) {
    Stage& st = stages_[s];
    const TimingSpec& t = st.cfg.timing;
    const ItemCost cost = costs ? costs[s] : ItemCost{};
    uint64_t& lane_free = st.lane_free[t.lanes == 1 ? 0 : i % t.lanes];
    const uint32_t slot = static_cast<uint32_t>(i % st.inflight_cap);
    // The item i - inflight_cap must have left before this one can enter.
    const uint64_t slot_free = i >= st.inflight_cap ? st.leaves[slot] : 0;
    // Items issue in order from the FIFO head, so never before the previous item issued.
    const uint64_t start = std::max({arrival, lane_free, slot_free, st.last_start});
    if (arrival > std::max(lane_free, slot_free)) {
      st.stats.stall_starved += arrival - std::max(lane_free, slot_free);
    } else if (slot_free > std::max(lane_free, arrival)) {
      st.stats.stall_full += slot_free - std::max(lane_free, arrival);
    }
    const uint64_t ii = uint64_t{t.ii} + cost.extra_ii;
    lane_free = start + ii;
    st.stats.busy += ii;
    st.stats.stall_extra += cost.extra_ii;
    const uint64_t finish = start + t.latency + cost.extra_latency;
    uint64_t leave = std::max(finish, st.last_leave);  // results retire in order
    if (s + 1 < n) {
      // Back-pressure: item i - depth must have left the next stage's input FIFO.
      const Stage& next = stages_[s + 1];
      const uint32_t depth = next.cfg.fifo_depth;
      if (i >= depth) leave = std::max(leave, next.starts[i % depth]);
    }
    st.stats.stall_blocked += leave - finish;
    if (leave - arrival > watchdog_) {
      std::ostringstream os;
      os << "pipeline stuck: item " << i << " waited more than " << watchdog_
         << " cycles in stage '" << st.cfg.name << "'\n";
      dump_state(os);
      throw DeadlockError(os.str());
    }
    st.starts[i % st.cfg.fifo_depth] = start;
    st.leaves[slot] = leave;
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

double ClockedPipeline::utilisation(int s) const {
  const auto& st = stages_[s];
  if (cycles_ == 0) return 0.0;
  return static_cast<double>(st.stats.busy) /
         (static_cast<double>(cycles_) * st.cfg.timing.lanes);
}

void ClockedPipeline::dump_state(std::ostream& os) const {
  for (const auto& st : stages_) {
    const uint64_t done = st.stats.items;
    os << "  stage '" << st.cfg.name << "': items " << done << ", last leave " << st.last_leave
       << ", lanes free at";
    for (auto f : st.lane_free) os << " " << f;
    os << ", fifo depth " << st.cfg.fifo_depth << ", in-flight cap " << st.inflight_cap << "\n";
  }
}

}  // namespace texsim
