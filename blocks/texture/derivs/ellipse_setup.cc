#include "blocks/texture/derivs/ellipse_setup.h"

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<EllipseSetup>);

EllipseL ellipse_reference(const DerivsL& d) {
  EllipseL e;
  e.a = d.vx * d.vx + d.vy * d.vy;
  e.b = -2 * (d.ux * d.vx + d.uy * d.vy);
  e.c = d.ux * d.ux + d.uy * d.uy;
  const long double j = d.ux * d.vy - d.uy * d.vx;
  e.f = j * j;
  return e;
}

EllipseSetup::Config EllipseSetup::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"f_form", "normalise", "datapath", "seed_misprints"});
  Config c;
  c.f_form = static_cast<FForm>(r.get_choice("f_form", 0, {"determinant", "ac_minus_b2"}));
  c.normalise = r.get_bool("normalise", c.normalise);
  c.datapath = parse_datapath(r, c.datapath);
  c.seed_misprints = r.get_bool("seed_misprints", c.seed_misprints);
  return c;
}

OpCounts EllipseSetup::ops_per_item() const {
  // A, B, C: two squares/products and one add each (×-2 is a shift); F: a 2×2 determinant and
  // its square, or AC, B² and one subtraction (/4 is a shift); the F > 0 check.
  OpCounts o;
  o.mul = 6 + 3;
  o.add = 3 + 1;
  o.cmp = 1;
  if (cfg_.f_form == FForm::AcMinusB2) o.mul -= 1;
  if (cfg_.normalise) {
    o.rcp = 1;
    o.mul += 3;
  }
  return o;
}

OpCounts EllipseSetup::pixel_critical_path() const {
  OpCounts p;
  // Determinant: product -> difference -> square; AC - B²/4: square -> sum -> AC -> difference.
  p.mul = 2;
  p.add = cfg_.f_form == FForm::Determinant ? 1 : 2;
  if (cfg_.normalise) {
    p.rcp = 1;
    p.mul += 1;
  }
  return p;
}

TimingSpec EllipseSetup::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), pixel_critical_path(), cfg_.datapath);
}

}  // namespace texsim
