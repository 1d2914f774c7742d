// texsim's ETC2 / EAC encoder (pipeline/image_io/etc_encoder.h): its own reconstruction agrees
// with texsim's decoders on random blocks (so the error it minimises is the real one); every
// block it makes of real textures (glmark2-data) decodes in texsim's decoders exactly as in
// Mesa (llvmpipe, the independent decoder); its PSNR stays above floors a broken mode search
// would miss; the search picks every mode somewhere; punch-through keeps transparency; bad
// formats are refused.
#include <gtest/gtest.h>
#include <png.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/texture/decode/eac_decoder.h"
#include "blocks/texture/decode/etc2_rgb_decoder.h"
#include "blocks/texture/decode/etc2_rgba_decoder.h"
#include "pipeline/image_io/etc_encoder.h"
#include "pipeline/reference/mesa_peer.h"

namespace {

using namespace texsim;  // NOLINT(google-build-using-namespace)

// A PNG as 8-bit RGBA (libpng's simplified reader: grey and RGB files get alpha 255).
Rgba8Image load_rgba(const std::string& path) {
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&img, path.c_str())) return {};
  img.format = PNG_FORMAT_RGBA;
  Rgba8Image out{static_cast<int>(img.width), static_cast<int>(img.height),
                 std::vector<uint8_t>(PNG_IMAGE_SIZE(img))};
  if (!png_image_finish_read(&img, nullptr, out.rgba.data(), 0, nullptr)) return {};
  return out;
}

// A w x h crop at (x0, y0).
Rgba8Image crop(const Rgba8Image& src, int x0, int y0, int w, int h) {
  Rgba8Image out{w, h, {}};
  for (int y = 0; y < h; ++y) {
    const uint8_t* row =
        src.rgba.data() +
        (static_cast<size_t>(y0 + y) * static_cast<size_t>(src.width) + static_cast<size_t>(x0)) *
            4;
    out.rgba.insert(out.rgba.end(), row, row + static_cast<size_t>(w) * 4);
  }
  return out;
}

const std::string kDir = "/usr/share/glmark2/textures/";

// OpenGL enums (GL/glcorearb.h).
constexpr uint32_t kGlR11Eac = 0x9270, kGlRg11Eac = 0x9272, kGlRgb8Etc2 = 0x9274,
                   kGlRgb8A1Etc2 = 0x9276, kGlRgba8Etc2Eac = 0x9278;
constexpr uint32_t kGlRed = 0x1903, kGlRg = 0x8227, kGlRgba = 0x1908;
constexpr uint32_t kGlUnsignedByte = 0x1401, kGlUnsignedShort = 0x1403;

const MesaPeer& mesa() {
  static const MesaPeer peer(MesaDriver::Llvmpipe);
  return peer;
}

struct Format {
  FileBlockFormat format;
  uint32_t gl;
  int channels;  // compared: 4 (RGBA8 read-back) or 1 / 2 (R11 / RG11, 16-bit read-back)
};

// texsim's decoding of block `b` of a level as `channels` values per texel in Mesa's read-back
// units (8-bit RGBA, or the spec's 16-bit extension of the 11-bit EAC values).
std::array<std::array<int, 4>, 16> texsim_decode(const Format& f, const uint8_t* b) {
  std::array<std::array<int, 4>, 16> out{};
  const auto from8 = [&](const Etc2RgbDecoder::Texels8& t) {
    for (size_t i = 0; i < 16; ++i) {
      for (size_t k = 0; k < 4; ++k) out[i][k] = t[i][k];
    }
  };
  const auto unorm16 = [](int v) { return (v << 5) + (v >> 6); };
  switch (f.format) {
    case FileBlockFormat::Etc2Rgb8:
    case FileBlockFormat::Etc2Rgb8A1:
      from8(Etc2RgbDecoder({f.format == FileBlockFormat::Etc2Rgb8A1, Datapath::Spatial})
                .decode_rgba8(std::span<const uint8_t, 8>(b, 8)));
      break;
    case FileBlockFormat::Etc2Rgba8:
      from8(Etc2RgbaDecoder().decode_rgba8(std::span<const uint8_t, 16>(b, 16)));
      break;
    default:
      for (int c = 0; c < f.channels; ++c) {
        const EacDecoder::Values11 v = EacDecoder().decode_r11(
            std::span<const uint8_t, 8>(b + static_cast<ptrdiff_t>(8) * c, 8));
        for (size_t i = 0; i < 16; ++i) out[i][static_cast<size_t>(c)] = unorm16(v[i]);
      }
  }
  return out;
}

struct Result {
  int blocks = 0, mismatches = 0;
  double psnr = 0;
};

