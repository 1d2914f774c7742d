#pragma once
// UvApproximationTriangle: texture coordinates over a triangle from a biquadratic (6 exact
// points: vertices + edge midpoints, 12 coefficients) or bicubic (10 points, 20 coefficients)
// polynomial in the barycentric coordinates, evaluated along rows by forward differences
// (seed 002's surface approximations; docs/derivations/coords-derivations.md §4.3).
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/raster/raster_types.h"
#include "blocks/texture/coords/coord_types.h"

namespace texsim {

class ConfigReader;

class UvApproximationTriangle {
 public:
  enum class Order { Biquadratic = 2, Bicubic = 3 };
  struct Config {
    Order order = Order::Biquadratic;
    Datapath datapath = Datapath::Spatial;
    double min_denominator = 1.0 / 4096;  // an exact node with q below it rejects the triangle
    static Config from_toml(const ConfigReader& r);
  };
  // Vertices in pixel-index coordinates (the pixel centre of pixel i is x = i).
  struct Triangle {
    double x[3] = {0, 0, 0};
    double y[3] = {0, 0, 0};
  };
  static constexpr int kMaxTerms = 10;
  // Per-triangle state: monomial coefficients in (l1, l2) and l = a·x + b·y + c for both.
  template <class T>
  struct Setup {
    std::array<T, kMaxTerms> cu{}, cv{};
    T l1a{}, l1b{}, l1c{}, l2a{}, l2b{}, l2c{};
    bool ok = false;
  };

  UvApproximationTriangle() = default;
  explicit UvApproximationTriangle(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }
  int nodes() const { return cfg_.order == Order::Biquadratic ? 6 : 10; }
  // Barycentric (l1, l2) of node i, and the constant matrix taking node values to monomial
  // coefficients (the inverse of the nodes' Vandermonde matrix, long double).
  static std::array<long double, 2> node(Order o, int i);
  static const std::array<std::array<long double, kMaxTerms>, kMaxTerms>& node_to_coeffs(Order o);

