#pragma once
// SampleProjection: inverse rotation and projection of object-space samples
// (docs/derivations/object-space.md §3): [M'] = [M][R_xy]⁻¹[P] with R_xy⁻¹ = R_y⁻¹ R_x⁻¹ and
// the perspective matrix P of r = −1/z_c (z_c: eye-to-projection-plane distance, here the
// focal length in pixels, so one unit of the projection plane is one pixel). The samples of a
// rotated polygon share z' (the plane is parallel to the screen), so per polygon the set-up
// folds R⁻¹, the eye shift and P into a 3 × 3 map of (x', y', 1); per sample it is three dot
// products and one reciprocal: xs = cx + X/w, ys = cy + Y/w, w = 1 + r (z_c − Z) = Z / z_c.
// Screen coordinates are continuous (pixel centres at +0.5, the Camera's convention).
// Orthographic cameras (parallel rays, f pixels per world unit): P is the identity with the
// scale f, so M' maps (x', y', 1) to screen X, Y and view depth Z directly: no w, no division
// (xs = cx + X, ys = cy + Y, depth = Z). Arithmetic: double.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/geometry/polygon_rotation.h"

namespace texsim {

class ConfigReader;

struct ProjectedSample {
  double x = 0, y = 0;  // continuous screen coordinates
  double depth = 0;     // view-space Z
  bool valid = false;   // in front of the eye (w > 0) and finite
};

class SampleProjection {
 public:
  struct Config {
    int lanes = 1;  // samples projected in parallel
    static Config from_toml(const ConfigReader& r);
  };
  // M' of one polygon: rows give X, Y and w as affine functions of (x', y').
  struct Setup {
    double m[3][3] = {};
    double cx = 0, cy = 0, z_c = 1;
    bool orthographic = false;  // rows X, Y (in pixels) and the depth Z; no division
  };

  SampleProjection() = default;
  explicit SampleProjection(const Config& c) : cfg_(c) {}

  // Per polygon: the columns of R⁻¹ applied to (1,0,0), (0,1,0), (0,0,z'), then P with
  // r = −1/z_c: 3 × inverse rotation (24 mul 12 add), 1 rcp, 3 mul.
  static Setup setup(const Rotation& r, double z_rot, double focal_px, double cx, double cy,
                     OpCounts& ops);
  // Per polygon, orthographic (f pixels per world unit): 3 × inverse rotation (24 mul 12 add),
  // 6 mul (the X and Y rows scaled by f).
  static Setup setup_orthographic(const Rotation& r, double z_rot, double px_per_unit, double cx,
                                  double cy, OpCounts& ops);
  // One sample: 6 mul 6 add (M'), 1 rcp, 3 mul 2 add (divide by w, centre; depth), 1 cmp.
  // Orthographic: 6 mul 6 add (M'), 2 add (centre), 1 cmp (finite).
  static ProjectedSample project(const Setup& s, double xr, double yr, OpCounts& ops);

  // The thesis's closed forms of [M″] = [M][R_xy]⁻¹[P] for one point p = (x′, y′, z′) of the
  // rotated polygon, in the thesis's frame (P: w = 1 + r z, r = −1/z_c), Ny and Nz the unit
  // normal's (object-space.md §3.1):
  //   x″ = (cos β x′ + sin β z′) / D,   y″ = (cos α y′ + Ny z′ − sin α sin β x′) / D,
  //   z″ = (Nz z′ − sin α y′ − cos α sin β x′) / D,
  //   Printed:   D = 1 − r sin α y′ + r Nz z′ − r Ny x′ (as the thesis prints it: erratum);
  //   Corrected: D = 1 + r (Nz z′ − sin α y′ − cos α sin β x′) = 1 + r·(z″'s numerator).
  // Per point, unfolded (sin α sin β, cos α sin β and the r products once per polygon):
  // Corrected 12 mul 6 add 1 rcp; Printed 14 mul 8 add 1 rcp.
  enum class ClosedForm : uint8_t { Printed, Corrected };
  static glm::dvec3 thesis_closed_form(const Rotation& rot, const glm::dvec3& p, double r,
                                       ClosedForm form, OpCounts& ops);

  OpCounts ops_per_item() const;  // item: one sample
  OpCounts polygon_ops() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "geometry.sample_projection"; }
  std::string arithmetic() const { return "double"; }

 private:
  Config cfg_{};
};

}  // namespace texsim
