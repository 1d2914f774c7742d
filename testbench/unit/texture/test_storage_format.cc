// Texel storage formats (storage_format.h): the Vulkan conversion rules, checked against
// independent formulas in double precision, exhaustively where the domain is small.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "blocks/base/input_error.h"
#include "blocks/texture/memory/storage_format.h"
#include "blocks/texture/memory/texture_memory.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"

namespace texsim {
namespace {

// The value of a binary16 bit pattern, from its definition.
double half_value(uint16_t h) {
  const int s = h >> 15, e = (h >> 10) & 31, m = h & 1023;
  const double mag = e == 0 ? std::ldexp(m, -24) : std::ldexp(1024 + m, e - 25);
  return s ? -mag : mag;
}

TEST(Half, EveryHalfDecodesToItsValueAndEncodesBack) {
  for (uint32_t h = 0; h < 65536; ++h) {
    const auto b = static_cast<uint16_t>(h);
    const float f = float_from_half(b);
    if (((h >> 10) & 31) == 31) {
      EXPECT_EQ(std::isnan(f), (h & 1023) != 0) << h;
      if (std::isnan(f)) {
        EXPECT_EQ(half_from_float(f) & 0x7c00, 0x7c00) << h;
        EXPECT_NE(half_from_float(f) & 0x3ff, 0) << h;
      } else {
        EXPECT_EQ(half_from_float(f), b) << h;
      }
      continue;
    }
    ASSERT_EQ(static_cast<double>(f), half_value(b)) << h;
    ASSERT_EQ(half_from_float(f), b) << h;
  }
}

// Between two neighbouring finite halves: the midpoint goes to the even one, a float just
// either side of it to the nearer one.
TEST(Half, RoundsToNearestEven) {
  for (uint32_t h = 0; h < 0x7bff; ++h) {  // positive finite halves with a finite successor
    const double lo = half_value(static_cast<uint16_t>(h));
    const double hi = half_value(static_cast<uint16_t>(h + 1));
    const auto mid = static_cast<float>((lo + hi) / 2);  // exact: 12 significant bits
    ASSERT_EQ(static_cast<double>(mid), (lo + hi) / 2);
    const uint16_t even = (h & 1) ? static_cast<uint16_t>(h + 1) : static_cast<uint16_t>(h);
    ASSERT_EQ(half_from_float(mid), even) << h;
    ASSERT_EQ(half_from_float(-mid), even | 0x8000) << h;
    ASSERT_EQ(half_from_float(std::nextafter(mid, 0.0f)), h) << h;
    ASSERT_EQ(half_from_float(std::nextafter(mid, 1e9f)), h + 1) << h;
  }
  EXPECT_EQ(half_from_float(65519.99f), 0x7bff);  // below the midpoint to 2^16: the largest
  EXPECT_EQ(half_from_float(65520.0f), 0x7c00);   // the midpoint rounds to even: infinity
  EXPECT_EQ(half_from_float(1e30f), 0x7c00);
  EXPECT_EQ(half_from_float(-1e30f), 0xfc00);
  EXPECT_EQ(half_from_float(std::ldexp(1.0f, -25)), 0);  // half the smallest subnormal: even
  EXPECT_EQ(half_from_float(std::nextafter(std::ldexp(1.0f, -25), 1.0f)), 1);
  EXPECT_EQ(half_from_float(1e-30f), 0);
  EXPECT_EQ(half_from_float(-0.0f), 0x8000);
}

TEST(Normalized, UnormCodesRoundTripAndHalvesRoundUp) {
  for (const StorageFormat f : {StorageFormat::Rgb565, StorageFormat::Rgba4444,
                                StorageFormat::Rgb10A2, StorageFormat::D16}) {
    const StorageFormatInfo& info = format_info(f);
    for (int c = 0; c < info.channels; ++c) {
      const int b = info.bits[c];
      const double max = std::ldexp(1.0, b) - 1;
      for (int code = 0; code <= static_cast<int>(max); ++code) {
        glm::vec4 in(0.0f);
        in[c] = static_cast<float>(code / max);
        const glm::vec4 out = convert_texel(f, in);
        ASSERT_EQ(static_cast<double>(out[c]), static_cast<double>(static_cast<float>(code / max)))
            << info.name << " channel " << c << " code " << code;
        if (code < max) {  // just above the midpoint to the next code: that code
          in[c] = static_cast<float>((code + 0.5) / max) * (1 + 1e-6f);
          ASSERT_EQ(static_cast<double>(convert_texel(f, in)[c]),
                    static_cast<double>(static_cast<float>((code + 1) / max)))
              << info.name << " " << code;
        }
      }
    }
  }
  const glm::vec4 out = convert_texel(StorageFormat::Rgb565,
                                      {-1.0f, 2.0f, std::numeric_limits<float>::quiet_NaN(), 0.3f});
  EXPECT_EQ(out, glm::vec4(0.0f, 1.0f, 0.0f, 1.0f));  // clamped, NaN 0, no alpha: 1
}

TEST(Normalized, SnormMinusOneHasTwoCodesAndDecodesClamped) {
  const glm::vec4 out = convert_texel(StorageFormat::Rgba8Snorm, {-1.0f, -2.0f, 0.5f, 1.0f});
  EXPECT_EQ(out.r, -1.0f);
  EXPECT_EQ(out.g, -1.0f);
  EXPECT_EQ(out.b, 64.0f / 127.0f);  // 63.5 rounds away from zero
  EXPECT_EQ(out.a, 1.0f);
  for (int code = -127; code <= 127; ++code) {
    const float v = static_cast<float>(code) / 127.0f;
    EXPECT_EQ(convert_texel(StorageFormat::R8Snorm, {v, 0, 0, 0}).r, v) << code;
  }
}

TEST(Srgb, DecodesEveryCodeThroughTheEotfBeforeFiltering) {
  for (int code = 0; code < 256; ++code) {
    const long double c = code / 255.0L;
    const long double exact = c <= 0.04045L ? c / 12.92L : std::pow((c + 0.055L) / 1.055L, 2.4L);
    const float got = srgb_to_linear(static_cast<uint8_t>(code));
    // Rounded once to float: within half a float ulp of the long-double value (plus pow's).
    const float ulp = std::nextafter(got, 2.0f) - got;
    EXPECT_LE(std::fabs(static_cast<long double>(got) - exact), 0.5L * ulp + 1e-15L) << code;
    const glm::vec4 t =
        convert_texel(StorageFormat::Srgb8A8, glm::vec4(static_cast<float>(code) / 255.0f));
    EXPECT_EQ(t.r, got);
    EXPECT_EQ(t.a, static_cast<float>(code) / 255.0f);  // alpha stays linear
  }
  EXPECT_EQ(srgb_to_linear(0), 0.0f);
  EXPECT_EQ(srgb_to_linear(255), 1.0f);
}

TEST(Formats, MissingChannelsReadZeroAndOneAndDepthIsRed) {
  const glm::vec4 in(0.25f, 0.5f, 0.75f, 0.5f);
  EXPECT_EQ(convert_texel(StorageFormat::R32f, in), glm::vec4(0.25f, 0, 0, 1));
  EXPECT_EQ(convert_texel(StorageFormat::Rg32f, in), glm::vec4(0.25f, 0.5f, 0, 1));
  EXPECT_EQ(convert_texel(StorageFormat::Rgba16f, in), in);  // exact in binary16
  EXPECT_EQ(convert_texel(StorageFormat::D32f, in), glm::vec4(0.25f, 0, 0, 1));
  EXPECT_EQ(convert_texel(StorageFormat::Rgb5A1, in).a, 1.0f);  // 0.5 rounds up to 1
  EXPECT_EQ(format_info(StorageFormat::Rgba16f).bytes, 8);
  EXPECT_EQ(format_info(StorageFormat::Rgb565).bytes, 2);
  for (int i = 0; i < static_cast<int>(StorageFormat::kCount); ++i) {
    const auto f = static_cast<StorageFormat>(i);
    EXPECT_EQ(storage_format_from_name(to_string(f)), f);
    int bits = 0;
    for (int c = 0; c < format_info(f).channels; ++c) bits += format_info(f).bits[c];
    EXPECT_EQ(bits, format_info(f).bytes * 8) << to_string(f);  // every bit of a texel used
  }
  EXPECT_FALSE(storage_format_from_name("rgb9e5"));
}

Texture ramp() {
  std::vector<float> px;
  for (int i = 0; i < 16 * 8; ++i) {
    const float v = static_cast<float>(i) / 127.0f;
    px.insert(px.end(), {v, 1.0f - v, 0.5f, 1.0f});
  }
  return Texture::from_rgba("ramp", 16, 8, px, TexelFormat::Rgba32f, true);
}

TEST(ConvertedTexture, KeepsItsSourceAsTheTruthAndMovesItsOwnBytes) {
  const Texture src = ramp();
  const Texture t = src.converted(StorageFormat::Rgb565);
  EXPECT_EQ(t.storage(), StorageFormat::Rgb565);
  EXPECT_EQ(t.bytes_per_texel(), 2);
  EXPECT_EQ(t.format(), TexelFormat::Rgba32f);  // 1/31 steps are not 8-bit values
  EXPECT_EQ(t.levels(), src.levels());
  EXPECT_EQ(t.address(0, 1, 0) - t.address(0, 0, 0), 2u);
  EXPECT_EQ(&t.reference().reference(), &t.reference());
  for (int l = 0; l < src.levels(); ++l) {
    for (int y = 0; y < src.height(l); ++y) {
      for (int x = 0; x < src.width(l); ++x) {
        ASSERT_EQ(t.texel(l, x, y), convert_texel(StorageFormat::Rgb565, src.texel(l, x, y)));
        ASSERT_EQ(t.reference().texel(l, x, y), src.texel(l, x, y));
      }
    }
  }
  const Texture r8 = src.converted(StorageFormat::Rg8Unorm);
  EXPECT_EQ(r8.format(), TexelFormat::Rgba8);  // the 8-bit kernels serve it
  EXPECT_EQ(r8.texel(0, 3, 0).b, 0.0f);
  // A second conversion keeps the first source as the truth.
  EXPECT_EQ(r8.converted(StorageFormat::R16f).reference().texel(0, 3, 0), src.texel(0, 3, 0));
  const Texture s = src.converted(StorageFormat::Srgb8A8);
  EXPECT_EQ(s.reference().texel(0, 5, 1).r, srgb_eotf(src.texel(0, 5, 1).r));
  EXPECT_EQ(s.reference().texel(0, 5, 1).a, src.texel(0, 5, 1).a);
}

std::string scene_error(const std::string& format) {
  const std::string text =
      "[textures.floor]\nsource = \"procedural:checker?size=8\"\nformat = " + format +
      "\n[materials.m]\ntexture = \"floor\"\n";
  try {
    const Scene sc = parse_scene(text, "s.toml", "");
    const Texture t = load_scene_texture(sc, 0);
    return std::string("ok ") + std::string(to_string(t.storage()));
  } catch (const InputError& e) {
    return e.what();
  }
}

TEST(SceneFormat, NamedFormatsLoadAndUnknownOnesNameTheKey) {
  EXPECT_EQ(scene_error("\"rgba4444\""), "ok rgba4444");
  const std::string e = scene_error("\"rgb9e5\"");
  EXPECT_EQ(e.rfind("s.toml:3:", 0), 0) << e;
  EXPECT_NE(e.find("unknown texel format 'rgb9e5' (one of r8, rg8"), std::string::npos) << e;
  EXPECT_NE(scene_error("5").find("s.toml:3:"), std::string::npos);
}

}  // namespace
}  // namespace texsim
