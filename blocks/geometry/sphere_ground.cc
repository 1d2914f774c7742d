#include "blocks/geometry/sphere_ground.h"

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<SphereGround>);

SphereGround::Config SphereGround::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"radius", "form", "max_iterations", "tolerance", "datapath"});
  Config c;
  c.radius = r.get_double("radius", c.radius);
  c.form = static_cast<Form>(r.get_choice("form", 0, {"stable", "textbook", "seed_iteration"}));
  c.max_iterations =
      static_cast<int32_t>(r.get_int("max_iterations", c.max_iterations, 1, 1 << 20));
  c.tolerance = r.get_double("tolerance", c.tolerance);
  c.datapath = parse_datapath(r, c.datapath);
  if (!(c.radius > 0 && c.radius <= 1e12)) r.fail("radius", "must be in (0, 1e12]");
  if (!(c.tolerance >= 0 && c.tolerance < 1)) r.fail("tolerance", "must be in [0, 1)");
  return c;
}

OpCounts SphereGround::ops_per_item() const {
  OpCounts o;
  if (cfg_.form == Form::SeedIteration) {
    // P = r_h + λV; ρ²; q_y and |q|; dc = R·ρ²/(|q|(|q| + q_y)); λ = (Y_h + dc)/-V_y; the test.
    o.mul = 3 + 2 + 1 + 3 + 1;
    o.add = 3 + 1 + 1 + 1 + 1 + 1 + 1;
    o.sqrt = 1;
    o.div = 1;
    o.cmp = 1;
    return o;
  }
  // a = V·V, b = o·V, b² - a·c, √, the near root (c is per frame), the three tests.
  o.mul = 3 + 3 + 2;
  o.add = 2 + 2 + 1 + 1;
  o.sqrt = 1;
  o.div = 1;
  o.cmp = 3;
  return o;
}

OpCounts SphereGround::critical_path() const {
  OpCounts p;
  if (cfg_.form == Form::SeedIteration) {  // one iteration: P, ρ², |q|, dc, λ
    p.mul = 5;
    p.add = 5;
    p.sqrt = 1;
    p.div = 1;
    return p;
  }
  p.mul = 2;  // o·V products, b²
  p.add = 4;  // o·V sums, the discriminant, the root's sum
  p.sqrt = 1;
  p.div = 1;
  return p;
}

OpCounts SphereGround::setup_ops() const {
  OpCounts o;
  switch (cfg_.form) {
    // Stable: o_y = Y_h + R; c = X_h² + Z_h² + Y_h(Y_h + 2R). Textbook: o_y;
    // c = X_h² + o_y² + Z_h² - R². The same counts.
    case Form::Stable:
    case Form::Textbook:
      o.mul = 3;
      o.add = 1 + 3;
      o.cmp = 1;
      break;
    case Form::SeedIteration:  // per ray: 1/-V_y, λ₀ = Y_h/-V_y; the tests, |q| = R at the end
      o.rcp = 1;
      o.mul = 1 + 1;
      o.add = 1;
      o.cmp = 2 + 2;
      break;
  }
  return o;
}

TimingSpec SphereGround::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), critical_path(), cfg_.datapath, 1, setup_ops());
}

}  // namespace texsim
