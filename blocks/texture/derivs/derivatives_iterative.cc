#include "blocks/texture/derivs/derivatives_iterative.h"

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<DerivativesIterative>);

DerivativesIterative::Config DerivativesIterative::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"datapath", "min_denominator", "seed_misprints"});
  Config c;
  c.datapath = parse_datapath(r, c.datapath);
  c.min_denominator = r.get_double("min_denominator", c.min_denominator);
  if (!(c.min_denominator > 0)) r.fail("min_denominator", "must be > 0");
  c.seed_misprints = r.get_bool("seed_misprints", c.seed_misprints);
  return c;
}

OpCounts DerivativesIterative::ops_per_item() const {
  // d2x = d1 + G, d2y = d1 + H; two products and two reciprocals; four numerator products;
  // steps num_uy += ·, num_vy += ·, d1 += G (d1 is the coordinate block's q: shared in a
  // combined datapath, counted here so the block stands alone).
  OpCounts o;
  o.add = 2 + 3;
  o.mul = 2 + 4;
  o.rcp = 2;
  o.cmp = 1;
  return o;
}

OpCounts DerivativesIterative::pixel_critical_path() const {
  OpCounts p;
  p.add = 1;
  p.mul = 2;
  p.rcp = 1;
  return p;
}

OpCounts DerivativesIterative::row_setup_ops() const {
  // num_ux, num_vx, num_uy, num_vy, K = I + H·y, d1 = K + G·x0.
  OpCounts o;
  o.mul = 6;
  o.add = 6;
  return o;
}

OpCounts DerivativesIterative::row_setup_critical_path() const {
  OpCounts p;
  p.mul = 1;
  p.add = 2;
  return p;
}

OpCounts DerivativesIterative::triangle_setup_ops() const {
  OpCounts o;
  o.mul = 16;  // eight 2×2 cross terms
  o.add = 8;
  return o;
}

TimingSpec DerivativesIterative::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), pixel_critical_path(), cfg_.datapath, 1,
                       row_setup_ops() + triangle_setup_ops());
}

TimingSpec DerivativesIterative::row_setup_timing(const TechTable& t) const {
  TimingSpec s = derive_timing(t, row_setup_ops(), row_setup_critical_path(), cfg_.datapath);
  s.area = 0;
  return s;
}

TimingSpec DerivativesIterative::triangle_setup_timing(const TechTable& t) const {
  OpCounts p;
  p.mul = 1;
  p.add = 1;
  TimingSpec s = derive_timing(t, triangle_setup_ops(), p, cfg_.datapath);
  s.area = 0;
  return s;
}

}  // namespace texsim
