// Vulkan conformance of border and mirror-clamp addressing, border colours, constant texel
// offsets and the LOD clamp (LodUnit → TexelAddressGen → TexelBlend against the independent
// checker in vulkan_conformance). Seeded random queries must pass; four deliberately wrong
// samplers must be rejected: a border colour one 8-bit LSB off, clamp-to-edge where border is
// asked, the offset added after wrapping, and the LOD clamped before the bias.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "blocks/texture/sampler/lod_unit.h"
#include "blocks/texture/sampler/texel_address_gen.h"
#include "blocks/texture/sampler/texel_blend.h"
#include "testbench/conformance/vulkan_conformance.h"
#include "testbench/lib/filter_fixtures.h"

namespace texsim {
namespace {

struct Sampler {
  LodUnit::Config lod;
  TexelAddressGen::Config addr;
};

VkSamplerState vk_state(const Sampler& s) { return vk_sampler_of(s.addr, s.lod); }

// texsim's sample of one fragment; `taps` receives the taps when not null.
Rgba sample(const Sampler& s, const Texture& tex, const Fragment& f, FilterTaps* taps = nullptr) {
  const LodResult r = LodUnit(s.lod).eval(f, tex.width(0), tex.height(0));
  FilterTaps t;
  TexelAddressGen(s.addr).taps(tex, f.u, f.v, r, t);
  if (taps) *taps = t;
  return TexelBlend().blend(t, tex);
}

// Coordinates mostly around the texture's edges (−1.5 .. 2.5 repeats), footprints from 1/16
// to 64 texels.
Fragment random_fragment(std::mt19937_64& rng, int w, int h) {
  std::uniform_real_distribution<double> uv(-1.5, 2.5), sc(-4, 6), ang(0, 6.283185307179586),
      coin(0, 1), bias(-1, 1);
  Fragment f;
  f.u = uv(rng);
  f.v = uv(rng);
  const double len = std::exp2(sc(rng)), a = ang(rng);
  f.dudx = len * std::cos(a) / w;
  f.dvdx = len * std::sin(a) / h;
  f.dudy = -len * std::sin(a) / w;
  f.dvdy = len * std::cos(a) / h;
  f.lod_bias = coin(rng) < 0.3 ? static_cast<float>(bias(rng)) : 0.0f;
  return f;
}

Sampler random_sampler(std::mt19937_64& rng) {
  constexpr AddressMode kModes[] = {AddressMode::Wrap, AddressMode::Clamp, AddressMode::Mirror,
                                    AddressMode::Border, AddressMode::MirrorClamp};
  constexpr FilterMode kFilters[] = {FilterMode::Nearest, FilterMode::Bilinear,
                                     FilterMode::Trilinear};
  std::uniform_int_distribution<int> mode(0, 4), filter(0, 2), off(-8, 7), border(0, 3);
  std::uniform_real_distribution<double> coin(0, 1);
  Sampler s;
  s.addr.filter = kFilters[filter(rng)];
  s.addr.address_u = kModes[mode(rng)];
  s.addr.address_v = coin(rng) < 0.5 ? AddressMode::Border : kModes[mode(rng)];
  const Rgba named[3] = {Rgba(0.0f), Rgba(0.0f, 0.0f, 0.0f, 1.0f), Rgba(1.0f)};
  const int b = border(rng);
  // A custom colour beyond [0, 1] in red: normalised formats clamp it, float formats keep it.
  s.addr.border = b < 3 ? named[b]
                        : Rgba(static_cast<float>(coin(rng) * 1.5), static_cast<float>(coin(rng)),
                               static_cast<float>(coin(rng)), static_cast<float>(coin(rng)));
  if (coin(rng) < 0.6) {
    s.addr.offset_u = off(rng);
    s.addr.offset_v = off(rng);
  }
  if (coin(rng) < 0.6) {
    s.lod.lod_bias = static_cast<float>(coin(rng) * 4 - 2);
    s.lod.min_lod = static_cast<float>(coin(rng) * 2);
    s.lod.max_lod = s.lod.min_lod + static_cast<float>(coin(rng) * 3);
  }
  return s;
}

// Textures of the kinds the substitution rules tell apart: RGBA8, RGBA32F, and R8 / RG16F
// stores (channels the format lacks).
std::vector<Texture> textures() {
  std::vector<Texture> t;
  t.push_back(random_texture(16, 16, 1, TexelFormat::Rgba8));
  t.push_back(random_texture(37, 23, 2, TexelFormat::Rgba32f));
  t.push_back(random_texture(1, 1, 3, TexelFormat::Rgba8));
  t.push_back(random_texture(32, 8, 4, TexelFormat::Rgba32f).converted(StorageFormat::R8Unorm));
  t.push_back(random_texture(8, 32, 5, TexelFormat::Rgba32f).converted(StorageFormat::Rg16f));
  return t;
}

TEST(VulkanBorderConformance, TexsimPassesRandomQueries) {
  std::mt19937_64 rng(0xB0D3ull);
  const std::vector<Texture> texs = textures();
  int total = 0, failures = 0, border_queries = 0;
  for (int k = 0; k < 300; ++k) {
    const Sampler s = random_sampler(rng);
    const VulkanConformance chk(vk_state(s), VkFilterPrecision{});
    for (const Texture& tex : texs) {
      for (int it = 0; it < 12; ++it) {
        const Fragment fr = random_fragment(rng, tex.width(0), tex.height(0));
        FilterTaps t;
        const Rgba got = sample(s, tex, fr, &t);
        border_queries += t.border_taps > 0;
        const ConformanceVerdict v = chk.check(tex, vk_query_of(fr), got);
        ++total;
        if (!v.pass && ++failures <= 5) {
          ADD_FAILURE() << tex.width(0) << "x" << tex.height(0) << " " << to_string(s.addr.filter)
                        << " " << to_string(s.addr.address_u) << "/" << to_string(s.addr.address_v)
                        << " offset " << s.addr.offset_u << "," << s.addr.offset_v << " u=" << fr.u
                        << " v=" << fr.v << ": " << v.reason;
        }
      }
    }
  }
  std::printf("%d queries (%d with border taps), %d rejected\n", total, border_queries, failures);
  EXPECT_EQ(failures, 0);
  EXPECT_GT(border_queries, total / 5);
}

struct Rejections {
  int n = 0, rejected = 0;
  double rate() const { return n ? static_cast<double>(rejected) / n : 0; }
};

// Runs `wrong` (a sampler's answer made wrong) against the checker of the honest sampler `s`
// on queries where `relevant` holds, counting rejections.
template <class Wrong, class Relevant>
Rejections control(const Sampler& s, const Texture& tex, uint64_t seed, Wrong&& wrong,
                   Relevant&& relevant) {
  std::mt19937_64 rng(seed);
  const VulkanConformance chk(vk_state(s), VkFilterPrecision{});
  Rejections r;
  for (int it = 0; it < 4000 && r.n < 1500; ++it) {
    const Fragment fr = random_fragment(rng, tex.width(0), tex.height(0));
    FilterTaps t;
    const Rgba good = sample(s, tex, fr, &t);
    if (!relevant(fr, t)) continue;
    EXPECT_TRUE(chk.check(tex, vk_query_of(fr), good).pass);
    ++r.n;
    if (!chk.check(tex, vk_query_of(fr), wrong(fr, t)).pass) ++r.rejected;
  }
  return r;
}

// Sum of the border taps' weights.
float border_weight(const FilterTaps& t) {
  float w = 0;
  for (int k = 0; k < t.count; ++k) {
    if (t.tap[static_cast<size_t>(k)].x == kBorderTexel ||
        t.tap[static_cast<size_t>(k)].y == kBorderTexel)
      w += t.tap[static_cast<size_t>(k)].w;
  }
  return w;
}

TEST(VulkanBorderConformance, RejectsBorderColourOneLsbOff) {
  const Texture tex = random_texture(16, 16, 11, TexelFormat::Rgba8);
  for (FilterMode f : {FilterMode::Nearest, FilterMode::Bilinear}) {
    Sampler s;
    s.addr.filter = f;
    s.addr.address_u = s.addr.address_v = AddressMode::Border;
    s.addr.border = Rgba(0.25f, 0.5f, 0.75f, 1.0f);
    Sampler off = s;
    off.addr.border.g += 1.0f / 255;
    const Rejections r = control(
        s, tex, 0xB1, [&](const Fragment& fr, const FilterTaps&) { return sample(off, tex, fr); },
        // Where every tap reads the border (with texels in the sum, one LSB of the border can
        // hide in the weights' own tolerance).
        [](const Fragment&, const FilterTaps& t) { return border_weight(t) >= 0.999f; });
    std::printf("%s, border colour +1 LSB (8-bit) in green: %d of %d rejected\n", to_string(f),
                r.rejected, r.n);
    EXPECT_GT(r.n, 300);
    EXPECT_EQ(r.rejected, r.n);
  }
}

TEST(VulkanBorderConformance, RejectsClampToEdgeForBorder) {
  const Texture tex = random_texture(16, 16, 12, TexelFormat::Rgba32f);
  for (FilterMode f : {FilterMode::Nearest, FilterMode::Bilinear, FilterMode::Trilinear}) {
    Sampler s;
    s.addr.filter = f;
    s.addr.address_u = s.addr.address_v = AddressMode::Border;
    s.addr.border = Rgba(0.0f, 0.0f, 0.0f, 1.0f);
    Sampler edge = s;
    edge.addr.address_u = edge.addr.address_v = AddressMode::Clamp;
    const Rejections r = control(
        s, tex, 0xB2, [&](const Fragment& fr, const FilterTaps&) { return sample(edge, tex, fr); },
        [](const Fragment&, const FilterTaps& t) { return border_weight(t) >= 0.25f; });
    std::printf("%s, clamp-to-edge for border: %d of %d rejected (%.1f%%)\n", to_string(f),
                r.rejected, r.n, 100 * r.rate());
    EXPECT_GT(r.n, 300);
    EXPECT_GT(r.rate(), 0.95);
  }
}

TEST(VulkanBorderConformance, RejectsOffsetAfterWrapping) {
  // Clamp and mirror: wrapping first and offsetting after (then wrapping again, to stay inside)
  // differs from Vulkan's offset-then-wrap when the coordinate is outside the level.
  const Texture tex = random_texture(16, 16, 13, TexelFormat::Rgba32f);
  for (AddressMode m : {AddressMode::Clamp, AddressMode::MirrorClamp}) {
    Sampler s;
    s.addr.filter = FilterMode::Nearest;
    s.addr.address_u = s.addr.address_v = m;
    s.addr.offset_u = 5;
    s.addr.offset_v = -6;
    Sampler plain = s;
    plain.addr.offset_u = plain.addr.offset_v = 0;
    const auto after = [&](const Fragment& fr, const FilterTaps&) {
      const LodResult lr = LodUnit(s.lod).eval(fr, tex.width(0), tex.height(0));
      FilterTaps t;
      TexelAddressGen(plain.addr).taps(tex, fr.u, fr.v, lr, t);
      for (int k = 0; k < t.count; ++k) {
        TexelTap& tp = t.tap[static_cast<size_t>(k)];
        const int w = tex.width(tp.level), h = tex.height(tp.level);
        tp.x = TexelAddressGen::address(int64_t{tp.x} + s.addr.offset_u, w, m);
        tp.y = TexelAddressGen::address(int64_t{tp.y} + s.addr.offset_v, h, m);
      }
      return TexelBlend().blend(t, tex);
    };
    // Magnified queries left of or below the texture: there the two orders part.
    const Rejections r = control(s, tex, 0xB3, after, [](const Fragment& fr, const FilterTaps&) {
      return (fr.u < -0.1 || fr.v > 1.1) && std::fabs(fr.dudx) * 16 < 0.5 &&
             std::fabs(fr.dudy) * 16 < 0.5;
    });
    std::printf("%s, offset after wrapping: %d of %d rejected (%.1f%%)\n", to_string(m), r.rejected,
                r.n, 100 * r.rate());
    EXPECT_GT(r.n, 100);
    EXPECT_GT(r.rate(), 0.9);
  }
}

TEST(VulkanBorderConformance, RejectsLodClampedBeforeBias) {
  // λ clamped to [min_lod, max_lod] first and biased after: off wherever the bias moves λ past
  // a clamp end.
  const Texture tex = random_texture(256, 256, 14, TexelFormat::Rgba32f);
  for (FilterMode f : {FilterMode::Nearest, FilterMode::Trilinear}) {
    Sampler s;
    s.addr.filter = f;
    s.lod.lod_bias = 2.0f;
    s.lod.min_lod = 1.0f;
    s.lod.max_lod = 3.0f;
    Sampler raw = s;  // λ_base: no bias, no clamp
    raw.lod.lod_bias = 0;
    raw.lod.min_lod = -1000;
    raw.lod.max_lod = 1000;
    const auto before = [&](const Fragment& fr, const FilterTaps&) {
      LodResult lr = LodUnit(raw.lod).eval(fr, tex.width(0), tex.height(0));
      lr.lambda = std::clamp(lr.lambda - fr.lod_bias, s.lod.min_lod, s.lod.max_lod) +
                  s.lod.lod_bias + fr.lod_bias;
      FilterTaps t;
      TexelAddressGen(s.addr).taps(tex, fr.u, fr.v, lr, t);
      return TexelBlend().blend(t, tex);
    };
    // λ_base + bias beyond max_lod, λ_base inside: the wrong order lands two levels finer or
    // more; the honest one at max_lod.
    const Rejections r = control(s, tex, 0xB4, before, [&](const Fragment& fr, const FilterTaps&) {
      const float base = LodUnit(raw.lod).eval(fr, 256, 256).lambda - fr.lod_bias;
      return base > 1.8f && base < 2.5f && fr.lod_bias == 0.0f;
    });
    std::printf("%s, LOD clamped before bias: %d of %d rejected (%.1f%%)\n", to_string(f),
                r.rejected, r.n, 100 * r.rate());
    EXPECT_GT(r.n, 100);
    EXPECT_GT(r.rate(), 0.9);
  }
}

}  // namespace
}  // namespace texsim
