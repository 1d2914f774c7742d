#pragma once
// LineStepper: the linear interpolator ЛІ and the step-increment block БКП of the rectangle-scan
// rasteriser (seed 002, fig. 4; docs/rasterizers.md §2). ЛІ holds ΔX = 2^slope_bits, ΔY and the
// sign of the row direction and runs a Bresenham error term; БКП turns each carry into the
// minor-axis increment that the coordinate counters apply. Every row of a triangle uses the same
// step sequence, so neighbouring rows are the same digital line shifted by one pixel.
#include <cstdint>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"

namespace texsim {

class ConfigReader;

// The digital row line: minor = t + d(n) at major = major0 + n, d(n) = sign·⌊(n·ΔY + ΔX/2)/ΔX⌋,
// the quantised slope k' = sign·ΔY/ΔX with |k'| <= 1 (the major axis is the one along which
// the constant-depth line moves fastest).
struct RowLine {
  bool x_major = true;  // rows advance in x (minor y) or in y (minor x)
  int sign = 1;         // direction of the minor steps
  int64_t delta_major = 1;
  int64_t delta_minor = 0;
  double slope() const {
    return sign * static_cast<double>(delta_minor) / static_cast<double>(delta_major);
  }
  int64_t offset(int64_t n) const {  // d(n), n >= 0
    return sign * ((n * delta_minor + delta_major / 2) / delta_major);
  }
};

class LineStepper {
 public:
  static constexpr int kMaxSlopeBits = 24;
  struct Config {
    int slope_bits = 12;  // ΔX = 2^slope_bits: the slope's resolution
    static Config from_toml(const ConfigReader& r);
  };
  LineStepper() = default;
  explicit LineStepper(const Config& c) : cfg_(c) {}

  // Rows along which q = G·x + H·y + I is constant: y = k·x + h with k = -G/H when |H| >= |G|
  // (x-major), else x = k·y + h with k = -H/G (y-major: B -> 0 scans columns). ΔY = round(|k|·ΔX).
  // Not finite or G = H = 0 (q constant everywhere): x-major with k = 0.
  RowLine line_for_denominator(double g, double h) const;
  // The same from a slope on a given axis (|k| <= 1 after the axis choice; clamped).
  RowLine line_for_slope(bool x_major, double k) const;

  // Row start: the error term takes ΔX/2 (rounding to the nearest minor position).
  void start_row(const RowLine& l) {
    acc_ = l.delta_major / 2;
    ++rows_;
  }
  // One major step; returns the БКП minor increment (0 or ±1).
  int step(const RowLine& l) {
    ++steps_;
    acc_ += l.delta_minor;
    if (acc_ >= l.delta_major) {
      acc_ -= l.delta_major;
      ++minor_steps_;
      return l.sign;
    }
    return 0;
  }
  uint64_t steps() const { return steps_; }
  uint64_t minor_steps() const { return minor_steps_; }
  uint64_t rows() const { return rows_; }

  // Item: one major step (error-term add, carry compare, conditional subtract).
  OpCounts ops_per_item() const;
  OpCounts setup_ops() const;  // per triangle: axis compare, ΔY = round(|k|·2^bits)
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "raster.rect_scan.line_stepper"; }
  std::string arithmetic() const;

 private:
  Config cfg_{};
  int64_t acc_ = 0;
  uint64_t steps_ = 0, minor_steps_ = 0, rows_ = 0;
};

}  // namespace texsim
