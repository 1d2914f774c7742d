#include "blocks/raster/rect_scan/line_stepper.h"

#include <algorithm>
#include <cmath>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<LineStepper>);

LineStepper::Config LineStepper::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"slope_bits"});
  Config c;
  c.slope_bits = static_cast<int>(r.get_int("slope_bits", c.slope_bits, 1, kMaxSlopeBits));
  return c;
}

RowLine LineStepper::line_for_denominator(double g, double h) const {
  if (!std::isfinite(g) || !std::isfinite(h) || (g == 0 && h == 0)) return line_for_slope(true, 0);
  const bool x_major = !(std::fabs(g) > std::fabs(h));
  return line_for_slope(x_major, x_major ? -g / h : -h / g);
}

RowLine LineStepper::line_for_slope(bool x_major, double k) const {
  RowLine l;
  l.x_major = x_major;
  l.delta_major = int64_t{1} << cfg_.slope_bits;
  if (!std::isfinite(k)) k = 0;
  k = std::clamp(k, -1.0, 1.0);
  l.sign = k < 0 ? -1 : 1;
  l.delta_minor =
      static_cast<int64_t>(std::llround(std::fabs(k) * static_cast<double>(l.delta_major)));
  return l;
}

OpCounts LineStepper::ops_per_item() const {
  OpCounts o;
  o.add = 2;  // acc += ΔY; acc -= ΔX on a carry
  o.cmp = 1;  // acc >= ΔX
  return o;
}

OpCounts LineStepper::setup_ops() const {
  OpCounts o;
  o.cmp = 2;  // |G| vs |H|, clamp
  o.mul = 1;  // |k|·2^bits (a shift of the slope the coordinate block divided)
  o.add = 1;  // rounding
  return o;
}

TimingSpec LineStepper::timing(const TechTable& t) const {
  OpCounts path;
  path.add = 1;
  path.cmp = 1;
  return derive_timing(t, ops_per_item(), path, Datapath::Spatial, 1, setup_ops());
}

std::string LineStepper::arithmetic() const {
  return "integer Bresenham error term, ΔX = 2^" + std::to_string(cfg_.slope_bits) +
         ", ΔY = round(|k|·ΔX) (slope quantised to 2^-" + std::to_string(cfg_.slope_bits) + ")";
}

}  // namespace texsim
