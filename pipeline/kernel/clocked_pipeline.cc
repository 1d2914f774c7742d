#include "pipeline/kernel/clocked_pipeline.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace texsim {

ClockedPipeline::ClockedPipeline(std::vector<StageConfig> stages) {
  if (stages.empty()) throw std::invalid_argument("pipeline: no stages");
  uint64_t longest = 1;  // the longest history any ring must hold
  for (auto& cfg : stages) {
    const auto& t = cfg.timing;
    if (t.ii == 0 || t.lanes == 0 || cfg.fifo_depth == 0) {
      throw std::invalid_argument("pipeline stage '" + cfg.name +
                                  "': ii, lanes and fifo_depth must be >= 1 "
                                  "(a zero would deadlock the pipeline)");
    }
    Stage st;
    st.inflight_cap = cfg.max_inflight
                          ? cfg.max_inflight
                          : t.lanes * std::max<uint32_t>(1, (t.latency + t.ii - 1) / t.ii);
    Hot h;
    h.latency = t.latency;
    h.ii = t.ii;
    h.lanes = t.lanes;
    h.lanes_w = t.lanes * kEntry;
    h.cap_w = st.inflight_cap * kEntry;
    longest = std::max<uint64_t>({longest, t.lanes, cfg.fifo_depth, st.inflight_cap});
    st.cfg = std::move(cfg);
    stages_.push_back(std::move(st));
    hot_.push_back(h);
  }
  for (size_t s = 0; s + 1 < stages_.size(); ++s)
    hot_[s].depth_w = stages_[s + 1].cfg.fifo_depth * kEntry;
  const uint64_t p = std::bit_ceil(longest);
  ring_mask_ = p - 1;
  ring_.assign((stages_.size() + 1) * p * kEntry, 0);
}

uint64_t ClockedPipeline::items_of(size_t s) const {
  // Stages before the one that raised DeadlockError had taken the item already.
  return items_ + (stuck_stage_ >= 0 && s < static_cast<size_t>(stuck_stage_) ? 1 : 0);
}

const StageStats& ClockedPipeline::stats(int s) const {
  const size_t k = static_cast<size_t>(s);
  const Hot& h = hot_[k];
  StageStats& st = stages_[k].stats;
  st.items = items_of(k);
  st.busy = st.items * h.ii + h.extra;
  st.stall_starved = h.starved;
  st.stall_blocked = h.blocked;
  st.stall_full = h.full;
  st.stall_extra = h.extra;
  st.last_done = h.last_leave;
  return st;
}

uint64_t ClockedPipeline::issue_end(int s) const {
  const size_t k = static_cast<size_t>(s);
  const uint64_t issued = items_of(k), p = ring_mask_ + 1;
  uint64_t end = 0;
  // Each lane was last used by one of the last `lanes` items.
  for (uint64_t j = 1; j <= std::min<uint64_t>(issued, hot_[k].lanes); ++j)
    end = std::max(end, ring_[(k * p + ((issued - j) & ring_mask_)) * kEntry + kLaneFree]);
  return end;
}

void ClockedPipeline::report_stuck(uint64_t item, int stage) {
  stuck_stage_ = stage;
  std::ostringstream os;
  os << "pipeline stuck: item " << item << " waited more than " << watchdog_ << " cycles in stage '"
     << stages_[stage].cfg.name << "'\n";
  dump_state(os);
  throw DeadlockError(os.str());
}

uint64_t ClockedPipeline::run_end() const {
  uint64_t end = cycles_;
  for (int s = 0; s < stage_count(); ++s) end = std::max(end, issue_end(s));
  return end;
}

double ClockedPipeline::utilisation(int s) const {
  const auto& st = stats(s);
  const uint64_t end = run_end();
  if (end == 0) return 0.0;
  return static_cast<double>(st.busy) / (static_cast<double>(end) * stages_[s].cfg.timing.lanes);
}

void ClockedPipeline::dump_state(std::ostream& os) const {
  const uint64_t p = ring_mask_ + 1;
  for (size_t s = 0; s < stages_.size(); ++s) {
    const Stage& st = stages_[s];
    const Hot& h = hot_[s];
    const uint64_t done = items_of(s);
    os << "  stage '" << st.cfg.name << "': items " << done << ", last leave " << h.last_leave
       << ", lanes free at";
    // Lane l was last used by the latest item j < issued with j mod lanes = l (the stuck
    // stage had issued the stuck item).
    const uint64_t issued = done + (static_cast<int>(s) == stuck_stage_ ? 1 : 0);
    for (uint64_t l = 0; l < h.lanes; ++l) {
      uint64_t f = 0;
      if (issued > l) {
        const uint64_t j = issued - 1 - (issued - 1 - l) % h.lanes;
        f = ring_[(s * p + (j & ring_mask_)) * kEntry + kLaneFree];
      }
      os << " " << f;
    }
    os << ", fifo depth " << st.cfg.fifo_depth << ", in-flight cap " << st.inflight_cap << "\n";
  }
}

ClockedPipeline::ItemTimes ClockedPipeline::last_item(int s) const {
  const uint64_t p = ring_mask_ + 1;
  const uint64_t* e =
      ring_.data() + static_cast<uint64_t>(s) * p * kEntry + ((items_ - 1) & ring_mask_) * kEntry;
  return {e[kStart], e[kFinish], e[kLeave]};
}

}  // namespace texsim
