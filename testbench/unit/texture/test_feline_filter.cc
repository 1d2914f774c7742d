// Feline-style trilinear probes: the line is the longer parallelogram side (Texram) or the
// ellipse's major axis (Feline); N, positions, weights and LOD follow the documented rules;
// constant textures are exact and texel counts agree. The double and fixed set-ups against a
// long-double reference, their hard cases, colours on a photograph, op counts and timing.
#include <gtest/gtest.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/texture/footprint/feline_filter.h"
#include "pipeline/scene/texture_loader.h"
#include "testbench/lib/probe_reference.h"

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

// Seed 004's geometry claims on the Texram line (the longer side of the parallelogram spanned
// by the derivative vectors a, b), against the footprint ellipse (the image of the unit pixel
// circle, semi-axes σ1 ≥ σ2 of J): the line deviates from the major axis by at most 45° — the
// bound holds and is approached — and it is shorter than the major axis by at most 2√2 (full
// axis 2σ1 against |longer side| ≥ σ1/√2, since |a|² + |b|² = σ1² + σ2²): not "almost four
// times" as the seed says, and the bound is approached too.
TEST(Feline, TexramLineGeometryAgainstTheSeedsClaims) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> d(-1, 1);
  double worst_angle = 0, worst_ratio = 0;
  for (int i = 0; i < 200000; ++i) {
    const double ux = d(rng), vx = d(rng), uy = d(rng), vy = d(rng);
    const double la = std::hypot(ux, vx), lb = std::hypot(uy, vy);
    if (std::fabs(ux * vy - uy * vx) < 1e-9 || la == lb) continue;
    // J Jᵀ = [[p, q], [q, r]]: its larger eigenvalue is σ1², its eigenvector the major axis.
    const double p = ux * ux + uy * uy, q = ux * vx + uy * vy, r = vx * vx + vy * vy;
    const double s1 = std::sqrt((p + r) / 2 + std::hypot((p - r) / 2, q));
    const double theta = 0.5 * std::atan2(2 * q, p - r);
    const double lx = la >= lb ? ux : uy, ly = la >= lb ? vx : vy;
    const double cosang =
        std::fabs(lx * std::cos(theta) + ly * std::sin(theta)) / std::hypot(lx, ly);
    worst_angle = std::max(worst_angle, std::acos(std::min(1.0, cosang)) * 180 / M_PI);
    worst_ratio = std::max(worst_ratio, 2 * s1 / std::max(la, lb));
  }
  EXPECT_LE(worst_angle, 45.0 + 1e-9);
  EXPECT_GT(worst_angle, 44.0);
  EXPECT_LE(worst_ratio, 2 * std::sqrt(2.0) + 1e-9);
  EXPECT_GT(worst_ratio, 2.7);
  EXPECT_LT(worst_ratio, 3.5);  // not "almost four times"
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
    const double du = (p.u[static_cast<size_t>(k)] - 0.25) * 256,
                 dv = (p.v[static_cast<size_t>(k)] - 0.25) * 256;
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
  EXPECT_EQ(c.arith, NumberFormat::Float);
  auto fx = toml::parse("arith = \"double\"\n");
  EXPECT_EQ(FelineFilter::Config::from_toml(ConfigReader(fx, "s.toml", "feline")).arith,
            NumberFormat::Double);
  auto badarith = toml::parse("arith = 3\n");
  try {
    (void)FelineFilter::Config::from_toml(ConfigReader(badarith, "s.toml", "feline"));
    ADD_FAILURE() << "arith = 3 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("arith"), std::string::npos) << e.what();
  }
  EXPECT_GT(FelineFilter().timing(TechTable::defaults()).latency, 10u);
}

// ---- double and fixed set-up ------------------------------------------------------------

