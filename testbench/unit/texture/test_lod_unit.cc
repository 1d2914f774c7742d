// LodUnit: λ and the Vulkan anisotropic rule against a long-double reference; directed corner
// cases (texel-exact powers of two, zero, NaN/Inf and overflowing derivatives, bias, clamps),
// op counts, timing and config parsing.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <sstream>

#include "blocks/base/input_error.h"
#include "blocks/texture/sampler/lod_unit.h"

namespace texsim {
namespace {

Fragment frag(double dudx, double dvdx, double dudy, double dvdy, float bias = 0) {
  Fragment f;
  f.u = 0.5;
  f.v = 0.5;
  f.dudx = dudx;
  f.dvdx = dvdx;
  f.dudy = dudy;
  f.dvdy = dvdy;
  f.lod_bias = bias;
  return f;
}

struct RefLod {
  long double lambda_base;  // before bias/clamp
  long double ratio;        // ρmax/ρmin (inf if ρmin = 0)
  int n;                    // Vulkan N
};

// Long-double reference of Vulkan's scale factor and LOD (ρ = Euclidean lengths).
RefLod reference(const Fragment& f, int w, int h, AnisoMode mode, int max_aniso) {
  const long double mux = static_cast<long double>(f.dudx) * w;
  const long double mvx = static_cast<long double>(f.dvdx) * h;
  const long double muy = static_cast<long double>(f.dudy) * w;
  const long double mvy = static_cast<long double>(f.dvdy) * h;
  const long double px = std::sqrt(mux * mux + mvx * mvx), py = std::sqrt(muy * muy + mvy * mvy);
  const long double pmax = std::max(px, py), pmin = std::min(px, py);
  RefLod r{};
  r.ratio = pmin > 0 ? pmax / pmin : std::numeric_limits<long double>::infinity();
  if (mode == AnisoMode::Isotropic || pmax == 0) {
    r.n = 1;
  } else if (pmin == 0) {
    r.n = max_aniso;
  } else {
    r.n = static_cast<int>(std::ceil(std::min(r.ratio, static_cast<long double>(max_aniso))));
  }
  r.lambda_base = std::log2(pmax / r.n);
  return r;
}

TEST(LodUnit, PowersOfTwoAreExact) {
  LodUnit::Config c;
  c.min_lod = -20;
  LodUnit lod(c);
  OpCounts ops;
  for (int k = -6; k <= 10; ++k) {
    const double s = std::ldexp(1.0, k) / 256.0;  // ρ = 2^k texels on a 256² texture
    EXPECT_EQ(lod.eval(frag(s, 0, 0, s), 256, 256, ops).lambda, static_cast<float>(k)) << k;
    // Diagonal footprint of length 2^k: Ux = Vx = 2^k/√2 per axis.
    const double d = s / std::sqrt(2.0);
    EXPECT_NEAR(lod.eval(frag(d, d, -d, d), 256, 256, ops).lambda, k, 1e-6) << k;
  }
}

TEST(LodUnit, NonSquareTextureScalesEachAxis) {
  LodUnit::Config c;
  c.min_lod = -20;
  LodUnit lod(c);
  OpCounts ops;
  // dv/dy = 1/64 on a 128-wide, 64-high texture is one texel; du/dx = 1/128 is one texel.
  EXPECT_EQ(lod.eval(frag(1.0 / 128, 0, 0, 1.0 / 64), 128, 64, ops).lambda, 0.0f);
  // ρy = 4 texels dominates.
  EXPECT_EQ(lod.eval(frag(1.0 / 128, 0, 0, 4.0 / 64), 128, 64, ops).lambda, 2.0f);
  // 1×1 texture: derivative 1 (one texture per pixel) is one texel.
  EXPECT_EQ(lod.eval(frag(1, 0, 0, 1), 1, 1, ops).lambda, 0.0f);
}

TEST(LodUnit, ZeroDerivativesGiveMinLod) {
  for (float min_lod : {0.0f, -3.5f, 2.25f}) {
    for (AnisoMode m : {AnisoMode::Isotropic, AnisoMode::Vulkan}) {
      LodUnit::Config c;
      c.aniso = m;
      c.min_lod = min_lod;
      c.lod_bias = 1.0f;  // bias cannot lift -inf above min_lod
      OpCounts ops;
      const LodResult r = LodUnit(c).eval(frag(0, 0, 0, 0), 64, 64, ops);
      EXPECT_EQ(r.lambda, min_lod);
      EXPECT_EQ(r.probes, 1);
      EXPECT_EQ(r.axis_u, 0.0f);
      EXPECT_EQ(r.axis_v, 0.0f);
    }
  }
}

TEST(LodUnit, NonFiniteDerivativesFallBackToLevelZero) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (AnisoMode m : {AnisoMode::Isotropic, AnisoMode::Vulkan}) {
    for (double bad : {nan, inf, -inf}) {
      LodUnit::Config c;
      c.aniso = m;
      c.min_lod = -4;
      OpCounts ops;
      LodUnit lod(c);
      for (int slot = 0; slot < 4; ++slot) {
        double d[4] = {0.01, 0.002, -0.003, 0.02};
        d[slot] = bad;
        LodResult r = lod.eval(frag(d[0], d[1], d[2], d[3]), 256, 256, ops);
        EXPECT_FALSE(std::isnan(r.lambda));
        EXPECT_EQ(r.lambda, 0.0f) << "slot " << slot;
        EXPECT_EQ(r.probes, 1);
        // Fallback still takes the bias and the clamp.
        r = lod.eval(frag(d[0], d[1], d[2], d[3], 1.5f), 256, 256, ops);
        EXPECT_EQ(r.lambda, 1.5f);
        LodUnit::Config c2 = c;
        c2.min_lod = 2;
        r = LodUnit(c2).eval(frag(d[0], d[1], d[2], d[3]), 256, 256, ops);
        EXPECT_EQ(r.lambda, 2.0f);
      }
    }
  }
}

TEST(LodUnit, OverflowingDerivativesGiveMaxLod) {
  for (AnisoMode m : {AnisoMode::Isotropic, AnisoMode::Vulkan}) {
    LodUnit::Config c;
    c.aniso = m;
    c.max_lod = 12.5f;
    OpCounts ops;
    const LodResult r = LodUnit(c).eval(frag(1e30, 1e30, 1e30, -1e30), 4096, 4096, ops);
    EXPECT_EQ(r.lambda, 12.5f);
    EXPECT_GE(r.probes, 1);
  }
}

TEST(LodUnit, BiasAndClamp) {
  LodUnit::Config c;
  c.lod_bias = 0.75f;
  c.min_lod = 0.5f;
  c.max_lod = 3.0f;
  LodUnit lod(c);
  OpCounts ops;
  const double s = 4.0 / 256;  // λ_base = 2
  EXPECT_EQ(lod.eval(frag(s, 0, 0, s), 256, 256, ops).lambda, 2.75f);
  EXPECT_EQ(lod.eval(frag(s, 0, 0, s, -0.5f), 256, 256, ops).lambda, 2.25f);
  EXPECT_EQ(lod.eval(frag(s, 0, 0, s, 5.0f), 256, 256, ops).lambda, 3.0f);
  EXPECT_EQ(lod.eval(frag(s / 64, 0, 0, s / 64), 256, 256, ops).lambda, 0.5f);
}

// Explicit LOD (textureLod): λ_base is the fragment's lod, the sampler bias is added before the
// clamp, and the fragment's lod_bias (the shader's Bias, not allowed with Lod) is ignored.
TEST(LodUnit, ExplicitLodBiasThenClamp) {
  LodUnit::Config c;
  c.lod_bias = 1.5f;
  c.min_lod = 0.0f;
  c.max_lod = 2.75f;
  c.aniso = AnisoMode::Vulkan;
  c.max_aniso = 8;
  LodUnit lod(c);
  const double s = 4.0 / 256;
  Fragment f = frag(8 * s, 0, 0, s, 3.0f);  // anisotropic derivatives, ignored
  f.op = static_cast<uint8_t>(SampleOp::kSampleLod);
  f.lod = -1.0f;
  LodResult r = lod.eval(f, 256, 256);
  EXPECT_EQ(r.lambda, 0.5f);  // clamp(-1 + 1.5): clamping first would give 1.5
  EXPECT_EQ(r.probes, 1);
  f.lod = 2.0f;
  EXPECT_EQ(lod.eval(f, 256, 256).lambda, 2.75f);
  f.lod = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(lod.eval(f, 256, 256).lambda, 1.5f);
  f.lod = std::numeric_limits<float>::infinity();
  EXPECT_EQ(lod.eval(f, 256, 256).lambda, 2.75f);
  f.lod = -std::numeric_limits<float>::infinity();
  EXPECT_EQ(lod.eval(f, 256, 256).lambda, 0.0f);
  // Its cost: the bias add, the select and the clamp, none of the derivative front.
  const OpCounts o = lod.ops_for(SampleOp::kSampleLod);
  EXPECT_EQ(o.add, 1u);
  EXPECT_EQ(o.cmp, 3u);
  EXPECT_EQ(o.mul + o.lut + o.div + o.sqrt, 0u);
  EXPECT_TRUE(lod.ops_for(SampleOp::kSampleGrad) == lod.ops_per_item());
}

// Explicit gradients (textureGrad): λ from the derivative fields like an implicit sample, with
// the sampler's bias only.
TEST(LodUnit, ExplicitGradientsTakeTheSamplerBiasOnly) {
  LodUnit::Config c;
  c.lod_bias = 0.25f;
  LodUnit lod(c);
  const double s = 4.0 / 256;  // λ_base = 2
  Fragment f = frag(s, 0, 0, s, 1.0f);
  EXPECT_EQ(lod.eval(f, 256, 256).lambda, 3.25f);
  f.op = static_cast<uint8_t>(SampleOp::kSampleGrad);
  EXPECT_EQ(lod.eval(f, 256, 256).lambda, 2.25f);
  f.dudx = f.dvdy = 0;  // zero gradients: min_lod
  EXPECT_EQ(lod.eval(f, 256, 256).lambda, 0.0f);
  f.dudx = f.dvdy = 1e38;  // overflowing gradients: max_lod
  EXPECT_EQ(lod.eval(f, 256, 256).lambda, c.max_lod);
}

TEST(LodUnit, VulkanAnisotropyDirected) {
  LodUnit::Config c;
  c.aniso = AnisoMode::Vulkan;
  c.min_lod = -10;
  LodUnit lod(c);
  OpCounts ops;
  // 16 × 4 texels: η = 4, λ = log2(16/4) = 2, major axis x.
  LodResult r = lod.eval(frag(16.0 / 256, 0, 0, 4.0 / 256), 256, 256, ops);
  EXPECT_EQ(r.probes, 4);
  EXPECT_EQ(r.lambda, 2.0f);
  EXPECT_FLOAT_EQ(r.axis_u, 16.0f / 256 / 4);
  EXPECT_EQ(r.axis_v, 0.0f);
  // Major axis y, ratio 3.5 → N = 4, λ = log2(14/4).
  r = lod.eval(frag(4.0 / 256, 0, 0, 14.0 / 256), 256, 256, ops);
  EXPECT_EQ(r.probes, 4);
  EXPECT_NEAR(r.lambda, std::log2(14.0 / 4), 1e-6);
  EXPECT_EQ(r.axis_u, 0.0f);
  EXPECT_FLOAT_EQ(r.axis_v, 14.0f / 256 / 4);
  // Ratio 40 → N = maxAniso = 16, λ = log2(40/16).
  r = lod.eval(frag(40.0 / 256, 0, 0, 1.0 / 256), 256, 256, ops);
  EXPECT_EQ(r.probes, 16);
  EXPECT_NEAR(r.lambda, std::log2(40.0 / 16), 1e-6);
  // ρmin = 0, ρmax ≠ 0: a line segment, η = maxAniso.
  r = lod.eval(frag(8.0 / 256, 0, 0, 0), 256, 256, ops);
  EXPECT_EQ(r.probes, 16);
  EXPECT_EQ(r.lambda, -1.0f);
  // Equal axes: isotropic, N = 1, same λ as the isotropic unit.
  r = lod.eval(frag(8.0 / 256, 0, 0, 8.0 / 256), 256, 256, ops);
  EXPECT_EQ(r.probes, 1);
  EXPECT_EQ(r.lambda, 3.0f);
  // max_aniso = 1 reduces the Vulkan rule to the isotropic one.
  LodUnit::Config c1 = c;
  c1.max_aniso = 1;
  r = LodUnit(c1).eval(frag(16.0 / 256, 0, 0, 4.0 / 256), 256, 256, ops);
  EXPECT_EQ(r.probes, 1);
  EXPECT_EQ(r.lambda, 4.0f);
}

// Seeded random footprints (log-uniform scale and anisotropy, random orientation) against the
// long-double reference: |Δλ| bounded by the float32 datapath's error (a few ulp of ρ²).
TEST(LodUnit, RandomAgainstLongDoubleReference) {
  std::mt19937_64 rng(0x10D5EEDu);
  std::uniform_real_distribution<double> scale(-12, 6), aniso(0, 6), ang(0, 6.283185307179586);
  std::uniform_int_distribution<int> size(0, 12);
  double worst_iso = 0, worst_vk = 0;
  int n_mismatch = 0;
  for (AnisoMode m : {AnisoMode::Isotropic, AnisoMode::Vulkan}) {
    LodUnit::Config c;
    c.aniso = m;
    c.min_lod = -100;
    c.max_lod = 100;
    LodUnit lod(c);
    for (int it = 0; it < 200000; ++it) {
      const int w = 1 + (1 << size(rng)) + (it % 3 == 0 ? size(rng) : 0);  // also NPOT
      const int h = 1 + (1 << size(rng));
      const double len = std::exp2(scale(rng));  // texels along the major axis
      const double minor = len / std::exp2(aniso(rng));
      const double a = ang(rng), b = a + 1.5707963267948966 + (ang(rng) - 3.14) * 0.2;
      Fragment f = frag(len * std::cos(a) / w, len * std::sin(a) / h, minor * std::cos(b) / w,
                        minor * std::sin(b) / h);
      if (it & 1) {
        std::swap(f.dudx, f.dudy);
        std::swap(f.dvdx, f.dvdy);
      }
      OpCounts ops;
      const LodResult r = lod.eval(f, w, h, ops);
      const RefLod ref = reference(f, w, h, m, c.max_aniso);
      // N may legitimately differ where the ratio sits within float rounding of an integer.
      const long double near_int = std::fabs(ref.ratio - std::round(ref.ratio));
      if (r.probes != ref.n) {
        ASSERT_EQ(m, AnisoMode::Vulkan);
        ASSERT_LT(near_int, 1e-5L) << "ratio " << static_cast<double>(ref.ratio);
        ++n_mismatch;
        continue;
      }
      const double err = std::fabs(static_cast<double>(r.lambda - ref.lambda_base));
      (m == AnisoMode::Isotropic ? worst_iso : worst_vk) =
          std::max(m == AnisoMode::Isotropic ? worst_iso : worst_vk, err);
    }
  }
  std::printf("max |λ - λ_ref|: isotropic %.3g, vulkan %.3g; N at integer-ratio ties: %d\n",
              worst_iso, worst_vk, n_mismatch);
  EXPECT_LT(worst_iso, 2e-6);
  EXPECT_LT(worst_vk, 2e-6);
  EXPECT_LT(n_mismatch, 20);
}

// Hard cases: footprints from 2^-74 to 2^63 texels, at the edges of float32's range for ρ².
// Down to 2^-71 texels λ stays within 1e-5·|λ| of the reference. Below, the squares are
// subnormal and lose bits: λ is then off by up to 2.5 but still below −69, which any
// practical min_lod clamps. Tinier still, ρ² flushes to 0 and λ = −∞ clamps to min_lod;
// above 2^64 texels ρ² overflows and λ clamps to max_lod.
TEST(LodUnit, ExtremeScalesAgainstLongDouble) {
  LodUnit::Config c;
  c.min_lod = -1000;
  c.max_lod = 1000;
  double worst = 0;
  for (AnisoMode m : {AnisoMode::Isotropic, AnisoMode::Vulkan}) {
    c.aniso = m;
    const LodUnit lod(c);
    for (int k = -74; k <= 63; ++k) {
      for (double frac : {1.0, 1.2345678, 1.9999999}) {
        const double len = std::ldexp(frac, k);  // texels on a 1024² texture
        const Fragment f = frag(len / 1024 * 0.6, len / 1024 * 0.8, 0, len / 1024 / 2.7);
        OpCounts ops;
        const LodResult r = lod.eval(f, 1024, 1024, ops);
        const RefLod ref = reference(f, 1024, 1024, m, 16);
        const double err = std::fabs(static_cast<double>(r.lambda - ref.lambda_base));
        if (k < -71) {
          EXPECT_LT(r.lambda, -69.0f) << "k=" << k;
          continue;
        }
        worst = std::max(worst, err);
        EXPECT_LT(err, 1e-5 * std::max(1.0, std::fabs(static_cast<double>(ref.lambda_base))))
            << "k=" << k << " frac=" << frac;
      }
    }
    OpCounts ops;
    EXPECT_EQ(lod.eval(frag(1e-30, 0, 0, 1e-30), 1024, 1024, ops).lambda, -1000.0f);  // ρ² = 0
    EXPECT_EQ(lod.eval(frag(1e17, 0, 0, 1e17), 1024, 1024, ops).lambda, 1000.0f);     // ρ² = inf
  }
  std::printf("extreme scales 2^-71..2^63 texels: max |λ - λ_ref| = %.3g\n", worst);
}

TEST(LodUnit, OpCountsAndTiming) {
  OpCounts ops;
  LodUnit iso;
  iso.eval(frag(0.01, 0, 0, 0.01), 64, 64, ops);
  iso.eval(frag(0, 0, 0, 0), 64, 64, ops);  // data-independent: the datapath always runs
  OpCounts one = iso.ops_per_item();
  EXPECT_EQ(ops, one * 2);
  EXPECT_EQ(one.mul, 8u);
  EXPECT_EQ(one.lut, 1u);
  EXPECT_EQ(one.sqrt, 0u);  // ½·log2 ρ² needs no square root
  LodUnit::Config c;
  c.aniso = AnisoMode::Vulkan;
  const OpCounts vk = LodUnit(c).ops_per_item();
  EXPECT_EQ(vk.div, 1u);
  EXPECT_EQ(vk.sqrt, 1u);
  EXPECT_EQ(vk.lut, 3u);

  const TechTable tech = TechTable::defaults();
  const TimingSpec ti = iso.timing(tech);
  // mul, mul, add, cmp, lut, add, add, cmp, cmp
  EXPECT_EQ(ti.latency,
            static_cast<uint32_t>(2 * tech.lat(OpKind::Mul) + 3 * tech.lat(OpKind::Add) +
                                  3 * tech.lat(OpKind::Cmp) + tech.lat(OpKind::Lut)));
  EXPECT_DOUBLE_EQ(ti.area, tech.area_of(one));
  const TimingSpec tv = LodUnit(c).timing(tech);
  EXPECT_GT(tv.latency, ti.latency);  // div + sqrt on the N path
  EXPECT_GT(tv.area, ti.area);
  // A slower divider shows up one for one in the Vulkan unit's latency.
  TechTable slow = tech;
  slow.latency[static_cast<int>(OpKind::Div)] += 10;
  EXPECT_EQ(LodUnit(c).timing(slow).latency, tv.latency + 10);
  EXPECT_EQ(iso.timing(slow).latency, ti.latency);
  std::printf("default tech: isotropic latency %u area %.1f; vulkan latency %u area %.1f\n",
              ti.latency, ti.area, tv.latency, tv.area);
}

TEST(LodUnit, ConfigFromToml) {
  auto parse = [](const std::string& text) {
    static toml::table t;
    t = toml::parse(std::string_view(text), std::string_view("scene.toml"));
    return LodUnit::Config::from_toml(ConfigReader(t, "scene.toml", "lod"));
  };
  const LodUnit::Config c =
      parse("aniso = 'vulkan'\nmax_aniso = 8\nlod_bias = -0.5\nmin_lod = 1\nmax_lod = 6.5\n");
  EXPECT_EQ(c.aniso, AnisoMode::Vulkan);
  EXPECT_EQ(c.max_aniso, 8);
  EXPECT_EQ(c.lod_bias, -0.5f);
  EXPECT_EQ(c.min_lod, 1.0f);
  EXPECT_EQ(c.max_lod, 6.5f);
  const LodUnit::Config d = parse("");
  EXPECT_EQ(d.aniso, AnisoMode::Isotropic);
  EXPECT_EQ(d.max_aniso, 16);
  try {
    parse("anisotropy = 'vulkan'\n");
    FAIL() << "unknown key accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scene.toml:1:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("anisotropy"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse("max_aniso = 32\n"), InputError);
  EXPECT_THROW(parse("aniso = 'ewa'\n"), InputError);
  EXPECT_THROW(parse("min_lod = 3\nmax_lod = 2\n"), InputError);
}

}  // namespace
}  // namespace texsim
