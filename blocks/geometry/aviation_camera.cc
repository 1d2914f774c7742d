#include "blocks/geometry/aviation_camera.h"

#include <cmath>
#include <glm/ext/matrix_transform.hpp>
#include <glm/mat4x4.hpp>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<AviationCamera>);

namespace {

glm::dmat3 rotation_about(double deg, const glm::dvec3& axis) {
  return glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(deg), axis));
}

// `eye_offset = [h_u, h_v, h_w]`: three finite numbers.
glm::dvec3 read_eye_offset(const ConfigReader& r, std::string_view key, const glm::dvec3& def) {
  const toml::node* n = r.table().get(key);
  if (!n) return def;
  const toml::array* a = n->as_array();
  if (!a || a->size() != 3) r.fail(key, "expected [h_u, h_v, h_w], three numbers (v frame)");
  glm::dvec3 h{0.0};
  for (int i = 0; i < 3; ++i) {
    const toml::node& e = *a->get(static_cast<size_t>(i));
    if (auto f = e.value<double>()) h[i] = *f;  // integers convert too
    if (!e.is_number() || !std::isfinite(h[i]))
      r.fail_at(e, "eye_offset: each must be a finite number");
  }
  return h;
}

}  // namespace

glm::dmat3 aviation_rotation(double yaw_deg, double pitch_deg, double roll_deg) {
  return rotation_about(yaw_deg, {0, 1, 0}) * rotation_about(pitch_deg, {0, 0, 1}) *
         rotation_about(roll_deg, {1, 0, 0});
}

AviationCamera::Config AviationCamera::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"x", "y", "z", "eye_offset", "yaw_deg", "pitch_deg", "roll_deg",
                    "screen_distance", "pixel_size", "width", "height", "near"});
  Config c;
  c.eye_offset = read_eye_offset(r, "eye_offset", c.eye_offset);
  c.x = r.get_double("x", c.x);
  c.y = r.get_double("y", c.y);
  c.z = r.get_double("z", c.z);
  c.yaw_deg = r.get_double("yaw_deg", c.yaw_deg);
  c.pitch_deg = r.get_double("pitch_deg", c.pitch_deg);
  c.roll_deg = r.get_double("roll_deg", c.roll_deg);
  c.screen_distance = r.get_double("screen_distance", c.screen_distance);
  c.pixel_size = r.get_double("pixel_size", c.pixel_size);
  c.near = r.get_double("near", c.near);
  c.width = static_cast<int>(r.get_int("width", c.width, 1, 1 << 15));
  c.height = static_cast<int>(r.get_int("height", c.height, 1, 1 << 15));
  if (!(c.screen_distance > 0)) r.fail("screen_distance", "must be > 0");
  if (!(c.pixel_size > 0)) r.fail("pixel_size", "must be > 0");
  if (!(c.near > 0)) r.fail("near", "must be > 0");
  return c;
}

AviationCamera::AviationCamera(const Config& c) : cfg_(c) {
  a_ = aviation_rotation(c.yaw_deg, c.pitch_deg, c.roll_deg);
  ye0_ = c.height / 2.0 * c.pixel_size;
  ze0_ = c.width / 2.0 * c.pixel_size;
  eye_ = glm::dvec3(c.x, c.y, c.z) + a_ * c.eye_offset;  // eq. 2.16, h rotated by A (2.21)
}

glm::dvec3 AviationCamera::view_vector(double xs, double ys) const {
  const double ye = (ys + 0.5) * cfg_.pixel_size, ze = (xs + 0.5) * cfg_.pixel_size;
  return a_ * glm::dvec3(cfg_.screen_distance, ye0_ - ye, ze - ze0_);
}

