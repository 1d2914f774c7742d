#include "blocks/texture/footprint/gaussian_weight.h"

#include <cmath>

#include "blocks/base/block.h"

namespace texsim {

static_assert(Block<GaussianWeight>);

namespace {

// Per texel, q = (a·U + b·V)·U + c·V·V: aU and bV side by side, add, ×U; cV, ×V beside them;
// the final add.
OpCounts q_ops() {
  OpCounts o;
  o.mul = 5;
  o.add = 2;
  return o;
}
OpCounts q_path() {
  OpCounts o;
  o.mul = 2;
  o.add = 2;
  return o;
}

// exp(−q/2): range check (q < 0 → 0), scale by −log2(e)/2, exp2 table.
// Power 8: range select (q ≥ 16 → 0, q < 0 → 0), t = 1 − q/16 (the /16 is wiring),
// three squarings.
OpCounts function_ops(GaussianWeightFunction f) {
  OpCounts o;
  if (f == GaussianWeightFunction::Exp) {
    o.cmp = 1;
    o.mul = 1;
    o.lut = 1;
  } else {
    o.cmp = 2;
    o.add = 1;
    o.mul = 3;
  }
  return o;
}
OpCounts function_path(GaussianWeightFunction f) {
  OpCounts o = function_ops(f);
  if (f == GaussianWeightFunction::Pow8) o.cmp = 1;  // both range tests side by side
  return o;
}

// Set-up path through the longest chain of each rule (see setup_ops for the totals).
OpCounts setup_path(GaussianAxes a) {
  OpCounts o;
  o.cmp = 1;  // degenerate select at the end
  switch (a) {
    case GaussianAxes::QuadraticForm:  // det: mul, add; F = det²: mul; 1/F: rcp; ×: mul
      o.mul = 3;
      o.add = 1;
      o.rcp = 1;
      break;
    case GaussianAxes::SeedAxes:  // L²: mul, add; √; 1/L; cos: mul; cos²: mul; ×1/L²: mul; +
      o.mul = 4;
      o.add = 2;
      o.sqrt = 1;
      o.rcp = 1;
      break;
    case GaussianAxes::SeedLiteral:  // C: mul, add; √; Ux/√C: div; cos²: mul; ×1/C: mul; +
      o.mul = 3;
      o.add = 2;
      o.sqrt = 1;
      o.div = 1;
      break;
  }
  return o;
}

}  // namespace

GaussianWeight::Config GaussianWeight::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"function", "axes", "lanes"});
  Config c;
  c.function = static_cast<GaussianWeightFunction>(
      r.get_choice("function", static_cast<int>(c.function), {"exp", "pow8"}));
  c.axes = static_cast<GaussianAxes>(r.get_choice("axes", static_cast<int>(c.axes),
                                                  {"quadratic_form", "seed_axes", "seed_literal"}));
  c.lanes = static_cast<uint32_t>(r.get_int("lanes", c.lanes, 1, 64));
  return c;
}

OpCounts GaussianWeight::setup_ops() const {
  OpCounts o;
  o.cmp = 1;  // degenerate footprint test
  switch (cfg_.axes) {
    case GaussianAxes::QuadraticForm:
      // A, C: 4 mul, 2 add; Ux·Vx + Uy·Vy: 2 mul, 1 add (×−2 is a shift); det: 2 mul, 1 add;
      // F = det²: 1 mul; 1/F: rcp; A/F, B/F, C/F: 3 mul.
      o.mul = 4 + 2 + 2 + 1 + 3;
      o.add = 2 + 1 + 1;
      o.rcp = 1;
      break;
    case GaussianAxes::SeedAxes:
      // L², d²: 4 mul, 2 add; 1/L = rcp(√L²); cos, sin: 2 mul; 1/L² = (1/L)²: 1 mul;
      // 1/d²: rcp; expansion (cos², sin², cos·sin, four products, 2·cs·(…)): 8 mul, 3 add.
      o.mul = 4 + 2 + 1 + 8;
      o.add = 2 + 3;
      o.sqrt = 1;
      o.rcp = 2;
      break;
    case GaussianAxes::SeedLiteral:
      // A, C: 4 mul, 2 add; L = √C, d = √A; cos = Ux/L, sin = Vy/d: 2 div; 1/C, 1/A: 2 rcp;
      // expansion: 8 mul, 3 add.
      o.mul = 4 + 8;
      o.add = 2 + 3;
      o.sqrt = 2;
      o.div = 2;
      o.rcp = 2;
      break;
  }
  return o;
}

OpCounts GaussianWeight::ops_per_item() const { return q_ops() + function_ops(cfg_.function); }

OpCounts GaussianWeight::texel_critical_path() const {
  return q_path() + function_path(cfg_.function);
}

TimingSpec GaussianWeight::timing(const TechTable& tech) const {
  return derive_timing(tech, ops_per_item(), texel_critical_path(), Datapath::Spatial, cfg_.lanes);
}

TimingSpec GaussianWeight::setup_timing(const TechTable& tech) const {
  return derive_timing(tech, setup_ops(), setup_path(cfg_.axes), Datapath::Spatial);
}

}  // namespace texsim
