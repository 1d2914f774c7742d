#pragma once
// What the four V(d) evaluator blocks share: their configuration (only the lane count) and
// the timing of a fully pipelined datapath (docs/derivations/vd-evaluators.md).
#include <cstdint>
#include <string>

#include "blocks/base/config_reader.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/subtexel/vd_evaluator_params.h"

namespace texsim {

struct VdEvaluatorConfig {
  uint32_t lanes = 1;  // parallel copies of the datapath
  // Keys: lanes.
  static VdEvaluatorConfig from_toml(const ConfigReader& r);
};

// Report name of an evaluator block, e.g. "V(d) P2".
std::string vd_evaluator_report_name(VdEvaluatorKind k);

// One evaluation per cycle per lane; latency along `path`, area of `ops` per lane
// (derive_timing with a spatial datapath).
TimingSpec vd_pipelined_timing(const TechTable& tech, const OpCounts& ops, const OpCounts& path,
                               uint32_t lanes);

}  // namespace texsim
