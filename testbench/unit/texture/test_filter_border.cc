// TexelAddressGen + TexelBlend: CLAMP_TO_BORDER and MIRROR_CLAMP_TO_EDGE addressing, border
// colours in the texture's format conversion, constant texel offsets, their operation counts and
// their scene keys (file:line:column messages).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "blocks/base/input_error.h"
#include "blocks/texture/sampler/texel_address_gen.h"
#include "blocks/texture/sampler/texel_blend.h"
#include "pipeline/reference/ground_truth.h"
#include "testbench/lib/filter_fixtures.h"

namespace texsim {
namespace {

TexelAddressGen::Config config(FilterMode f, AddressMode m, Rgba border = Rgba(0.0f)) {
  TexelAddressGen::Config c;
  c.filter = f;
  c.address_u = c.address_v = m;
  c.border = border;
  return c;
}

LodResult lod_at(float lambda) {
  LodResult r;
  r.lambda = lambda;
  return r;
}

// Independent statements of the two modes.
int64_t ref_mirror_clamp(int64_t i, int64_t s) {
  const int64_t m = i < 0 ? -i - 1 : i;  // mirror(i)
  return m > s - 1 ? s - 1 : m;
}

TEST(TexelAddressBorder, ModesMatchVulkan) {
  for (int32_t s : {1, 2, 3, 8, 13}) {
    for (int64_t i = -40; i <= 40; ++i) {
      const int32_t b = TexelAddressGen::address(i, s, AddressMode::Border);
      EXPECT_EQ(b, i >= 0 && i < s ? i : kBorderTexel) << i << " " << s;
      const int32_t m = TexelAddressGen::address(i, s, AddressMode::MirrorClamp);
      EXPECT_EQ(m, ref_mirror_clamp(i, s)) << i << " " << s;
    }
  }
  // Mirror-clamp of size 3 from i = −5: 2 2 2 1 0 | 0 1 2 | 2 2 2 (one mirror, then the edge).
  const int expect[] = {2, 2, 2, 1, 0, 0, 1, 2, 2, 2, 2};
  for (int k = 0; k < 11; ++k) {
    EXPECT_EQ(TexelAddressGen::address(k - 5, 3, AddressMode::MirrorClamp), expect[k]) << k;
  }
  EXPECT_EQ(TexelAddressGen::address(-(int64_t{1} << 40), 7, AddressMode::MirrorClamp), 6);
  EXPECT_EQ(TexelAddressGen::address(int64_t{1} << 40, 7, AddressMode::Border), kBorderTexel);
}

TEST(TexelAddressBorder, BorderTapsReadTheBorderColour) {
  const Texture tex = random_texture(8, 8, 1);
  const Rgba border(0.25f, 0.5f, 0.75f, 1.0f);
  const TexelAddressGen g(config(FilterMode::Bilinear, AddressMode::Border, border));
  FilterTaps t;
  // Far outside: four border taps, the colour is the border's exactly.
  g.taps(tex, -0.5, 0.5, lod_at(0), t);
  EXPECT_EQ(t.border_taps, 4);
  EXPECT_EQ(TexelBlend().blend(t, tex), border);
  // On the left edge of texel column 0 (u = 0): half border, half column 0.
  g.taps(tex, 0.0, (3 + 0.5) / 8, lod_at(0), t);
  EXPECT_EQ(t.border_taps, 2);
  const Rgba want = 0.5f * border + 0.5f * tex.texel(0, 0, 3);
  const Rgba got = TexelBlend().blend(t, tex);
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(got[c], want[c], 1e-6) << c;
  // Inside: no border tap, the same colour as clamp-to-edge.
  g.taps(tex, 0.4, 0.6, lod_at(0), t);
  EXPECT_EQ(t.border_taps, 0);
  FilterTaps e;
  TexelAddressGen(config(FilterMode::Bilinear, AddressMode::Clamp))
      .taps(tex, 0.4, 0.6, lod_at(0), e);
  EXPECT_EQ(TexelBlend().blend(t, tex), TexelBlend().blend(e, tex));
  // One axis border, the other wrap: v wraps, u leaves the texture.
  TexelAddressGen::Config c = config(FilterMode::Nearest, AddressMode::Wrap, border);
  c.address_u = AddressMode::Border;
  TexelAddressGen(c).taps(tex, 1.2, 0.5, lod_at(0), t);
  EXPECT_EQ(t.border_taps, 1);
  TexelAddressGen(c).taps(tex, 0.5, 7.3, lod_at(0), t);
  EXPECT_EQ(t.border_taps, 0);
}

TEST(TexelAddressBorder, BorderColourInTheFormatsConversion) {
  const Rgba white(1.0f), custom(1.5f, -0.5f, 0.5f, 0.25f);
  // Channels the format lacks: 0 for colour, 1 for alpha.
  EXPECT_EQ(border_texel(StorageFormat::R8Unorm, white), Rgba(1, 0, 0, 1));
  EXPECT_EQ(border_texel(StorageFormat::Rg16f, custom), Rgba(1.5f, -0.5f, 0, 1));
  // Normalised formats hold only their range; float formats keep the colour.
  EXPECT_EQ(border_texel(StorageFormat::Rgba8Unorm, custom), Rgba(1.0f, 0.0f, 0.5f, 0.25f));
  EXPECT_EQ(border_texel(StorageFormat::Rgba8Snorm, custom), Rgba(1.0f, -0.5f, 0.5f, 0.25f));
  EXPECT_EQ(border_texel(StorageFormat::Rgba32f, custom), custom);
  // sRGB: the border colour is linear already (no EOTF).
  EXPECT_EQ(border_texel(StorageFormat::Srgb8A8, Rgba(0.5f)), Rgba(0.5f));
  // Through the filter: an R8 texture's border reads (r, 0, 0, 1).
  const Texture r8 = random_texture(4, 4, 2).converted(StorageFormat::R8Unorm);
  FilterTaps t;
  TexelAddressGen(config(FilterMode::Nearest, AddressMode::Border, Rgba(0.2f, 0.4f, 0.6f, 0.8f)))
      .taps(r8, 2.0, 2.0, lod_at(0), t);
  EXPECT_EQ(TexelBlend().blend(t, r8), Rgba(0.2f, 0, 0, 1));
}

TEST(TexelAddressBorder, OffsetsJoinBeforeWrapping) {
  const Texture tex = random_texture(16, 8, 3);
  for (AddressMode m : {AddressMode::Wrap, AddressMode::Clamp, AddressMode::Mirror,
                        AddressMode::Border, AddressMode::MirrorClamp}) {
    for (int o : {-8, -3, 0, 5, 7}) {
      TexelAddressGen::Config c = config(FilterMode::Nearest, m);
      c.offset_u = o;
      c.offset_v = -o;
      FilterTaps t;
      for (int k = -20; k < 36; ++k) {
        // Texel centres: i = k exactly, then i + offset is wrapped.
        const double u = (k + 0.5) / 16, v = (k + 0.5) / 8;
        TexelAddressGen(c).taps(tex, u, v, lod_at(0), t);
        ASSERT_EQ(t.count, 1);
        EXPECT_EQ(t.tap[0].x, TexelAddressGen::address(k + o, 16, m)) << to_string(m) << k;
        EXPECT_EQ(t.tap[0].y, TexelAddressGen::address(k - o, 8, m)) << to_string(m) << k;
      }
    }
  }
  // Bilinear: both neighbours move together.
  TexelAddressGen::Config c = config(FilterMode::Bilinear, AddressMode::Clamp);
  c.offset_u = 3;
  const TexelQuad q = TexelAddressGen(c).linear_quad(tex, 0, 0.25f, 0.5f, 1.0f);
  EXPECT_EQ(q.x0, 3 + 3);  // ⌊0.25·16 − ½⌋ = 3
  EXPECT_EQ(q.x1, 4 + 3);
}

TEST(TexelAddressBorder, OperationCounts) {
  // ops_address per mode, per integer coordinate.
  const OpCounts border = TexelAddressGen::ops_address(AddressMode::Border);
  EXPECT_EQ(border.cmp, 2u);
  EXPECT_EQ(border.add + border.mul, 0u);
  const OpCounts mc = TexelAddressGen::ops_address(AddressMode::MirrorClamp);
  EXPECT_EQ(mc.cmp, 2u);
  EXPECT_EQ(mc.add, 1u);
  EXPECT_EQ(mc.mul, 0u);
  // A non-zero offset adds its two integer adds per level; a zero one adds nothing.
  TexelAddressGen::Config c = config(FilterMode::Bilinear, AddressMode::Clamp);
  const OpCounts plain = TexelAddressGen(c).ops_per_item(false);
  c.offset_u = 1;
  EXPECT_EQ(TexelAddressGen(c).ops_per_item(false).add, plain.add + 2);
  for (AddressMode m : {AddressMode::Clamp, AddressMode::Wrap, AddressMode::Mirror,
                        AddressMode::Border, AddressMode::MirrorClamp}) {
    const OpCounts o = TexelAddressGen::ops_address(m);
    std::printf("%-13s add %lu mul %lu cmp %lu\n", to_string(m), static_cast<unsigned long>(o.add),
                static_cast<unsigned long>(o.mul), static_cast<unsigned long>(o.cmp));
  }
}

TEST(TexelAddressBorder, TruthReadsTheBorder) {
  const Texture tex = random_texture(8, 8, 4);
  const glm::dvec4 border(0.1, 0.2, 0.3, 0.4);
  SamplerExtras ex;
  ex.border = border;
  const glm::dvec4 far =
      reference_bilinear(tex, AddressMode::Border, AddressMode::Border, -1.0, 0.5, ex);
  EXPECT_EQ(far, border);
  // An offset of (2, −1) texels reads the texel two columns right and one row up.
  ex.offset_u = 2;
  ex.offset_v = -1;
  const glm::dvec4 shifted = reference_bilinear(tex, AddressMode::Border, AddressMode::Border,
                                                (1 + 0.5) / 8, (4 + 0.5) / 8, ex);
  EXPECT_EQ(shifted, glm::dvec4(tex.texel(0, 3, 3)));
  // Mirror-clamp one texel beyond the left edge mirrors once: column 0 again.
  const glm::dvec4 mc = reference_bilinear(tex, AddressMode::MirrorClamp, AddressMode::Clamp,
                                           -0.5 / 8, (2 + 0.5) / 8);
  EXPECT_EQ(mc, glm::dvec4(tex.texel(0, 0, 2)));
}

// The scene keys: border names and custom colours, offsets in −8..7, and messages that name
// file:line:column.
TEST(TexelAddressBorder, ConfigFromToml) {
  static toml::table t;
  auto parse = [](const std::string& text) {
    t = toml::parse(std::string_view(text), std::string_view("m.toml"));
    return TexelAddressGen::Config::from_toml(ConfigReader(t, "m.toml", "filter"));
  };
  auto message = [&](const std::string& text) -> std::string {
    try {
      parse(text);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  };
  auto c = parse("address = 'border'\nborder = 'opaque_white'\noffset = [-8, 7]\n");
  EXPECT_EQ(c.address_u, AddressMode::Border);
  EXPECT_EQ(c.border, Rgba(1.0f));
  EXPECT_EQ(c.offset_u, -8);
  EXPECT_EQ(c.offset_v, 7);
  EXPECT_EQ(parse("border = 'opaque_black'").border, Rgba(0, 0, 0, 1));
  EXPECT_EQ(parse("border = 'transparent_black'").border, Rgba(0.0f));
  EXPECT_EQ(parse("").border, Rgba(0.0f));
  EXPECT_EQ(parse("border = [0.5, 2, -1, 0.25]").border, Rgba(0.5f, 2.0f, -1.0f, 0.25f));
  c = parse("address_u = 'mirror_clamp'\naddress_v = 'border'\n");
  EXPECT_EQ(c.address_u, AddressMode::MirrorClamp);
  EXPECT_EQ(c.address_v, AddressMode::Border);
  // Refusals, each naming the file, line and column of the value.
  EXPECT_NE(message("\nborder = 'red'").find("m.toml:2:"), std::string::npos);
  EXPECT_NE(message("border = [1, 2, 3]").find("custom float colour"), std::string::npos);
  EXPECT_NE(message("border = [1, 2, 'x', 3]").find("m.toml:1:17"), std::string::npos)
      << message("border = [1, 2, 'x', 3]");
  EXPECT_NE(message("\n\nborder_int = [1, 2, 3, 4]").find("m.toml:3:"), std::string::npos);
  EXPECT_NE(message("border_int = [1, 2, 3, 4]").find("integer texture format"), std::string::npos);
  EXPECT_NE(message("offset = [0, 8]").find("m.toml:1:14"), std::string::npos)
      << message("offset = [0, 8]");
  EXPECT_NE(message("offset = [-9, 0]").find("[-8, 7]"), std::string::npos);
  EXPECT_NE(message("offset = [0.5, 0]").find("integer"), std::string::npos);
  EXPECT_NE(message("offset = [1]").find("two integers"), std::string::npos);
  EXPECT_NE(message("offset = 3").find("two integers"), std::string::npos);
  EXPECT_NE(message("address = 'clamp_to_border'").find("mirror_clamp"), std::string::npos);
}

}  // namespace
}  // namespace texsim