bool AviationCamera::ground_point(double xs, double ys, double& gx, double& gz) const {
  const glm::dvec3 v = view_vector(xs, ys);
  const double lambda = -eye_.y / v.y;  // eq. 2.14 / 2.26 with the eye's height Y_h
  if (!(lambda > 0) || !std::isfinite(lambda)) return false;
  gx = eye_.x + lambda * v.x;  // eq. 2.20 / 2.27: X_h - Y_h·Vx/Vy
  gz = eye_.z + lambda * v.z;
  return true;
}

ProjectiveMap AviationCamera::ground_map() const {
  // V = A·(u1, Ye0 - (ys + 1/2)δ, (xs + 1/2)δ - Ze0) is linear in (xs, ys): V = Vx·xs + Vy·ys + V0.
  const glm::dvec3 cx = a_[2] * cfg_.pixel_size, cy = -a_[1] * cfg_.pixel_size;
  const glm::dvec3 c0 = a_ * glm::dvec3(cfg_.screen_distance, ye0_ - 0.5 * cfg_.pixel_size,
                                        0.5 * cfg_.pixel_size - ze0_);
  // ground X = (X_h·V_y - Y_h·V_x)/V_y, ground Z = (Z_h·V_y - Y_h·V_z)/V_y (the eye r_h).
  const glm::dvec3& e = eye_;
  ProjectiveMap m;
  m.A = e.x * cx.y - e.y * cx.x;
  m.B = e.x * cy.y - e.y * cy.x;
  m.C = e.x * c0.y - e.y * c0.x;
  m.D = e.z * cx.y - e.y * cx.z;
  m.E = e.z * cy.y - e.y * cy.z;
  m.F = e.z * c0.y - e.y * c0.z;
  m.G = cx.y;
  m.H = cy.y;
  m.I = c0.y;
  return m;
}

bool AviationCamera::project(const glm::dvec3& p, ScreenVertex& out) const {
  // v-components: Aᵀ·(P - r0) (A is orthonormal).
  const glm::dvec3 d = glm::transpose(a_) * (p - eye_);
  if (!(d.x >= cfg_.near)) return false;
  const double r = cfg_.screen_distance / d.x;
  const double ye = ye0_ - r * d.y, ze = ze0_ + r * d.z;
  out = {ze / cfg_.pixel_size - 0.5, ye / cfg_.pixel_size - 0.5, d.x};
  return true;
}

OpCounts AviationCamera::ops_per_item() const {
  OpCounts o;
  o.add = 3 + 6 + 2 + 2;  // P - r0, the mat-vec sums, Ye/Ze, the pixel offsets
  o.mul = 9 + 2 + 2;      // mat-vec, r·d_v and r·d_w, 1/δ
  o.div = 1;              // r = u1/d_u
  o.cmp = 1;              // in front of the eye
  return o;
}

OpCounts AviationCamera::ground_point_ops() const {
  // Eq. 2.39 with the c coefficients: three linear forms in (Ze, Ye) (2 mul, 2 add each), one
  // reciprocal of the V_y form and two products for the ratios, Y0 times each ratio, X0 and Z0
  // minus them, and the horizon test.
  OpCounts o;
  o.mul = 6 + 2 + 2;
  o.add = 6 + 2;
  o.rcp = 1;
  o.cmp = 1;
  return o;
}

OpCounts AviationCamera::setup_ops() const {
  OpCounts o;
  o.lut = 6;   // sin and cos of the three angles
  o.mul = 16;  // the products of eq. 2.38
  o.add = 6;
  if (cfg_.eye_offset != glm::dvec3(0.0)) {  // the eye r0 + A·h (eq. 2.16, 2.21)
    o.mul += 9;
    o.add += 6 + 3;
  }
  return o;
}

TimingSpec AviationCamera::timing(const TechTable& t) const {
  OpCounts path;  // subtract, multiply, two adds (mat-vec), divide, multiply, add
  path.add = 4;
  path.mul = 2;
  path.div = 1;
  return derive_timing(t, ops_per_item(), path, Datapath::Spatial, 1, setup_ops());
}

}  // namespace texsim
