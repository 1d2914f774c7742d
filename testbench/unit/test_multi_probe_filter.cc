// Multi-ellipse probes (Mavridis & Papaioannou, seed 004 eq. 12–17): probe count, spacing and
// span from the formulas, probes on the major axis, the printed θ formula's quadrant error,
// temporal subsets, Gaussian weights, constant textures exact, bounded error on smooth ones.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <toml++/toml.h>

#include "blocks/input_error.h"
#include "blocks/multi_probe_filter.h"
#include "testbench/lib/footprint_reference.h"

namespace texsim {
namespace {

constexpr double kPi = 3.14159265358979323846;

Texture smooth_texture(int size) {
  std::vector<float> px(static_cast<size_t>(size) * static_cast<size_t>(size) * 4);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const double u = (x + 0.5) / size, v = (y + 0.5) / size;
      const size_t i = (static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x)) * 4;
      px[i] = static_cast<float>(0.5 + 0.3 * std::sin(2 * kPi * (2 * u + v)));
      px[i + 1] = static_cast<float>(0.5 + 0.3 * std::cos(2 * kPi * (u - 3 * v)));
      px[i + 2] = static_cast<float>(0.5 + 0.2 * std::sin(2 * kPi * 3 * u));
      px[i + 3] = 1;
    }
  }
  return Texture::from_rgba("s", size, size, px, TexelFormat::Rgba32f, true);
}

Fragment footprint(double u, double v, double major, double minor, double theta, int size) {
  Fragment f;
  f.u = u;
  f.v = v;
  const double c = std::cos(theta), s = std::sin(theta);
  f.dudx = major * c / size;
  f.dvdx = major * s / size;
  f.dudy = -minor * s / size;
  f.dvdy = minor * c / size;
  return f;
}

TEST(MultiProbe, ProbeCountSpacingAndAxis) {
  const Texture tex = smooth_texture(256);
  for (double alpha : {1.0, 2.0}) {
    MultiProbeFilter::Config c;
    c.alpha = alpha;
    c.max_probes = 31;
    const MultiProbeFilter mp(c);
    for (double theta : {0.0, 0.4, 1.3, 2.5}) {
      const double major = 16, minor = 2;
      const Fragment f = footprint(0.5, 0.5, major, minor, theta, 256);
      OpCounts ops;
      const ProbeSet p = mp.probes(tex, f, ops);
      // N = 2·R_major/(α·R_minor) − 1 = 15 (α = 1) or 7 (α = 2), odd.
      const int n = static_cast<int>(2 * major / (alpha * minor) - 1);
      ASSERT_EQ(p.n, n) << alpha;
      EXPECT_NEAR(p.lambda, std::log2(alpha * minor), 1e-5);
      // Positions: k·step along (cos θ, sin θ), step = L/(N−1), L = 2(R_major − α R_minor).
      const double step = 2 * (major - alpha * minor) / (n - 1);
      for (int k = 0; k < p.n; ++k) {
        const double du = (p.u[static_cast<size_t>(k)] - 0.5) * 256, dv = (p.v[static_cast<size_t>(k)] - 0.5) * 256;
        const double along = du * std::cos(theta) + dv * std::sin(theta);
        const double across = -du * std::sin(theta) + dv * std::cos(theta);
        EXPECT_NEAR(across, 0.0, 1e-3) << theta;
        EXPECT_NEAR(std::fabs(along), std::fabs(k - (n - 1) / 2) * step, 1e-3);
        // Gaussian weight of the distance along the major axis.
        EXPECT_NEAR(p.w[static_cast<size_t>(k)], std::exp(-2.0 * (along / major) * (along / major)), 1e-5);
      }
    }
  }
  // Isotropic: one probe. Clamped: at most max_probes.
  OpCounts ops;
  EXPECT_EQ(MultiProbeFilter().probes(tex, footprint(0.3, 0.3, 4, 4, 0, 256), ops).n, 1);
  EXPECT_EQ(MultiProbeFilter().probes(tex, footprint(0.3, 0.3, 400, 1, 0, 256), ops).n, 15);
}

