#pragma once
// UvApproximation: texture coordinates along a raster row from a polynomial through exact
// points (affine: 2, quadratic: 3, cubic: 4), evaluated per pixel by forward differences
// (seed 002's approximations; docs/derivations/coords-derivations.md §4, incl. the A2 erratum).
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/raster/raster_types.h"
#include "blocks/texture/coords/coord_types.h"

namespace texsim {

class ConfigReader;

// Coefficients of the quadratic u(s) = A1 s^2 + A2 s + A3 through u(0) = u0, u(1/2) = u1,
// u(1) = u2. `seed_misprint` reproduces the printed A2 = -3u0 + 4u1 - 2u2 (for the erratum test).
template <class T>
std::array<T, 3> quadratic_coeffs(T u0, T u1, T u2, bool seed_misprint = false) {
  const T two = static_cast<T>(2), three = static_cast<T>(3), four = static_cast<T>(4);
  const T a1 = two * u0 - four * u1 + two * u2;
  const T a2 = (seed_misprint ? -three * u0 + four * u1 - two * u2 : -three * u0 + four * u1 - u2);
  return {a1, a2, u0};
}

// Coefficients c3..c0 of the cubic through u(0), u(1/3), u(2/3), u(1) (Lagrange, expanded).
template <class T>
std::array<T, 4> cubic_coeffs(T u0, T u1, T u2, T u3) {
  auto k = [](double c) { return static_cast<T>(c); };
  const T c3 = k(-4.5) * u0 + k(13.5) * u1 - k(13.5) * u2 + k(4.5) * u3;
  const T c2 = k(9.0) * u0 - k(22.5) * u1 + k(18.0) * u2 - k(4.5) * u3;
  const T c1 = k(-5.5) * u0 + k(9.0) * u1 - k(4.5) * u2 + u3;
  return {c3, c2, c1, u0};
}

class UvApproximation {
 public:
  enum class Order { Affine = 1, Quadratic = 2, Cubic = 3 };
  struct Config {
    Order order = Order::Quadratic;
    // Longest span one polynomial covers; longer rows are cut into segments of this many
    // pixels, each with its own set-up (0 = the whole row: the seed's form).
    int segment = 0;
    Datapath datapath = Datapath::Spatial;
    double min_denominator = 1.0 / 4096;  // exact points with q below it reject the row
    static Config from_toml(const ConfigReader& r);
  };

  UvApproximation() = default;
  explicit UvApproximation(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }
  int points() const { return static_cast<int>(cfg_.order) + 1; }

  // The spans that get their own polynomial (one per segment).
  std::vector<RowSpan> segments(const RowSpan& s) const {
    std::vector<RowSpan> v;
    const int32_t len = cfg_.segment > 0 ? cfg_.segment : std::max(1, s.n);
    for (int32_t a = 0; a < s.n; a += len) v.push_back({s.x0 + a, s.y, std::min(len, s.n - a)});
    return v;
  }

  // Functional core in T: exact (Heckbert) values at the span's sample points s = i/order,
  // polynomial coefficients in s, then forward differences in the pixel index with step
  // h = 1/(n-1). A one-pixel span gets the exact value.
  template <class T>
  void eval_row(const MapCoeffs<T>& m, const RowSpan& s, CoordSample* out) const {
    if (s.n <= 0) return;
    if (cfg_.segment > 0 && s.n > cfg_.segment) {
      for (const RowSpan& g : segments(s)) eval_row(m, g, out + (g.x0 - s.x0));
      return;
    }
    std::fill(out, out + s.n, CoordSample{});
    if (!m.ok) return;
    const int order = static_cast<int>(cfg_.order);
    const int np = s.n == 1 ? 1 : order + 1;
    std::array<T, 4> pu{}, pv{};
    const T yt = static_cast<T>(s.y);
    const T bu = m.B * yt + m.C, bv = m.E * yt + m.F, bq = m.H * yt + m.I;
    for (int i = 0; i < np; ++i) {
      const double xs = np == 1 ? s.x0 : s.x0 + static_cast<double>(s.n - 1) * i / order;
      const T xt = static_cast<T>(xs);
      const T q = m.G * xt + bq;
      if (!is_finite_value(q) || !(q >= static_cast<T>(cfg_.min_denominator))) return;
      pu[i] = (m.A * xt + bu) / q;
      pv[i] = (m.D * xt + bv) / q;
    }
    if (np == 1) {
      if (!out_of_range(pu[0]) && !out_of_range(pv[0]))
        out[0] = {to_double(pu[0]), to_double(pv[0]), true};
      return;
    }
    const T h = static_cast<T>(1) / static_cast<T>(s.n - 1);
    std::array<T, 4> du = diff_table(pu, h), dv = diff_table(pv, h);
    for (int32_t n = 0; n < s.n; ++n) {
      const bool ok = is_finite_value(du[0]) && is_finite_value(dv[0]) && !out_of_range(du[0]) &&
                      !out_of_range(dv[0]);
      out[n] = ok ? CoordSample{to_double(du[0]), to_double(dv[0]), true} : CoordSample{};
      for (int k = 0; k < order; ++k) {
        du[k] += du[k + 1];
        dv[k] += dv[k + 1];
      }
    }
  }

  // Item: one pixel.
  OpCounts ops_per_item() const;
  OpCounts pixel_critical_path() const;
  OpCounts row_setup_ops() const;
  OpCounts row_setup_critical_path() const;
  TimingSpec timing(const TechTable& t) const;
  // Report name; the number format is the caller's T, so arithmetic() names the datapath.
  std::string name() const { return "coords.approximation"; }
  std::string arithmetic() const { return std::string(datapath_name(cfg_.datapath)) + " datapath"; }
  TimingSpec row_setup_timing(const TechTable& t) const;

 private:
  // Forward-difference table {f(0), Δf(0), Δ²f(0), Δ³f(0)} of the polynomial through the
  // sample values p, for a unit pixel step h in s.
  template <class T>
  std::array<T, 4> diff_table(const std::array<T, 4>& p, T h) const {
    std::array<T, 4> d{};
    const T two = static_cast<T>(2), six = static_cast<T>(6);
    switch (cfg_.order) {
      // The coefficients other than the constant term are differences of the samples, so
      // they are formed from q_i = p_i - p_0: small numbers, no overflow of a fixed-point
      // format's range by the sums (9·u0 - 22.5·u1 ... would exceed s16.16 for u > 1456).
      case Order::Affine:
        d = {p[0], (p[1] - p[0]) * h, T{}, T{}};
        break;
      case Order::Quadratic: {
        const auto c = quadratic_coeffs(T{}, p[1] - p[0], p[2] - p[0]);
        const T a1h = c[0] * h;  // (A1·h)·h keeps precision in fixed point where h^2 underflows
        d = {p[0], (a1h + c[1]) * h, two * a1h * h, T{}};
        break;
      }
      case Order::Cubic: {
        const auto c = cubic_coeffs(T{}, p[1] - p[0], p[2] - p[0], p[3] - p[0]);
        const T c3h = c[0] * h;
        d = {p[0], ((c3h + c[1]) * h + c[2]) * h, (six * c3h + two * c[1]) * h * h,
             six * c3h * h * h};
        break;
      }
    }
    return d;
  }

  Config cfg_{};
};

}  // namespace texsim
