#include "blocks/texture/subtexel/vd_evaluator_common.h"

#include <cmath>

namespace texsim {

VdEvaluatorConfig VdEvaluatorConfig::from_toml(const ConfigReader& r) {
  r.reject_unknown({"lanes"});
  VdEvaluatorConfig c;
  c.lanes = static_cast<uint32_t>(r.get_int("lanes", c.lanes, 1, 64));
  return c;
}

TimingSpec vd_pipelined_timing(const TechTable& tech, const OpCounts& ops, const OpCounts& path,
                               uint32_t lanes) {
  TimingSpec t;
  t.latency = static_cast<uint32_t>(std::ceil(tech.path_latency(path)));
  t.ii = 1;
  t.lanes = lanes;
  t.area = tech.area_of(ops) * lanes;
  return t;
}

}  // namespace texsim
