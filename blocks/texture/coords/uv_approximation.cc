#include "blocks/texture/coords/uv_approximation.h"

#include "blocks/base/config_reader.h"

namespace texsim {

UvApproximation::Config UvApproximation::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"order", "segment", "datapath", "min_denominator"});
  Config c;
  c.order = static_cast<Order>(1 + r.get_choice("order", 1, {"affine", "quadratic", "cubic"}));
  c.segment = static_cast<int>(r.get_int("segment", c.segment, 0, 1 << 20));
  c.datapath = parse_datapath(r, c.datapath);
  c.min_denominator = r.get_double("min_denominator", c.min_denominator);
  if (!(c.min_denominator > 0)) r.fail("min_denominator", "must be > 0");
  return c;
}

OpCounts UvApproximation::pixel_ops() const {
  // One add per forward-difference order and coordinate.
  OpCounts o;
  o.add = 2 * static_cast<uint64_t>(cfg_.order);
  return o;
}

OpCounts UvApproximation::pixel_critical_path() const {
  OpCounts p;
  p.add = 1;  // the output register is updated by one adder per pixel
  return p;
}

OpCounts UvApproximation::row_setup_ops() const {
  const uint64_t pts = static_cast<uint64_t>(points());
  OpCounts o;
  // y-parts b·y + c of the three linear forms, then per sample point a·x + (b·y + c) for
  // three forms and two divisions.
  o.mul = 3 + 3 * pts;
  o.add = 3 + 3 * pts;
  o.div = 2 * pts;
  o.cmp = pts;
  o.rcp = 1;  // h = 1/(n-1)
  // Coefficients and difference table, per coordinate (u and v):
  constexpr uint64_t kCoords = 2;
  switch (cfg_.order) {
    case Order::Affine:
      o.add += kCoords * 1;
      o.mul += kCoords * 1;
      break;
    // A1 = 2u0-4u1+2u2 (shifts, 2 adds), A2 = -3u0+4u1-u2 (3 adds); A1·h, (A1h+A2)·h, 2A1h·h.
    case Order::Quadratic:
      o.add += kCoords * (5 + 1);
      o.mul += kCoords * 3;
      break;
    // c3, c2, c1: 4 constant products and 3 adds each; then 8 products and 4 adds.
    case Order::Cubic:
      o.add += kCoords * (9 + 4);
      o.mul += kCoords * (12 + 8);
      break;
  }
  return o;
}

OpCounts UvApproximation::row_setup_critical_path() const {
  // linear form -> divide -> coefficient sum -> difference-table products.
  OpCounts p;
  p.mul = 1;
  p.add = 1;
  p.div = 1;
  switch (cfg_.order) {
    case Order::Affine:
      p.add += 1;
      p.mul += 1;
      break;
    case Order::Quadratic:
      p.add += 3;
      p.mul += 3;
      break;
    case Order::Cubic:
      p.add += 4;
      p.mul += 4;
      break;
  }
  return p;
}

TimingSpec UvApproximation::timing(const TechTable& t) const {
  return derive_timing(t, pixel_ops(), pixel_critical_path(), cfg_.datapath, 1, row_setup_ops());
}

TimingSpec UvApproximation::row_setup_timing(const TechTable& t) const {
  TimingSpec s = derive_timing(t, row_setup_ops(), row_setup_critical_path(), cfg_.datapath);
  s.area = 0;
  return s;
}

}  // namespace texsim
