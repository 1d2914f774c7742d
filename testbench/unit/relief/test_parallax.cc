// Parallax mapping: offset parallax against its formula, the iterative variant (linear search +
// binary refinement) against a long double fine-step reference, op and fetch counts.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/base/tech_table.h"
#include "blocks/texture/relief/parallax_mapper.h"

namespace texsim {
namespace {

ReliefHeightMap wave_map(int32_t n, double freq) {
  ReliefHeightMap hm(n, n);
  for (int32_t y = 0; y < n; ++y) {
    for (int32_t x = 0; x < n; ++x) {
      const double a = 2 * std::numbers::pi * freq / n;
      hm.at(x, y) = static_cast<float>(0.5 + 0.25 * std::sin(a * x) + 0.2 * std::cos(a * y));
    }
  }
  return hm;
}

long double bilinear_ld(const ReliefHeightMap& hm, long double x, long double y) {
  const long double fx = std::floor(x), fy = std::floor(y), ax = x - fx, ay = y - fy;
  const auto ix = static_cast<int32_t>(fx), iy = static_cast<int32_t>(fy);
  const long double h00 = hm.texel(ix, iy), h10 = hm.texel(ix + 1, iy);
  const long double h01 = hm.texel(ix, iy + 1), h11 = hm.texel(ix + 1, iy + 1);
  return (1 - ay) * ((1 - ax) * h00 + ax * h10) + ay * ((1 - ax) * h01 + ax * h11);
}

// First depth s in [0, 1] where the ray is at or below the surface: steps of 1e-5, then
// bisection.
long double reference_depth(const ReliefHeightMap& hm, long double u, long double v, long double sx,
                            long double sy) {
  auto below = [&](long double s) { return s >= 1 - bilinear_ld(hm, u + sx * s, v + sy * s); };
  long double lo = 0, hi = 0;
  const long double ds = 1e-5L;
  for (long double s = 0; s <= 1 + ds / 2; s += ds) {
    hi = std::min<long double>(s, 1);
    if (below(hi)) break;
    lo = hi;
  }
  if (hi == 0) return 0;
  for (int k = 0; k < 60; ++k) {
    const long double mid = (lo + hi) / 2;
    (below(mid) ? hi : lo) = mid;
  }
  return hi;
}

TEST(Parallax, NormalIncidenceDoesNotShift) {
  const ReliefHeightMap hm = wave_map(32, 2);
  for (const auto method : {ParallaxMapper::Method::Offset, ParallaxMapper::Method::Iterative}) {
    ParallaxMapper::Config c;
    c.method = method;
    OpCounts ops;
    const auto r = ParallaxMapper(c).map(hm, 7.3, 11.9, 0, 0, 1, ops);
    EXPECT_DOUBLE_EQ(r.u, 7.3);
    EXPECT_DOUBLE_EQ(r.v, 11.9);
  }
}

TEST(Parallax, OffsetMatchesItsFormula) {
  const ReliefHeightMap hm = wave_map(32, 2);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> pos(2, 30), dir(-1, 1), up(0.2, 1);
  for (int i = 0; i < 200; ++i) {
    const double u = pos(rng), v = pos(rng), vx = dir(rng), vy = dir(rng), vz = up(rng);
    const long double lx = vx, ly = vy, lz = vz;
    const long double len = std::sqrt(lx * lx + ly * ly + lz * lz);
    const long double d = 1 - bilinear_ld(hm, u, v);
    for (const bool limit : {true, false}) {
      ParallaxMapper::Config c;
      c.method = ParallaxMapper::Method::Offset;
      c.offset_limiting = limit;
      c.min_view_z = 0.01;
      OpCounts ops;
      const auto r = ParallaxMapper(c).map(hm, u, v, vx, vy, vz, ops);
      const long double k = c.depth_texels * d / (limit ? len : lz);
      EXPECT_NEAR(r.u, static_cast<double>(u - vx * k), 1e-9);
      EXPECT_NEAR(r.v, static_cast<double>(v - vy * k), 1e-9);
      EXPECT_EQ(r.samples, 1U);
      EXPECT_EQ(ops.mem, 4U);
      if (limit) {
        EXPECT_LE(std::hypot(r.u - u, r.v - v), c.depth_texels + 1e-12);
      }
    }
  }
}

TEST(Parallax, IterativeMatchesLongDoubleReference) {
  const ReliefHeightMap hm = wave_map(64, 3);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> pos(8, 56), ang(0, 2 * std::numbers::pi), tilt(0, 1.2);
  const ParallaxMapper pm;  // 8..32 layers, 5 binary steps
  int within_bracket = 0, n = 1000;
  double worst = 0;
  for (int i = 0; i < n; ++i) {
    const double u = pos(rng), v = pos(rng), a = ang(rng), t = tilt(rng);
    const double vx = std::sin(t) * std::cos(a), vy = std::sin(t) * std::sin(a), vz = std::cos(t);
    OpCounts ops;
    const auto r = pm.map(hm, u, v, vx, vy, vz, ops);
    const long double sx = -vx / vz * pm.config().depth_texels,
                      sy = -vy / vz * pm.config().depth_texels;
    const long double ref = reference_depth(hm, u, v, sx, sy);
    const auto layers = std::lround(32 + (8 - 32) * vz);
    const double bracket = 1.0 / static_cast<double>(layers) / 32;  // one layer / 2^5
    const double err = std::fabs(r.depth - static_cast<double>(ref));
    worst = std::max(worst, err);
    within_bracket += err <= bracket + 1e-12;
    EXPECT_EQ(r.samples, r.linear_steps + r.binary_steps);
    EXPECT_EQ(ops.mem, 4U * r.samples);
    EXPECT_LE(r.linear_steps, static_cast<uint32_t>(layers + 1));
  }
  std::printf("iterative parallax: %d of %d within the final bracket, worst depth error %.4g\n",
              within_bracket, n, worst);
  EXPECT_GE(within_bracket, n * 99 / 100);
}

TEST(Parallax, MethodsCostAgainstError) {
  // Per method: height reads per fragment and the mean texel-coordinate error against the
  // long double reference intersection, on the smooth map, views up to 60° from the normal.
  const ReliefHeightMap hm = wave_map(64, 3);
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> pos(8, 56), ang(0, 2 * std::numbers::pi), tilt(0, 1.05);
  ParallaxMapper::Config off, lim, it4, it;
  off.method = lim.method = ParallaxMapper::Method::Offset;
  off.offset_limiting = false;
  it4.min_layers = 4;
  it4.max_layers = 8;
  it4.binary_steps = 2;
  const ParallaxMapper methods[] = {ParallaxMapper(off), ParallaxMapper(lim), ParallaxMapper(it4),
                                    ParallaxMapper(it)};
  const char* names[] = {"offset", "offset limited", "iterative 4..8 + 2", "iterative 8..32 + 5"};
  double err[4] = {}, reads[4] = {};
  const int n = 400;
  for (int i = 0; i < n; ++i) {
    const double u = pos(rng), v = pos(rng), a = ang(rng), t = tilt(rng);
    const double vx = std::sin(t) * std::cos(a), vy = std::sin(t) * std::sin(a), vz = std::cos(t);
    const long double sx = -vx / vz * 4, sy = -vy / vz * 4;
    const long double ref = reference_depth(hm, u, v, sx, sy);
    for (int m = 0; m < 4; ++m) {
      OpCounts ops;
      const auto r = methods[m].map(hm, u, v, vx, vy, vz, ops);
      err[m] += std::hypot(r.u - static_cast<double>(u + sx * ref),
                           r.v - static_cast<double>(v + sy * ref));
      reads[m] += r.samples;
    }
  }
  for (int m = 0; m < 4; ++m) {
    std::printf("parallax %-20s %.2f height reads, mean error %.4f texel\n", names[m], reads[m] / n,
                err[m] / n);
  }
  EXPECT_LT(err[3], err[2]);
  EXPECT_LT(err[2], err[0]);
  EXPECT_LT(err[3] / n, 0.01);
}

TEST(Parallax, FlatMapsAtTopAndBottom) {
  const ParallaxMapper pm;
  OpCounts ops;
  const auto top = pm.map(ReliefHeightMap(8, 8, 1.0F), 3, 3, 0.5, 0, 0.5, ops);
  EXPECT_DOUBLE_EQ(top.depth, 0.0);
  EXPECT_EQ(top.linear_steps, 1U);
  EXPECT_EQ(top.binary_steps, 0U);
  EXPECT_DOUBLE_EQ(top.u, 3.0);
  const auto bottom = pm.map(ReliefHeightMap(8, 8, 0.0F), 3, 3, 0.5, 0, 0.5, ops);
  EXPECT_NEAR(bottom.depth, 1.0, 1e-12);
  EXPECT_NEAR(bottom.u, 3 - 4.0, 1e-9);  // V at 45 degrees: shift = depth_texels
}

TEST(Parallax, TimingFromOps) {
  const ParallaxMapper pm;
  const TimingSpec s = pm.timing(TechTable::defaults());
  EXPECT_GE(s.latency, 1U);
  EXPECT_EQ(pm.ops_per_item().mem, 4U);
}

TEST(Parallax, ConfigsReadAndReject) {
  const toml::table t = toml::parse("method = \"offset\"\ndepth_texels = 2\n");
  const auto c = ParallaxMapper::Config::from_toml(ConfigReader(t, "s.toml", "parallax"));
  EXPECT_EQ(c.method, ParallaxMapper::Method::Offset);
  EXPECT_EQ(ParallaxMapper(c).name(), "relief.parallax_offset");
  for (const char* bad : {"min_view_z = 0\n", "min_layers = 40\n", "method = \"steep\"\n"}) {
    const toml::table b = toml::parse(bad);
    EXPECT_THROW(ParallaxMapper::Config::from_toml(ConfigReader(b, "s.toml", "parallax")),
                 InputError);
  }
}

}  // namespace
}  // namespace texsim