TEST(MultiProbe, PrintedThetaLosesTheQuadrant) {
  // Σuu > Σvv: the printed atan(B/(A − C))/2 is the major axis; Σvv > Σuu: it is the minor.
  for (double theta : {0.1, 0.3, 0.7}) {
    const double c = std::cos(theta), s = std::sin(theta);
    const double a = 100, b = 4;  // eigenvalues
    const double suu = a * c * c + b * s * s, svv = a * s * s + b * c * c, suv = (a - b) * c * s;
    const double exact = MultiProbeFilter::major_angle(suu, suv, svv, false);
    const double printed = MultiProbeFilter::major_angle(suu, suv, svv, true);
    EXPECT_NEAR(exact, theta, 1e-12);
    if (theta < kPi / 4) EXPECT_NEAR(printed, theta, 1e-12);
    else EXPECT_NEAR(std::fabs(printed - theta), kPi / 2, 1e-12);
  }
}

TEST(MultiProbe, TemporalSubsetsAlternate) {
  const Texture tex = smooth_texture(256);
  MultiProbeFilter::Config c;
  c.temporal = true;
  const MultiProbeFilter mp(c);
  Fragment f = footprint(0.5, 0.5, 14, 2, 0.0, 256);  // N = 13
  OpCounts ops;
  f.frame = 0;
  const ProbeSet even = mp.probes(tex, f, ops);
  f.frame = 1;
  const ProbeSet odd = mp.probes(tex, f, ops);
  EXPECT_EQ(even.n + odd.n, 13 + 1);  // the centre probe is in both frames
  EXPECT_EQ(even.n, 7);
  EXPECT_EQ(odd.n, 7);
}

TEST(MultiProbe, ConstantExactSmoothBoundedCountsAgree) {
  std::vector<float> px(64 * 64 * 4, 0.375f);
  const Texture flat = Texture::from_rgba("c", 64, 64, px, TexelFormat::Rgba32f, true);
  const Texture tex = smooth_texture(256);
  const MultiProbeFilter mp;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(0, 1);
  FootprintReferenceConfig rc;
  double worst = 0;
  for (int k = 0; k < 200; ++k) {
    const double minor = 1 + 2 * uni(rng), major = minor * (1 + 15 * uni(rng)), th = uni(rng) * kPi;
    OpCounts ops;
    std::vector<TexelRef> fetched;
    const FilterOutput c = mp.filter(flat, footprint(uni(rng), uni(rng), major / 4, minor / 4, th, 64), &fetched, ops);
    ASSERT_NEAR(c.colour.r, 0.375, 1e-5);
    ASSERT_EQ(fetched.size(), c.stats.texels);
    ASSERT_EQ(c.stats.texels, 8u * c.stats.probes);
    ASSERT_EQ(ops.mem, c.stats.texels);
    const Fragment f = footprint(uni(rng), uni(rng), major, minor, th, 256);
    const FilterOutput o = mp.filter(tex, f, nullptr, ops);
    const glm::dvec4 ref = footprint_reference_affine(tex, f, rc).colour;
    for (int ch = 0; ch < 3; ++ch) worst = std::max(worst, std::fabs(o.colour[ch] - ref[ch]));
  }
  std::printf("multi-ellipse probes vs Gaussian reference, smooth texture: max error %.4f\n", worst);
  // Trilinear probes blur by their box-filtered levels; on waves of ≥ 85 texels that stays small.
  EXPECT_LT(worst, 0.03);
}

TEST(MultiProbe, ConfigAndTiming) {
  auto t = toml::parse("alpha = 2.0\nmax_probes = 9\ntemporal = true\n");
  const auto c = MultiProbeFilter::Config::from_toml(ConfigReader(t, "s.toml", "multi_probe"));
  EXPECT_EQ(c.alpha, 2.0);
  EXPECT_EQ(c.max_probes, 9);
  EXPECT_TRUE(c.temporal);
  auto even = toml::parse("max_probes = 8\n");
  EXPECT_THROW(MultiProbeFilter::Config::from_toml(ConfigReader(even, "s.toml", "multi_probe")), InputError);
  auto unknown = toml::parse("probes = 8\n");
  EXPECT_THROW(MultiProbeFilter::Config::from_toml(ConfigReader(unknown, "s.toml", "multi_probe")), InputError);
  const TimingSpec ts = MultiProbeFilter().timing(TechTable::defaults());
  EXPECT_GT(ts.latency, 20u);
  EXPECT_GT(ts.area, 100.0);
  FilterStats s;
  s.probes = 7;
  EXPECT_EQ(MultiProbeFilter().issue_cycles(s), 7u);
}

}  // namespace
}  // namespace texsim
