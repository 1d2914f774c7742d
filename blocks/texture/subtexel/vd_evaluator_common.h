#pragma once
// What the four V(d) evaluator blocks share: their configuration (only the lane count) and
// the timing of a fully pipelined datapath (docs/vd-evaluators.md).
#include <cstdint>

#include "blocks/base/config_reader.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"

namespace texsim {

struct VdEvaluatorConfig {
  uint32_t lanes = 1;  // parallel copies of the datapath
  // Keys: lanes.
  static VdEvaluatorConfig from_toml(const ConfigReader& r);
};

// One evaluation per cycle per lane; latency along `path`, area of `ops` per lane.
TimingSpec vd_pipelined_timing(const TechTable& tech, const OpCounts& ops, const OpCounts& path,
                               uint32_t lanes);

}  // namespace texsim
