// The footprint after a relief shift: the analytic derivatives of the shifted coordinates
// (chain rule through the parallax offset, implicit function through a ray hit) against
// central finite differences of the shift itself, a flat map that must leave the derivatives
// exactly as they were, and the configuration keys.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/base/tech_table.h"
#include "blocks/texture/relief/parallax_mapper.h"
#include "blocks/texture/relief/relief_footprint.h"

namespace texsim {
namespace {

// Smooth relief: a few texels per period of each wave, heights in [0.05, 0.95].
ReliefHeightMap wave_map(int32_t n, double freq) {
  ReliefHeightMap hm(n, n);
  const double a = 2 * std::numbers::pi * freq / n;
  for (int32_t y = 0; y < n; ++y) {
    for (int32_t x = 0; x < n; ++x)
      hm.at(x, y) = static_cast<float>(0.5 + 0.25 * std::sin(a * x) + 0.2 * std::cos(a * y));
  }
  return hm;
}

double norm4(double a, double b, double c, double d) {
  return std::sqrt(a * a + b * b + c * c + d * d);
}

ReliefFootprint analytic_footprint() {
  ReliefFootprint::Config c;
  c.mode = ReliefFootprint::Mode::Analytic;
  c.max_stretch = 1e6;  // no clamp: the finite difference is not clamped either
  return ReliefFootprint(c);
}

struct View {
  double vx, vy, vz;
};

// Agreement of the analytic Jacobian with central differences of the mapper's shift, for the
// offset and for a fine iterative search (whose hit is a smooth function of the entry point
// inside a bilinear cell).
void check_against_differences(ParallaxMapper::Method method, bool limiting, int* agree,
                               int* stretched, int n) {
  const ReliefHeightMap hm = wave_map(64, 4);
  ParallaxMapper::Config pc;
  pc.method = method;
  pc.offset_limiting = limiting;
  pc.depth_texels = 6;
  pc.min_view_z = 0.05;
  pc.min_layers = pc.max_layers = 1024;
  pc.binary_steps = 32;
  const ParallaxMapper pm(pc);
  const ReliefFootprint fp = analytic_footprint();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> pos(16, 48), ang(0, 2 * std::numbers::pi), tilt(0.2, 1.1),
      d(-1.5, 1.5);
  for (int i = 0; i < n; ++i) {
    const double x = pos(rng), y = pos(rng), a = ang(rng), t = tilt(rng);
    const View v{std::sin(t) * std::cos(a), std::sin(t) * std::sin(a), std::cos(t)};
    const ReliefFootprint::Derivs in{d(rng), d(rng), d(rng), d(rng)};
    OpCounts ops;
    const auto r = pm.map(hm, x, y, v.vx, v.vy, v.vz, ops);
    // The shift per unit depth as the mapper forms it (the view is a unit vector here).
    double sx = -v.vx / v.vz * pc.depth_texels, sy = -v.vy / v.vz * pc.depth_texels;
    if (method == ParallaxMapper::Method::Offset && limiting) {
      sx = -v.vx * pc.depth_texels;
      sy = -v.vy * pc.depth_texels;
    }
    const bool offset = method == ParallaxMapper::Method::Offset;
    const auto kind = offset ? ReliefFootprint::Kind::Offset : ReliefFootprint::Kind::RayHit;
    const ReliefFootprint::Derivs an =
        fp.analytic(hm, kind, offset ? x : r.u, offset ? y : r.v, sx, sy, in, ops);
    const double h = 1e-6;
    const auto diff = [&](double dx, double dy, double& ou, double& ov) {
      OpCounts o;
      const auto p = pm.map(hm, x + h * dx, y + h * dy, v.vx, v.vy, v.vz, o);
      const auto m = pm.map(hm, x - h * dx, y - h * dy, v.vx, v.vy, v.vz, o);
      ou = (p.u - m.u) / (2 * h);
      ov = (p.v - m.v) / (2 * h);
    };
    double fxx = 0, fyx = 0, fxy = 0, fyy = 0;
    diff(in.xx, in.yx, fxx, fyx);
    diff(in.xy, in.yy, fxy, fyy);
    const double scale = std::max(norm4(fxx, fyx, fxy, fyy), 1.0);
    const double err = std::max({std::fabs(an.xx - fxx), std::fabs(an.yx - fyx),
                                 std::fabs(an.xy - fxy), std::fabs(an.yy - fyy)});
    *agree += err <= 1e-3 * scale;
    const double moved = std::max({std::fabs(an.xx - in.xx), std::fabs(an.yx - in.yx),
                                   std::fabs(an.xy - in.xy), std::fabs(an.yy - in.yy)});
    *stretched += moved >= 0.1 * norm4(in.xx, in.yx, in.xy, in.yy);
  }
}

TEST(ReliefFootprint, AnalyticMatchesDifferencesOfTheOffsetShift) {
  for (const bool limiting : {true, false}) {
    int agree = 0, stretched = 0;
    const int n = 200;
    check_against_differences(ParallaxMapper::Method::Offset, limiting, &agree, &stretched, n);
    std::printf("offset (limiting %d): %d of %d agree, %d deformed by >= 10 %%\n", limiting, agree,
                n, stretched);
    EXPECT_GE(agree, n * 97 / 100);      // a difference may straddle a cell edge
    EXPECT_GE(stretched, n * 30 / 100);  // the footprint is deformed: the test can tell
  }
}

TEST(ReliefFootprint, AnalyticMatchesDifferencesOfTheRayHit) {
  int agree = 0, stretched = 0;
  const int n = 200;
  check_against_differences(ParallaxMapper::Method::Iterative, false, &agree, &stretched, n);
  std::printf("ray hit: %d of %d agree, %d deformed by >= 10 %%\n", agree, n, stretched);
  EXPECT_GE(agree, n * 95 / 100);
  EXPECT_GE(stretched, n * 30 / 100);
}

TEST(ReliefFootprint, FlatHeightMapKeepsTheDerivativesExactly) {
  const ReliefFootprint fp = analytic_footprint();
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> pos(-3, 40), d(-7, 7), s(-50, 50);
  for (const float level : {0.0F, 0.37F, 1.0F}) {
    const ReliefHeightMap hm(32, 32, level);
    for (int i = 0; i < 100; ++i) {
      const ReliefFootprint::Derivs in{d(rng), d(rng), d(rng), d(rng)};
      for (const auto kind : {ReliefFootprint::Kind::Offset, ReliefFootprint::Kind::RayHit}) {
        OpCounts ops;
        const auto o = fp.analytic(hm, kind, pos(rng), pos(rng), s(rng), s(rng), in, ops);
        EXPECT_EQ(o.xx, in.xx);
        EXPECT_EQ(o.yx, in.yx);
        EXPECT_EQ(o.xy, in.xy);
        EXPECT_EQ(o.yy, in.yy);
        EXPECT_EQ(ops.mem, 4U);
      }
    }
  }
}

TEST(ReliefFootprint, StretchIsClampedNearASilhouette) {
  // A ramp falling along the ray (∇h·s → −1): the hit runs away from the entry point.
  ReliefHeightMap hm(16, 16);
  for (int32_t y = 0; y < 16; ++y) {
    for (int32_t x = 0; x < 16; ++x) hm.at(x, y) = static_cast<float>(1.0 - 0.06 * x);
  }
  ReliefFootprint::Config c;
  c.mode = ReliefFootprint::Mode::Analytic;
  c.max_stretch = 4;
  OpCounts ops;
  // s = (16.5, 0): 1 + ∇h·s = 1 − 0.99 = 0.01, clamped to 1/4.
  const auto o = ReliefFootprint(c).analytic(hm, ReliefFootprint::Kind::RayHit, 8.2, 8.4, 16.5, 0,
                                             {1, 0, 0, 1}, ops);
  EXPECT_NEAR(o.xx, 1 + 16.5 * 0.06 * 4, 1e-5);
  EXPECT_NEAR(o.yy, 1, 1e-12);
}

TEST(ReliefFootprint, ConfigIsValidated) {
  const auto read = [](const char* text) {
    const toml::table t = toml::parse(text);
    return ReliefFootprint::Config::from_toml(ConfigReader(t, "s.toml", "relief"));
  };
  EXPECT_EQ(read("").mode, ReliefFootprint::Mode::Unshifted);
  EXPECT_EQ(read("footprint = \"analytic\"").mode, ReliefFootprint::Mode::Analytic);
  EXPECT_EQ(read("footprint = \"quad\"").mode, ReliefFootprint::Mode::QuadFine);
  EXPECT_EQ(read("footprint = \"quad_coarse\"").mode, ReliefFootprint::Mode::QuadCoarse);
  EXPECT_THROW(read("footprint = \"shifted\""), InputError);
  EXPECT_THROW(read("footprint = 1"), InputError);
  EXPECT_THROW(read("footprint_max_stretch = 0.5"), InputError);
}

TEST(ReliefFootprint, CostsAreCounted) {
  ReliefFootprint::Config c;
  EXPECT_EQ(ReliefFootprint(c).ops_per_item().total(), 0U);
  c.mode = ReliefFootprint::Mode::Analytic;
  const ReliefFootprint an(c);
  EXPECT_EQ(an.ops_per_item().mem, 4U);
  EXPECT_EQ(an.ops_per_item().rcp, 1U);
  c.mode = ReliefFootprint::Mode::QuadFine;
  const ReliefFootprint q(c);
  EXPECT_EQ(q.ops_per_item().add, 4U);
  const TechTable tech = TechTable::defaults();
  EXPECT_GT(an.timing(tech).latency, q.timing(tech).latency);
  EXPECT_EQ(an.name(), "relief.footprint[analytic]");
}

}  // namespace
}  // namespace texsim
