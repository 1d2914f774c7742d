#pragma once
// UvHeckbertDirect: per-pixel perspective-correct texture coordinates by Heckbert's ratio of
// linear forms, with two dividers or one reciprocal and two multipliers
// (docs/derivations/coords-derivations.md §2).
#include <cstdint>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/raster/raster_types.h"
#include "blocks/texture/coords/coord_types.h"

namespace texsim {

class ConfigReader;

class UvHeckbertDirect {
 public:
  enum class Form { Divide, Reciprocal };
  struct Config {
    Form form = Form::Divide;
    Datapath datapath = Datapath::Spatial;
    // Pixels whose denominator q is below this are rejected: beyond the far limit or past the
    // horizon (q <= 0). In units of the normalised map (q <= 1 on screen).
    double min_denominator = 1.0 / 4096;
    static Config from_toml(const ConfigReader& r);
  };

  UvHeckbertDirect() = default;
  explicit UvHeckbertDirect(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // Functional core: arithmetic in T (float, double or Fixed<I,F>), every operation rounded
  // to T as the hardware does.
  template <class T>
  CoordSample eval(const MapCoeffs<T>& m, int32_t x, int32_t y) const {
    if (!m.ok) return {};
    const T xt = static_cast<T>(x), yt = static_cast<T>(y);
    const T q = m.G * xt + m.H * yt + m.I;
    if (!is_finite_value(q) || !(q >= static_cast<T>(cfg_.min_denominator))) return {};
    const T w = m.A * xt + m.B * yt + m.C;
    const T t = m.D * xt + m.E * yt + m.F;
    T u{}, v{};
    if (cfg_.form == Form::Divide) {
      u = w / q;
      v = t / q;
    } else {
      const T r = static_cast<T>(1) / q;
      u = w * r;
      v = t * r;
    }
    if (out_of_range(u) || out_of_range(v)) return {};
    return {to_double(u), to_double(v), true};
  }
  template <class T>
  void eval_row(const MapCoeffs<T>& m, const RowSpan& s, CoordSample* out) const {
    for (int32_t n = 0; n < s.n; ++n) out[n] = eval(m, s.x0 + n, s.y);
  }

  // A-priori bound (texels) on the error at pixel (x, y) in format T
  // (docs/derivations/coords-derivations.md §3.3); +inf where the denominator is within its error
  // of 0.
  template <class T>
  double error_bound(const ProjectiveMap& m, int32_t x, int32_t y) const {
    return bound_impl(m, x, y, format_is_fixed<T>(), format_unit<T>());
  }

  // Item: one pixel.
  OpCounts ops_per_item() const;
  OpCounts pixel_critical_path() const;
  OpCounts row_setup_ops() const { return {}; }
  // Per-pixel timing (no row set-up: every pixel is independent).
  TimingSpec timing(const TechTable& t) const;
  // Report name; the number format is the caller's T, so arithmetic() names the datapath.
  std::string name() const { return "coords.heckbert"; }
  std::string arithmetic() const { return std::string(datapath_name(cfg_.datapath)) + " datapath"; }
  TimingSpec row_setup_timing(const TechTable&) const { return TimingSpec{0, 0, 1, 0.0}; }

 private:
  double bound_impl(const ProjectiveMap& m, int32_t x, int32_t y, bool fixed, double unit) const;
  Config cfg_{};
};

}  // namespace texsim