  template <class T>
  Setup<T> setup_triangle(const MapCoeffs<T>& m, const Triangle& tri) const {
    Setup<T> s;
    if (!m.ok) return s;
    const double lim = format_max<T>();
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(tri.x[k]) || !std::isfinite(tri.y[k]) || std::fabs(tri.x[k]) >= lim ||
          std::fabs(tri.y[k]) >= lim) {
        return s;
      }
    }
    const T x0 = static_cast<T>(tri.x[0]), y0 = static_cast<T>(tri.y[0]);
    const T e1x = static_cast<T>(tri.x[1]) - x0, e1y = static_cast<T>(tri.y[1]) - y0;
    const T e2x = static_cast<T>(tri.x[2]) - x0, e2y = static_cast<T>(tri.y[2]) - y0;
    // Fixed point saturates silently: a product at a rail means the triangle is too large for
    // the format (vertices far off-screen), so it is rejected rather than mis-interpolated.
    const T p1 = e1x * e2y, p2 = e1y * e2x;
    const T det = p1 - p2;
    if (det == T{} || !is_finite_value(det) || out_of_range(p1) || out_of_range(p2) ||
        out_of_range(det)) {
      return s;
    }
    const T r = static_cast<T>(1) / det;
    if (out_of_range(r) || r == T{}) return s;
    // l1 = ((x-x0)·e2y - (y-y0)·e2x)/det, l2 = ((y-y0)·e1x - (x-x0)·e1y)/det.
    s.l1a = e2y * r;
    s.l1b = -(e2x * r);
    s.l1c = -(s.l1a * x0 + s.l1b * y0);
    s.l2a = -(e1y * r);
    s.l2b = e1x * r;
    s.l2c = -(s.l2a * x0 + s.l2b * y0);
    const int nn = nodes();
    std::array<T, kMaxTerms> pu{}, pv{};
    for (int i = 0; i < nn; ++i) {
      const auto l = node(cfg_.order, i);
      const T xt = x0 + static_cast<T>(static_cast<double>(l[0])) * e1x +
                   static_cast<T>(static_cast<double>(l[1])) * e2x;
      const T yt = y0 + static_cast<T>(static_cast<double>(l[0])) * e1y +
                   static_cast<T>(static_cast<double>(l[1])) * e2y;
      const T q = m.G * xt + m.H * yt + m.I;
      if (!is_finite_value(q) || !(q >= static_cast<T>(cfg_.min_denominator))) return s;
      pu[i] = (m.A * xt + m.B * yt + m.C) / q;
      pv[i] = (m.D * xt + m.E * yt + m.F) / q;
    }
    // Node 0 is the vertex (l1, l2) = (0, 0): the constant coefficient is its value and every
    // other row of the matrix sums to zero, so the matrix is applied to the differences from
    // node 0 (small numbers: no overflow of fixed-point ranges, less cancellation in float).
    const auto& inv = node_to_coeffs(cfg_.order);
    const T u0 = pu[0], v0 = pv[0];
    for (int i = 0; i < nn; ++i) {
      pu[i] = pu[i] - u0;
      pv[i] = pv[i] - v0;
    }
    for (int j = 0; j < nn; ++j) {
      T au{}, av{};
      for (int i = 1; i < nn; ++i) {
        if (inv[j][i] == 0) continue;
        const T c = static_cast<T>(static_cast<double>(inv[j][i]));
        au += c * pu[i];
        av += c * pv[i];
      }
      s.cu[j] = au;
      s.cv[j] = av;
    }
    s.cu[0] = s.cu[0] + u0;
    s.cv[0] = s.cv[0] + v0;
    s.ok = true;
    for (int j = 0; j < nn; ++j)
      s.ok = s.ok && is_finite_value(s.cu[j]) && is_finite_value(s.cv[j]);
    return s;
  }

  // Row evaluation: the polynomial restricted to the row, as a polynomial in the pixel index
  // n (l1 = a0 + α·n, l2 = b0 + β·n substituted into the monomials), then its forward
  // differences from those coefficients. (Differencing sampled values instead would amplify
  // their rounding by up to n³/6 over the row in the cubic case.)
  template <class T>
  void eval_row(const Setup<T>& st, const RowSpan& s, CoordSample* out) const {
    if (s.n <= 0) return;
    std::fill(out, out + s.n, CoordSample{});
    if (!st.ok) return;
    const bool cubic = cfg_.order == Order::Bicubic;
    const int order = cubic ? 3 : 2;
    const T xt = static_cast<T>(s.x0), yt = static_cast<T>(s.y);
    const T a0 = st.l1a * xt + st.l1b * yt + st.l1c, al = st.l1a;
    const T b0 = st.l2a * xt + st.l2b * yt + st.l2c, be = st.l2a;
    using Poly = std::array<T, 4>;
    const T one = static_cast<T>(1), two = static_cast<T>(2);
    std::array<Poly, kMaxTerms> mono{};
    mono[0] = {one, T{}, T{}, T{}};
    mono[1] = {a0, al, T{}, T{}};
    mono[2] = {b0, be, T{}, T{}};
    mono[3] = {a0 * a0, two * (a0 * al), al * al, T{}};
    mono[4] = {a0 * b0, a0 * be + al * b0, al * be, T{}};
    mono[5] = {b0 * b0, two * (b0 * be), be * be, T{}};
    auto times_linear = [](const Poly& p, T c0, T c1) {
      return Poly{p[0] * c0, p[0] * c1 + p[1] * c0, p[1] * c1 + p[2] * c0, p[2] * c1};
    };
    if (cubic) {
      mono[6] = times_linear(mono[3], a0, al);
      mono[7] = times_linear(mono[3], b0, be);
      mono[8] = times_linear(mono[5], a0, al);
      mono[9] = times_linear(mono[5], b0, be);
    }
    const int terms = nodes();
    auto row_poly = [&](const std::array<T, kMaxTerms>& c) {
      Poly e{};
      for (int j = 0; j < terms; ++j) {
        for (int d = 0; d <= order; ++d) {
          if (!(mono[j][d] == T{})) e[d] += c[j] * mono[j][d];
        }
      }
      // Forward differences of e0 + e1 n + e2 n² + e3 n³ at n = 0.
      const T six = static_cast<T>(6);
      return Poly{e[0], e[1] + e[2] + e[3], two * e[2] + six * e[3], six * e[3]};
    };
    Poly du = row_poly(st.cu), dv = row_poly(st.cv);
    for (int32_t n = 0; n < s.n; ++n) {
      const bool ok = !out_of_range(du[0]) && !out_of_range(dv[0]);
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
  OpCounts triangle_setup_ops() const;
  OpCounts triangle_setup_critical_path() const;
  TimingSpec timing(const TechTable& t) const;
  // Report name; the number format is the caller's T, so arithmetic() names the datapath.
  std::string name() const { return "coords.approximation_triangle"; }
  std::string arithmetic() const { return std::string(datapath_name(cfg_.datapath)) + " datapath"; }
  TimingSpec row_setup_timing(const TechTable& t) const;
  TimingSpec triangle_setup_timing(const TechTable& t) const;

 private:
  Config cfg_{};
};

}  // namespace texsim
