#include "blocks/texture/subtexel/vd_evaluator_common.h"

#include "blocks/base/derive_timing.h"

namespace texsim {

VdEvaluatorConfig VdEvaluatorConfig::from_toml(const ConfigReader& r) {
  r.reject_unknown({"lanes"});
  VdEvaluatorConfig c;
  c.lanes = static_cast<uint32_t>(r.get_int("lanes", c.lanes, 1, 64));
  return c;
}

TimingSpec vd_pipelined_timing(const TechTable& tech, const OpCounts& ops, const OpCounts& path,
                               uint32_t lanes) {
  return derive_timing(tech, ops, path, Datapath::Spatial, lanes);
}

std::string vd_evaluator_report_name(VdEvaluatorKind k) {
  std::string ev(vd_evaluator_name(k));
  if (ev.size() == 2 && ev[0] == 'p') ev[0] = 'P';  // P3, P2, P1 as the thesis writes them
  return "V(d) " + ev;
}

}  // namespace texsim
