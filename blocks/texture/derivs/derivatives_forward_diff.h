#pragma once
// DerivativesForwardDiff: the thesis's baseline derivatives, formula (9): u(x+1,y) - u(x,y)
// and u(x,y+1) - u(x,y) with the neighbours' coordinates evaluated by Heckbert's formula
// ("classic") or from the pixel's own numerators plus A, G, D / B, H, E ("accelerated")
// (docs/derivations/coords-derivations.md §6.3).
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

class DerivativesForwardDiff {
 public:
  enum class Form { Classic, Accelerated };
  struct Config {
    Form form = Form::Classic;
    Datapath datapath = Datapath::Spatial;
    double min_denominator = 1.0 / 4096;
    static Config from_toml(const ConfigReader& r);
  };
  DerivativesForwardDiff() = default;
  explicit DerivativesForwardDiff(const Config& c) : cfg_(c) {}

  // Functional core in T. The pixel's own w, t, q, u, v come from the coordinate block
  // (incremental, not charged here); the neighbours are this block's work.
  template <class T>
  void eval_row(const MapCoeffs<T>& m, const RowSpan& s, CoordDerivs* out) const {
    if (s.n <= 0) return;
    std::fill(out, out + s.n, CoordDerivs{});
    if (!m.ok) return;
    const T yt = static_cast<T>(s.y), y1 = static_cast<T>(s.y + 1);
    T xt = static_cast<T>(s.x0);
    T w = m.A * xt + m.B * yt + m.C, t = m.D * xt + m.E * yt + m.F, q = m.G * xt + m.H * yt + m.I;
    const T lim = static_cast<T>(cfg_.min_denominator);
    const T one = static_cast<T>(1);
    for (int32_t n = 0; n < s.n; ++n) {
      T wx{}, tx{}, qx{}, wy{}, ty{}, qy{};
      if (cfg_.form == Form::Classic) {
        const T x1 = xt + one;
        wx = m.A * x1 + m.B * yt + m.C;
        tx = m.D * x1 + m.E * yt + m.F;
        qx = m.G * x1 + m.H * yt + m.I;
        wy = m.A * xt + m.B * y1 + m.C;
        ty = m.D * xt + m.E * y1 + m.F;
        qy = m.G * xt + m.H * y1 + m.I;
      } else {
        wx = w + m.A;
        tx = t + m.D;
        qx = q + m.G;
        wy = w + m.B;
        ty = t + m.E;
        qy = q + m.H;
      }
      if (is_finite_value(q) && q >= lim && qx >= lim && qy >= lim && is_finite_value(qx) &&
          is_finite_value(qy)) {
        const T u = w / q, v = t / q;
        const T ux = wx / qx - u, vx = tx / qx - v, uy = wy / qy - u, vy = ty / qy - v;
        const bool ok =
            !out_of_range(ux) && !out_of_range(vx) && !out_of_range(uy) && !out_of_range(vy);
        if (ok) out[n] = {to_double(ux), to_double(vx), to_double(uy), to_double(vy), true};
      }
      w += m.A;
      t += m.D;
      q += m.G;
      xt += one;
    }
  }

  // Item: one pixel.
  OpCounts ops_per_item() const;
  OpCounts pixel_critical_path() const;
  OpCounts row_setup_ops() const { return {}; }
  TimingSpec timing(const TechTable& t) const;
  // Report name; the number format is the caller's T, so arithmetic() names the datapath.
  std::string name() const { return "derivs.forward_diff"; }
  std::string arithmetic() const { return std::string(datapath_name(cfg_.datapath)) + " datapath"; }
  TimingSpec row_setup_timing(const TechTable&) const { return TimingSpec{0, 0, 1, 0.0}; }

 private:
  Config cfg_{};
};

}  // namespace texsim