// The probes from the documented rules in long double. q = |line|/minor: N = ⌈q⌉, clamped.
RefProbes reference(const FelineFilter::Config& c, const Fragment& f, int w0, int h0) {
  using L = long double;
  RefProbes r;
  r.u[0] = f.u;
  r.v[0] = f.v;
  r.w[0] = 1;
  const RefEllipse e = reference_ellipse(f, w0, h0, c.radius_px, c.max_aniso);
  L lu, lv, minor;
  if (c.axis == FelineFilter::Axis::Parallelogram) {
    const L la = std::hypot(e.ux, e.vx), lb = std::hypot(e.uy, e.vy);
    lu = la >= lb ? e.ux : e.uy;
    lv = la >= lb ? e.vx : e.vy;
    minor = std::min(la, lb);
  } else {
    const L th = std::atan2(e.suv, e.d) / 2;
    lu = std::sqrt(e.major2) * std::cos(th);
    lv = std::sqrt(e.major2) * std::sin(th);
    minor = std::sqrt(e.minor2);
  }
  r.len = std::hypot(lu, lv);
  if (!(r.len > 0)) {
    r.special = true;
    return r;
  }
  r.q = minor > 0 ? r.len / minor : 1e9L;
  const int n = std::clamp(static_cast<int>(std::min(std::ceil(r.q), static_cast<L>(c.max_probes))),
                           1, c.max_probes);
  r.n = n;
  r.lambda = std::log2(std::max(minor, r.len / n)) + f.lod_bias;
  for (int k = 0; k < n; ++k) {
    const L t = static_cast<L>(2 * k + 1 - n) / n;
    r.u[k] = f.u + t * lu / w0;
    r.v[k] = f.v + t * lv / h0;
    r.w[k] = c.weights == FelineFilter::Weights::Equal ? 1 : std::exp(-c.weight_alpha * t * t);
  }
  return r;
}

TEST(Feline, DoubleAndFixedAgainstLongDoubleReference) {
  // Bounds as for the multi-ellipse probes (test_multi_probe_filter.cc): positions within
  // 10⁻⁹·(1 + |line|) texel (double); fixed: 3·10⁻⁶·(1 + |line|) for the two CORDIC residual
  // angles of the ellipse's line, 4·10⁻⁹·(1 + |line|) for the parallelogram's (no CORDIC: the
  // u1.32 1/N times up to 31), plus the centre's, offsets' and derivatives' roundings (ProbeBound);
  // Gaussian weights within the 2^-f table's 3.4·10⁻⁴ + ½ LSB of u1.15; λ within the log2
  // table's 1.44·2^-11 = 7.0·10⁻⁴ (log2 of a length, not ½·log2 of its square) + rounding.
  const std::vector<std::pair<int, int>> sizes = {{256, 256}, {384, 96}};
  for (NumberFormat a : {NumberFormat::Double, NumberFormat::S16_24HalfUp}) {
    for (auto axis : {FelineFilter::Axis::Ellipse, FelineFilter::Axis::Parallelogram}) {
      Deviation d;
      FelineFilter::Config c;
      c.arith = a;
      c.axis = axis;
      c.max_probes = 31;
      for (auto [w0, h0] : sizes) {
        std::vector<float> px(static_cast<size_t>(w0) * static_cast<size_t>(h0) * 4, 0.5f);
        const Texture tex = Texture::from_rgba("t", w0, h0, px, TexelFormat::Rgba32f, true);
        const FelineFilter fl(c);
        std::mt19937 rng(12);
        for (int k = 0; k < 3000; ++k) {
          const Fragment f = random_footprint(rng, w0, h0, k % 3 == 0);
          OpCounts ops;
          const double rel = a == NumberFormat::Double             ? 1e-9
                             : axis == FelineFilter::Axis::Ellipse ? 3e-6
                                                                   : 4e-9;
          // N = ⌈q⌉ reaches max_probes for every q above max_probes + 1.
          const ProbeBound b{w0, h0, rel, a == NumberFormat::S16_24HalfUp, c.max_probes + 1};
          compare_probes(fl.probes(tex, f, ops), reference(c, f, w0, h0), b, d);
        }
      }
      std::printf("feline %s %s vs long double: %s\n",
                  axis == FelineFilter::Axis::Ellipse ? "ellipse" : "parallelogram",
                  kProbeArith.key_of(a).data(), describe(d).c_str());
      EXPECT_EQ(d.n_mismatch, 0);
      EXPECT_GT(d.compared, 5800);
      EXPECT_LE(d.pos, 1.0);
      if (a == NumberFormat::Double) {
        EXPECT_LT(d.w, 1e-7);
        EXPECT_LT(d.lambda, 2e-6);
      } else {
        EXPECT_LT(d.w, 3.4e-4 + 1.6e-5);
        EXPECT_LT(d.lambda, 7.1e-4 + 1e-5);
      }
    }
  }
}

