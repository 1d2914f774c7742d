#include "blocks/vd_evaluator_p1.h"

#include <cmath>

namespace texsim {

VdEvaluatorP1::Config VdEvaluatorP1::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"lanes"});
  Config c;
  c.lanes = static_cast<uint32_t>(r.get_int("lanes", c.lanes, 1, 64));
  return c;
}

TimingSpec VdEvaluatorP1::timing(const TechTable& tech) const {
  TimingSpec t;
  t.latency = static_cast<uint32_t>(std::ceil(tech.path_latency(critical_path())));
  t.ii = 1;
  t.lanes = cfg_.lanes;
  t.area = tech.area_of(ops()) * cfg_.lanes;
  return t;
}

}  // namespace texsim
