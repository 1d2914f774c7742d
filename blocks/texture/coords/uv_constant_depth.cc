#include "blocks/texture/coords/uv_constant_depth.h"

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<UvConstantDepth>);

UvConstantDepth::Config UvConstantDepth::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"axis", "datapath", "min_denominator"});
  Config c;
  c.axis = static_cast<Axis>(r.get_choice("axis", 0, {"auto", "x", "y"}));
  c.datapath = parse_datapath(r, c.datapath);
  c.min_denominator = r.get_double("min_denominator", c.min_denominator);
  if (!(c.min_denominator > 0)) r.fail("min_denominator", "must be > 0");
  return c;
}

bool UvConstantDepth::x_major(const ProjectiveMap& m) const {
  if (cfg_.axis != Axis::Auto) return cfg_.axis == Axis::X;
  return !(std::fabs(m.G) > std::fabs(m.H));
}

long double UvConstantDepth::slope(const ProjectiveMap& m) const {
  const bool xm = x_major(m);
  const long double num = xm ? m.G : m.H, den = xm ? m.H : m.G;
  return den == 0 ? 0.0L : -num / den;
}

OpCounts UvConstantDepth::ops_per_item() const {
  OpCounts o;
  o.add = 2;  // u += R·ak, v += R·dk
  return o;
}

OpCounts UvConstantDepth::pixel_critical_path() const {
  OpCounts p;
  p.add = 1;
  return p;
}

OpCounts UvConstantDepth::row_setup_ops() const {
  // minor = k·s0 + h; q = H·h + I; R = 1/q (+ limit compare); the two numerators at the line
  // start (2 mul + 2 add each); u, v, du, dv = products with R.
  OpCounts o;
  o.mul = 1 + 1 + 4 + 4;
  o.add = 1 + 1 + 4;
  o.rcp = 1;
  o.cmp = 1;
  return o;
}

OpCounts UvConstantDepth::row_setup_critical_path() const {
  // (q: mul, add) -> rcp -> mul, in parallel with the numerators (mul, add, mul, 2 add).
  OpCounts p;
  p.mul = 2;
  p.add = 1;
  p.rcp = 1;
  return p;
}

OpCounts UvConstantDepth::triangle_setup_ops() const {
  // |G| vs |H|, k = -G/H, ak = A + B·k, dk = D + E·k.
  OpCounts o;
  o.cmp = 1;
  o.div = 1;
  o.mul = 2;
  o.add = 2;
  return o;
}

TimingSpec UvConstantDepth::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), pixel_critical_path(), cfg_.datapath, 1,
                       row_setup_ops() + triangle_setup_ops());
}

TimingSpec UvConstantDepth::row_setup_timing(const TechTable& t) const {
  TimingSpec s = derive_timing(t, row_setup_ops(), row_setup_critical_path(), cfg_.datapath);
  s.area = 0;
  return s;
}

TimingSpec UvConstantDepth::triangle_setup_timing(const TechTable& t) const {
  OpCounts path;
  path.cmp = 1;
  path.div = 1;
  path.mul = 1;
  path.add = 1;
  TimingSpec s = derive_timing(t, triangle_setup_ops(), path, cfg_.datapath);
  s.area = 0;
  return s;
}

}  // namespace texsim
