// LinearBatchSampler against the scalar blocks it batches (LodUnit, TexelAddressGen,
// TexelBlend): on every SIMD target this CPU has, every fragment the batch marks done must have
// the scalar path's levels, texels and colour bit for bit — over random and hard inputs (NaN,
// infinities, huge coordinates and derivatives, zero derivatives, every address mode, bilinear
// and trilinear, isotropic and anisotropic LOD, 1..16 fraction bits). Ordinary fragments must
// be done by the batch, so a batch that left everything to the scalar path fails.
#include <gtest/gtest.h>
#include <hwy/targets.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "blocks/texture/sampler/linear_batch.h"
#include "blocks/texture/sampler/texel_blend.h"

namespace texsim {
namespace {

Texture random_texture(int w, int h, uint64_t seed, bool mips = true) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> c(0.0f, 1.0f);
  std::vector<float> px(static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
  for (float& p : px) p = c(rng);
  return Texture::from_rgba("rnd", w, h, px, TexelFormat::Rgba8, mips);
}

// Fragments: ordinary ones (first `ordinary`), then hard ones.
std::vector<Fragment> fragments(uint64_t seed, size_t ordinary, size_t hard) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto deriv = [&] {
    const double mag = std::pow(10.0, -6.0 + 7.0 * unit(rng));
    return unit(rng) < 0.5 ? -mag : mag;
  };
  auto ordinary_fragment = [&] {
    Fragment f;
    f.u = -3.0 + 6.0 * unit(rng);
    f.v = -3.0 + 6.0 * unit(rng);
    f.dudx = deriv();
    f.dvdx = deriv();
    f.dudy = deriv();
    f.dvdy = deriv();
    return f;
  };
  std::vector<Fragment> out;
  for (size_t i = 0; i < ordinary; ++i) {
    Fragment f = ordinary_fragment();
    f.lod_bias = static_cast<float>(-2.0 + 4.0 * unit(rng));
    out.push_back(f);
  }
  const double specials[] = {0.0, -0.0, inf, -inf, nan, 1e30, -1e30, 1e300, 1e6, -1e6, 4e6, 1e-40};
  const size_t ns = std::size(specials);
  for (size_t i = 0; i < hard; ++i) {
    Fragment f = ordinary_fragment();
    // One to three fields replaced by special values.
    const int k = 1 + static_cast<int>(rng() % 3);
    for (int j = 0; j < k; ++j) {
      const double s = specials[rng() % ns];
      switch (rng() % 8) {
        case 0:
          f.u = s;
          break;
        case 1:
          f.v = s;
          break;
        case 2:
          f.dudx = s;
          break;
        case 3:
          f.dvdx = s;
          break;
        case 4:
          f.dudy = s;
          break;
        case 5:
          f.dvdy = s;
          break;
        case 6:
          f.lod_bias = static_cast<float>(s);
          break;
        default:
          f.dudx = f.dvdx = f.dudy = f.dvdy = s;
          break;
      }
    }
    out.push_back(f);
  }
  return out;
}

struct Expected {
  bool one_probe;
  int32_t level[2], x0[2], x1[2], y0[2], y1[2];
  Rgba colour;
  std::vector<uint64_t> lines;  // distinct cache lines in order of first use
};

// Distinct lines of the taps in order of first use, as the texture unit's cache model forms
// them: each tap's byte address (Texture::address) >> shift.
std::vector<uint64_t> tap_lines(const Texture& tex, const Expected& e, int quads, uint32_t shift) {
  std::vector<uint64_t> out;
  for (int j = 0; j < quads; ++j) {
    const int32_t xs[4] = {e.x0[j], e.x1[j], e.x0[j], e.x1[j]};
    const int32_t ys[4] = {e.y0[j], e.y0[j], e.y1[j], e.y1[j]};
    for (int k = 0; k < 4; ++k) {
      const uint64_t line = tex.address(e.level[j], xs[k], ys[k]) >> shift;
      if (std::find(out.begin(), out.end(), line) == out.end()) out.push_back(line);
    }
  }
  return out;
}

// The scalar datapath of TextureUnit::process_linear.
Expected scalar(const LodUnit& lod, const TexelAddressGen& addr, const TexelBlend& blend,
                const Texture& tex, const Fragment& f) {
  using texel_address_detail::finite_or_zero;
  Expected e{};
  const LodResult r = lod.eval(f, tex.width(0), tex.height(0));
  e.one_probe = TexelAddressGen::issue_cycles(r) == 1;
  const TexelAddressGen::LevelSelect sel = addr.select_levels(r.lambda, tex.levels());
  const float uf = finite_or_zero(static_cast<float>(f.u));
  const float vf = finite_or_zero(static_cast<float>(f.v));
  const bool tri = addr.config().filter == FilterMode::Trilinear;
  TexelQuad q[2];
  q[0] = addr.linear_quad(tex, sel.d_hi, uf, vf, tri ? 1.0f - sel.delta : 1.0f);
  if (tri) q[1] = addr.linear_quad(tex, sel.d_lo, uf, vf, sel.delta);
  e.colour = blend.blend_quads(q, tri ? 2 : 1, tex);
  for (int j = 0; j < (tri ? 2 : 1); ++j) {
    e.level[j] = q[j].level;
    e.x0[j] = q[j].x0;
    e.x1[j] = q[j].x1;
    e.y0[j] = q[j].y0;
    e.y1[j] = q[j].y1;
  }
  return e;
}

bool same_bits(const Rgba& a, const Rgba& b) {
  for (int c = 0; c < 4; ++c) {
    if (std::bit_cast<uint32_t>(a[c]) != std::bit_cast<uint32_t>(b[c])) return false;
  }
  return true;
}

struct Case {
  FilterMode filter = FilterMode::Bilinear;
  AnisoMode aniso = AnisoMode::Isotropic;
  int max_aniso = 16;
  AddressMode au = AddressMode::Wrap, av = AddressMode::Wrap;
  int sub_bits = 8, mip_bits = 8;
  float min_lod = 0, max_lod = 1000, lod_bias = 0;
  int w = 64, h = 64;
  bool mips = true;
  TexelLayout layout = TexelLayout::Tiled4x4;
  uint64_t base = 4096;     // where the texture is placed in memory
  uint32_t line_shift = 6;  // 64-byte cache lines
};

// Runs one configuration over the fragments; returns how many ordinary fragments were done.
size_t check(const Case& c, const std::vector<Fragment>& frags, size_t ordinary) {
  LodUnit::Config lc;
  lc.aniso = c.aniso;
  lc.max_aniso = c.max_aniso;
  lc.min_lod = c.min_lod;
  lc.max_lod = c.max_lod;
  lc.lod_bias = c.lod_bias;
  TexelAddressGen::Config ac;
  ac.filter = c.filter;
  ac.address_u = c.au;
  ac.address_v = c.av;
  ac.sub_texel_bits = c.sub_bits;
  ac.mipmap_bits = c.mip_bits;
  Texture tex = random_texture(c.w, c.h, 7 + static_cast<uint64_t>(c.w), c.mips);
  tex.place(c.base, c.layout);
  const LodUnit lod(lc);
  const TexelAddressGen addr(ac);
  const TexelBlend blend;
  const LinearBatchSampler batch(lc, ac);
  EXPECT_TRUE(batch.serves(tex));
  const bool tri = c.filter == FilterMode::Trilinear;
  size_t done_ordinary = 0;
  auto out = std::make_unique<LinearBatch>();
  size_t start = 0, round = 0;
  while (start < frags.size()) {
    // Uneven batch sizes, so partial vectors are covered.
    const size_t n = std::min(LinearBatch::kMax - (round++ % 7), frags.size() - start);
    batch.filter(frags.data() + start, n, tex, *out, c.line_shift);
    for (size_t i = 0; i < n; ++i) {
      if (!out->done[i]) continue;
      const Fragment& f = frags[start + i];
      const Expected e = scalar(lod, addr, blend, tex, f);
      SCOPED_TRACE("fragment " + std::to_string(start + i) + " u=" + std::to_string(f.u) +
                   " v=" + std::to_string(f.v) + " dudx=" + std::to_string(f.dudx));
      EXPECT_TRUE(e.one_probe);
      EXPECT_TRUE(same_bits(out->colour(i), e.colour)) << out->colour(i).r << " vs " << e.colour.r;
      for (int j = 0; j < (tri ? 2 : 1); ++j) {
        EXPECT_EQ(out->level[j][i], e.level[j]);
        EXPECT_EQ(out->x0[j][i], e.x0[j]);
        EXPECT_EQ(out->x1[j][i], e.x1[j]);
        EXPECT_EQ(out->y0[j][i], e.y0[j]);
        EXPECT_EQ(out->y1[j][i], e.y1[j]);
      }
      if (start + i < ordinary) ++done_ordinary;
      // Addresses from 2^31 on are the scalar cache model's.
      EXPECT_EQ(out->has_lines, c.base < (uint64_t{1} << 31));
      if (!out->has_lines) continue;
      std::vector<uint64_t> lines;
      for (int k = 0; k < (tri ? 8 : 4); ++k) {
        if (out->first_use[i] & (1 << k)) lines.push_back(static_cast<uint64_t>(out->line[k][i]));
      }
      EXPECT_EQ(lines, tap_lines(tex, e, tri ? 2 : 1, c.line_shift));
    }
    start += n;
  }
  return done_ordinary;
}

std::vector<int64_t> targets() { return hwy::SupportedAndGeneratedTargets(); }

TEST(LinearBatch, IdenticalToScalarOnEveryTarget) {
  const size_t ordinary = 3000;
  const std::vector<Fragment> frags = fragments(1, ordinary, 3000);
  const AddressMode modes[] = {AddressMode::Wrap, AddressMode::Clamp, AddressMode::Mirror};
  ASSERT_FALSE(targets().empty());
  for (int64_t t : targets()) {
    hwy::SetSupportedTargetsForTest(t);
    SCOPED_TRACE(std::string("target ") + LinearBatchSampler::target());
    for (FilterMode filter : {FilterMode::Bilinear, FilterMode::Trilinear}) {
      for (AddressMode au : modes) {
        for (AddressMode av : modes) {
          for (TexelLayout layout :
               {TexelLayout::Linear, TexelLayout::Tiled4x4, TexelLayout::Morton}) {
            Case c{.filter = filter, .au = au, .av = av, .h = 32};
            c.layout = layout;
            c.line_shift = 4 + 2 * static_cast<uint32_t>(layout);
            // Isotropic LOD: every ordinary fragment is the batch's.
            EXPECT_EQ(check(c, frags, ordinary), ordinary);
          }
        }
      }
    }
  }
  hwy::SetSupportedTargetsForTest(0);
}

TEST(LinearBatch, FractionBitsLodRangesAndTextureShapes) {
  const std::vector<Fragment> frags = fragments(2, 1500, 1500);
  for (int64_t t : targets()) {
    hwy::SetSupportedTargetsForTest(t);
    SCOPED_TRACE(std::string("target ") + LinearBatchSampler::target());
    for (int bits : {1, 4, 12, 16}) {
      for (FilterMode filter : {FilterMode::Bilinear, FilterMode::Trilinear}) {
        const Case c{.filter = filter,
                     .av = AddressMode::Mirror,
                     .sub_bits = bits,
                     .mip_bits = 17 - bits,
                     .min_lod = 0.5f,
                     .max_lod = 3.25f,
                     .lod_bias = -0.75f,
                     .w = 256,
                     .h = 16};
        EXPECT_GT(check(c, frags, 1500), 1000u);
      }
    }
    // 1×1, a single column, no mips, and a non-power-of-two texture under clamp.
    const Case one{.filter = FilterMode::Trilinear, .w = 1, .h = 1};
    EXPECT_EQ(check(one, frags, 1500), 1500u);
    const Case column{.au = AddressMode::Mirror, .w = 1};
    EXPECT_EQ(check(column, frags, 1500), 1500u);
    const Case flat{.filter = FilterMode::Trilinear, .w = 32, .h = 32, .mips = false};
    EXPECT_EQ(check(flat, frags, 1500), 1500u);
    Case high{};
    high.base = uint64_t{3} << 30;
    EXPECT_EQ(check(high, frags, 1500), 1500u);
    const Case npot{.filter = FilterMode::Trilinear,
                    .au = AddressMode::Clamp,
                    .av = AddressMode::Clamp,
                    .w = 37,
                    .h = 23};
    EXPECT_EQ(check(npot, frags, 1500), 1500u);
  }
  hwy::SetSupportedTargetsForTest(0);
}

TEST(LinearBatch, AnisotropicLodLeavesMultiProbeFragmentsToTheScalarPath) {
  const std::vector<Fragment> frags = fragments(3, 2000, 2000);
  for (int64_t t : targets()) {
    hwy::SetSupportedTargetsForTest(t);
    SCOPED_TRACE(std::string("target ") + LinearBatchSampler::target());
    for (int max_aniso : {1, 2, 16}) {
      const Case c{.filter = FilterMode::Trilinear,
                   .aniso = AnisoMode::Vulkan,
                   .max_aniso = max_aniso,
                   .av = AddressMode::Clamp,
                   .lod_bias = 0.5f,
                   .w = 128,
                   .h = 128};
      // check() requires one probe for every done fragment; with maxAniso 1 all are done.
      const size_t done = check(c, frags, 2000);
      if (max_aniso == 1) {
        EXPECT_EQ(done, 2000u);
      }
    }
    // Isotropic footprints (equal axes) under the Vulkan rule are one probe: the batch's.
    std::vector<Fragment> iso = frags;
    for (Fragment& f : iso) {
      f.dudy = -f.dvdx;
      f.dvdy = f.dudx;
    }
    const Case c{.aniso = AnisoMode::Vulkan};
    EXPECT_GT(check(c, iso, 2000), 1000u);
  }
  hwy::SetSupportedTargetsForTest(0);
}

// Fragments whose λ lies a few float32 steps around the rounding ties of the fixed-point LOD
// ((k + ½) / 2^8): where the batch's double-precision interval cannot decide the rounding it
// must fall back to the scalar arithmetic, and the results must agree bit for bit.
std::vector<Fragment> near_ties(int size, float bias) {
  std::vector<Fragment> out;
  for (int k = 0; k < 6 * 256; k += 7) {
    const double lambda = (k + 0.5) / 256.0 - bias;
    const double rho = std::exp2(lambda);  // ρ = 2^λ texels per pixel
    for (int step = -12; step <= 12; ++step) {
      Fragment f;
      f.u = 0.3 + 0.001 * k;
      f.v = 0.7;
      f.dudx = rho / size;
      for (int j = 0; j < std::abs(step); ++j)
        f.dudx = std::nextafter(static_cast<float>(f.dudx), step < 0 ? 0.0f : 1e30f);
      f.dvdy = f.dudx * 0.5;
      f.lod_bias = bias;
      out.push_back(f);
    }
  }
  return out;
}

TEST(LinearBatch, LevelsNearTheFixedPointTiesAreTheScalarOnes) {
  for (int64_t t : targets()) {
    hwy::SetSupportedTargetsForTest(t);
    SCOPED_TRACE(std::string("target ") + LinearBatchSampler::target());
    for (float bias : {0.0f, 0.3f, -1.7f}) {
      const std::vector<Fragment> frags = near_ties(512, bias);
      for (FilterMode filter : {FilterMode::Bilinear, FilterMode::Trilinear}) {
        const Case c{.filter = filter, .w = 512, .h = 512};
        EXPECT_EQ(check(c, frags, frags.size()), frags.size());
      }
    }
  }
  hwy::SetSupportedTargetsForTest(0);
}

// The batch's assumption about the C library: log2f within 4 ulp of log2 over the positive
// normal floats (every 101st of them, and the neighbours of every power of two).
TEST(LinearBatch, LibraryLog2fIsWithinFourUlp) {
  double worst = 0;
  auto check_at = [&](uint32_t bits) {
    float x;
    std::memcpy(&x, &bits, sizeof x);
    const double exact = std::log2(static_cast<double>(x));
    const float got = std::log2(x);
    if (exact == 0) {
      EXPECT_EQ(got, 0.0f);
      return;
    }
    const float e = static_cast<float>(exact);
    const double ulp = std::nextafter(std::fabs(e), 1e30f) - std::fabs(e);
    worst = std::max(worst, std::fabs(static_cast<double>(got) - exact) / ulp);
  };
  for (uint32_t b = 0x00800000u; b < 0x7f800000u; b += 101) check_at(b);
  for (uint32_t e = 1; e < 255; ++e) {
    for (uint32_t d = 0; d < 64; ++d) {
      check_at((e << 23) + d);
      check_at((e << 23) - d - 1);
    }
  }
  EXPECT_LE(worst, 4.0);
  EXPECT_GT(worst, 0.0);  // the check measured something
}

TEST(LinearBatch, ServesOnlyWhatItCanDoExactly) {
  TexelAddressGen::Config ac;
  ac.filter = FilterMode::Bilinear;
  const LinearBatchSampler wrap(LodUnit::Config{}, ac);
  EXPECT_TRUE(wrap.serves(random_texture(64, 32, 1)));
  EXPECT_FALSE(wrap.serves(random_texture(37, 32, 1)));  // wrap needs powers of two
  std::vector<float> px(size_t{16} * 4, 0.5f);
  EXPECT_FALSE(
      wrap.serves(Texture::from_rgba("f", 4, 4, px, TexelFormat::Rgba32f, true)));  // RGBA8 only
  ac.address_u = ac.address_v = AddressMode::Clamp;
  EXPECT_TRUE(LinearBatchSampler(LodUnit::Config{}, ac).serves(random_texture(37, 23, 1)));
  ac.filter = FilterMode::Nearest;
  EXPECT_THROW(LinearBatchSampler(LodUnit::Config{}, ac), std::invalid_argument);
  EXPECT_NE(std::string(LinearBatchSampler::target()), "");
}

}  // namespace
}  // namespace texsim
