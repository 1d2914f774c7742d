#pragma once
// DerivativesQuad: derivatives as a GPU 2×2 quad computes them (coarse): du/dx = u(x1,y0) -
// u(x0,y0), du/dy = u(x0,y1) - u(x0,y0) of the quad's coordinates, shared by its four pixels
// (docs/derivations/coords-derivations.md §6.2).
#include <algorithm>
#include <cstdint>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/raster/raster_types.h"
#include "blocks/texture/coords/coord_types.h"
#include "blocks/texture/coords/uv_heckbert_direct.h"

namespace texsim {

class ConfigReader;

class DerivativesQuad {
 public:
  struct Config {
    Datapath datapath = Datapath::Spatial;
    double min_denominator = 1.0 / 4096;
    static Config from_toml(const ConfigReader& r);
  };
  DerivativesQuad() = default;
  explicit DerivativesQuad(const Config& c) : cfg_(c) {}

  // Functional core in T: the quad's coordinates come from Heckbert's formula in T (helper
  // pixels outside the primitive included, as a GPU runs them); the block subtracts.
  template <class T>
  void eval_row(const MapCoeffs<T>& m, const RowSpan& s, CoordDerivs* out) const {
    if (s.n <= 0) return;
    std::fill(out, out + s.n, CoordDerivs{});
    if (!m.ok) return;
    UvHeckbertDirect::Config hc;
    hc.min_denominator = cfg_.min_denominator;
    const UvHeckbertDirect coords(hc);
    const int32_t qy = s.y & ~1;
    int32_t qx_done = INT32_MIN;
    CoordDerivs d{};
    for (int32_t n = 0; n < s.n; ++n) {
      const int32_t qx = (s.x0 + n) & ~1;
      if (qx != qx_done) {
        const CoordSample p00 = coords.eval(m, qx, qy), p10 = coords.eval(m, qx + 1, qy),
                          p01 = coords.eval(m, qx, qy + 1);
        d = {};
        if (p00.valid && p10.valid && p01.valid) {
          // Differences in T (the inputs are T values widened exactly to double).
          const T u0 = static_cast<T>(p00.u), v0 = static_cast<T>(p00.v);
          const T ux = static_cast<T>(p10.u) - u0, vx = static_cast<T>(p10.v) - v0;
          const T uy = static_cast<T>(p01.u) - u0, vy = static_cast<T>(p01.v) - v0;
          d = {to_double(ux), to_double(vx), to_double(uy), to_double(vy), true};
        }
        qx_done = qx;
      }
      out[n] = d;
    }
  }

  // Per pixel: 4 subtractions per quad = 1 per pixel (the helper pixels' coordinate cost is
  // charged by the study as extra coordinate evaluations).
  // Item: one pixel.
  OpCounts ops_per_item() const;
  OpCounts pixel_critical_path() const;
  OpCounts row_setup_ops() const { return {}; }
  TimingSpec timing(const TechTable& t) const;
  // Report name; the number format is the caller's T, so arithmetic() names the datapath.
  std::string name() const { return "derivs.quad"; }
  std::string arithmetic() const { return std::string(datapath_name(cfg_.datapath)) + " datapath"; }
  TimingSpec row_setup_timing(const TechTable&) const { return TimingSpec{0, 0, 1, 0.0}; }

 private:
  Config cfg_{};
};

}  // namespace texsim
