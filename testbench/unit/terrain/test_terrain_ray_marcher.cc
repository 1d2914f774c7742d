// Reverse ray marching of finite-function terrain from the aviation camera: flat ground
// against the camera's own ground projection, a raised plane against its closed form, smooth
// terrain against a long double fine-step march, normals, the horizon and the iteration cap.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <random>
#include <vector>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/base/tech_table.h"
#include "blocks/texture/relief/terrain_ray_marcher.h"

namespace texsim {
namespace {

AviationCamera camera(double y, double pitch, double yaw = 30) {
  AviationCamera::Config c;
  c.x = 20;
  c.y = y;
  c.z = 20;
  c.yaw_deg = yaw;
  c.pitch_deg = pitch;
  c.roll_deg = 5;
  c.width = 64;
  c.height = 48;
  c.screen_distance = 48;
  return AviationCamera(c);
}

TEST(TerrainRayMarcher, FlatGroundMatchesTheCameraGroundPoint) {
  const TerrainGrid g(64, 64, 0.0F);
  const AviationCamera cam = camera(10, -30);
  const TerrainRayMarcher m;
  int hits = 0;
  for (int ys = 0; ys < 48; ys += 3) {
    for (int xs = 0; xs < 64; xs += 3) {
      OpCounts ops;
      const auto r = m.march(cam, g, m.top_bound(g), xs, ys, ops);
      double gx = 0, gz = 0;
      if (!cam.ground_point(xs, ys, gx, gz)) {
        EXPECT_FALSE(r.hit);
        continue;
      }
      if (gx < 0 || gx > 63 || gz < 0 || gz > 63) continue;  // the grid clamps beyond its edge
      ASSERT_TRUE(r.hit) << xs << ' ' << ys;
      ++hits;
      // The bracket after the bisections bounds the error along the (unit) ray.
      const double tol = m.config().step / std::ldexp(1.0, m.config().refine_steps) + 1e-12;
      EXPECT_NEAR(r.point.x, gx, tol);
      EXPECT_NEAR(r.point.z, gz, tol);
      EXPECT_NEAR(r.normal.y, 1.0, 1e-12);
      EXPECT_EQ(r.fetches, 4 * r.evaluations);
      EXPECT_EQ(r.evaluations, r.steps + r.refinements + 1);
    }
  }
  EXPECT_GT(hits, 100);
}

TEST(TerrainRayMarcher, RaisedPlaneMatchesClosedForm) {
  // Constant heights: every finite function (and variant 2) reproduces the plane exactly.
  const TerrainGrid g(64, 64, 5.0F);
  const AviationCamera cam = camera(25, -40);
  for (const Deformation d : {Deformation::None, Deformation::Blended}) {
    TerrainRayMarcher::Config c;
    c.evaluator.basis.deformation = d;
    const TerrainRayMarcher m(c);
    OpCounts ops;
    const auto r = m.march(cam, g, m.top_bound(g), 32, 24, ops);
    ASSERT_TRUE(r.hit);
    const glm::dvec3 v = glm::normalize(cam.view_vector(32, 24));
    const double t = (25 - 5) / -v.y;
    EXPECT_NEAR(r.t, t, c.step / 1024 + 1e-12);
    // The skip to the top of the field: the first step is already at the plane.
    EXPECT_LE(r.steps, 2U);
  }
}

// A smooth random terrain and a long double march with 1/64 of the step, then 60 bisections.
TerrainGrid smooth_grid(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(0.0F, 3.0F);
  TerrainGrid g(48, 48);
  for (auto& v : g.h) v = u(rng);
  return g;
}

long double reference_t(const TerrainRayMarcher& m, const AviationCamera& cam, const TerrainGrid& g,
                        double xs, double ys) {
  const glm::dvec3 v = glm::normalize(cam.view_vector(xs, ys));
  const glm::dvec3 e = cam.eye();
  OpCounts ops;
  auto below = [&](long double t) {
    const long double x = e.x + t * v.x, y = e.y + t * v.y, z = e.z + t * v.z;
    return y < m.evaluator().height(g, static_cast<double>(x), static_cast<double>(z), ops);
  };
  const long double dt = m.config().step / 64.0L;
  long double t = 0;
  for (; t < 500 && !below(t); t += dt) {
  }
  if (t >= 500) return -1;
  long double lo = t - dt, hi = t;
  for (int k = 0; k < 60; ++k) {
    const long double mid = (lo + hi) / 2;
    (below(mid) ? hi : lo) = mid;
  }
  return hi;
}

TEST(TerrainRayMarcher, SmoothTerrainMatchesFineReference) {
  const TerrainGrid g = smooth_grid(4);
  const AviationCamera cam = camera(8, -25);
  TerrainRayMarcher::Config c;
  c.step = 0.05;
  const TerrainRayMarcher m(c);
  int agree = 0, n = 0;
  for (int ys = 20; ys < 48; ys += 4) {
    for (int xs = 0; xs < 64; xs += 4) {
      OpCounts ops;
      const auto r = m.march(cam, g, m.top_bound(g), xs, ys, ops);
      const long double ref = reference_t(m, cam, g, xs, ys);
      if (ref < 0 || !r.hit) continue;
      ++n;
      agree += std::fabs(r.t - static_cast<double>(ref)) <= c.step / 1024 + 1e-9;
    }
  }
  // A step of dt can jump over a ridge thinner than dt: the coarse march then hits later.
  EXPECT_GT(n, 50);
  EXPECT_GE(agree, n * 95 / 100);
}

TEST(TerrainRayMarcher, CentralDifferenceNormalNearGradient) {
  const TerrainGrid g = smooth_grid(8);
  const AviationCamera cam = camera(8, -25);
  TerrainRayMarcher::Config grad, cd;
  cd.normal = TerrainRayMarcher::NormalMode::CentralDifference;
  const TerrainRayMarcher mg(grad), mc(cd);
  for (int xs = 0; xs < 64; xs += 7) {
    OpCounts ops;
    const auto a = mg.march(cam, g, mg.top_bound(g), xs, 40, ops);
    const auto b = mc.march(cam, g, mc.top_bound(g), xs, 40, ops);
    ASSERT_EQ(a.hit, b.hit);
    if (!a.hit) continue;
    EXPECT_GT(glm::dot(a.normal, b.normal), 1 - 1e-4);
    EXPECT_EQ(b.evaluations, a.evaluations + 3);
  }
}

TEST(TerrainRayMarcher, HorizonAndCap) {
  const TerrainGrid g(32, 32, 1.0F);
  const AviationCamera level = camera(10, 0);
  const TerrainRayMarcher m;
  OpCounts ops;
  const auto sky = m.march(level, g, m.top_bound(g), 32, 0, ops);  // above the horizon
  EXPECT_FALSE(sky.hit);
  EXPECT_EQ(sky.steps, 0U);
  TerrainRayMarcher::Config c;
  c.max_steps = 3;
  c.step = 0.01;
  const auto capped = TerrainRayMarcher(c).march(camera(10, -20), g, 5.0, 32, 24, ops);
  EXPECT_TRUE(capped.capped);
  EXPECT_FALSE(capped.hit);
  EXPECT_EQ(capped.steps, 3U);
  EXPECT_GE(m.timing(TechTable::defaults()).latency, 1U);
}

// The altitude-dependent step max(dt, k·(Y - y)): low rolling ground (0–2) with a few peaks of
// 15 (so the march starts high, at the top bound), seen from 25 up at pitch -20°. Against a
// march with dt/4 (30 bisections, no cap in reach): the steps saved, the hits on the same
// surface (|Δt| <= 1e-3), those that crossed a ridge (later), and the rays the 4096-step cap
// stopped before the ground (dt = 0.05 reaches 205 units).
TEST(TerrainRayMarcher, AltitudeStepSavesStepsAtMeasuredError) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<float> u(0.0F, 2.0F);
  TerrainGrid g(96, 96);
  for (auto& v : g.h) v = u(rng);
  for (int k = 0; k < 6; ++k) g.h[static_cast<size_t>(rng() % g.h.size())] = 15.0F;
  const AviationCamera cam = camera(25, -20, 45);
  TerrainRayMarcher::Config fine;
  fine.step = 0.05 / 4;
  fine.refine_steps = 30;
  fine.max_steps = 1 << 20;
  const TerrainRayMarcher ref(fine);
  std::vector<TerrainRayMarcher::Result> refs;
  for (int ys = 0; ys < 48; ys += 3) {
    for (int xs = 0; xs < 64; xs += 3) {
      OpCounts ops;
      refs.push_back(ref.march(cam, g, ref.top_bound(g), xs, ys, ops));
    }
  }
  uint64_t steps_off = 0;
  for (double k : {0.0, 0.25, 0.5, 1.0, 2.0}) {
    TerrainRayMarcher::Config c;
    c.step = 0.05;
    c.altitude_step = k;
    const TerrainRayMarcher m(c);
    uint64_t steps = 0;
    int n = 0, same = 0, later = 0, capped = 0;
    double worst_same = 0;
    size_t i = 0;
    for (int ys = 0; ys < 48; ys += 3) {
      for (int xs = 0; xs < 64; xs += 3) {
        OpCounts ops;
        const auto r = m.march(cam, g, m.top_bound(g), xs, ys, ops);
        const auto& f = refs[i++];
        steps += r.steps;
        if (!f.hit) continue;
        ++n;
        const double d = r.hit ? std::fabs(r.t - f.t) : 1e9;
        if (d <= 1e-3) {
          ++same;
          worst_same = std::max(worst_same, d);
        } else {
          later += r.hit && r.t > f.t;
          capped += r.capped;
        }
      }
    }
    if (k == 0) steps_off = steps;
    std::printf(
        "k = %.2f: steps %llu (%.2fx fewer), same surface %d / %d (worst |dt| %.1e), "
        "later %d, capped %d, other %d\n",
        k, static_cast<unsigned long long>(steps),
        static_cast<double>(steps_off) / static_cast<double>(steps), same, n, worst_same, later,
        capped, n - same - later - capped);
    ASSERT_GT(n, 250);
    EXPECT_EQ(n, same + later + capped);  // never an earlier hit: a step never lands inside
    if (k > 0) {
      EXPECT_LT(steps, steps_off);
    }
    if (k == 0.5) {
      EXPECT_LT(steps * 8, steps_off);
      EXPECT_GE(same, n * 98 / 100);
    }
    if (k == 2.0) {
      EXPECT_GT(later, n / 4);  // too long: steps cross the rising ground
    }
  }
  // The op counts follow the key: one multiply and one max more per step.
  TerrainRayMarcher::Config on;
  on.altitude_step = 0.5;
  EXPECT_EQ(TerrainRayMarcher(on).ops_per_item().mul, TerrainRayMarcher().ops_per_item().mul + 1);
}

TEST(TerrainRayMarcher, ConfigsReadAndReject) {
  const toml::table t =
      toml::parse("step = 0.5\nnormal = \"central\"\ndeformation = \"widened\"\n");
  const auto c = TerrainRayMarcher::Config::from_toml(ConfigReader(t, "s.toml", "terrain"));
  EXPECT_DOUBLE_EQ(c.step, 0.5);
  EXPECT_EQ(c.normal, TerrainRayMarcher::NormalMode::CentralDifference);
  EXPECT_EQ(TerrainRayMarcher(c).evaluator().fetches_per_item(), 9);
  const toml::table a = toml::parse("altitude_step = 0.5\n");
  EXPECT_DOUBLE_EQ(
      TerrainRayMarcher::Config::from_toml(ConfigReader(a, "s.toml", "terrain")).altitude_step,
      0.5);
  for (const char* bad : {"step = 0\n", "normal_epsilon = 2\n", "steps = 3\n",
                          "altitude_step = -1\n", "altitude_step = nan\n"}) {
    const toml::table b = toml::parse(bad);
    EXPECT_THROW(TerrainRayMarcher::Config::from_toml(ConfigReader(b, "s.toml", "terrain")),
                 InputError);
  }
}

}  // namespace
}  // namespace texsim
