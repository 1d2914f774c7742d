#pragma once
// Types shared by the coordinate-generation blocks (uv_*, derivatives_*, ellipse_setup): their
// input (the map's coefficients in the block's number format) and outputs (CoordSample,
// CoordDerivs).
#include <cmath>

#include "blocks/geometry/projective_map.h"
#include "rtl_model/number/format_limits.h"

namespace texsim {

// A block's output coordinate, widened to double (exact for float and for Fixed up to 53
// bits). Invalid = rejected (non-finite input, denominator below the limit, out of range):
// u = v = 0 then, never NaN.
struct CoordSample {
  double u = 0, v = 0;
  bool valid = false;
};

// Screen-space derivatives (texels per pixel) as computed by a derivative block.
struct CoordDerivs {
  double ux = 0, vx = 0, uy = 0, vy = 0;
  bool valid = false;
};

// The map's coefficients rounded to the block's number format. ok = false if any coefficient
// is non-finite, the map is degenerate, or a coefficient does not fit the format.
template <class T>
struct MapCoeffs {
  T A{}, B{}, C{}, D{}, E{}, F{}, G{}, H{}, I{};
  bool ok = false;
};

template <class T>
MapCoeffs<T> to_coeffs(const ProjectiveMap& m) {
  MapCoeffs<T> c;
  const long double src[9] = {m.A, m.B, m.C, m.D, m.E, m.F, m.G, m.H, m.I};
  T* dst[9] = {&c.A, &c.B, &c.C, &c.D, &c.E, &c.F, &c.G, &c.H, &c.I};
  bool ok = !m.degenerate;
  const double lim = format_max<T>();
  for (int k = 0; k < 9; ++k) {
    const double x = static_cast<double>(src[k]);
    if (!std::isfinite(x) || std::fabs(x) >= lim) {
      ok = false;
      continue;
    }
    *dst[k] = static_cast<T>(x);
  }
  c.ok = ok;
  return c;
}

}  // namespace texsim
