#include "pipeline/texture/stages/unit_stage.h"

#include <algorithm>

namespace texsim {

void SlotPlan::occupy(Slot s, uint32_t latency, uint32_t lanes) {
  const int k = static_cast<int>(s);
  present_[k] = true;
  timing_[k].latency = std::max(timing_[k].latency, latency);
  timing_[k].lanes = std::max(timing_[k].lanes, lanes);
}

void SlotPlan::set(Slot s, const TimingSpec& t, uint32_t max_inflight) {
  const int k = static_cast<int>(s);
  present_[k] = true;
  timing_[k] = t;
  inflight_[k] = max_inflight;
}

void SlotPlan::finish() {
  int next = 0;
  for (int k = 0; k < kSlots; ++k) index_[k] = present_[k] ? next++ : -1;
}

std::vector<StageConfig> SlotPlan::stages() const {
  static const char* const names[kSlots] = {"coords",  "derivs", "relief", "lod",
                                            "address", "cache",  "blend",  "lighting"};
  std::vector<StageConfig> out;
  for (int k = 0; k < kSlots; ++k) {
    if (present_[k]) out.push_back({names[k], timing_[k], fifo_depth_, inflight_[k]});
  }
  return out;
}

}  // namespace texsim
