#include "blocks/texture/derivs/derivatives_analytic.h"

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<DerivativesAnalytic>);

DerivativesAnalytic::Config DerivativesAnalytic::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"datapath", "min_denominator"});
  Config c;
  c.datapath = parse_datapath(r, c.datapath);
  c.min_denominator = r.get_double("min_denominator", c.min_denominator);
  if (!(c.min_denominator > 0)) r.fail("min_denominator", "must be > 0");
  return c;
}

OpCounts DerivativesAnalytic::ops_per_item() const {
  // r = 1/q; u = w·r, v = t·r; g·u, g·v, h·u, h·v; four subtractions; four products with r.
  OpCounts o;
  o.rcp = 1;
  o.mul = 2 + 4 + 4;
  o.add = 4;
  o.cmp = 1;
  return o;
}

OpCounts DerivativesAnalytic::pixel_critical_path() const {
  OpCounts p;
  p.rcp = 1;
  p.mul = 3;  // u = w·r, g·u, ·r
  p.add = 1;
  return p;
}

TimingSpec DerivativesAnalytic::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), pixel_critical_path(), cfg_.datapath);
}

}  // namespace texsim
