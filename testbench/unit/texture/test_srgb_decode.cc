// The sRGB decoder's placement ([pipeline] srgb_decode): before the filter each texel is taken
// to linear (the specification's rule); after it the filter sums sRGB codes and the filtered
// colour is decoded once. A two-texel blend computed by hand, equality on constant regions,
// differences where texels straddle, the border colour, the decoder's operation counts and the
// key's validation.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <string_view>

#include "blocks/base/input_error.h"
#include "blocks/texture/sampler/srgb_decoder.h"
#include "blocks/texture/sampler/texel_address_gen.h"
#include "blocks/texture/sampler/texel_blend.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {
namespace {

// An srgb8_a8 texture of w × h texels with the given 8-bit codes (RGB alike, alpha 255), no
// mips.
Texture srgb_texture(int w, int h, const std::vector<int>& codes) {
  std::vector<float> px(static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
  for (size_t i = 0; i < codes.size(); ++i) {
    for (size_t k = 0; k < 3; ++k) px[i * 4 + k] = static_cast<float>(codes[i]) / 255.0f;
    px[i * 4 + 3] = 1.0f;
  }
  return Texture::from_rgba("s", w, h, px, TexelFormat::Rgba8, false)
      .converted(StorageFormat::Srgb8A8);
}

TexelAddressGen bilinear_clamp(AddressMode m = AddressMode::Clamp) {
  TexelAddressGen::Config c;
  c.filter = FilterMode::Bilinear;
  c.address_u = c.address_v = m;
  c.border = Rgba(0.25f, 0.5f, 0.75f, 1.0f);
  return TexelAddressGen(c);
}

// Codes 64 and 192 side by side, sampled half way between their centres (u = 0.5 on a 2 × 1
// texture): weights 1/2 and 1/2. By hand, with EOTF(c) = ((c + 0.055) / 1.055)^2.4:
//   before the filter: (EOTF(64/255) + EOTF(192/255)) / 2 = (0.0512695 + 0.5271151) / 2
//                      = 0.2891923;
//   after the filter:  EOTF((64 + 192) / 2 / 255) = EOTF(128/255) = 0.2158605.
TEST(SrgbDecode, TwoTexelBlendByHand) {
  const Texture before = srgb_texture(2, 1, {64, 192});
  const Texture after = before.srgb_stored(true);
  ASSERT_TRUE(after.srgb_after_filter());
  ASSERT_FALSE(before.srgb_after_filter());
  EXPECT_EQ(after.bytes_per_texel(), 4);
  EXPECT_EQ(after.storage(), StorageFormat::Srgb8A8);
  FilterTaps t;
  LodResult lod;
  bilinear_clamp().taps(before, 0.5, 0.5, lod, t);
  const Rgba lin = TexelBlend().blend(t, before);
  const Rgba enc = SrgbDecoder::decode_filtered(TexelBlend().blend(t, after));
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(lin[c], 0.2891923, 1e-6) << c;
    EXPECT_NEAR(enc[c], 0.2158605, 1e-6) << c;
  }
  EXPECT_FLOAT_EQ(lin.a, 1.0f);
  EXPECT_FLOAT_EQ(enc.a, 1.0f);
  // Back to before the filter: the same linear texels as converted() gave.
  const Texture back = after.srgb_stored(false);
  for (int x = 0; x < 2; ++x) EXPECT_EQ(back.texel(0, x, 0), before.texel(0, x, 0)) << x;
}

// Every code maps to its own linear value and back.
TEST(SrgbDecode, CodesRoundTrip) {
  for (int c = 0; c < 256; ++c) {
    EXPECT_EQ(srgb_code(srgb_to_linear(static_cast<uint8_t>(c))), c) << c;
    EXPECT_EQ(srgb_code(srgb_eotf(srgb_oetf(srgb_to_linear(static_cast<uint8_t>(c))))), c) << c;
  }
}

struct UnitRun {
  std::vector<Rgba> colours;
  std::vector<BlockUse> blocks;
  uint64_t fragments = 0, texels = 0;
};

// A 16 × 16 texture of random codes in its top half and one code in its bottom half, bilinear
// (clamp), magnified 4× so most fragments straddle texels; through process_batch.
UnitRun run_unit(SrgbDecode where) {
  std::vector<int> codes(256);
  std::mt19937 rng(7);
  for (size_t i = 0; i < codes.size(); ++i)
    codes[i] = i < 128 ? static_cast<int>(rng() % 256) : 100;
  TextureSet set;
  set.add(srgb_texture(16, 16, codes));
  MaterialSetup m;
  m.name = "m";
  m.filter.filter = FilterMode::Bilinear;
  m.filter.address_u = m.filter.address_v = AddressMode::Clamp;
  PipelineSetup setup;
  setup.srgb_decode = where;
  TextureUnit unit(set, {m}, setup, TechTable::defaults(), false);
  std::vector<Fragment> frags;
  for (uint32_t y = 0; y < 64; ++y) {
    for (uint32_t x = 0; x < 64; ++x) {
      Fragment f;
      f.x = x;
      f.y = y;
      f.u = (x + 0.5) / 64;
      f.v = (y + 0.5) / 64;
      f.dudx = f.dvdy = 1.0 / 64;
      frags.push_back(f);
    }
  }
  UnitRun r;
  r.colours.resize(frags.size());
  unit.process_batch(frags.data(), frags.size(), 0, r.colours.data());
  r.blocks = unit.blocks();
  r.fragments = unit.srgb_fragments();
  r.texels = unit.srgb_texels();
  return r;
}

const BlockUse* find_block(const std::vector<BlockUse>& b, const std::string& name) {
  for (const BlockUse& u : b)
    if (u.name == name) return &u;
  return nullptr;
}

TEST(SrgbDecode, EqualOnConstantRegionsDifferentWhereTexelsStraddle) {
  const UnitRun before = run_unit(SrgbDecode::BeforeFilter);
  const UnitRun after = run_unit(SrgbDecode::AfterFilter);
  ASSERT_EQ(before.colours.size(), after.colours.size());
  int differ = 0;
  for (size_t i = 0; i < before.colours.size(); ++i) {
    const size_t y = i / 64;
    if (y >= 34) {  // taps all on the constant half (texel rows 8..15)
      for (int c = 0; c < 4; ++c)
        EXPECT_NEAR(before.colours[i][c], after.colours[i][c], 1e-6) << i << " " << c;
    } else if (y < 30) {
      differ += std::fabs(before.colours[i].r - after.colours[i].r) > 1e-3f;
    }
  }
  // Between two different codes the linear mean lies above the decoded mean of the codes
  // (the EOTF is convex): most fragments of the random half differ.
  EXPECT_GT(differ, 64 * 30 / 2);
}

TEST(SrgbDecode, DecoderCountsPerTexelBeforeAndPerFragmentAfter) {
  const UnitRun before = run_unit(SrgbDecode::BeforeFilter);
  const UnitRun after = run_unit(SrgbDecode::AfterFilter);
  EXPECT_EQ(before.fragments, 64u * 64u);
  EXPECT_EQ(before.texels, 4u * 64u * 64u);  // bilinear: four texels a fragment
  EXPECT_EQ(after.fragments, before.fragments);
  EXPECT_EQ(after.texels, before.texels);
  const BlockUse* b = find_block(before.blocks, "srgb_decode");
  const BlockUse* a = find_block(after.blocks, "srgb_decode");
  ASSERT_TRUE(b && a);
  EXPECT_EQ(b->ops.lut, 3u * before.texels);  // three table reads a texel
  EXPECT_EQ(b->ops.mul, 0u);
  EXPECT_EQ(a->ops.lut, 6u * after.fragments);  // log2 and exp2 per colour channel
  EXPECT_EQ(a->ops.mul, 6u * after.fragments);
  EXPECT_EQ(a->ops.cmp, 3u * after.fragments);
  EXPECT_GT(b->timing.area, 0.0);
  EXPECT_GT(a->timing.area, 0.0);
  EXPECT_GT(a->timing.latency, b->timing.latency);
}

// A fragment of border taps reads the border colour in both placements (after the filter the
// border enters the sum encoded and decodes back).
TEST(SrgbDecode, BorderColourIsLinearInBothPlacements) {
  const Texture before = srgb_texture(2, 2, {10, 20, 30, 40});
  const Texture after = before.srgb_stored(true);
  FilterTaps t;
  LodResult lod;
  const TexelAddressGen g = bilinear_clamp(AddressMode::Border);
  g.taps(before, -2.0, 0.5, lod, t);
  ASSERT_EQ(t.border_taps, 4);
  const Rgba lin = TexelBlend().blend(t, before);
  g.taps(after, -2.0, 0.5, lod, t);
  const Rgba dec = SrgbDecoder::decode_filtered(TexelBlend().blend(t, after));
  const Rgba want(0.25f, 0.5f, 0.75f, 1.0f);
  for (int c = 0; c < 4; ++c) {
    EXPECT_FLOAT_EQ(lin[c], want[c]) << c;
    EXPECT_NEAR(dec[c], want[c], 1e-6) << c;
  }
}

TEST(SrgbDecode, KeyIsValidatedWithItsPlace) {
  const toml::table ok =
      toml::parse(std::string_view("srgb_decode = \"after_filter\"\n"), std::string_view("s.toml"));
  EXPECT_EQ(PipelineSetup::from_toml(ok, "s.toml").srgb_decode, SrgbDecode::AfterFilter);
  EXPECT_EQ(PipelineSetup::from_toml(toml::table{}, "s.toml").srgb_decode,
            SrgbDecode::BeforeFilter);
  try {
    (void)PipelineSetup::from_toml(
        toml::parse(std::string_view("\nsrgb_decode = \"sideways\"\n"), std::string_view("s.toml")),
        "s.toml");
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("s.toml:2:"), std::string::npos) << m;
    EXPECT_NE(m.find("before_filter"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace texsim