TEST(Feline, HardCasesDefinedInEveryArithmetic) {
  std::vector<float> px(size_t{256} * 256 * 4);
  for (size_t i = 0; i < px.size(); ++i)
    px[i] = static_cast<float>((i * 2654435761u) % 1000) / 1000.0f;
  const Texture tex = Texture::from_rgba("n", 256, 256, px, TexelFormat::Rgba32f, true);
  const Rgba mean = tex.texel(tex.levels() - 1, 0, 0);
  for (NumberFormat a : {NumberFormat::Float, NumberFormat::Double, NumberFormat::S16_24HalfUp}) {
    for (auto axis : {FelineFilter::Axis::Ellipse, FelineFilter::Axis::Parallelogram}) {
      SCOPED_TRACE(std::string(kProbeArith.key_of(a).data()) +
                   (axis == FelineFilter::Axis::Ellipse ? " ellipse" : " parallelogram"));
      FelineFilter::Config c;
      c.arith = a;
      c.axis = axis;
      const FelineFilter fl(c);
      ProbeSet p;
      FilterOutput o;
      auto run = [&](const Fragment& f) {
        OpCounts ops;
        p = fl.probes(tex, f, ops);
        std::vector<TexelRef> fetched;
        o = fl.filter(tex, f, &fetched, ops);
        for (int ch = 0; ch < 4; ++ch) ASSERT_TRUE(std::isfinite(o.colour[ch]));
        ASSERT_EQ(fetched.size(), o.stats.texels);
      };
      // Anisotropy 10⁴:1: N = max_probes and the LOD grows to |line|/N.
      Fragment f;
      f.u = 0.3;
      f.v = 0.6;
      f.dudx = 4000 * std::cos(0.7) / 256;
      f.dvdx = 4000 * std::sin(0.7) / 256;
      f.dudy = -0.4 * std::sin(0.7) / 256;
      f.dvdy = 0.4 * std::cos(0.7) / 256;
      run(f);
      EXPECT_EQ(p.n, 16);
      EXPECT_NEAR(p.lambda, std::log2(4000.0 / 16), 1e-3);
      // det = 0 (parallel derivative vectors): the ellipse clamps the minor axis to 1/64 of the
      // major; the parallelogram's minor is the shorter vector: N = max_probes either way.
      f.dudx = 8.0 / 256;
      f.dvdx = 4.0 / 256;
      f.dudy = 16.0 / 256;
      f.dvdy = 8.0 / 256;
      run(f);
      EXPECT_EQ(p.n, axis == FelineFilter::Axis::Ellipse ? 16 : 2);
      // Zero derivatives: one probe at level 0.
      f.dudx = f.dvdx = f.dudy = f.dvdy = 0;
      run(f);
      EXPECT_EQ(p.n, 1);
      EXPECT_LT(p.lambda, -1e20f);
      for (double bad :
           {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
            -std::numeric_limits<double>::infinity()}) {
        f.dvdy = bad;
        run(f);
        EXPECT_TRUE(o.stats.bad_input);
        EXPECT_EQ(p.n, 1);
        EXPECT_LT(p.lambda, -1e20f);
      }
      // 10⁶-texel derivatives: every read from the 1×1 level.
      f.dudx = 1e6 / 256;
      f.dvdx = 3e5 / 256;
      f.dudy = -2e5 / 256;
      f.dvdy = 9e5 / 256;
      run(f);
      for (int ch = 0; ch < 4; ++ch) EXPECT_NEAR(o.colour[ch], mean[ch], 1e-5);
      f.u = std::numeric_limits<double>::infinity();
      f.dudx = 3.0 / 256;
      f.dvdx = f.dudy = 0;
      f.dvdy = 1.0 / 256;
      run(f);
    }
  }
}

