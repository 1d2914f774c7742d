#include "blocks/texture/derivs/derivatives_quad.h"

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<DerivativesQuad>);

DerivativesQuad::Config DerivativesQuad::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"datapath", "min_denominator"});
  Config c;
  c.datapath = parse_datapath(r, c.datapath);
  c.min_denominator = r.get_double("min_denominator", c.min_denominator);
  if (!(c.min_denominator > 0)) r.fail("min_denominator", "must be > 0");
  return c;
}

OpCounts DerivativesQuad::ops_per_item() const {
  OpCounts o;
  o.add = 1;
  return o;
}

OpCounts DerivativesQuad::pixel_critical_path() const {
  OpCounts p;
  p.add = 1;
  return p;
}

TimingSpec DerivativesQuad::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), pixel_critical_path(), cfg_.datapath);
}

}  // namespace texsim
