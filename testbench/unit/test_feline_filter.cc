// Feline-style trilinear probes: the line is the longer parallelogram side (Texram) or the
// ellipse's major axis (Feline); N, positions, weights and LOD follow the documented rules;
// constant textures are exact and texel counts agree.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <toml++/toml.h>

#include "blocks/feline_filter.h"
#include "blocks/input_error.h"

namespace texsim {
namespace {

Texture flat(int size, float value) {
  std::vector<float> px(static_cast<size_t>(size) * static_cast<size_t>(size) * 4, value);
  return Texture::from_rgba("c", size, size, px, TexelFormat::Rgba32f, true);
}

TEST(Feline, ParallelogramUsesTheLongerSide) {
  const Texture tex = flat(256, 0.5f);
  FelineFilter::Config c;
  c.axis = FelineFilter::Axis::Parallelogram;
  c.weights = FelineFilter::Weights::Equal;
  const FelineFilter fl(c);
  // The seed's example: (∂u/∂x, ∂v/∂x) = (13, 0), (∂u/∂y, ∂v/∂y) = (12, 5) texels.
  Fragment f;
  f.u = f.v = 0.5;
  f.dudx = 13.0 / 256;
  f.dvdx = 0;
  f.dudy = 12.0 / 256;
  f.dvdy = 5.0 / 256;
  OpCounts ops;
  const ProbeSet p = fl.probes(tex, f, ops);
  // Both sides have length 13: the x side wins ties; N = ⌈13/13⌉ = 1.
  EXPECT_EQ(p.n, 1);
  f.dudx = 40.0 / 256;  // now the x side (40) is longer: N = ⌈40/13⌉ = 4
  const ProbeSet q = fl.probes(tex, f, ops);
  ASSERT_EQ(q.n, 4);
  for (int k = 0; k < 4; ++k) {
    const double t = (2.0 * k + 1 - 4) / 4;
    EXPECT_NEAR((q.u[static_cast<size_t>(k)] - 0.5) * 256, t * 40, 1e-9);
    EXPECT_NEAR(q.v[static_cast<size_t>(k)], 0.5, 1e-12);
    EXPECT_EQ(q.w[static_cast<size_t>(k)], 1.0f);
  }
  EXPECT_NEAR(q.lambda, std::log2(13.0), 1e-5);
}

TEST(Feline, EllipseUsesTheMajorAxisAndGaussianWeights) {
  const Texture tex = flat(256, 0.5f);
  const FelineFilter fl;  // ellipse, Gaussian
  Fragment f;
  f.u = f.v = 0.25;
  const double th = 0.6, major = 24, minor = 3;
  f.dudx = major * std::cos(th) / 256;
  f.dvdx = major * std::sin(th) / 256;
  f.dudy = -minor * std::sin(th) / 256;
  f.dvdy = minor * std::cos(th) / 256;
  OpCounts ops;
  const ProbeSet p = fl.probes(tex, f, ops);
  ASSERT_EQ(p.n, 8);  // ⌈24/3⌉
  for (int k = 0; k < p.n; ++k) {
    const double du = (p.u[static_cast<size_t>(k)] - 0.25) * 256, dv = (p.v[static_cast<size_t>(k)] - 0.25) * 256;
    EXPECT_NEAR(-du * std::sin(th) + dv * std::cos(th), 0.0, 1e-3);
    const double t = (2.0 * k + 1 - 8) / 8;
    EXPECT_NEAR(du * std::cos(th) + dv * std::sin(th), t * major, 1e-3);
    EXPECT_NEAR(p.w[static_cast<size_t>(k)], std::exp(-2.0 * t * t), 1e-6);
  }
  EXPECT_NEAR(p.lambda, std::log2(3.0), 1e-4);
  // Clamped at max_probes: the LOD grows to |line|/N so the probes still cover the line.
  f.dudx = 400 * std::cos(th) / 256;
  f.dvdx = 400 * std::sin(th) / 256;
  const ProbeSet q = fl.probes(tex, f, ops);
  EXPECT_EQ(q.n, 16);
  EXPECT_NEAR(q.lambda, std::log2(400.0 / 16), 1e-3);
}

TEST(Feline, ConstantExactAndCounts) {
  const Texture tex = flat(64, 0.625f);
  for (auto axis : {FelineFilter::Axis::Parallelogram, FelineFilter::Axis::Ellipse}) {
    FelineFilter::Config c;
    c.axis = axis;
    const FelineFilter fl(c);
    for (int k = 1; k < 50; ++k) {
      Fragment f;
      f.u = 0.01 * k;
      f.v = 0.37;
      f.dudx = 0.2 * k / 64;
      f.dvdx = 0.05 / 64;
      f.dudy = 0.03 * k / 64;
      f.dvdy = 1.0 / 64;
      OpCounts ops;
      std::vector<TexelRef> fetched;
      const FilterOutput o = fl.filter(tex, f, &fetched, ops);
      ASSERT_NEAR(o.colour.g, 0.625, 1e-5);
      ASSERT_EQ(fetched.size(), o.stats.texels);
      ASSERT_EQ(o.stats.texels, 8u * o.stats.probes);
      ASSERT_EQ(ops.mem, o.stats.texels);
      ASSERT_LE(o.stats.probes, 16u);
    }
  }
}

TEST(Feline, Config) {
  auto t = toml::parse("axis = \"parallelogram\"\nweights = \"equal\"\nmax_probes = 8\n");
  const auto c = FelineFilter::Config::from_toml(ConfigReader(t, "s.toml", "feline"));
  EXPECT_EQ(c.axis, FelineFilter::Axis::Parallelogram);
  EXPECT_EQ(c.weights, FelineFilter::Weights::Equal);
  EXPECT_EQ(c.max_probes, 8);
  auto bad = toml::parse("axis = \"diagonal\"\n");
  EXPECT_THROW(FelineFilter::Config::from_toml(ConfigReader(bad, "s.toml", "feline")), InputError);
  EXPECT_GT(FelineFilter().timing(TechTable::defaults()).latency, 10u);
}

}  // namespace
}  // namespace texsim
