// Ground models of the flight camera's ray casting (seed 003 §2.2, examples 1 and 2): the
// spherical Earth and the piecewise-planar surface against long double references, their hard
// cases, the seed's eq. 2.8 read as a fixed-point iteration, the erratum in its dc, and the
// per-pixel error and cost over a flight view (docs/derivations/terrain.md §8).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <utility>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/base/tech_table.h"
#include "blocks/geometry/aviation_camera.h"
#include "blocks/geometry/plane_ground.h"
#include "blocks/geometry/sphere_ground.h"

namespace texsim {
namespace {

constexpr double kEarth = 6371000.0;
using LD = long double;

// Reference: the textbook root in long double (64-bit significand: R² = 4.1e13 m² is held to
// ~2e-6 m², far below every float and double error measured here); NaN when it misses.
LD sphere_reference(const glm::dvec3& e, const glm::dvec3& v, double radius) {
  const LD r = radius, ex = e.x, ey = e.y, ez = e.z, vx = v.x, vy = v.y, vz = v.z;
  const LD oy = ey + r;
  const LD a = vx * vx + vy * vy + vz * vz, b = ex * vx + oy * vy + ez * vz;
  const LD c = ex * ex + oy * oy + ez * ez - r * r;
  const LD disc = b * b - a * c;
  if (!(c > 0) || !(b < 0) || disc < 0) return std::numeric_limits<LD>::quiet_NaN();
  return (-b - std::sqrt(disc)) / a;
}

SphereGround sphere(SphereGround::Form f, int iterations = 64) {
  SphereGround::Config c;
  c.form = f;
  c.max_iterations = iterations;
  return SphereGround(c);
}

// Distance between the points at λ and λ_ref along V, relative to the reference's range.
double rel_err(double lambda, LD ref) {
  return static_cast<double>(std::fabs(static_cast<LD>(lambda) - ref) / ref);
}

TEST(SphereGround, FormsAgainstLongDoubleOnRandomRays) {
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> alt(0, 4), pos(-5e4, 5e4), dz(-1, 1), down(0.01, 1);
  const SphereGround stable = sphere(SphereGround::Form::Stable);
  const SphereGround textbook = sphere(SphereGround::Form::Textbook);
  const SphereGround seed = sphere(SphereGround::Form::SeedIteration, 200);
  double worst_d = 0, worst_f = 0, worst_tf = 0, worst_seed = 0;
  int n = 0, seed_open = 0;
  for (int t = 0; t < 20000; ++t) {
    const glm::dvec3 e(pos(rng), std::pow(10.0, alt(rng)), pos(rng));  // 1 m to 10 km up
    const glm::dvec3 v(dz(rng), -down(rng), dz(rng));
    const LD ref = sphere_reference(e, v, kEarth);
    const auto hd = stable.intersect<double>(e, v);
    ASSERT_EQ(hd.hit, !std::isnan(ref)) << t;
    if (!hd.hit) continue;
    worst_d = std::max(worst_d, rel_err(hd.lambda, ref));
    const auto hf = stable.intersect<float>(e, v);
    ASSERT_TRUE(hf.hit) << t;
    worst_f = std::max(worst_f, rel_err(hf.lambda, ref));
    const auto ht = textbook.intersect<float>(e, v);
    worst_tf = std::max(worst_tf, ht.hit ? rel_err(ht.lambda, ref) : 1.0);
    const auto hs = seed.intersect<double>(e, v);
    if (hs.hit)
      worst_seed = std::max(worst_seed, rel_err(hs.lambda, ref));
    else
      ++seed_open;
    ++n;
  }
  std::printf(
      "random rays %d: stable double %.2e, stable float %.2e, textbook float %.2e, "
      "seed iteration (double) %.2e (%d not converged in 200)\n",
      n, worst_d, worst_f, worst_tf, worst_seed, seed_open);
  EXPECT_GT(n, 15000);
  // The worst rays graze the sphere (λ is ill-conditioned there: the relative error grows as
  // 1/√disc); away from grazing double stays near 1e-15.
  EXPECT_LT(worst_d, 1e-12);
  EXPECT_LT(worst_f, 1e-5);
  EXPECT_GT(worst_tf, 0.1);  // the R² cancellation: low eyes lose every digit in float
  EXPECT_LT(worst_seed, 1e-11);
}

// The hard cases: grazing, above and at the horizon, starting inside or on the sphere, V = 0,
// NaN and Inf, and the seed's iteration where the ray misses.
TEST(SphereGround, HardCases) {
  const double h = 1000, r = kEarth;
  const glm::dvec3 eye(0, h, 0);
  // The tangent from the eye: it touches the sphere at distance s = √(h(2R + h)), dipping
  // below the horizontal by atan(s/R).
  const double s = std::sqrt(h * (2 * r + h));
  const glm::dvec3 tangent(r, -s, 0);
  for (auto form : {SphereGround::Form::Stable, SphereGround::Form::Textbook,
                    SphereGround::Form::SeedIteration}) {
    const SphereGround g = sphere(form, 100000);
    SCOPED_TRACE(static_cast<int>(form));
    // Just below the tangent: hits near the tangent point (the seed's iteration crawls there:
    // its rate 1 - √(1 - 2h/(R·s²)) tends to 1).
    const glm::dvec3 below(tangent.x, tangent.y * (1 + 1e-6), 0);
    const auto hb = g.intersect<double>(eye, below);
    const LD ref = sphere_reference(eye, below, r);
    ASSERT_TRUE(hb.hit);
    EXPECT_LT(rel_err(hb.lambda, ref), 1e-9);
    if (form == SphereGround::Form::SeedIteration) {
      std::printf("seed iteration 1e-6 below the tangent: %d iterations\n", hb.iterations);
      EXPECT_GT(hb.iterations, 1000);
    }
    // Above the tangent (towards the sky over the horizon) and level: miss.
    EXPECT_FALSE(g.intersect<double>(eye, {tangent.x, tangent.y * (1 - 1e-6), 0}).hit);
    EXPECT_FALSE(g.intersect<double>(eye, {1, 0, 0}).hit);
    EXPECT_FALSE(g.intersect<double>(eye, {0, 1, 0}).hit);
    // Straight down: λ = h exactly enough.
    const auto hd = g.intersect<double>(eye, {0, -1, 0});
    ASSERT_TRUE(hd.hit);
    EXPECT_NEAR(hd.lambda, h, 1e-9);
    // On or below the surface, V = 0, non-finite inputs: no hit, no crash.
    EXPECT_FALSE(g.intersect<double>({0, 0, 0}, {0, -1, 0}).hit);
    EXPECT_FALSE(g.intersect<double>({0, -5, 0}, {0, -1, 0}).hit);
    EXPECT_FALSE(g.intersect<double>(eye, {0, 0, 0}).hit);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_FALSE(g.intersect<double>({nan, h, 0}, {0, -1, 0}).hit);
    EXPECT_FALSE(g.intersect<double>(eye, {0, -inf, 0}).hit);
    EXPECT_FALSE(g.intersect<float>({0, 1e39, 0}, {0, -1, 0}).hit);  // overflows float
  }
  // The seed's iteration on a ray that misses converges too: to the spurious root where the
  // ray crosses Y = -R (dc = R there), which the block rejects (|q| > R there).
  const SphereGround seed = sphere(SphereGround::Form::SeedIteration, 1000);
  const glm::dvec3 over(tangent.x, tangent.y * 0.99, 0);
  EXPECT_FALSE(seed.intersect<double>(eye, over).hit);
  EXPECT_FALSE(sphere_reference(eye, over, r) > 0);
  // The spurious root itself: λ with Y_h + λV_y = -R solves eq. 2.8's fixed point.
  const double ls = (h + r) / -over.y;
  const double px = ls * over.x, py = h + ls * over.y;
  const double qy = py + r, q = std::hypot(px, qy);
  EXPECT_NEAR((h + r * (1 - qy / q)) / -over.y, ls, 1e-9 * ls);
}

// Eq. 2.6–2.7: for a point P of the sphere, r·n = dc = R(1 - cos α) with α the angle at the
// centre between the radii to P and to the origin, and β the angle between r and r1:
// dc = 2R cos²β. The printed "dc = 2R·cos 2β" is off (it is -2R cos α).
TEST(SphereGround, SeedsDcIsTwoRCosSquaredBeta) {
  const double r = 1000;
  const glm::dvec3 r1(0, -r, 0), n(0, -1, 0);
  double worst_sq = 0, best_printed = 1e300;
  for (double alpha = 0.05; alpha < 3.0; alpha += 0.05) {
    const glm::dvec3 p(r * std::sin(alpha), -r + r * std::cos(alpha), 0);
    const double rn = p.x * n.x + p.y * n.y + p.z * n.z;
    const double beta =
        std::acos((p.x * r1.x + p.y * r1.y + p.z * r1.z) / (std::hypot(p.x, p.y, p.z) * r));
    EXPECT_NEAR(rn, r * (1 - std::cos(alpha)), 1e-9);
    worst_sq = std::max(worst_sq, std::fabs(rn - 2 * r * std::cos(beta) * std::cos(beta)));
    best_printed = std::min(best_printed, std::fabs(rn - 2 * r * std::cos(2 * beta)));
  }
  EXPECT_LT(worst_sq, 1e-9);
  EXPECT_GT(best_printed, 1.0);
}

// The flight view: every pixel of a 320 × 240 aviation camera, eye h up, pitch -2°, ψ = 30°,
// γ = 5°, 50° vertical field. Per model and format: pixels that hit, the worst relative error
// of λ against long double, and the flat ground's distance error against the sphere.
struct ViewStats {
  int hits = 0, seed_not_converged = 0, seed_spurious = 0;
  double worst_d = 0, worst_f = 0, worst_tf = 0, worst_seed = 0, flat_miss_m = 0;
  double seed_mean_iter = 0;
  int seed_max_iter = 0;
};

ViewStats flight_view(double h) {
  AviationCamera::Config c;
  c.y = h;
  c.yaw_deg = 30;
  c.pitch_deg = -2;
  c.roll_deg = 5;
  c.width = 320;
  c.height = 240;
  c.screen_distance = 120 / std::tan(25 * M_PI / 180);
  const AviationCamera cam(c);
  const SphereGround stable = sphere(SphereGround::Form::Stable);
  const SphereGround textbook = sphere(SphereGround::Form::Textbook);
  const SphereGround seed = sphere(SphereGround::Form::SeedIteration, 64);
  ViewStats st;
  long iters = 0;
  for (int j = 0; j < c.height; ++j) {
    for (int i = 0; i < c.width; ++i) {
      const glm::dvec3 v = cam.view_vector(i, j);
      const LD ref = sphere_reference(cam.eye(), v, kEarth);
      const auto hd = stable.intersect<double>(cam.eye(), v);
      EXPECT_EQ(hd.hit, !std::isnan(ref)) << i << "," << j;
      const auto hs = seed.intersect<double>(cam.eye(), v);
      if (!hd.hit) {
        st.seed_spurious += hs.hit;
        continue;
      }
      ++st.hits;
      st.worst_d = std::max(st.worst_d, rel_err(hd.lambda, ref));
      const auto hf = stable.intersect<float>(cam.eye(), v);
      st.worst_f = std::max(st.worst_f, hf.hit ? rel_err(hf.lambda, ref) : 1.0);
      const auto ht = textbook.intersect<float>(cam.eye(), v);
      st.worst_tf = std::max(st.worst_tf, ht.hit ? rel_err(ht.lambda, ref) : 1.0);
      if (!hs.hit) {
        ++st.seed_not_converged;
      } else {
        st.worst_seed = std::max(st.worst_seed, rel_err(hs.lambda, ref));
        iters += hs.iterations;
        st.seed_max_iter = std::max(st.seed_max_iter, hs.iterations);
      }
      double gx = 0, gz = 0;  // the flat ground Y = 0 (eq. 2.26–2.27) at the same pixel
      if (cam.ground_point(i, j, gx, gz)) {
        const double px = cam.eye().x + static_cast<double>(ref) * v.x;
        const double pz = cam.eye().z + static_cast<double>(ref) * v.z;
        st.flat_miss_m = std::max(st.flat_miss_m, std::hypot(gx - px, gz - pz));
      }
    }
  }
  const int conv = st.hits - st.seed_not_converged;
  st.seed_mean_iter = conv > 0 ? static_cast<double>(iters) / conv : 0;
  return st;
}

TEST(SphereGround, FlightViewErrorAndIterations) {
  for (double h : {100.0, 1000.0, 10000.0}) {
    const ViewStats s = flight_view(h);
    std::printf(
        "h %6.0f m: hits %d; rel. err. stable double %.1e, stable float %.1e, "
        "textbook float %.1e; seed iteration: mean %.1f, max %d iterations, %d not "
        "converged in 64, worst %.1e; flat ground off by up to %.0f m\n",
        h, s.hits, s.worst_d, s.worst_f, s.worst_tf, s.seed_mean_iter, s.seed_max_iter,
        s.seed_not_converged, s.worst_seed, s.flat_miss_m);
    EXPECT_GT(s.hits, 30000);
    EXPECT_LT(s.worst_d, 1e-9);
    EXPECT_LT(s.worst_f, 1e-2);
    EXPECT_LT(s.worst_seed, 1e-9);
    EXPECT_EQ(s.seed_spurious, 0);  // sky pixels: the spurious root is rejected
  }
}

// Example 2: planes n·r = d against long double, a two-piece surface, the hard cases.
TEST(PlaneGround, PlanesAgainstLongDoubleAndHardCases) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1, 1), pos(-1e3, 1e3);
  double worst_d = 0, worst_f = 0;
  int n = 0;
  for (int t = 0; t < 5000; ++t) {
    PlaneGround::Config c;
    c.elements[0].n = glm::dvec3(u(rng), 1 + u(rng), u(rng));
    c.elements[0].n /=
        std::sqrt(c.elements[0].n.x * c.elements[0].n.x + c.elements[0].n.y * c.elements[0].n.y +
                  c.elements[0].n.z * c.elements[0].n.z);
    c.elements[0].d = pos(rng) / 10;
    const PlaneGround g(c);
    const glm::dvec3 e(pos(rng), 50 + pos(rng) / 2 + 600, pos(rng)),
        v(u(rng), -0.5 + u(rng), u(rng));
    const PlaneGround::Element& el = c.elements[0];
    const LD f =
        static_cast<LD>(el.d) - (static_cast<LD>(el.n.x) * e.x + static_cast<LD>(el.n.y) * e.y +
                                 static_cast<LD>(el.n.z) * e.z);
    const LD gg = static_cast<LD>(el.n.x) * v.x + static_cast<LD>(el.n.y) * v.y +
                  static_cast<LD>(el.n.z) * v.z;
    const LD ref = f / gg;
    const auto hd = g.intersect<double>(e, v);
    ASSERT_EQ(hd.hit, ref > 0) << t;
    if (!hd.hit) continue;
    worst_d = std::max(worst_d, rel_err(hd.lambda, ref));
    const auto hf = g.intersect<float>(e, v);
    if (hf.hit) worst_f = std::max(worst_f, rel_err(hf.lambda, ref));
    ++n;
  }
  std::printf("planes %d: worst relative error of λ: double %.1e, float %.1e\n", n, worst_d,
              worst_f);
  EXPECT_GT(n, 1000);
  EXPECT_LT(worst_d, 1e-9);  // F/G: relative error grows as 1/|G| (rays nearly parallel)
  const glm::dvec3 eye(0, 10, 0);
  const PlaneGround flat;  // the default: Y = 0, unbounded (eq. 2.14)
  const auto h = flat.intersect<double>(eye, {3, -1, 4});
  ASSERT_TRUE(h.hit);
  EXPECT_DOUBLE_EQ(h.lambda, 10);
  EXPECT_FALSE(flat.intersect<double>(eye, {1, 0, 0}).hit);         // parallel: G = 0
  EXPECT_FALSE(flat.intersect<double>(eye, {1, 1e-300, 0}).hit);    // away from it
  EXPECT_FALSE(flat.intersect<double>({0, 0, 0}, {1, -1, 0}).hit);  // starting on it
  EXPECT_FALSE(flat.intersect<double>(eye, {1, -1e-310, 0}).hit);   // λ overflows
  EXPECT_FALSE(flat.intersect<double>(eye, {std::nan(""), -1, 0}).hit);
  EXPECT_FALSE(flat.intersect<float>(eye, {1, -1e-300, 0}).hit);  // V_y underflows in float
  // Two pieces: a raised block (Y = 5 over X in [10, 20]) on the ground; the nearest wins.
  PlaneGround::Config two;
  two.elements.push_back({{0, 1, 0}, 5, 10, 20, -1e9, 1e9});
  const PlaneGround step(two);
  const auto hs = step.intersect<double>(eye, {3, -1, 0});  // meets Y = 5 at X = 15
  ASSERT_TRUE(hs.hit);
  EXPECT_EQ(hs.element, 1);
  EXPECT_DOUBLE_EQ(hs.lambda, 5);
  const auto hg = step.intersect<double>(eye, {1, -1, 0});  // ground at X = 10 < the block's 5
  EXPECT_EQ(hg.element, 0);
  EXPECT_DOUBLE_EQ(hg.lambda, 10);
}

