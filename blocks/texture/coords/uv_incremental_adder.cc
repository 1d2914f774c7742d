#include "blocks/texture/coords/uv_incremental_adder.h"

#include <cmath>
#include <limits>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/texture/coords/error_bounds.h"

namespace texsim {

static_assert(Block<UvIncrementalAdder>);

UvIncrementalAdder::Config UvIncrementalAdder::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"form", "lanes", "division", "datapath", "min_denominator"});
  Config c;
  c.form = static_cast<Form>(
      r.get_choice("form", 0, {"sequential", "klane", "bidirectional", "direct"}));
  c.lanes = static_cast<int>(r.get_int("lanes", c.lanes, 1, 64));
  c.division = static_cast<Division>(r.get_choice("division", 0, {"divide", "reciprocal"}));
  c.datapath = parse_datapath(r, c.datapath);
  c.min_denominator = r.get_double("min_denominator", c.min_denominator);
  if (!(c.min_denominator > 0)) r.fail("min_denominator", "must be > 0");
  return c;
}

uint32_t UvIncrementalAdder::lane_count() const {
  switch (cfg_.form) {
    case Form::Sequential:
      return 1;
    case Form::KLane:
    case Form::DirectN:
      return static_cast<uint32_t>(std::max(1, cfg_.lanes));
    case Form::Bidirectional:
      return 2;
  }
  return 1;
}

OpCounts UvIncrementalAdder::ops_per_item() const {
  // w += A, z += G, t += D (direct-n: w0 + A·n, z0 + G·n, t0 + D·n, 3 mul more); the
  // q >= limit compare; the division pair.
  OpCounts o;
  o.add = 3;
  if (cfg_.form == Form::DirectN) o.mul = 3;
  o.cmp = 1;
  if (cfg_.division == Division::Divide) {
    o.div = 2;
  } else {
    o.rcp = 1;
    o.mul += 2;
  }
  return o;
}

OpCounts UvIncrementalAdder::pixel_critical_path() const {
  // The adders feed the next pixel; the current pixel's path is the division (or rcp -> mul).
  // Direct-n: the pixel's own A·n and w0 + A·n come first.
  OpCounts p;
  if (cfg_.form == Form::DirectN) {
    p.mul = 1;
    p.add = 1;
  }
  if (cfg_.division == Division::Divide) {
    p.div = 1;
  } else {
    p.rcp = 1;
    p.mul += 1;
  }
  return p;
}

OpCounts UvIncrementalAdder::row_setup_ops() const {
  // w0, z0, t0 = a·x0 + b·y + c: 6 mul + 6 add.
  OpCounts o;
  o.mul = 6;
  o.add = 6;
  if (cfg_.form == Form::KLane) {
    const uint64_t k = lane_count();
    o.mul += 3;            // k·A, k·G, k·D
    o.add += 3 * (k - 1);  // lane start values w_j = w_{j-1} + A, j < k
  } else if (cfg_.form == Form::Bidirectional) {
    o.mul += 6;  // the right lane's start values at x0 + n - 1
    o.add += 6;
  }
  return o;
}

OpCounts UvIncrementalAdder::row_setup_critical_path() const {
  OpCounts p;
  p.mul = 1;
  p.add = 2;
  if (cfg_.form == Form::KLane) p.add += lane_count() - 1;
  return p;
}

TimingSpec UvIncrementalAdder::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), pixel_critical_path(), cfg_.datapath, lane_count(),
                       row_setup_ops());
}

TimingSpec UvIncrementalAdder::row_setup_timing(const TechTable& t) const {
  TimingSpec s = derive_timing(t, row_setup_ops(), row_setup_critical_path(), cfg_.datapath);
  s.area = 0;  // counted in timing().area
  return s;
}

void UvIncrementalAdder::lane_history(const RowSpan& s, int32_t n, double& roundings,
                                      double& increments, int32_t& x_start) const {
  x_start = s.x0;
  increments = n;
  roundings = n;
  if (cfg_.form == Form::KLane) {
    const int32_t k = std::max(1, cfg_.lanes);
    const int32_t j = n % k;
    const int32_t steps = (n - j) / k;  // lane j's k-steps before pixel n (exact: n - j = steps·k)
    roundings = j + steps;
  } else if (cfg_.form == Form::DirectN) {
    roundings = n > 0 ? 1 : 0;  // one rounded sum w0 + A·n (the product's rounding is
                                // within the bound's factor 2 on the increments)
  } else if (cfg_.form == Form::Bidirectional) {
    const int32_t mid = (s.n + 1) / 2;
    if (n >= mid) {
      x_start = s.x0 + s.n - 1;
      increments = s.n - 1 - n;
      roundings = increments;
    }
  }
}

double UvIncrementalAdder::bound_impl(const ProjectiveMap& m, const RowSpan& s, int32_t n,
                                      bool fixed, double unit) const {
  double roundings = 0, increments = 0;
  int32_t xs = 0;
  lane_history(s, n, roundings, increments, xs);
  const long double x = s.x0 + n, y = s.y;
  const long double x_lo = s.x0, x_hi = s.x0 + s.n - 1 + std::max(1, cfg_.lanes);
  auto range_max = [&](long double a, long double b, long double c) {
    return static_cast<double>(
        std::max(std::fabs(a * x_lo + b * y + c), std::fabs(a * x_hi + b * y + c)));
  };
  // Start value at xs, then `increments` copies of the rounded increment and `roundings`
  // rounded additions (float: each <= unit·max|w| over the lane's range; fixed: exact).
  auto err = [&](long double a, long double b, long double c) {
    const double start = linear_form_error_bound(a, b, c, xs, y, fixed, unit);
    if (fixed) return start + increments * unit / 2;
    return start + 2.0 * increments * unit * static_cast<double>(std::fabs(a)) +
           roundings * unit * range_max(a, b, c) * (1 + 1e-6);
  };
  const double dw = err(m.A, m.B, m.C), dt = err(m.D, m.E, m.F), dz = err(m.G, m.H, m.I);
  const double z = static_cast<double>(m.den(x, y));
  const bool rcp = cfg_.division == Division::Reciprocal;
  return std::max(
      quotient_error_bound(static_cast<double>(m.num_u(x, y)), z, dw, dz, rcp, fixed, unit),
      quotient_error_bound(static_cast<double>(m.num_v(x, y)), z, dt, dz, rcp, fixed, unit));
}

}  // namespace texsim
