#pragma once
// ProjectiveMap: the 3x3 screen->texture map A..I of a textured plane seen by a pinhole camera,
// in long double (the reference of every coordinate block); docs/derivations/coords-derivations.md
// §1. Timing of the blocks that use it comes from blocks/base/derive_timing.h (included here).
#include <cstdint>

#include "blocks/base/derive_timing.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/geometry/camera.h"

namespace texsim {

struct Vec3L {
  long double x = 0, y = 0, z = 0;
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
  // Only its imaging counts (the plane is given in view space): by default a 512 × 512 image
  // with a 90° field of view, f = 256 pixels.
  Camera camera = square_camera(512);
};

// View-space frame of a textured plane: texel (u, v) sits at origin + u·axis_u + v·axis_v.
struct PlaneFrame {
  Vec3L origin, axis_u, axis_v;
};
PlaneFrame plane_frame(const PlaneView& pv);
// Pixel-index coordinates (centre of pixel i at x = i) of a view-space point with Z > 0.
void project_to_pixel(const Vec3L& p, const Camera& cam, long double& x, long double& y);

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
                                  const Camera& cam);
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

}  // namespace texsim