// The flat model as a plane element equals the camera's own ground projection.
TEST(PlaneGround, FlatElementEqualsTheCamerasGroundPoint) {
  AviationCamera::Config c;
  c.y = 60;
  c.yaw_deg = 30;
  c.pitch_deg = -12;
  c.roll_deg = 8;
  c.eye_offset = {2, 1.5, -1};
  const AviationCamera cam(c);
  const PlaneGround flat;
  int hits = 0;
  for (int j = 0; j < 512; j += 13) {
    for (int i = 0; i < 512; i += 11) {
      double gx = 0, gz = 0;
      const bool a = cam.ground_point(i, j, gx, gz);
      const glm::dvec3 v = cam.view_vector(i, j);
      const auto h = flat.intersect<double>(cam.eye(), v);
      ASSERT_EQ(a, h.hit);
      if (!a) continue;
      EXPECT_NEAR(cam.eye().x + h.lambda * v.x, gx, 1e-9 * (1 + std::fabs(gx)));
      EXPECT_NEAR(cam.eye().z + h.lambda * v.z, gz, 1e-9 * (1 + std::fabs(gz)));
      ++hits;
    }
  }
  EXPECT_GT(hits, 500);
}

TEST(GroundModels, ConfigAndBlockContract) {
  const toml::table t = toml::parse("radius = 1000.0\nform = \"seed_iteration\"\n");
  const auto sc = SphereGround::Config::from_toml(ConfigReader(t, "s.toml", "ground"));
  EXPECT_EQ(sc.form, SphereGround::Form::SeedIteration);
  EXPECT_DOUBLE_EQ(sc.radius, 1000);
  for (const char* b : {"radius = 0.0\n", "form = \"exact\"\n", "radius = nan\n", "r = 1\n"}) {
    const toml::table e = toml::parse(b);
    EXPECT_THROW(SphereGround::Config::from_toml(ConfigReader(e, "s.toml", "ground")), InputError)
        << b;
  }
  const toml::table p = toml::parse(
      "elements = [{ normal = [0, 2, 0], d = 1.5 }, { normal = [1, 1, 0], d = 0, x = [0, 10] }]\n");
  const auto pc = PlaneGround::Config::from_toml(ConfigReader(p, "s.toml", "ground"));
  ASSERT_EQ(pc.elements.size(), 2u);
  EXPECT_DOUBLE_EQ(pc.elements[0].n.y, 1);  // normalised
  EXPECT_DOUBLE_EQ(pc.elements[1].x1, 10);
  for (const char* b : {"elements = []\n", "elements = [{ normal = [0, 0, 0] }]\n",
                        "elements = [{ normal = [0, 1] }]\n", "elements = [{ x = [2, 1] }]\n",
                        "elements = [{ dd = 1 }]\n", "elements = [1]\n"}) {
    const toml::table e = toml::parse(b);
    EXPECT_THROW(PlaneGround::Config::from_toml(ConfigReader(e, "s.toml", "ground")), InputError)
        << b;
  }
  const TechTable tech = TechTable::defaults();
  const SphereGround s;
  EXPECT_EQ(s.ops_per_item().sqrt, 1u);
  EXPECT_EQ(s.ops_per_item().div, 1u);
  EXPECT_EQ(s.ops_per_item().mul, 8u);
  EXPECT_GE(s.timing(tech).latency, 1u);
  EXPECT_EQ(s.name(), "geometry.sphere_ground");
  const PlaneGround g;
  EXPECT_EQ(g.ops_per_item().div, 1u);
  EXPECT_EQ(g.ops_per_item().mul, 5u);
  EXPECT_GE(g.timing(tech).latency, 1u);
  EXPECT_LT(g.timing(tech).latency, s.timing(tech).latency);  // no root
  EXPECT_EQ(g.name(), "geometry.plane_ground");
  const SphereGround it = sphere(SphereGround::Form::SeedIteration);
  for (const auto& [name, ts] :
       {std::pair{"sphere stable", s.timing(tech)},
        std::pair{"sphere seed iteration (per iteration)", it.timing(tech)},
        std::pair{"plane element", g.timing(tech)}}) {
    std::printf("%s: latency %u cycles, II %u, area %.0f adder-equivalents\n", name, ts.latency,
                ts.ii, ts.area);
  }
}

}  // namespace
}  // namespace texsim
