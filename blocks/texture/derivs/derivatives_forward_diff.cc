#include "blocks/texture/derivs/derivatives_forward_diff.h"

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<DerivativesForwardDiff>);

DerivativesForwardDiff::Config DerivativesForwardDiff::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"form", "datapath", "min_denominator"});
  Config c;
  c.form = static_cast<Form>(r.get_choice("form", 0, {"classic", "accelerated"}));
  c.datapath = parse_datapath(r, c.datapath);
  c.min_denominator = r.get_double("min_denominator", c.min_denominator);
  if (!(c.min_denominator > 0)) r.fail("min_denominator", "must be > 0");
  return c;
}

OpCounts DerivativesForwardDiff::ops_per_item() const {
  OpCounts o;
  if (cfg_.form == Form::Classic) {
    // Two neighbours × three linear forms (2 mul + 2 add) + the x+1 / y+1 adds.
    o.mul = 12;
    o.add = 12 + 2;
  } else {
    o.add = 6;  // w+A, t+D, q+G, w+B, t+E, q+H
  }
  o.div = 4;   // the neighbours' u, v
  o.add += 4;  // minus the pixel's own u, v
  o.cmp = 2;
  return o;
}

OpCounts DerivativesForwardDiff::pixel_critical_path() const {
  OpCounts p;
  if (cfg_.form == Form::Classic) {
    p.add = 1 + 2;
    p.mul = 1;
  } else {
    p.add = 1;
  }
  p.div = 1;
  p.add += 1;
  return p;
}

TimingSpec DerivativesForwardDiff::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), pixel_critical_path(), cfg_.datapath);
}

}  // namespace texsim
