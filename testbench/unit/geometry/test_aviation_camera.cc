// Aviation camera: A = Aψ·Aϑ·Aγ built with GLM against the seed's explicit entries (eq. 2.38),
// the ground-plane projection against eq. 2.39, its projective map, and the vertex projection
// as the inverse of the ground projection.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/base/tech_table.h"
#include "blocks/geometry/aviation_camera.h"

namespace texsim {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180;

// Eq. 2.38 verbatim: rows x, y, z (ground), columns u, v, w (view).
struct SeedMatrix {
  double xu, xv, xw, yu, yv, yw, zu, zv, zw;
};
SeedMatrix seed_matrix(double psi, double theta, double gamma) {
  const double sp = std::sin(psi), cp = std::cos(psi), st = std::sin(theta), ct = std::cos(theta);
  const double sg = std::sin(gamma), cg = std::cos(gamma);
  SeedMatrix a{};
  a.zw = cp * cg - sp * st * sg;  // c11
  a.zv = cp * sg + sp * st * cg;  // c12
  a.zu = -sp * ct;
  a.xw = sp * cg + cp * st * sg;  // c21
  a.xv = sp * sg - cp * st * cg;  // c22
  a.xu = cp * ct;
  a.yw = -ct * sg;  // c31
  a.yv = ct * cg;   // c32
  a.yu = st;
  return a;
}

AviationCamera::Config random_config(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> ang(-180, 180), pitch(-89, 89), pos(-1000, 1000),
      height(1, 500);
  AviationCamera::Config c;
  c.yaw_deg = ang(rng);
  c.pitch_deg = pitch(rng);
  c.roll_deg = ang(rng);
  c.x = pos(rng);
  c.y = height(rng);
  c.z = pos(rng);
  c.width = 320;
  c.height = 240;
  c.screen_distance = 0.2;
  c.pixel_size = 1e-3;
  return c;
}

TEST(AviationCamera, RotationMatchesTheSeedsExplicitMatrix) {
  std::mt19937_64 rng(31);
  for (int t = 0; t < 2000; ++t) {
    const AviationCamera::Config c = random_config(rng);
    const glm::dmat3& a = AviationCamera(c).rotation();
    const SeedMatrix s = seed_matrix(c.yaw_deg * kDeg, c.pitch_deg * kDeg, c.roll_deg * kDeg);
    // GLM is column-major: a[column][row].
    const double expect[3][3] = {{s.xu, s.xv, s.xw}, {s.yu, s.yv, s.yw}, {s.zu, s.zv, s.zw}};
    for (int row = 0; row < 3; ++row) {
      for (int col = 0; col < 3; ++col) ASSERT_NEAR(a[col][row], expect[row][col], 1e-14) << t;
    }
  }
}

TEST(AviationCamera, GroundPointMatchesEquation239) {
  std::mt19937_64 rng(32);
  std::uniform_real_distribution<double> px(0, 320), py(0, 240);
  int checked = 0;
  for (int t = 0; t < 500; ++t) {
    const AviationCamera::Config c = random_config(rng);
    const AviationCamera cam(c);
    const ProjectiveMap m = cam.ground_map();
    const SeedMatrix s = seed_matrix(c.yaw_deg * kDeg, c.pitch_deg * kDeg, c.roll_deg * kDeg);
    const double u1 = c.screen_distance, ye0 = 120 * c.pixel_size, ze0 = 160 * c.pixel_size;
    const double c13 = s.zv * ye0 - s.zw * ze0 + s.zu * u1;
    const double c23 = s.xv * ye0 - s.xw * ze0 + s.xu * u1;
    const double c33 = s.yv * ye0 - s.yw * ze0 + s.yu * u1;
    for (int k = 0; k < 20; ++k) {
      const double xs = px(rng), ys = py(rng);
      const double ze = (xs + 0.5) * c.pixel_size, ye = (ys + 0.5) * c.pixel_size;
      const double den = s.yw * ze - s.yv * ye + c33;
      const double x = c.x - c.y * (s.xw * ze - s.xv * ye + c23) / den;  // eq. 2.39
      const double z = c.z - c.y * (s.zw * ze - s.zv * ye + c13) / den;
      double gx = 0, gz = 0;
      const bool hit = cam.ground_point(xs, ys, gx, gz);
      ASSERT_EQ(hit, den < 0) << t;  // the ray goes down iff V_y < 0
      if (!hit) continue;
      // Relative to the distance on the ground (grows without bound towards the horizon).
      const double scale = std::abs(x - c.x) + std::abs(z - c.z) + c.y;
      ASSERT_NEAR(gx, x, 1e-12 * scale) << t;
      ASSERT_NEAR(gz, z, 1e-12 * scale) << t;
      ASSERT_NEAR(static_cast<double>(m.u(xs, ys)), x, 1e-11 * scale) << t;
      ASSERT_NEAR(static_cast<double>(m.v(xs, ys)), z, 1e-11 * scale) << t;
      // Back to the screen: the vertex projection inverts the ground projection.
      ScreenVertex sv;
      ASSERT_TRUE(cam.project({gx, 0, gz}, sv));
      ASSERT_NEAR(sv.x, xs, 1e-9 * (1 + scale / c.y));
      ASSERT_NEAR(sv.y, ys, 1e-9 * (1 + scale / c.y));
      ++checked;
    }
  }
  EXPECT_GT(checked, 3000);
}

// The eye offset h (eq. 2.16, 2.20–2.21): h is given in the v frame and turned into the g frame
// by the seed's explicit rows A_x, A_y, A_z (eq. 2.38); the ground point is then eq. 2.39 with
// the eye r_h = r0 + A·h in place of r0. Leaving h unrotated (r0 + h) misses by metres.
TEST(AviationCamera, EyeOffsetMatchesEquation216) {
  std::mt19937_64 rng(33);
  std::uniform_real_distribution<double> px(0, 320), py(0, 240), off(-20, 20);
  int checked = 0;
  double unrotated_miss = 0;
  for (int t = 0; t < 300; ++t) {
    AviationCamera::Config c = random_config(rng);
    c.y += 25;  // stays above the ground with |h| <= 35
    c.eye_offset = {off(rng), off(rng), off(rng)};
    const AviationCamera cam(c);
    const SeedMatrix s = seed_matrix(c.yaw_deg * kDeg, c.pitch_deg * kDeg, c.roll_deg * kDeg);
    const glm::dvec3 h = c.eye_offset;
    const double xh = c.x + s.xu * h.x + s.xv * h.y + s.xw * h.z;  // eq. 2.20–2.21
    const double yh = c.y + s.yu * h.x + s.yv * h.y + s.yw * h.z;
    const double zh = c.z + s.zu * h.x + s.zv * h.y + s.zw * h.z;
    ASSERT_NEAR(cam.eye().x, xh, 1e-12 * (1 + std::abs(xh))) << t;
    ASSERT_NEAR(cam.eye().y, yh, 1e-12 * (1 + std::abs(yh))) << t;
    ASSERT_NEAR(cam.eye().z, zh, 1e-12 * (1 + std::abs(zh))) << t;
    const double u1 = c.screen_distance, ye0 = 120 * c.pixel_size, ze0 = 160 * c.pixel_size;
    const double c13 = s.zv * ye0 - s.zw * ze0 + s.zu * u1;
    const double c23 = s.xv * ye0 - s.xw * ze0 + s.xu * u1;
    const double c33 = s.yv * ye0 - s.yw * ze0 + s.yu * u1;
    const ProjectiveMap m = cam.ground_map();
    for (int k = 0; k < 10; ++k) {
      const double xs = px(rng), ys = py(rng);
      const double ze = (xs + 0.5) * c.pixel_size, ye = (ys + 0.5) * c.pixel_size;
      const double den = s.yw * ze - s.yv * ye + c33;
      const double rx = (s.xw * ze - s.xv * ye + c23) / den,
                   rz = (s.zw * ze - s.zv * ye + c13) / den;
      double gx = 0, gz = 0;
      const bool hit = cam.ground_point(xs, ys, gx, gz);
      ASSERT_EQ(hit, den < 0 && yh > 0) << t;
      if (!hit) continue;
      const double x = xh - yh * rx, z = zh - yh * rz;  // eq. 2.39 from the eye r_h
      const double scale = std::abs(x - xh) + std::abs(z - zh) + yh;
      ASSERT_NEAR(gx, x, 1e-12 * scale) << t;
      ASSERT_NEAR(gz, z, 1e-12 * scale) << t;
      ASSERT_NEAR(static_cast<double>(m.u(xs, ys)), x, 1e-11 * scale) << t;
      ASSERT_NEAR(static_cast<double>(m.v(xs, ys)), z, 1e-11 * scale) << t;
      ScreenVertex sv;  // the vertex projection starts at the same eye
      ASSERT_TRUE(cam.project({gx, 0, gz}, sv));
      ASSERT_NEAR(sv.x, xs, 1e-9 * (1 + scale / yh));
      ASSERT_NEAR(sv.y, ys, 1e-9 * (1 + scale / yh));
      // The wrong model, h taken as g-frame components.
      const double wy = c.y + h.y;
      if (wy > 0) unrotated_miss = std::max(unrotated_miss, std::abs(c.x + h.x - wy * rx - x));
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(unrotated_miss, 1.0);
  // h = 0 leaves every result of the camera as it was (the eye is r0).
  AviationCamera::Config c;
  c.x = 3;
  c.z = -4;
  const AviationCamera plain(c);
  EXPECT_EQ(plain.eye(), glm::dvec3(3, 100, -4));
  EXPECT_EQ(plain.setup_ops().mul, 16u);
  c.eye_offset = {1, 0, 0};
  EXPECT_EQ(AviationCamera(c).setup_ops().mul, 16u + 9u);
}

TEST(AviationCamera, DirectedCases) {
  AviationCamera::Config c;
  c.yaw_deg = c.pitch_deg = c.roll_deg = 0;
  const AviationCamera level(c);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) EXPECT_DOUBLE_EQ(level.rotation()[i][j], i == j ? 1 : 0);
  }
  // Level flight: the screen's upper half sees the sky, the lower half the ground.
  double gx = 0, gz = 0;
  EXPECT_FALSE(level.ground_point(255.5, 100, gx, gz));
  EXPECT_TRUE(level.ground_point(255.5, 400, gx, gz));
  // Pitch -90°: looking straight down, the screen centre sees the point below the eye.
  c.pitch_deg = -90;
  c.x = 7;
  c.z = -3;
  const AviationCamera down(c);
  ASSERT_TRUE(down.ground_point(255.5, 255.5, gx, gz));
  EXPECT_NEAR(gx, 7, 1e-12);
  EXPECT_NEAR(gz, -3, 1e-12);
  // Behind the eye: rejected.
  ScreenVertex sv;
  EXPECT_FALSE(level.project({-10, 100, 0}, sv));
  EXPECT_TRUE(level.project({10, 100, 0}, sv));
  EXPECT_NEAR(sv.x, 255.5, 1e-12);  // on the view axis: the screen centre
  EXPECT_NEAR(sv.y, 255.5, 1e-12);
  EXPECT_NEAR(sv.w, 10, 1e-12);
}

TEST(AviationCamera, ConfigAndBlockContract) {
  const toml::table t = toml::parse("yaw_deg = 30\npitch_deg = -10\nwidth = 64\n");
  const AviationCamera::Config c =
      AviationCamera::Config::from_toml(ConfigReader(t, "s.toml", "camera"));
  EXPECT_EQ(c.width, 64);
  EXPECT_DOUBLE_EQ(c.yaw_deg, 30);
  const toml::table bad = toml::parse("screen_distance = 0\n");
  EXPECT_THROW(AviationCamera::Config::from_toml(ConfigReader(bad, "s.toml", "camera")),
               InputError);
  const toml::table off = toml::parse("eye_offset = [1, -2.5, 3]\n");
  EXPECT_EQ(AviationCamera::Config::from_toml(ConfigReader(off, "s.toml", "camera")).eye_offset,
            glm::dvec3(1, -2.5, 3));
  for (const char* b : {"eye_offset = [1, 2]\n", "eye_offset = [1, \"a\", 3]\n",
                        "eye_offset = [1, nan, 3]\n", "eye_offset = 2\n"}) {
    const toml::table e = toml::parse(b);
    EXPECT_THROW(AviationCamera::Config::from_toml(ConfigReader(e, "s.toml", "camera")), InputError)
        << b;
  }
  const toml::table typo = toml::parse("yaw = 3\n");
  EXPECT_THROW(AviationCamera::Config::from_toml(ConfigReader(typo, "s.toml", "camera")),
               InputError);
  const AviationCamera cam(c);
  EXPECT_EQ(cam.ops_per_item().div, 1u);  // one division per vertex
  EXPECT_EQ(cam.ops_per_item().mul, 13u);
  EXPECT_EQ(cam.ground_point_ops().rcp, 1u);
  EXPECT_GE(cam.timing(TechTable::defaults()).latency, 1u);
  EXPECT_EQ(cam.name(), "geometry.aviation_camera");
}

}  // namespace
}  // namespace texsim
