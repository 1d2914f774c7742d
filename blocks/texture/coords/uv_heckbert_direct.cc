#include "blocks/texture/coords/uv_heckbert_direct.h"

#include <algorithm>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/texture/coords/error_bounds.h"

namespace texsim {

static_assert(Block<UvHeckbertDirect>);

UvHeckbertDirect::Config UvHeckbertDirect::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"form", "datapath", "min_denominator"});
  Config c;
  c.form = static_cast<Form>(r.get_choice("form", 0, {"divide", "reciprocal"}));
  c.datapath = parse_datapath(r, c.datapath);
  c.min_denominator = r.get_double("min_denominator", c.min_denominator);
  if (!(c.min_denominator > 0)) r.fail("min_denominator", "must be > 0");
  return c;
}

OpCounts UvHeckbertDirect::ops_per_item() const {
  // Three linear forms a·x + b·y + c (2 mul + 2 add each), the q >= limit compare, then
  // two divisions, or one reciprocal and two multiplications.
  OpCounts o;
  o.mul = 6;
  o.add = 6;
  o.cmp = 1;
  if (cfg_.form == Form::Divide) {
    o.div = 2;
  } else {
    o.rcp = 1;
    o.mul += 2;
  }
  return o;
}

OpCounts UvHeckbertDirect::pixel_critical_path() const {
  // mul -> add -> add (the linear form), then div, or rcp -> mul.
  OpCounts p;
  p.mul = 1;
  p.add = 2;
  if (cfg_.form == Form::Divide) {
    p.div = 1;
  } else {
    p.rcp = 1;
    p.mul += 1;
  }
  return p;
}

double UvHeckbertDirect::bound_impl(const ProjectiveMap& m, int32_t x, int32_t y, bool fixed,
                                    double unit) const {
  const long double xl = x, yl = y;
  const double dw = linear_form_error_bound(m.A, m.B, m.C, xl, yl, fixed, unit);
  const double dt = linear_form_error_bound(m.D, m.E, m.F, xl, yl, fixed, unit);
  const double dz = linear_form_error_bound(m.G, m.H, m.I, xl, yl, fixed, unit);
  const double z = static_cast<double>(m.den(xl, yl));
  const bool rcp = cfg_.form == Form::Reciprocal;
  return std::max(
      quotient_error_bound(static_cast<double>(m.num_u(xl, yl)), z, dw, dz, rcp, fixed, unit),
      quotient_error_bound(static_cast<double>(m.num_v(xl, yl)), z, dt, dz, rcp, fixed, unit));
}

TimingSpec UvHeckbertDirect::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), pixel_critical_path(), cfg_.datapath);
}

}  // namespace texsim
