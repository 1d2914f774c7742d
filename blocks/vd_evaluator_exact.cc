#include "blocks/vd_evaluator_exact.h"

#include <cmath>

namespace texsim {

VdEvaluatorExact::Config VdEvaluatorExact::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"lanes"});
  Config c;
  c.lanes = static_cast<uint32_t>(r.get_int("lanes", c.lanes, 1, 64));
  return c;
}

TimingSpec VdEvaluatorExact::timing(const TechTable& tech) const {
  TimingSpec t;
  t.latency = static_cast<uint32_t>(std::ceil(tech.path_latency(critical_path())));
  t.ii = 1;
  t.lanes = cfg_.lanes;
  t.area = tech.area_of(ops()) * cfg_.lanes;
  return t;
}

}  // namespace texsim
