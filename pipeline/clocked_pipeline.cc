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
    st.finishes.assign(st.inflight_cap, 0);
    stages_.push_back(std::move(st));
  }
}

void ClockedPipeline::report_stuck(uint64_t item, int stage) const {
  std::ostringstream os;
  os << "pipeline stuck: item " << item << " waited more than " << watchdog_
     << " cycles in stage '" << stages_[stage].cfg.name << "'\n";
  dump_state(os);
  throw DeadlockError(os.str());
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
