#pragma once
// ProjectiveMap: the 3x3 screen->texture map A..I of a textured plane seen by a pinhole camera,
// in long double (the reference of every coordinate block); docs/coords-derivations.md §1.
// Also the types shared by the coordinate-generation blocks (uv_*, derivatives_*,
// ellipse_setup): their inputs (MapCoeffs<T>, RowSpan) and outputs (CoordSample, CoordDerivs);
// timing comes from the shared derivation in blocks/base/derive_timing.h.
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "blocks/base/derive_timing.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "rtl_model/number/fixed.h"

namespace texsim {

class ConfigReader;

struct Vec3L {
  long double x = 0, y = 0, z = 0;
};

// Pinhole camera in view space (camera at the origin looking along +Z). Screen coordinates:
// xs = cx + f·X/Z, ys = cy + f·Y/Z; pixel (i, j) has its centre at xs = i + 0.5, ys = j + 0.5.
struct PinholeCamera {
  long double focal_px = 256;
  long double cx = 256, cy = 256;
};

// A plane through the view axis at `distance`, tilted by `tilt_deg` (0 = parallel to the
// screen, 90 = edge-on) about an axis in the screen plane at `azimuth_deg` from the x axis.
// At tilt 0 one texel covers 1/texels_per_pixel pixels; (u_offset, v_offset) is the texture
// coordinate (in texels) where the view axis meets the plane.
struct PlaneView {
  double tilt_deg = 0;
  double azimuth_deg = 0;
  double distance = 1;
  double texels_per_pixel = 1;
  double u_offset = 0, v_offset = 0;
  PinholeCamera camera{};
};

// View-space frame of a textured plane: texel (u, v) sits at origin + u·axis_u + v·axis_v.
struct PlaneFrame {
  Vec3L origin, axis_u, axis_v;
};
PlaneFrame plane_frame(const PlaneView& pv);
// Pixel-index coordinates (centre of pixel i at x = i) of a view-space point with Z > 0.
void project_to_pixel(const Vec3L& p, const PinholeCamera& cam, long double& x, long double& y);

// Screen (pixel index) -> texture (texels) map:
//   u = (A x + B y + C) / (G x + H y + I),  v = (D x + E y + F) / (G x + H y + I)
// with x, y pixel indices (the half-pixel centre offset is folded into C, F, I). As built by
// from_plane(), the denominator q = G x + H y + I equals s/Z (Z: view depth of the point seen
// at the pixel; s: the normalisation scale), so q > 0 in front of the camera, q -> 0 at the
// horizon and q < 0 beyond it.
struct ProjectiveMap {
  long double A = 1, B = 0, C = 0;
  long double D = 0, E = 1, F = 0;
  long double G = 0, H = 0, I = 1;
  bool degenerate = false;  // the plane passes through the eye (edge-on): no map exists

  long double num_u(long double x, long double y) const { return A * x + B * y + C; }
  long double num_v(long double x, long double y) const { return D * x + E * y + F; }
  long double den(long double x, long double y) const { return G * x + H * y + I; }
  long double u(long double x, long double y) const { return num_u(x, y) / den(x, y); }
  long double v(long double x, long double y) const { return num_v(x, y) / den(x, y); }
  bool finite() const;

  // Same map with every coefficient times s (u, v unchanged; q scaled by s).
  ProjectiveMap scaled(long double s) const;
  // Scaled by a power of two so that max |q| over the given points is in (0.5, 1]: the range
  // that fixed-point formats are sized for. Exact in binary formats.
  ProjectiveMap normalised(const long double* xs, const long double* ys, int n) const;
  // u' = u - du, v' = v - dv: texture-space translation folded into the map (exact in
  // long double), used to keep coordinates small when a texture wraps (rebase by whole tiles).
  ProjectiveMap translated(long double du, long double dv) const;

  // Builds the map for texture coordinate (u, v) at view-space point origin + u·axis_u +
  // v·axis_v. Marks the map degenerate (coefficients NaN) if the plane contains the eye.
  static ProjectiveMap from_plane(const Vec3L& origin, const Vec3L& axis_u, const Vec3L& axis_v,
                                  const PinholeCamera& cam);
  static ProjectiveMap from_plane_view(const PlaneView& pv);
};

// Analytic derivatives and the EWA ellipse of the pixel footprint, in long double.
struct DerivsL {
  long double ux = 0, vx = 0, uy = 0, vy = 0;
};
DerivsL analytic_derivs(const ProjectiveMap& m, long double x, long double y);
// Forward differences u(x+1,y)-u(x,y) etc. of the exact map (what a quad or the thesis's
// iterative formulas estimate), in long double.
DerivsL forward_diff_derivs(const ProjectiveMap& m, long double x, long double y);

// ----- Types shared by the coordinate blocks -----

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

template <class T>
bool is_finite_value(T x) {
  if constexpr (is_fixed_v<T>)
    return true;
  else
    return std::isfinite(x);
}

// A result the format could not hold: non-finite (float) or saturated at a rail (Fixed).
template <class T>
bool out_of_range(T x) {
  if constexpr (is_fixed_v<T>)
    return x == T::max() || x == T::min();
  else
    return !std::isfinite(x);
}

// Largest magnitude a number format can hold (used to reject maps that would saturate).
template <class T>
double format_max() {
  if constexpr (is_fixed_v<T>)
    return to_double(T::max());
  else
    return static_cast<double>(std::numeric_limits<T>::max());
}

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

// ----- Error bounds (docs/coords-derivations.md §3.3) -----

// Bound on |ŵ/ẑ − w/z| (texels) after the division step of a block, given |ŵ − w| <= dw and
// |ẑ − z| <= dz at the exact values w, z (z > dz > = 0), for a number format with `unit` = the
// LSB (fixed, round to nearest: each rounding <= unit/2) or the unit roundoff (float: each
// rounding <= unit·|result|). `reciprocal` = r = 1/ẑ then ŵ·r (two roundings, the first
// scaled by |ŵ|). +inf if z <= dz.
double quotient_error_bound(double w, double z, double dw, double dz, bool reciprocal, bool fixed,
                            double unit);
// Error of a linear form a·x + b·y + c evaluated in the format (coefficients rounded into it,
// then two products and two sums): fixed-point products of integers are exact, so only the
// coefficients' rounding counts; in float every operation rounds.
double linear_form_error_bound(long double a, long double b, long double c, long double x,
                               long double y, bool fixed, double unit);
template <class T>
constexpr bool format_is_fixed() {
  return is_fixed_v<T>;
}
template <class T>
constexpr double format_unit() {
  if constexpr (is_fixed_v<T>)
    return T::lsb();
  else
    return static_cast<double>(std::numeric_limits<T>::epsilon()) / 2;
}

}  // namespace texsim