// The level's blocks decoded by texsim and by Mesa (mismatching blocks counted), and texsim's
// decoding against the source: PSNR over the format's channels (RGB; RGBA with alpha, for
// punch-through against alpha thresholded at 128; R or RG with the 16-bit values taken back to
// 8 bits).
Result validate(const Format& f, const Rgba8Image& src, const EncodedLevel& e) {
  Result r;
  const int bw = src.width / 4, bh = src.height / 4;
  const size_t bytes = static_cast<size_t>(format_block_bytes(f.format));
  const bool wide = f.channels < 4;
  const std::vector<uint8_t> got = mesa().decode_compressed(
      f.gl, src.width, src.height, e.bytes, wide ? (f.channels == 1 ? kGlRed : kGlRg) : kGlRgba,
      wide ? kGlUnsignedShort : kGlUnsignedByte, static_cast<size_t>(f.channels) * (wide ? 2 : 1));
  const int compared = f.format == FileBlockFormat::Etc2Rgb8 ? 3 : f.channels;
  double se = 0;
  for (int by = 0; by < bh; ++by) {
    for (int bx = 0; bx < bw; ++bx) {
      const auto dec = texsim_decode(
          f, e.bytes.data() +
                 (static_cast<size_t>(by) * static_cast<size_t>(bw) + static_cast<size_t>(bx)) *
                     bytes);
      bool same = true;
      for (int i = 0; i < 16; ++i) {
        const size_t texel = static_cast<size_t>(by * 4 + i / 4) * static_cast<size_t>(src.width) +
                             static_cast<size_t>(bx * 4 + i % 4);
        for (int k = 0; k < f.channels; ++k) {
          const size_t at = texel * static_cast<size_t>(f.channels) + static_cast<size_t>(k);
          const int mesa_v = wide ? got[at * 2] | (got[at * 2 + 1] << 8) : got[at];
          const int mine = dec[static_cast<size_t>(i)][static_cast<size_t>(k)];
          same = same && mesa_v == mine;
          if (k >= compared) continue;
          const double v8 = wide ? mine * 255.0 / 65535.0 : mine;
          int want = src.rgba[texel * 4 + static_cast<size_t>(k)];
          if (f.format == FileBlockFormat::Etc2Rgb8A1) {
            // Punch-through's target: alpha < 128 transparent black, the rest opaque.
            const bool clear = src.rgba[texel * 4 + 3] < 128;
            want = clear ? 0 : (k == 3 ? 255 : want);
          }
          const double d = v8 - want;
          se += d * d;
        }
      }
      ++r.blocks;
      r.mismatches += same ? 0 : 1;
    }
  }
  const double mse = se / (static_cast<double>(src.width) * src.height * compared);
  r.psnr = mse == 0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 / mse);
  return r;
}

#define REQUIRE_MESA(peer) \
  if (!(peer).available()) GTEST_SKIP() << (peer).why_not()

struct Case {
  Format f;
  const char* texture;
  int side;      // the crop's size (from the top-left corner)
  double floor;  // PSNR floor of the normal effort
};

TEST(EtcEncoder, EveryBlockOfRealTexturesDecodesAsInMesaWithSanePsnr) {
  REQUIRE_MESA(mesa());
  using F = FileBlockFormat;
  const std::vector<Case> cases = {
      {{F::Etc2Rgb8, kGlRgb8Etc2, 4}, "crate-base.png", 256, 30.0},
      {{F::Etc2Rgb8, kGlRgb8Etc2, 4}, "jellyfish-caustics-01.png", 256, 30.0},
      {{F::Etc2Rgb8A1, kGlRgb8A1Etc2, 4}, "desktop-window.png", 256, 30.0},
      {{F::Etc2Rgba8, kGlRgba8Etc2Eac, 4}, "glyph-atlas.png", 256, 30.0},
      {{F::EacR11Unorm, kGlR11Eac, 1}, "crate-base.png", 256, 35.0},
      {{F::EacRg11Unorm, kGlRg11Eac, 2}, "crate-base.png", 256, 35.0},
  };
  for (const Case& c : cases) {
    const Rgba8Image full = load_rgba(kDir + c.texture);
    ASSERT_GE(full.width, c.side) << c.texture;
    const Rgba8Image src = crop(full, 0, 0, c.side, c.side);
    const auto t0 = std::chrono::steady_clock::now();
    const EncodedLevel e = etc_encode(src, c.f.format, EtcEffort::Normal);
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const Result r = validate(c.f, src, e);
    EXPECT_EQ(r.mismatches, 0) << format_name(c.f.format) << " " << c.texture;
    EXPECT_GT(r.psnr, c.floor) << format_name(c.f.format) << " " << c.texture;
    std::printf("%s %s %dx%d: %d blocks, %d mismatches, PSNR %.2f dB, %.3f s\n",
                format_name(c.f.format), c.texture, c.side, c.side, r.blocks, r.mismatches, r.psnr,
                secs);
  }
}

