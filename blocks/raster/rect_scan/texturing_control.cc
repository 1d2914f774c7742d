#include "blocks/raster/rect_scan/texturing_control.h"

#include <cmath>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<TexturingControl>);

TexturingControl::Config TexturingControl::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({});
  return {};
}

void TexturingControl::load(const EdgeRasterizer::Setup& st, const RowLine& line, int32_t minor_lo,
                            int32_t minor_hi, RectScanCoverage coverage) {
  st_ = &st;
  line_ = line;
  minor_lo_ = minor_lo;
  minor_hi_ = minor_hi;
  coverage_ = coverage;
  for (int e = 0; e < 3; ++e) {
    // Edge value change per step (units of 2^bits): a major step, and a major step with a
    // minor step of the line's sign. Which of the two the row uses depends on ΔY.
    const int64_t d_major = line.x_major ? -st.dy[e] : st.dx[e];
    const int64_t d_minor = line.x_major ? st.dx[e] : -st.dy[e];
    const int64_t plain = d_major, carry = d_major + line.sign * d_minor;
    const bool has_plain = line.delta_minor<line.delta_major, has_carry = line.delta_minor> 0;
    closing_[e] = (!has_plain || plain <= 0) && (!has_carry || carry <= 0);
    const double s = std::ldexp(1.0, -st.bits);
    vx_[e] = static_cast<int32_t>(std::lround(static_cast<double>(st.vx[e]) * s));
    vy_[e] = static_cast<int32_t>(std::lround(static_cast<double>(st.vy[e]) * s));
  }
}

TexturingControl::Decision TexturingControl::start_row(int32_t major0, int32_t minor0) {
  const int32_t x = line_.x_major ? major0 : minor0, y = line_.x_major ? minor0 : major0;
  for (int e = 0; e < 3; ++e) {
    inside_[e] = EdgeRasterizer::inside(*st_, e, EdgeRasterizer::edge_value(*st_, e, x, y));
  }
  was_inside_ = false;
  return decide(minor0);
}

TexturingControl::Decision TexturingControl::on_pixel(uint8_t hits, int32_t major, int32_t minor) {
  for (int e = 0; e < 3; ++e) {
    if (hits & (1u << e)) {
      inside_[e] = !inside_[e];
      ++crossings_;
    }
  }
  const int32_t x = line_.x_major ? major : minor, y = line_.x_major ? minor : major;
  for (int e = 0; e < 3; ++e) vertex_hits_ += (x == vx_[e] && y == vy_[e]);
  return decide(minor);
}

TexturingControl::Decision TexturingControl::decide(int32_t minor) {
  Decision d;
  const bool in_scissor = minor >= minor_lo_ && minor <= minor_hi_;
  const bool inside = inside_[0] && inside_[1] && inside_[2] && in_scissor;
  d.texture = inside || (coverage_ != RectScanCoverage::TopLeft && was_inside_ && in_scissor);
  was_inside_ = inside;
  for (int e = 0; e < 3; ++e) d.end_of_row = d.end_of_row || (closing_[e] && !inside_[e]);
  return d;
}

OpCounts TexturingControl::ops_per_item() const {
  OpCounts o;
  o.cmp = 3;  // all-inside decision, end of row, scissor
  return o;
}

OpCounts TexturingControl::row_ops() const {
  OpCounts o;
  o.add = 3;      // edge values at the next row start
  o.cmp = 3 + 1;  // their signs, end of triangle
  return o;
}

TimingSpec TexturingControl::timing(const TechTable& t) const {
  OpCounts path;
  path.cmp = 2;
  return derive_timing(t, ops_per_item(), path, Datapath::Spatial, 1, row_ops());
}

}  // namespace texsim
