#include "blocks/uv_heckbert_direct.h"

#include "blocks/config_reader.h"

namespace texsim {

UvHeckbertDirect::Config UvHeckbertDirect::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"form", "datapath", "min_denominator"});
  Config c;
  c.form = static_cast<Form>(r.get_choice("form", 0, {"divide", "reciprocal"}));
  c.datapath = parse_datapath(r, c.datapath);
  c.min_denominator = r.get_double("min_denominator", c.min_denominator);
  if (!(c.min_denominator > 0)) r.fail("min_denominator", "must be > 0");
  return c;
}

OpCounts UvHeckbertDirect::pixel_ops() const {
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

TimingSpec UvHeckbertDirect::timing(const TechTable& t) const {
  return derive_timing(t, pixel_ops(), pixel_critical_path(), cfg_.datapath);
}

}  // namespace texsim
