#pragma once
// DerivativesAnalytic: exact screen-space derivatives of the perspective map per pixel,
// du/dx = (A - G·u)/q etc., from the row's incremental u, v and q
// (docs/derivations/coords-derivations.md §6.1).
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

class DerivativesAnalytic {
 public:
  struct Config {
    Datapath datapath = Datapath::Spatial;
    double min_denominator = 1.0 / 4096;
    static Config from_toml(const ConfigReader& r);
  };
  DerivativesAnalytic() = default;
  explicit DerivativesAnalytic(const Config& c) : cfg_(c) {}

  // Functional core in T. The numerators w, t and denominator q advance by +A, +D, +G as in
  // UvIncrementalAdder (their ops are charged there); this block adds r = 1/q, u = w·r,
  // v = t·r and the four (a - g·u)·r.
  template <class T>
  void eval_row(const MapCoeffs<T>& m, const RowSpan& s, CoordDerivs* out) const {
    if (s.n <= 0) return;
    std::fill(out, out + s.n, CoordDerivs{});
    if (!m.ok) return;
    const T yt = static_cast<T>(s.y), xt = static_cast<T>(s.x0);
    T w = m.A * xt + m.B * yt + m.C, t = m.D * xt + m.E * yt + m.F, q = m.G * xt + m.H * yt + m.I;
    for (int32_t n = 0; n < s.n; ++n) {
      if (is_finite_value(q) && q >= static_cast<T>(cfg_.min_denominator)) {
        const T r = static_cast<T>(1) / q;
        const T u = w * r, v = t * r;
        const T ux = (m.A - m.G * u) * r, vx = (m.D - m.G * v) * r;
        const T uy = (m.B - m.H * u) * r, vy = (m.E - m.H * v) * r;
        const bool ok =
            !out_of_range(ux) && !out_of_range(vx) && !out_of_range(uy) && !out_of_range(vy);
        if (ok) out[n] = {to_double(ux), to_double(vx), to_double(uy), to_double(vy), true};
      }
      w += m.A;
      t += m.D;
      q += m.G;
    }
  }

  // Item: one pixel.
  OpCounts ops_per_item() const;
  OpCounts pixel_critical_path() const;
  OpCounts row_setup_ops() const { return {}; }  // shares the coordinate block's set-up
  TimingSpec timing(const TechTable& t) const;
  // Report name; the number format is the caller's T, so arithmetic() names the datapath.
  std::string name() const { return "derivs.analytic"; }
  std::string arithmetic() const { return std::string(datapath_name(cfg_.datapath)) + " datapath"; }
  TimingSpec row_setup_timing(const TechTable&) const { return TimingSpec{0, 0, 1, 0.0}; }

 private:
  Config cfg_{};
};

}  // namespace texsim