// The encoder's reconstruction is the decoders' result on any bytes (random blocks hit every
// mode, punch-through and multiplier 0).
TEST(EtcEncoder, ReconstructionAgreesWithTheDecodersOnRandomBlocks) {
  std::mt19937_64 rng(7);
  const EacDecoder r11, sr11({true, Datapath::Spatial});
  const Etc2RgbaDecoder rgba;
  for (int n = 0; n < 4000; ++n) {
    EtcBlock b{};
    for (uint8_t& v : b) v = static_cast<uint8_t>(rng() >> 56);
    const std::span<const uint8_t, 8> s(b);
    for (bool punch : {false, true}) {
      const auto want = Etc2RgbDecoder({punch, Datapath::Spatial}).decode_rgba8(s);
      ASSERT_EQ(etc_reconstruct_rgb(b, punch), want) << n << " punch " << punch;
    }
    const auto u = r11.decode_r11(s);
    const auto v = sr11.decode_r11(s);
    std::array<uint8_t, 16> two{};
    std::memcpy(two.data(), b.data(), 8);  // alpha block, then an RGB block of zeros
    const auto a = rgba.decode_rgba8(std::span<const uint8_t, 16>(two));
    const auto ru = eac_reconstruct(b, EacKind::R11), rs = eac_reconstruct(b, EacKind::SignedR11);
    const auto ra = eac_reconstruct(b, EacKind::Alpha8);
    for (size_t i = 0; i < 16; ++i) {
      ASSERT_EQ(ru[i], u[i]) << n;
      ASSERT_EQ(rs[i], v[i]) << n;
      ASSERT_EQ(ra[i], a[i][3]) << n;
    }
  }
}

// Sum of squared RGB errors of a crop's blocks made by `make`, and how often each mode occurs.
template <class Make>
double crop_error(const Rgba8Image& img, const Make& make, std::array<int, 5>* modes) {
  double e = 0;
  for (int by = 0; by < img.height / 4; ++by) {
    for (int bx = 0; bx < img.width / 4; ++bx) {
      EtcPixels px{};
      for (size_t i = 0; i < 16; ++i) {
        const size_t at = (static_cast<size_t>(by * 4) + i / 4) * static_cast<size_t>(img.width) +
                          static_cast<size_t>(bx * 4) + i % 4;
        std::memcpy(px[i].data(), img.rgba.data() + at * 4, 4);
      }
      const EtcBlock b = make(px);
      if (modes) ++(*modes)[static_cast<size_t>(etc_block_mode(b, false))];
      const EtcPixels got = etc_reconstruct_rgb(b, false);
      for (size_t i = 0; i < 16; ++i) {
        for (size_t k = 0; k < 3; ++k) {
          const double d = static_cast<double>(got[i][k]) - px[i][k];
          e += d * d;
        }
      }
    }
  }
  return e;
}

// The search keeps the best block: it beats every single mode and fast; normal beats fast; on
// a photograph every mode wins some blocks.
TEST(EtcEncoder, SearchBeatsEverySingleModeAndPicksEachSomewhere) {
  const Rgba8Image full = load_rgba(kDir + "crate-base.png");
  ASSERT_GE(full.width, 192);
  const Rgba8Image img = crop(full, 64, 64, 128, 128);
  std::array<int, 5> modes{};
  const double normal = crop_error(
      img, [](const EtcPixels& px) { return etc_encode_rgb(px, false, EtcEffort::Normal); },
      &modes);
  const double fast = crop_error(
      img, [](const EtcPixels& px) { return etc_encode_rgb(px, false, EtcEffort::Fast); }, nullptr);
  EXPECT_LT(normal, fast);
  for (int m = 0; m < 5; ++m) {
    const double single = crop_error(
        img,
        [m](const EtcPixels& px) {
          return etc_encode_rgb_mode(px, static_cast<EtcMode>(m), false);
        },
        nullptr);
    EXPECT_LT(fast, single) << "mode " << m;
    EXPECT_GT(modes[static_cast<size_t>(m)], 0) << "mode " << m;
  }
  std::printf("modes I/D/T/H/P %d/%d/%d/%d/%d; squared error normal %.0f fast %.0f\n", modes[0],
              modes[1], modes[2], modes[3], modes[4], normal, fast);
}

