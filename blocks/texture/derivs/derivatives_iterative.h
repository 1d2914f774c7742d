#pragma once
// DerivativesIterative: the thesis's iterative forward-difference derivatives: x numerators
// constant along a row, y numerators stepped by (BG - AH), (EG - DH) per pixel, denominators
// (K+Gx)(K+G+Gx) for x and the corrected (K+Gx)(K+H+Gx) for y
// (docs/derivations/coords-derivations.md §6.4).
#include <algorithm>
#include <cstdint>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/raster/raster_types.h"
#include "blocks/texture/coords/coord_types.h"

namespace texsim {

class ConfigReader;

class DerivativesIterative {
 public:
  struct Config {
    Datapath datapath = Datapath::Spatial;
    double min_denominator = 1.0 / 4096;
    // Reproduce the printed formulas (y denominators (K+Gx)(L+Gx) and the dv/dx numerator
    // DI - FG - DHy + EHy) to show the errata; never for real use.
    bool seed_misprints = false;
    static Config from_toml(const ConfigReader& r);
  };
  // Per-triangle constants (numerators of the four forward differences).
  template <class T>
  struct Setup {
    T p_ux{}, s_ux{}, p_vx{}, s_vx{};        // num_ux = p_ux + s_ux·y, num_vx likewise
    T step_uy{}, p_uy{}, step_vy{}, p_vy{};  // num_uy = step_uy·x + p_uy, num_vy likewise
    bool ok = false;
  };

  DerivativesIterative() = default;
  explicit DerivativesIterative(const Config& c) : cfg_(c) {}

  template <class T>
  Setup<T> setup_triangle(const MapCoeffs<T>& m) const {
    Setup<T> s;
    if (!m.ok) return s;
    s.p_ux = m.A * m.I - m.C * m.G;
    s.s_ux = m.A * m.H - m.B * m.G;
    s.p_vx = m.D * m.I - m.F * m.G;
    s.s_vx = cfg_.seed_misprints ? m.E * m.H - m.D * m.H : m.D * m.H - m.E * m.G;
    s.step_uy = m.B * m.G - m.A * m.H;
    s.p_uy = m.B * m.I - m.C * m.H;
    s.step_vy = m.E * m.G - m.D * m.H;
    s.p_vy = m.E * m.I - m.F * m.H;
    s.ok = true;
    for (T c : {s.p_ux, s.s_ux, s.p_vx, s.s_vx, s.step_uy, s.p_uy, s.step_vy, s.p_vy}) {
      s.ok = s.ok && is_finite_value(c) && !out_of_range(c);
    }
    return s;
  }

  template <class T>
  void eval_row(const MapCoeffs<T>& m, const Setup<T>& st, const RowSpan& s,
                CoordDerivs* out) const {
    if (s.n <= 0) return;
    std::fill(out, out + s.n, CoordDerivs{});
    if (!st.ok) return;
    const T yt = static_cast<T>(s.y), xt = static_cast<T>(s.x0);
    const T num_ux = st.p_ux + st.s_ux * yt, num_vx = st.p_vx + st.s_vx * yt;
    T num_uy = st.step_uy * xt + st.p_uy, num_vy = st.step_vy * xt + st.p_vy;
    const T k = m.I + m.H * yt;
    T d1 = k + m.G * xt;  // = q, the coordinate block's incremental denominator
    const T lim = static_cast<T>(cfg_.min_denominator);
    const T step_y_den = cfg_.seed_misprints ? m.G : m.H;
    for (int32_t n = 0; n < s.n; ++n) {
      const T d2x = d1 + m.G, d2y = d1 + step_y_den;
      if (is_finite_value(d1) && d1 >= lim && d2x >= lim && d2y >= lim) {
        const T rx = static_cast<T>(1) / (d1 * d2x), ry = static_cast<T>(1) / (d1 * d2y);
        const T ux = num_ux * rx, vx = num_vx * rx, uy = num_uy * ry, vy = num_vy * ry;
        const bool ok = !out_of_range(ux) && !out_of_range(vx) && !out_of_range(uy) &&
                        !out_of_range(vy) && !out_of_range(rx) && !out_of_range(ry);
        if (ok) out[n] = {to_double(ux), to_double(vx), to_double(uy), to_double(vy), true};
      }
      num_uy += st.step_uy;
      num_vy += st.step_vy;
      d1 += m.G;
    }
  }

  // Item: one pixel.
  OpCounts ops_per_item() const;
  OpCounts pixel_critical_path() const;
  OpCounts row_setup_ops() const;
  OpCounts row_setup_critical_path() const;
  OpCounts triangle_setup_ops() const;
  TimingSpec timing(const TechTable& t) const;
  // Report name; the number format is the caller's T, so arithmetic() names the datapath.
  std::string name() const { return "derivs.iterative"; }
  std::string arithmetic() const { return std::string(datapath_name(cfg_.datapath)) + " datapath"; }
  TimingSpec row_setup_timing(const TechTable& t) const;
  TimingSpec triangle_setup_timing(const TechTable& t) const;

 private:
  Config cfg_{};
};

}  // namespace texsim
