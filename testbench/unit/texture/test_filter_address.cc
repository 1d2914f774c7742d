// TexelAddressGen + TexelBlend: Vulkan address modes, level selection, taps at texel centres and
// borders, 1×1 and odd-sized textures, anisotropic probes; seeded random queries against a
// double-precision reference filter written here; op counts, timing and config parsing.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <random>

#include "blocks/base/input_error.h"
#include "blocks/texture/sampler/texel_address_gen.h"
#include "blocks/texture/sampler/texel_blend.h"
#include "pipeline/texture/texture_unit.h"
#include "testbench/lib/filter_fixtures.h"

namespace texsim {
namespace {

TexelAddressGen gen(FilterMode f, AddressMode mu, AddressMode mv, int sub_bits = 8,
                    int mip_bits = 8) {
  TexelAddressGen::Config c;
  c.filter = f;
  c.address_u = mu;
  c.address_v = mv;
  c.sub_texel_bits = sub_bits;
  c.mipmap_bits = mip_bits;
  return TexelAddressGen(c);
}

LodResult lod_at(float lambda) {
  LodResult r;
  r.lambda = lambda;
  return r;
}

// Independent statement of the three address modes (mirrored repeat as a triangle wave).
int64_t ref_address(int64_t i, int64_t s, AddressMode m) {
  switch (m) {
    case AddressMode::Wrap:
      return ((i % s) + s) % s;
    case AddressMode::Clamp:
      return i < 0 ? 0 : (i >= s ? s - 1 : i);
    case AddressMode::Mirror: {
      const int64_t t = ((i % (2 * s)) + 2 * s) % (2 * s);
      return t < s ? t : 2 * s - 1 - t;
    }
    case AddressMode::Border:  // test_filter_border.cc states these two
    case AddressMode::MirrorClamp:
      break;
  }
  return -1;
}

TEST(TexelAddressGen, AddressModesMatchVulkan) {
  for (int32_t s : {1, 2, 3, 5, 8, 13}) {
    for (int64_t i = -40; i <= 40; ++i) {
      for (AddressMode m : {AddressMode::Wrap, AddressMode::Clamp, AddressMode::Mirror}) {
        const int32_t a = TexelAddressGen::address(i, s, m);
        EXPECT_EQ(a, ref_address(i, s, m)) << "i=" << i << " size=" << s << " " << to_string(m);
        EXPECT_GE(a, 0);
        EXPECT_LT(a, s);
      }
    }
  }
  // Mirrored repeat of size 3 from i = −4: 2 2 1 0 | 0 1 2 | 2 1 0 | 0.
  const int expect[] = {2, 2, 1, 0, 0, 1, 2, 2, 1, 0, 0};
  for (int k = 0; k < 11; ++k) {
    EXPECT_EQ(TexelAddressGen::address(k - 4, 3, AddressMode::Mirror), expect[k]) << k;
  }
  // Far-away coordinates stay in range.
  EXPECT_EQ(TexelAddressGen::address(int64_t{1} << 40, 7, AddressMode::Wrap),
            ref_address(int64_t{1} << 40, 7, AddressMode::Wrap));
  EXPECT_EQ(TexelAddressGen::address(-(int64_t{1} << 40) - 3, 6, AddressMode::Mirror),
            ref_address(-(int64_t{1} << 40) - 3, 6, AddressMode::Mirror));
}

TEST(TexelAddressGen, LevelSelection) {
  const auto near = gen(FilterMode::Bilinear, AddressMode::Wrap, AddressMode::Wrap);
  const auto tri = gen(FilterMode::Trilinear, AddressMode::Wrap, AddressMode::Wrap);
  const float lsb = 1.0f / 256;
  // Nearest: ⌈d' + ½⌉ − 1, so exactly .5 rounds down.
  EXPECT_EQ(near.select_levels(0.5f, 9).d_hi, 0);
  EXPECT_EQ(near.select_levels(0.5f + lsb, 9).d_hi, 1);
  EXPECT_EQ(near.select_levels(0.5f + 0.4f * lsb, 9).d_hi, 0);  // quantised to .5 first
  EXPECT_EQ(near.select_levels(1.5f, 9).d_hi, 1);
  EXPECT_EQ(near.select_levels(1.49f, 9).d_hi, 1);
  EXPECT_EQ(near.select_levels(2.7f, 9).d_hi, 3);
  EXPECT_EQ(near.select_levels(-3.0f, 9).d_hi, 0);
  EXPECT_EQ(near.select_levels(100.0f, 9).d_hi, 8);
  EXPECT_EQ(near.select_levels(100.0f, 1).d_hi, 0);  // no mips
  EXPECT_EQ(near.select_levels(std::numeric_limits<float>::quiet_NaN(), 9).d_hi, 0);
  EXPECT_EQ(near.select_levels(std::numeric_limits<float>::infinity(), 9).d_hi, 8);
  // Linear: d_hi = ⌊d'⌋, d_lo = min(d_hi + 1, q), δ quantised to mipmap_bits.
  auto s = tri.select_levels(1.25f, 9);
  EXPECT_EQ(s.d_hi, 1);
  EXPECT_EQ(s.d_lo, 2);
  EXPECT_EQ(s.delta, 0.25f);
  s = tri.select_levels(1.0f / 3, 9);
  EXPECT_EQ(s.d_hi, 0);
  EXPECT_EQ(s.delta, 85.0f / 256);  // round(85.33)
  s = gen(FilterMode::Trilinear, AddressMode::Wrap, AddressMode::Wrap, 8, 6)
          .select_levels(1.0f / 3, 9);
  EXPECT_EQ(s.delta, 21.0f / 64);
  s = tri.select_levels(8.0f, 9);
  EXPECT_EQ(s.d_hi, 8);
  EXPECT_EQ(s.d_lo, 8);
  EXPECT_EQ(s.delta, 0.0f);
  s = tri.select_levels(7.999f, 9);  // rounds up to level 8 at 8 bits
  EXPECT_EQ(s.d_hi, 8);
  EXPECT_EQ(s.delta, 0.0f);
  s = tri.select_levels(-1.0f, 9);
  EXPECT_EQ(s.d_hi, 0);
  EXPECT_EQ(s.d_lo, 1);
  EXPECT_EQ(s.delta, 0.0f);
}

TEST(TexelAddressGen, TexelCentresAndBorders) {
  const Texture tex = random_texture(5, 3, 1);  // odd sizes
  OpCounts ops;
  FilterTaps t;
  for (AddressMode m : {AddressMode::Wrap, AddressMode::Clamp, AddressMode::Mirror}) {
    // Texel centres: one tap of weight 1 (bilinear: three zero-weight neighbours).
    for (int y = 0; y < 3; ++y) {
      for (int x = 0; x < 5; ++x) {
        const double u = (x + 0.5) / 5, v = (y + 0.5) / 3;
        gen(FilterMode::Nearest, m, m).taps(tex, u, v, lod_at(0), t, ops);
        ASSERT_EQ(t.count, 1);
        EXPECT_EQ(t.tap[0].x, x);
        EXPECT_EQ(t.tap[0].y, y);
        EXPECT_EQ(t.tap[0].w, 1.0f);
        gen(FilterMode::Bilinear, m, m).taps(tex, u, v, lod_at(0), t, ops);
        ASSERT_EQ(t.count, 4);
        EXPECT_EQ(t.tap[0].x, x);
        EXPECT_EQ(t.tap[0].y, y);
        EXPECT_EQ(t.tap[0].w, 1.0f);
        EXPECT_EQ(t.tap[1].w + t.tap[2].w + t.tap[3].w, 0.0f);
      }
    }
  }
  // u = v = 0: halfway between texel −1 and 0 on both axes.
  struct Case {
    AddressMode m;
    int x0, x1;
  };
  for (const Case& c : {Case{AddressMode::Wrap, 4, 0}, Case{AddressMode::Clamp, 0, 0},
                        Case{AddressMode::Mirror, 0, 0}}) {
    gen(FilterMode::Bilinear, c.m, AddressMode::Clamp).taps(tex, 0.0, 0.5, lod_at(0), t, ops);
    EXPECT_EQ(t.tap[0].x, c.x0) << to_string(c.m);
    EXPECT_EQ(t.tap[1].x, c.x1) << to_string(c.m);
    EXPECT_EQ(t.tap[0].w + t.tap[2].w, 0.5f);
  }
  // u = 1 on the right edge: texels 4 and wrap 0 / clamp 4 / mirror 4.
  for (const Case& c : {Case{AddressMode::Wrap, 4, 0}, Case{AddressMode::Clamp, 4, 4},
                        Case{AddressMode::Mirror, 4, 4}}) {
    gen(FilterMode::Bilinear, c.m, AddressMode::Clamp).taps(tex, 1.0, 0.5, lod_at(0), t, ops);
    EXPECT_EQ(t.tap[0].x, c.x0) << to_string(c.m);
    EXPECT_EQ(t.tap[1].x, c.x1) << to_string(c.m);
  }
  // Nearest at u just below 0 and at 1: wrap to the far side, clamp to the edge, mirror back.
  gen(FilterMode::Nearest, AddressMode::Wrap, AddressMode::Wrap)
      .taps(tex, -0.1, 1.0, lod_at(0), t, ops);
  EXPECT_EQ(t.tap[0].x, 4);
  EXPECT_EQ(t.tap[0].y, 0);
  gen(FilterMode::Nearest, AddressMode::Clamp, AddressMode::Clamp)
      .taps(tex, -0.1, 1.0, lod_at(0), t, ops);
  EXPECT_EQ(t.tap[0].x, 0);
  EXPECT_EQ(t.tap[0].y, 2);
  gen(FilterMode::Nearest, AddressMode::Mirror, AddressMode::Mirror)
      .taps(tex, -0.1, 1.0, lod_at(0), t, ops);
  EXPECT_EQ(t.tap[0].x, 0);
  EXPECT_EQ(t.tap[0].y, 2);
}

TEST(TexelAddressGen, OneByOneTextureAndCoarsestLevel) {
  const Texture one = random_texture(1, 1, 2);
  const Texture odd = random_texture(7, 3, 3);  // levels 7×3, 3×1, 1×1
  ASSERT_EQ(odd.levels(), 3);
  ASSERT_EQ(odd.width(1), 3);
  ASSERT_EQ(odd.height(1), 1);
  OpCounts ops;
  FilterTaps t;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uv(-3, 3);
  for (FilterMode f : {FilterMode::Nearest, FilterMode::Bilinear, FilterMode::Trilinear}) {
    for (AddressMode m : {AddressMode::Wrap, AddressMode::Clamp, AddressMode::Mirror}) {
      for (int it = 0; it < 200; ++it) {
        gen(f, m, m).taps(one, uv(rng), uv(rng), lod_at(static_cast<float>(it % 5)), t, ops);
        float sum = 0;
        for (int k = 0; k < t.count; ++k) {
          EXPECT_EQ(t.tap[k].level, 0);
          EXPECT_EQ(t.tap[k].x, 0);
          EXPECT_EQ(t.tap[k].y, 0);
          sum += t.tap[k].w;
        }
        EXPECT_EQ(sum, 1.0f);
        gen(f, m, m).taps(odd, uv(rng), uv(rng), lod_at(10.0f), t, ops);
        for (int k = 0; k < t.count; ++k) {
          EXPECT_EQ(t.tap[k].level, 2);
          EXPECT_EQ(t.tap[k].x, 0);
          EXPECT_EQ(t.tap[k].y, 0);
        }
      }
    }
  }
}

TEST(TexelAddressGen, NonFiniteAndHugeCoordinates) {
  const Texture tex = random_texture(6, 10, 4);
  OpCounts ops;
  FilterTaps a, b;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (FilterMode f : {FilterMode::Nearest, FilterMode::Bilinear, FilterMode::Trilinear}) {
    for (AddressMode m : {AddressMode::Wrap, AddressMode::Clamp, AddressMode::Mirror}) {
      const auto g = gen(f, m, m);
      g.taps(tex, nan, std::numeric_limits<double>::infinity(), lod_at(1.3f), a, ops);
      g.taps(tex, 0.0, 0.0, lod_at(1.3f), b, ops);
      ASSERT_EQ(a.count, b.count);
      for (int k = 0; k < a.count; ++k) {
        EXPECT_EQ(a.tap[k].x, b.tap[k].x);
        EXPECT_EQ(a.tap[k].y, b.tap[k].y);
        EXPECT_EQ(a.tap[k].w, b.tap[k].w);
      }
      for (double huge : {1e12, -1e12, 3e38, 1e300}) {
        g.taps(tex, huge, -huge, lod_at(0.0f), a, ops);
        for (int k = 0; k < a.count; ++k) {
          EXPECT_GE(a.tap[k].x, 0);
          EXPECT_LT(a.tap[k].x, tex.width(a.tap[k].level));
          EXPECT_GE(a.tap[k].y, 0);
          EXPECT_LT(a.tap[k].y, tex.height(a.tap[k].level));
          EXPECT_TRUE(std::isfinite(a.tap[k].w));
        }
      }
    }
  }
}

// Double-precision reference filter: exact coordinates (no float32), fractions quantised with
// the same round-to-nearest rule, Vulkan addressing stated independently above.
Rgba ref_level(const Texture& tex, int level, double u, double v, FilterMode f, AddressMode mu,
               AddressMode mv, int bits, bool quantise) {
  const int w = tex.width(level), h = tex.height(level);
  const double scale = std::ldexp(1.0, bits);
  auto q = [&](double x) { return quantise ? std::nearbyint(x * scale) / scale : x; };
  if (f == FilterMode::Nearest) {
    const auto i = static_cast<int64_t>(std::floor(q(u * w)));
    const auto j = static_cast<int64_t>(std::floor(q(v * h)));
    return tex.texel(level, static_cast<int>(ref_address(i, w, mu)),
                     static_cast<int>(ref_address(j, h, mv)));
  }
  const double x = q(u * w - 0.5), y = q(v * h - 0.5);
  const double fx = std::floor(x), fy = std::floor(y);
  const double a = x - fx, b = y - fy;
  const auto i0 = static_cast<int64_t>(fx), j0 = static_cast<int64_t>(fy);
  auto T = [&](int64_t i, int64_t j) {
    const Rgba c = tex.texel(level, static_cast<int>(ref_address(i, w, mu)),
                             static_cast<int>(ref_address(j, h, mv)));
    return glm::dvec4(c);
  };
  const glm::dvec4 r = (1 - a) * (1 - b) * T(i0, j0) + a * (1 - b) * T(i0 + 1, j0) +
                       (1 - a) * b * T(i0, j0 + 1) + a * b * T(i0 + 1, j0 + 1);
  return Rgba(r);
}

double max_abs(const Rgba& a, const Rgba& b) {
  double m = 0;
  for (int c = 0; c < 4; ++c) m = std::max(m, std::fabs(static_cast<double>(a[c] - b[c])));
  return m;
}

// Seeded random queries, all filters × address modes × (8, 6) bits × sizes, magnification and
// minification: the float32 filter + blend must equal the double reference with the same
// quantisation to float rounding (≤ 1e-5), except where float32 rounding of u·w moves the
// coordinate across a quantisation tie (then ≤ one weight LSB); and it must stay within the
// quantisation bound (2^-bits per axis, per level) of the unquantised filter.
TEST(TexelAddressGen, RandomAgainstDoubleReference) {
  const int sizes[][2] = {{1, 1}, {2, 7}, {5, 3}, {16, 16}, {33, 17}, {64, 128}, {300, 5}};
  std::mt19937_64 rng(0xF117E5u);
  std::uniform_real_distribution<double> uv(-2.5, 2.5), lam(-2, 9);
  int ties = 0, n = 0;
  double worst_exact = 0, worst_quant = 0;
  for (auto [w, h] : sizes) {
    const Texture tex =
        random_texture(w, h, static_cast<uint64_t>(w) * 1000 + static_cast<uint64_t>(h));
    for (FilterMode f : {FilterMode::Nearest, FilterMode::Bilinear, FilterMode::Trilinear}) {
      for (AddressMode mu : {AddressMode::Wrap, AddressMode::Clamp, AddressMode::Mirror}) {
        for (AddressMode mv : {AddressMode::Wrap, AddressMode::Clamp, AddressMode::Mirror}) {
          for (int bits : {8, 6}) {
            const TexelAddressGen g = gen(f, mu, mv, bits, bits);
            const TexelBlend blend;
            for (int it = 0; it < 300; ++it) {
              const double u = uv(rng), v = uv(rng);
              const float lambda = static_cast<float>(lam(rng));
              FilterTaps t;
              OpCounts ops;
              g.taps(tex, u, v, lod_at(lambda), t, ops);
              const Rgba got = blend.blend(t, tex, ops);
              const auto sel = g.select_levels(lambda, tex.levels());
              // Reference with λ's level split taken from select_levels (tested above).
              const double uf = static_cast<float>(u), vf = static_cast<float>(v);
              auto ref = [&](bool qz) {
                if (f != FilterMode::Trilinear) {
                  return ref_level(tex, sel.d_hi, uf, vf, f, mu, mv, bits, qz);
                }
                const glm::dvec4 a(ref_level(tex, sel.d_hi, uf, vf, f, mu, mv, bits, qz));
                const glm::dvec4 b(ref_level(tex, sel.d_lo, uf, vf, f, mu, mv, bits, qz));
                return Rgba((1.0 - sel.delta) * a + static_cast<double>(sel.delta) * b);
              };
              const double e_exact = max_abs(got, ref(true));
              const double e_quant = max_abs(got, ref(false));
              ++n;
              // Tie: the float32 product u·w differs from the exact one near a
              // quantisation boundary; allow one LSB on each axis there.
              const double lsb = std::ldexp(1.0, -bits);
              if (e_exact > 1e-5) {
                ++ties;
                ASSERT_LE(e_exact, (f == FilterMode::Nearest ? 1.0 : 2 * lsb) + 1e-5)
                    << w << "x" << h << " " << to_string(f) << " u=" << u << " v=" << v;
              } else {
                worst_exact = std::max(worst_exact, e_exact);
              }
              if (f != FilterMode::Nearest) worst_quant = std::max(worst_quant, e_quant);
              if (f != FilterMode::Nearest) {
                ASSERT_LE(e_quant, 2 * lsb + 1e-5) << w << "x" << h << " u=" << u;
              }
            }
          }
        }
      }
    }
  }
  std::printf(
      "%d queries: max |filter - quantised double ref| %.3g (%d float32 tie cases); "
      "max |filter - unquantised ref| %.3g\n",
      n, worst_exact, ties, worst_quant);
  EXPECT_LT(ties, n / 200);
}

TEST(TexelAddressGen, AnisotropicProbesAreCentredAndAveraged) {
  const Texture tex = random_texture(64, 32, 5);
  OpCounts ops;
  for (FilterMode f : {FilterMode::Nearest, FilterMode::Bilinear, FilterMode::Trilinear}) {
    const auto g = gen(f, AddressMode::Wrap, AddressMode::Mirror);
    for (int n : {2, 3, 16}) {
      LodResult lod = lod_at(1.6f);
      lod.probes = n;
      lod.axis_u = 0.013f;
      lod.axis_v = -0.004f;
      FilterTaps t;
      g.taps(tex, 0.3, 0.7, lod, t, ops);
      ASSERT_EQ(t.count, n * g.taps_per_probe());
      float sum = 0;
      for (int k = 0; k < t.count; ++k) sum += t.tap[k].w;
      EXPECT_NEAR(sum, 1.0f, 2e-6f);
      // Probe k equals an isotropic lookup at (u, v) + (k − (N−1)/2)·axis, weights × 1/N.
      for (int k = 0; k < n; ++k) {
        const float off = static_cast<float>(k) - 0.5f * static_cast<float>(n - 1);
        FilterTaps one;
        g.taps(tex, 0.3f + off * lod.axis_u, 0.7f + off * lod.axis_v, lod_at(1.6f), one, ops);
        for (int j = 0; j < one.count; ++j) {
          const TexelTap& a = t.tap[static_cast<size_t>(k) * static_cast<size_t>(one.count) +
                                    static_cast<size_t>(j)];
          EXPECT_EQ(a.x, one.tap[j].x);
          EXPECT_EQ(a.y, one.tap[j].y);
          EXPECT_EQ(a.level, one.tap[j].level);
          EXPECT_FLOAT_EQ(a.w, one.tap[j].w / static_cast<float>(n));
        }
      }
      // Probes are symmetric about (u, v): first and last offsets are ±(N−1)/2 steps.
      EXPECT_EQ(TexelAddressGen::issue_cycles(lod), static_cast<uint32_t>(n));
    }
  }
}

TEST(TexelBlend, WeightedSumAndTree) {
  const Texture tex = random_texture(9, 9, 6);
  std::mt19937_64 rng(8);
  std::uniform_int_distribution<int> xy(0, 8), cnt(1, 128);
  std::uniform_real_distribution<float> wd(0, 1);
  for (int tpc : {1, 4, 8, 32}) {
    TexelBlend::Config c;
    c.taps_per_cycle = tpc;
    const TexelBlend b(c);
    for (int it = 0; it < 500; ++it) {
      FilterTaps t;
      t.count = cnt(rng);
      glm::dvec4 ref(0.0);
      double wsum = 0;
      for (int k = 0; k < t.count; ++k) {
        t.tap[k] = {0, xy(rng), xy(rng), wd(rng) / static_cast<float>(t.count)};
        ref += glm::dvec4(tex.texel(0, t.tap[k].x, t.tap[k].y)) * static_cast<double>(t.tap[k].w);
        wsum += t.tap[k].w;
      }
      OpCounts ops;
      const Rgba got = b.blend(t, tex, ops);
      for (int ch = 0; ch < 4; ++ch)
        EXPECT_NEAR(got[ch], ref[ch], 8e-6 * (1 + wsum));  // n·2^-24 for n ≤ 128
      EXPECT_EQ(ops.mem, static_cast<uint64_t>(t.count));
      EXPECT_EQ(ops.mul, 4u * static_cast<uint64_t>(t.count));
      EXPECT_EQ(b.issue_cycles(t), static_cast<uint32_t>((t.count + tpc - 1) / tpc));
    }
  }
  // Constant texture: result = weight sum exactly for dyadic weights.
  const Texture flat =
      Texture::from_rgba("flat", 2, 2, std::vector<float>(16, 0.5f), TexelFormat::Rgba32f, false);
  FilterTaps t;
  t.count = 3;
  t.tap[0] = {0, 0, 0, 0.25f};
  t.tap[1] = {0, 1, 0, 0.5f};
  t.tap[2] = {0, 1, 1, 0.25f};
  OpCounts ops;
  EXPECT_EQ(TexelBlend().blend(t, flat, ops), Rgba(0.5f));
}

// The converters' rounding without a library call must be std::llrint (ties to even) bit for
// bit: exhaustively over [2^21, 2^25) of both signs, where the 2^23 trick switches over, and
// on a stride through every other finite float below 2^62.
TEST(TexelAddressGen, RoundHalfEvenMatchesLlrint) {
  auto check = [](float x) {
    ASSERT_EQ(TexelAddressGen::round_half_even(x), std::llrint(x)) << std::hexfloat << x;
  };
  for (float sign : {1.0f, -1.0f}) {
    for (float x = std::ldexp(1.0f, 21); x < std::ldexp(1.0f, 25);
         x = std::nextafter(x, std::numeric_limits<float>::infinity())) {
      check(sign * x);
    }
  }
  for (uint32_t bits = 0; bits < 0xff000000u; bits += 97) {
    float x;
    std::memcpy(&x, &bits, sizeof x);
    if (std::isfinite(x) && std::fabs(x) < std::ldexp(1.0f, 62)) check(x);
  }
  // Hard cases: halves (ties go to the even neighbour), ±0, subnormals, just below 2^23.
  for (float x : {0.5f, 1.5f, 2.5f, -0.5f, -1.5f, -2.5f, 0.0f, -0.0f, 1e-45f, -1e-45f, 8388607.5f,
                  -8388607.5f, 4194303.5f, 8388608.0f, 16777215.0f}) {
    check(x);
  }
  EXPECT_EQ(TexelAddressGen::round_half_even(2.5f), 2);
  EXPECT_EQ(TexelAddressGen::round_half_even(-3.5f), -4);
  EXPECT_EQ(TexelAddressGen::round_half_even(8388607.5f), 8388608);
}

// Reference for the blend order of docs/derivations/filters.md §5: groups of taps_per_cycle taps in
// tap order, a binary tree in each group (pairs, an odd last element passed up), the group sums
// accumulated from 0. Written with plain Rgba arithmetic and Texture::texel.
Rgba reference_blend(const FilterTaps& t, const Texture& tex, int g) {
  Rgba acc(0.0f);
  for (int base = 0; base < t.count; base += g) {
    const int n = std::min(g, t.count - base);
    std::vector<Rgba> p;
    for (int k = 0; k < n; ++k) {
      const TexelTap& tk = t.tap[static_cast<size_t>(base) + static_cast<size_t>(k)];
      p.push_back(tex.texel(tk.level, tk.x, tk.y) * tk.w);
    }
    while (p.size() > 1) {
      std::vector<Rgba> q;
      for (size_t k = 0; k + 1 < p.size(); k += 2) q.push_back(p[k] + p[k + 1]);
      if (p.size() % 2) q.push_back(p.back());
      p = q;
    }
    acc += p[0];
  }
  return acc;
}

// The blend's fast paths (one bilinear or trilinear probe, RGBA8 widening) give exactly the
// reference's bits, for every group size, tap count and texel format.
TEST(TexelBlend, BitExactAgainstReferenceOrder) {
  std::mt19937_64 rng(77);
  for (TexelFormat fmt : {TexelFormat::Rgba8, TexelFormat::Rgba32f}) {
    const Texture tex = random_texture(13, 6, 31, fmt);
    std::uniform_int_distribution<int> lv(0, tex.levels() - 1);
    std::uniform_real_distribution<float> wd(0, 1);
    for (int tpc : {1, 2, 4, 8, 16, 32}) {
      TexelBlend::Config c;
      c.taps_per_cycle = tpc;
      const TexelBlend b(c);
      for (int it = 0; it < 400; ++it) {
        FilterTaps t;
        t.count = it % 3 == 0 ? 4 : (it % 3 == 1 ? 8 : 1 + static_cast<int>(rng() % 40));
        for (int k = 0; k < t.count; ++k) {
          const int l = lv(rng);
          t.tap[static_cast<size_t>(k)] = {
              l, static_cast<int32_t>(rng() % static_cast<uint64_t>(tex.width(l))),
              static_cast<int32_t>(rng() % static_cast<uint64_t>(tex.height(l))),
              wd(rng) - (it % 7 == 0 ? 0.5f : 0.0f)};
        }
        const Rgba got = b.blend(t, tex), want = reference_blend(t, tex, tpc);
        for (int ch = 0; ch < 4; ++ch) {
          ASSERT_EQ(std::bit_cast<uint32_t>(got[ch]), std::bit_cast<uint32_t>(want[ch]))
              << "count " << t.count << " taps_per_cycle " << tpc << " channel " << ch;
        }
      }
    }
  }
}

// The texture unit counts fragments and probes and multiplies the blocks' per-fragment and
// per-probe counts at report time; that must equal summing each call's own count, and its
// colours must be the blocks' colours bit for bit, in both modes.
TEST(TextureUnit, CountedOpsAndColoursEqualPerCallBlocks) {
  TextureSet ts;
  ts.add(random_texture(64, 32, 5, TexelFormat::Rgba8));
  ts.add(random_texture(300, 7, 6, TexelFormat::Rgba32f));
  std::vector<MaterialSetup> mats(3);
  mats[0].name = "a";
  mats[0].filter.filter = FilterMode::Bilinear;
  mats[0].lod.aniso = AnisoMode::Vulkan;
  mats[0].lod.max_aniso = 8;
  mats[1].name = "b";
  mats[1].texture = 1;
  mats[1].filter.filter = FilterMode::Trilinear;
  mats[1].filter.address_u = AddressMode::Mirror;
  mats[2].name = "c";
  mats[2].filter.filter = FilterMode::Nearest;
  mats[2].filter.address_v = AddressMode::Clamp;
  mats[2].lod.aniso = AnisoMode::Vulkan;
  for (bool timing : {false, true}) {
    TextureUnit unit(ts, mats, PipelineSetup{}, TechTable::defaults(), timing);
    const TexelBlend blend(PipelineSetup{}.blend);
    std::vector<OpCounts> lod_ops(3), addr_ops(3), blend_ops(3);
    uint64_t taps_total = 0;
    std::mt19937_64 rng(21);
    std::uniform_real_distribution<double> uv(-2, 2), d(-0.2, 0.2);
    for (int i = 0; i < 3000; ++i) {
      Fragment f;
      f.frame = static_cast<uint32_t>(i / 1000);
      f.u = uv(rng);
      f.v = uv(rng);
      f.dudx = d(rng);
      f.dvdx = d(rng) * 0.1;
      f.dudy = d(rng) * 0.1;
      f.dvdy = d(rng);
      const int m = i % 3;
      f.tex = static_cast<uint32_t>(mats[static_cast<size_t>(m)].texture);
      const Rgba got = unit.process(f, m);
      const Texture& tex = ts[mats[static_cast<size_t>(m)].texture];
      const LodResult lod =
          LodUnit(mats[static_cast<size_t>(m)].lod)
              .eval(f, tex.width(0), tex.height(0), lod_ops[static_cast<size_t>(m)]);
      FilterTaps t;
      TexelAddressGen(mats[static_cast<size_t>(m)].filter)
          .taps(tex, f.u, f.v, lod, t, addr_ops[static_cast<size_t>(m)]);
      const Rgba want = blend.blend(t, tex, blend_ops[static_cast<size_t>(m)]);
      taps_total += static_cast<uint64_t>(t.count);
      for (int ch = 0; ch < 4; ++ch) {
        ASSERT_EQ(std::bit_cast<uint32_t>(got[ch]), std::bit_cast<uint32_t>(want[ch])) << i;
      }
    }
    EXPECT_GT(addr_ops[0].lut, 0u);  // some fragments were anisotropic
    std::map<std::string, OpCounts> want;
    want["lod"] = lod_ops[0] + lod_ops[1] + lod_ops[2];
    want["filter.bilinear"] = addr_ops[0];
    want["filter.trilinear"] = addr_ops[1];
    want["filter.nearest"] = addr_ops[2];
    want["blend"] = blend_ops[0] + blend_ops[1] + blend_ops[2];
    want["cache"].mem = taps_total;
    const auto blocks = unit.blocks();
    ASSERT_EQ(blocks.size(), want.size());
    for (const BlockUse& b : blocks)
      EXPECT_EQ(b.ops, want[b.name]) << b.name << " timing " << timing;
    EXPECT_EQ(unit.fragments(), 3000u);
  }
}

TEST(TexelAddressGen, OpCountsAndTiming) {
  const Texture tex = random_texture(32, 32, 9);
  const auto bil = gen(FilterMode::Bilinear, AddressMode::Clamp, AddressMode::Clamp);
  OpCounts ops;
  FilterTaps t;
  bil.taps(tex, 0.3, 0.4, lod_at(1.0f), t, ops);
  OpCounts want = bil.ops_setup(false) + bil.ops_per_item(false);
  EXPECT_EQ(ops, want);
  // Clamp addressing: 2 cmp per coordinate, 4 coordinates.
  EXPECT_EQ(bil.ops_per_item(false).cmp, 8u);
  EXPECT_EQ(bil.ops_per_item(false).mul, 2u + 4u);  // scale + weight products
  // N probes: N × per-probe (with offset and 1/N) + setup with 1/N.
  LodResult lod = lod_at(1.0f);
  lod.probes = 5;
  ops = {};
  bil.taps(tex, 0.3, 0.4, lod, t, ops);
  EXPECT_EQ(ops, bil.ops_setup(true) + bil.ops_per_item(true) * 5);
  // Trilinear doubles the level work and adds per-tap level weights.
  const auto tri = gen(FilterMode::Trilinear, AddressMode::Clamp, AddressMode::Clamp);
  EXPECT_EQ(tri.ops_per_item(false).mul, 2 * bil.ops_per_item(false).mul + 8);
  // Wrap on NPOT-capable hardware costs multiplies; clamp does not.
  const auto wrap = gen(FilterMode::Bilinear, AddressMode::Wrap, AddressMode::Wrap);
  EXPECT_EQ(wrap.ops_per_item(false).mul, bil.ops_per_item(false).mul + 8);

  const TechTable tech = TechTable::defaults();
  const auto near = gen(FilterMode::Nearest, AddressMode::Clamp, AddressMode::Clamp);
  const auto mir = gen(FilterMode::Bilinear, AddressMode::Mirror, AddressMode::Clamp);
  EXPECT_LT(near.timing(tech).latency, bil.timing(tech).latency);
  EXPECT_LE(bil.timing(tech).latency, tri.timing(tech).latency);
  EXPECT_LT(bil.timing(tech).latency, mir.timing(tech).latency);
  EXPECT_LT(bil.timing(tech).area, tri.timing(tech).area);
  // Mirror path: mul, mul, add, cmp, add, cmp, add, add after i1 = i0 + 1.
  const double front = 3 * tech.lat(OpKind::Cmp) + 2 * tech.lat(OpKind::Add) +  // level select
                       tech.lat(OpKind::Mul) + tech.lat(OpKind::Add) +          // probe offset
                       tech.lat(OpKind::Mul) + 2 * tech.lat(OpKind::Add);       // coordinate
  const double mirror = 2 * tech.lat(OpKind::Mul) + 4 * tech.lat(OpKind::Add) +
                        2 * tech.lat(OpKind::Cmp) + tech.lat(OpKind::Add);
  EXPECT_EQ(mir.timing(tech).latency, static_cast<uint32_t>(front + mirror));
  const TimingSpec bt = TexelBlend().timing(tech);
  EXPECT_EQ(bt.latency, static_cast<uint32_t>(tech.lat(OpKind::Mem) + tech.lat(OpKind::Mul) +
                                              4 * tech.lat(OpKind::Add)));
}

// Prints latency/area/op counts per filter and address mode under the default tech table
// (docs/derivations/filters.md quotes this table), and checks the orderings an architect relies on.
TEST(TexelAddressGen, TimingTable) {
  const TechTable tech = TechTable::defaults();
  std::printf("%-9s %-6s %7s %7s  per isotropic fragment: %4s %4s %4s\n", "filter", "mode",
              "latency", "area", "add", "mul", "cmp");
  double prev_area = 0;
  for (FilterMode f : {FilterMode::Nearest, FilterMode::Bilinear, FilterMode::Trilinear}) {
    double area_clamp = 0;
    for (AddressMode m : {AddressMode::Clamp, AddressMode::Wrap, AddressMode::Mirror}) {
      const auto g = gen(f, m, m);
      const TimingSpec t = g.timing(tech);
      const OpCounts o = g.ops_setup(false) + g.ops_per_item(false);
      std::printf("%-9s %-6s %7u %7.1f  %27lu %4lu %4lu\n", to_string(f), to_string(m), t.latency,
                  t.area, static_cast<unsigned long>(o.add), static_cast<unsigned long>(o.mul),
                  static_cast<unsigned long>(o.cmp));
      if (m == AddressMode::Clamp) area_clamp = t.area;
      EXPECT_GE(t.area, area_clamp);  // clamp is the cheapest address mode
    }
    EXPECT_GT(area_clamp, prev_area);  // nearest < bilinear < trilinear
    prev_area = area_clamp;
  }
  for (int k : {4, 8}) {
    TexelBlend::Config c;
    c.taps_per_cycle = k;
    const TimingSpec t = TexelBlend(c).timing(tech);
    std::printf("blend, %d taps/cycle: latency %u, area %.1f\n", k, t.latency, t.area);
  }
}

TEST(TexelAddressGen, ConfigFromToml) {
  auto parse = [](const std::string& text) {
    static toml::table t;
    t = toml::parse(std::string_view(text), std::string_view("m.toml"));
    return TexelAddressGen::Config::from_toml(ConfigReader(t, "m.toml", "filter"));
  };
  const auto c = parse(
      "mode = 'trilinear'\naddress_u = 'mirror'\naddress_v = 'clamp'\nsub_texel_bits = 6\n"
      "mipmap_bits = 4\n");
  EXPECT_EQ(c.filter, FilterMode::Trilinear);
  EXPECT_EQ(c.address_u, AddressMode::Mirror);
  EXPECT_EQ(c.address_v, AddressMode::Clamp);
  EXPECT_EQ(c.sub_texel_bits, 6);
  EXPECT_EQ(c.mipmap_bits, 4);
  const auto d = parse("");
  EXPECT_EQ(d.filter, FilterMode::Bilinear);
  EXPECT_EQ(d.address_u, AddressMode::Wrap);
  EXPECT_EQ(d.sub_texel_bits, 8);
  // `address` sets both axes; it may not be combined with an axis of its own.
  const auto e = parse("mode = 'nearest'\naddress = 'mirror'\n");
  EXPECT_EQ(e.filter, FilterMode::Nearest);
  EXPECT_EQ(e.address_u, AddressMode::Mirror);
  EXPECT_EQ(e.address_v, AddressMode::Mirror);
  EXPECT_THROW(parse("address = 'clamp'\naddress_u = 'wrap'\n"), InputError);
  EXPECT_THROW(parse("address = 'clamp'\naddress_v = 'clamp'\n"), InputError);
  EXPECT_THROW(parse("address = 'clamp_to_border'\n"), InputError);
  EXPECT_THROW(parse("filter = 'nearest'\n"), InputError);  // the old name of `mode`
  EXPECT_THROW(parse("mode = 'cubic'\n"), InputError);
  EXPECT_THROW(parse("sub_texel_bits = 0\n"), InputError);
  EXPECT_THROW(parse("address_u = 'mirror_once'\n"), InputError);
  static toml::table bt;
  bt = toml::parse(std::string_view("taps_per_cycle = 6\n"), std::string_view("m.toml"));
  EXPECT_THROW(TexelBlend::Config::from_toml(ConfigReader(bt, "m.toml", "blend")), InputError);
}

}  // namespace
}  // namespace texsim
