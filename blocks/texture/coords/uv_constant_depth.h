#pragma once
// UvConstantDepth: texture coordinates along constant-depth lines (seed 002): per triangle the
// slope k = -G/H of the lines on which the denominator is constant (scan axis chosen by |k|),
// per line one reciprocal R = 1/q, per pixel u += R·(A + B·k)
// (docs/derivations/coords-derivations.md §5).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/coords/coord_types.h"

namespace texsim {

class ConfigReader;

class UvConstantDepth {
 public:
  enum class Axis { Auto, X, Y };
  struct Config {
    // Auto: walk x (lines y = k·x + h) if |H| >= |G|, else walk y (x = k·y + h), so |k| <= 1
    // and H -> 0 (the seed's B -> 0) needs no infinite slope. X/Y force an axis (for tests).
    Axis axis = Axis::Auto;
    Datapath datapath = Datapath::Spatial;
    double min_denominator = 1.0 / 4096;  // a line whose q is below it is rejected
    static Config from_toml(const ConfigReader& r);
  };
  // Per-triangle state: scan axis, slope and the per-step numerator increments.
  template <class T>
  struct Setup {
    bool x_major = true;
    T k{}, ak{}, dk{};
    bool ok = false;
  };
  // One line: major coordinate s0 .. s0+n-1 along it; the line is minor = k·major + h.
  struct SlopedSpan {
    int32_t s0 = 0;
    double h = 0;
    int32_t n = 0;
  };

  UvConstantDepth() = default;
  explicit UvConstantDepth(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // The exact scan axis and slope (long double) that a rasterizer walking these lines uses.
  bool x_major(const ProjectiveMap& m) const;
  long double slope(const ProjectiveMap& m) const;

  template <class T>
  Setup<T> setup_triangle(const MapCoeffs<T>& m) const {
    Setup<T> s;
    if (!m.ok) return s;
    s.x_major = cfg_.axis == Axis::Auto ? !(abs_t(m.G) > abs_t(m.H)) : cfg_.axis == Axis::X;
    const T num = s.x_major ? m.G : m.H, den = s.x_major ? m.H : m.G;
    if (den == T{}) {
      if (!(num == T{})) return s;  // infinite slope on a forced axis: reject the triangle
      s.k = T{};
    } else {
      s.k = -(num / den);
    }
    if (out_of_range(s.k)) return s;
    // Along the line the numerators change by A + B·k per x step (or A·k + B per y step).
    s.ak = s.x_major ? m.A + m.B * s.k : m.A * s.k + m.B;
    s.dk = s.x_major ? m.D + m.E * s.k : m.D * s.k + m.E;
    s.ok = is_finite_value(s.ak) && is_finite_value(s.dk);
    return s;
  }

  // Values on the exact line at major = s0 + n (the rasterizer writes them to the pixel whose
  // centre is nearest the line: that offset is part of this method's error).
  template <class T>
  void eval_row(const MapCoeffs<T>& m, const Setup<T>& st, const SlopedSpan& l,
                CoordSample* out) const {
    if (l.n <= 0) return;
    std::fill(out, out + l.n, CoordSample{});
    if (!st.ok || !std::isfinite(l.h) || std::fabs(l.h) >= format_max<T>()) return;
    const T h = static_cast<T>(l.h), s0 = static_cast<T>(l.s0);
    const T minor = st.k * s0 + h;
    const T x = st.x_major ? s0 : minor, y = st.x_major ? minor : s0;
    // q = H·h + I on a line y = k·x + h (G + H·k = 0), or G·h + I on x = k·y + h.
    const T q = (st.x_major ? m.H : m.G) * h + m.I;
    if (!is_finite_value(q) || !(q >= static_cast<T>(cfg_.min_denominator))) return;
    const T r = static_cast<T>(1) / q;
    T u = (m.A * x + m.B * y + m.C) * r;
    T v = (m.D * x + m.E * y + m.F) * r;
    const T du = st.ak * r, dv = st.dk * r;
    for (int32_t n = 0; n < l.n; ++n) {
      const bool ok = !out_of_range(u) && !out_of_range(v);
      out[n] = ok ? CoordSample{to_double(u), to_double(v), true} : CoordSample{};
      u += du;
      v += dv;
    }
  }

  // Item: one pixel.
  OpCounts ops_per_item() const;
  OpCounts pixel_critical_path() const;
  OpCounts row_setup_ops() const;  // per line
  OpCounts row_setup_critical_path() const;
  OpCounts triangle_setup_ops() const;
  TimingSpec timing(const TechTable& t) const;
  // Report name; the number format is the caller's T, so arithmetic() names the datapath.
  std::string name() const { return "coords.constant_depth"; }
  std::string arithmetic() const { return std::string(datapath_name(cfg_.datapath)) + " datapath"; }
  TimingSpec row_setup_timing(const TechTable& t) const;
  TimingSpec triangle_setup_timing(const TechTable& t) const;

 private:
  template <class T>
  static T abs_t(T x) {
    return x < T{} ? -x : x;
  }
  Config cfg_{};
};

}  // namespace texsim