TEST(Feline, FixedColoursTrackDoubleOnAPhotograph) {
  const Texture tex = load_texture("/usr/share/glmark2/textures/crate-base.png", "");
  const int w0 = tex.width(0), h0 = tex.height(0);
  for (auto axis : {FelineFilter::Axis::Ellipse, FelineFilter::Axis::Parallelogram}) {
    FelineFilter::Config cd, cx;
    cd.axis = cx.axis = axis;
    cd.arith = NumberFormat::Double;
    cx.arith = NumberFormat::S16_24HalfUp;
    const FelineFilter fd(cd), fx(cx);
    std::mt19937 rng(9);
    ColourDeviation dev;
    for (int k = 0; k < 600; ++k) {
      const Fragment f = random_ellipse_footprint(rng, w0, h0);
      OpCounts ops;
      const FilterOutput a = fd.filter(tex, f, nullptr, ops), b = fx.filter(tex, f, nullptr, ops);
      ASSERT_EQ(a.stats.probes, b.stats.probes);
      dev.add(a.colour, b.colour);
    }
    std::printf("feline %s on crate-base.png: fixed vs double max %.3g mean %.3g\n",
                axis == FelineFilter::Axis::Ellipse ? "ellipse" : "parallelogram", dev.worst,
                dev.mean());
    // At most one address-generator quantisation step (1/256 of a texel difference) moves.
    EXPECT_LT(dev.worst, 1.0 / 256);
    EXPECT_LT(dev.mean(), 1e-4);
  }
}

TEST(Feline, OpsAndTimingFollowTheArithmetic) {
  const Texture tex = flat(256, 0.5f);
  TexelAddressGen::Config ac;
  ac.filter = FilterMode::Trilinear;
  const TexelAddressGen addr(ac);
  const TechTable tech = TechTable::defaults();
  for (auto axis : {FelineFilter::Axis::Ellipse, FelineFilter::Axis::Parallelogram}) {
    FelineFilter::Config cf, cx;
    cf.axis = cx.axis = axis;
    cx.arith = NumberFormat::S16_24HalfUp;
    const FelineFilter ff(cf), fx(cx);
    for (const FelineFilter* fl : {&ff, &fx}) {
      Fragment f;
      f.u = f.v = 0.4;
      f.dudx = 20.0 / 256;
      f.dvdy = 3.0 / 256;
      OpCounts ops;
      const FilterOutput o = fl->filter(tex, f, nullptr, ops);
      ASSERT_EQ(o.stats.probes, 7u);
      EXPECT_EQ(ops, fl->setup_ops() + (fl->ops_per_item() + addr.ops_setup(false)) * 7u +
                         probe_normalise_ops());
    }
    const OpCounts sf = ff.setup_ops(), sx = fx.setup_ops();
    EXPECT_EQ(sx.rcp, 0u);  // the divider and the 1/N table replace both reciprocals
    EXPECT_EQ(sx.sqrt, 2u);
    const TimingSpec tf = ff.timing(tech), tx = fx.timing(tech);
    EXPECT_EQ(tx.ii, 1u);
    if (axis == FelineFilter::Axis::Ellipse) {
      EXPECT_EQ(sf.lut - sx.lut, 2u);  // atan2, cos, sin, log2 → 1/N, log2
      EXPECT_GE(sx.add, sf.add + uint64_t{2} * 3 * ProbeFx::kCordicSteps - 10);
      EXPECT_GT(tx.latency, tf.latency + 2 * ProbeFx::kCordicSteps);
    } else {
      EXPECT_EQ(sx.lut, sf.lut + 1);      // the 1/N table
      EXPECT_GT(tx.latency, tf.latency);  // the 6-step divider against rcp + mul
    }
    EXPECT_NE(fx.arithmetic().find(ProbeFx::Coord::name()), std::string::npos);
  }
}

}  // namespace
}  // namespace texsim
