#pragma once
// Timing of one hardware block as the clocked pipeline sees it (docs/timing-model.md).
#include <cstdint>

namespace texsim {

struct TimingSpec {
  uint32_t latency = 1;  // cycles from accepting an item to its result
  uint32_t ii = 1;       // initiation interval: cycles between accepted items (per lane)
  uint32_t lanes = 1;    // parallel copies of the datapath
  double area = 0.0;     // adder-equivalents (from the technology table)
};

}  // namespace texsim