// Punch-through: every texel of alpha < 128 decodes transparent, every other opaque.
TEST(EtcEncoder, PunchThroughKeepsEachTexelsTransparency) {
  const Rgba8Image full = load_rgba(kDir + "desktop-window.png");
  ASSERT_GE(full.width, 128);
  const Rgba8Image img = crop(full, 0, 0, 128, 128);
  const EncodedLevel e = etc_encode(img, FileBlockFormat::Etc2Rgb8A1, EtcEffort::Fast);
  int wrong = 0, clear = 0;
  for (int by = 0; by < 32; ++by) {
    for (int bx = 0; bx < 32; ++bx) {
      EtcBlock b{};
      std::memcpy(b.data(), e.bytes.data() + (static_cast<size_t>(by) * 32 + bx) * 8, 8);
      const EtcPixels got = etc_reconstruct_rgb(b, true);
      for (size_t i = 0; i < 16; ++i) {
        const size_t at =
            (static_cast<size_t>(by * 4) + i / 4) * 128 + static_cast<size_t>(bx * 4) + i % 4;
        const bool want_clear = img.rgba[at * 4 + 3] < 128;
        clear += want_clear ? 1 : 0;
        wrong += (got[i][3] == 0) != want_clear ? 1 : 0;
      }
    }
  }
  EXPECT_GT(clear, 0);
  EXPECT_EQ(wrong, 0);
}

TEST(EtcEncoder, OtherFormatsAndBadImagesAreRefused) {
  const Rgba8Image img{4, 4, std::vector<uint8_t>(64, 128)};
  for (FileBlockFormat f : {FileBlockFormat::Bc1Unorm, FileBlockFormat::EacR11Snorm,
                            FileBlockFormat::Etc2Rgb8Srgb, FileBlockFormat::Astc}) {
    try {
      (void)etc_encode(img, f, EtcEffort::Fast);
      ADD_FAILURE() << format_name(f);
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("is not encoded"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW((void)etc_encode({4, 4, {}}, FileBlockFormat::Etc2Rgb8, EtcEffort::Fast),
               InputError);
  // A 5 x 3 image: 2 x 1 blocks, the edge texels repeated.
  const Rgba8Image odd{5, 3, std::vector<uint8_t>(60, 77)};
  const EncodedLevel e = etc_encode(odd, FileBlockFormat::Etc2Rgba8, EtcEffort::Normal);
  EXPECT_EQ(e.bytes.size(), 32u);
  EXPECT_EQ(e.provenance, "texsim etc encoder (ETC2_RGBA8, normal)");
}

// The figures of docs/compressed-files.md#encoders: whole textures, both efforts, against Mesa
// (run with --gtest_also_run_disabled_tests; seconds of encoding on one thread).
TEST(EtcEncoder, DISABLED_MeasureWholeTextures) {
  REQUIRE_MESA(mesa());
  using F = FileBlockFormat;
  const std::vector<std::pair<Format, std::vector<const char*>>> runs = {
      {{F::Etc2Rgb8, kGlRgb8Etc2, 4}, {"crate-base.png", "jellyfish-caustics-01.png"}},
      {{F::Etc2Rgb8A1, kGlRgb8A1Etc2, 4}, {"desktop-window.png", "glyph-atlas.png"}},
      {{F::Etc2Rgba8, kGlRgba8Etc2Eac, 4}, {"desktop-window.png", "glyph-atlas.png"}},
      {{F::EacR11Unorm, kGlR11Eac, 1}, {"crate-base.png"}},
      {{F::EacRg11Unorm, kGlRg11Eac, 2}, {"crate-base.png"}},
  };
  std::printf(
      "| format | texture | blocks | mismatches | PSNR fast | PSNR normal | s fast | s normal |\n");
  for (const auto& [f, names] : runs) {
    for (const char* name : names) {
      const Rgba8Image src = load_rgba(kDir + name);
      std::array<Result, 2> r{};
      std::array<double, 2> secs{};
      for (size_t q = 0; q < 2; ++q) {
        const auto t0 = std::chrono::steady_clock::now();
        const EncodedLevel e =
            etc_encode(src, f.format, q == 0 ? EtcEffort::Fast : EtcEffort::Normal);
        secs[q] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        r[q] = validate(f, src, e);
        EXPECT_EQ(r[q].mismatches, 0) << name;
      }
      std::printf("| %s | %s | %d | %d | %.2f | %.2f | %.2f | %.2f |\n", format_name(f.format),
                  name, r[0].blocks + r[1].blocks, r[0].mismatches + r[1].mismatches, r[0].psnr,
                  r[1].psnr, secs[0], secs[1]);
    }
  }
}

}  // namespace
