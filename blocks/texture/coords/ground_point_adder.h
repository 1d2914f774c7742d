#pragma once
// GroundPointAdder: the ground point of every pixel of a row by eq. 2.39 evaluated
// incrementally (seed 003 §2.2; docs/derivations/terrain.md §9). With Ze, Ye the pixel's screen
// position, V_x, V_y, V_z (eq. 2.37) are linear in the pixel index, so along a row each is one
// add per pixel; Y_h is folded into the numerators' start values and increments at the row
// set-up (N_x = Y_h·V_x, N_z = Y_h·V_z), leaving per pixel
//   x = X_h - N_x/V_y,  z = Z_h - N_z/V_y
// (Form::PerPixel: 3 adds for the forms, 2 divisions by one divisor, 2 adds). When the row is a
// line of constant depth (V_y does not change along it: c31 = -cos ϑ·sin γ = 0, i.e. roll
// γ = 0), x and z are themselves linear along the row: one reciprocal and four multiplies per
// row give x, z and their steps, and each pixel is 2 adds (Form::ConstantDepthRows, seed 002's
// constant-depth lines with slope 0). With γ ≠ 0 that form keeps the row start's V_y for the
// whole row, which is wrong by the measured amount: the lines of constant V_y are tilted then
// (UvConstantDepth walks them).
#include <cmath>
#include <cstdint>
#include <glm/vec3.hpp>
#include <string>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/geometry/aviation_camera.h"
#include "rtl_model/number/fixed.h"
#include "rtl_model/number/format_limits.h"

namespace texsim {

class ConfigReader;

// One pixel's ground point (g frame X, Z). Invalid: the ray does not go down to the ground
// (V_y >= 0), or a value left the number format.
struct GroundSample {
  double x = 0, z = 0;
  bool valid = false;
};

class GroundPointAdder {
 public:
  enum class Form { PerPixel, ConstantDepthRows };
  struct Config {
    Form form = Form::PerPixel;
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };

  GroundPointAdder() = default;
  explicit GroundPointAdder(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // The n pixels (x0 .. x0 + n - 1, ys) of camera `cam`, in number format T (float, double,
  // Fixed): the row set-up is computed in double and rounded once to T; every per-pixel add,
  // reciprocal and multiply rounds to T.
  template <class T>
  void eval_row(const AviationCamera& cam, int32_t ys, int32_t x0, int32_t n,
                GroundSample* out) const;

  // Item: one pixel.
  OpCounts ops_per_item() const;
  OpCounts critical_path() const;
  OpCounts row_setup_ops() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "coords.ground_point_adder"; }
  std::string arithmetic() const { return std::string(datapath_name(cfg_.datapath)) + " datapath"; }

 private:
  Config cfg_{};
};

template <class T>
void GroundPointAdder::eval_row(const AviationCamera& cam, int32_t ys, int32_t x0, int32_t n,
                                GroundSample* out) const {
  const auto& c = cam.config();
  const glm::dmat3& a = cam.rotation();
  const glm::dvec3 e = cam.eye();
  // V at pixel (x0, ys) and its step along the row (eq. 2.36–2.37 in pixel indices).
  const double ze = (x0 + 0.5) * c.pixel_size, ye = (ys + 0.5) * c.pixel_size;
  const glm::dvec3 v0 = a * glm::dvec3(c.screen_distance, c.height / 2.0 * c.pixel_size - ye,
                                       ze - c.width / 2.0 * c.pixel_size);
  const glm::dvec3 dv = a[2] * c.pixel_size;
  const double lim = format_max<T>();
  auto fits = [&](double x) { return std::isfinite(x) && std::fabs(x) < lim; };
  auto invalid_row = [&] {
    for (int32_t k = 0; k < n; ++k) out[k] = GroundSample{};
  };
  const T xh = static_cast<T>(e.x), zh = static_cast<T>(e.z);
  if (!fits(e.x) || !fits(e.z) || !fits(e.y)) return invalid_row();
  if (cfg_.form == Form::PerPixel) {
    const double s[6] = {e.y * v0.x, e.y * v0.z, v0.y, e.y * dv.x, e.y * dv.z, dv.y};
    for (double x : s) {
      if (!fits(x)) return invalid_row();
    }
    T nx = static_cast<T>(s[0]), nz = static_cast<T>(s[1]), d = static_cast<T>(s[2]);
    const T dnx = static_cast<T>(s[3]), dnz = static_cast<T>(s[4]), dd = static_cast<T>(s[5]);
    for (int32_t k = 0; k < n; ++k) {
      GroundSample g;
      if (d < static_cast<T>(0)) {  // the ray goes down (V_y < 0)
        const T x = xh - nx / d, z = zh - nz / d;
        g = {to_double(x), to_double(z),
             std::isfinite(to_double(x)) && std::isfinite(to_double(z))};
      }
      out[k] = g;
      nx = nx + dnx;
      nz = nz + dnz;
      d = d + dd;
    }
    return;
  }
  // Constant-depth rows: one reciprocal per row (of V_y at the row start).
  if (!(v0.y < 0)) return invalid_row();
  const double r = 1.0 / v0.y;
  const double s[4] = {e.x - e.y * v0.x * r, e.z - e.y * v0.z * r, -e.y * dv.x * r,
                       -e.y * dv.z * r};
  for (double x : s) {
    if (!fits(x)) return invalid_row();
  }
  T x = static_cast<T>(s[0]), z = static_cast<T>(s[1]);
  const T dx = static_cast<T>(s[2]), dz = static_cast<T>(s[3]);
  for (int32_t k = 0; k < n; ++k) {
    out[k] = {to_double(x), to_double(z), true};
    x = x + dx;
    z = z + dz;
  }
}

}  // namespace texsim
