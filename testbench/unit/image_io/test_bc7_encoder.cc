// texsim's BC7 encoder (pipeline/image_io/bc7_encoder.h): its own reconstruction of the
// blocks it makes is texsim's decoder's; every block it makes of real textures (glmark2-data)
// decodes in texsim's decoder exactly as in Mesa (llvmpipe, the independent decoder); its PSNR
// stays above floors a broken endpoint fit would miss (Mesa's own BC7 encoder's PSNR printed
// beside it); normal beats fast and uses both modes; other formats are refused.
#include <gtest/gtest.h>
#include <png.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/texture/decode/bc7_decoder.h"
#include "pipeline/image_io/bc7_encoder.h"
#include "pipeline/reference/mesa_peer.h"

namespace {

using namespace texsim;  // NOLINT(google-build-using-namespace)

constexpr uint32_t kGlBptcUnorm = 0x8E8C;  // GL_COMPRESSED_RGBA_BPTC_UNORM

// A w x h crop at the top-left of a PNG, as 8-bit RGBA (grey and RGB files get alpha 255).
Rgba8Image load_crop(const std::string& path, int w, int h) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str())) return {};
  png.format = PNG_FORMAT_RGBA;
  std::vector<uint8_t> px(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, px.data(), 0, nullptr)) return {};
  if (static_cast<int>(png.width) < w || static_cast<int>(png.height) < h) return {};
  Rgba8Image out{w, h, {}};
  for (int y = 0; y < h; ++y) {
    const uint8_t* row = px.data() + static_cast<size_t>(y) * png.width * 4;
    out.rgba.insert(out.rgba.end(), row, row + static_cast<size_t>(w) * 4);
  }
  return out;
}

// PSNR of RGBA8 texels against the source's: over RGB when the source is opaque (as for the
// ETC2 RGB formats), else over RGBA.
double psnr(const std::vector<uint8_t>& a, const std::vector<uint8_t>& src) {
  bool opaque = true;
  for (size_t i = 3; i < src.size(); i += 4) opaque = opaque && src[i] == 255;
  double se = 0, n = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    if (opaque && i % 4 == 3) continue;
    const double d = static_cast<double>(a[i]) - src[i];
    se += d * d;
    n += 1;
  }
  const double mse = se / n;
  return mse == 0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 / mse);
}

// texsim's decoding of a level's blocks, as RGBA8 rows (w a multiple of 4).
std::vector<uint8_t> texsim_decode(const std::vector<uint8_t>& blocks, int w, int h) {
  std::vector<uint8_t> out(static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
  const Bc7Decoder dec;
  for (size_t n = 0; n < blocks.size() / 16; ++n) {
    const DecodedBlock d = dec.decode(std::span<const uint8_t, 16>(blocks.data() + 16 * n, 16));
    const size_t bx = n % static_cast<size_t>(w / 4), by = n / static_cast<size_t>(w / 4);
    for (size_t t = 0; t < 16; ++t) {
      const size_t at = ((by * 4 + t / 4) * static_cast<size_t>(w) + bx * 4 + t % 4) * 4;
      for (size_t c = 0; c < 4; ++c)
        out[at + c] = static_cast<uint8_t>(std::lround(d.texels[t][static_cast<int>(c)] * 255.0F));
    }
  }
  return out;
}

const MesaPeer& mesa() {
  static const MesaPeer peer(MesaDriver::Llvmpipe);
  return peer;
}

TEST(Bc7Encoder, EveryBlockOfRealTexturesDecodesAsInMesaWithSanePsnr) {
  if (!mesa().available()) GTEST_SKIP() << mesa().why_not();
  const struct {
    const char* texture;
    int side;
    double floor;  // PSNR floor of the normal quality
  } cases[] = {{"crate-base.png", 256, 40.0},
               {"desktop-window.png", 256, 42.0},
               {"glyph-atlas.png", 256, 34.0}};
  for (const auto& c : cases) {
    const Rgba8Image src =
        load_crop(std::string("/usr/share/glmark2/textures/") + c.texture, c.side, c.side);
    ASSERT_EQ(src.width, c.side) << c.texture;
    const auto t0 = std::chrono::steady_clock::now();
    const EncodedLevel e = bc7_encode(src, FileBlockFormat::Bc7Unorm, Bc7Quality::Normal);
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::vector<uint8_t> mine = texsim_decode(e.bytes, src.width, src.height);
    const MesaImage m = mesa().decode_blocks(kGlBptcUnorm, src.width, src.height, e.bytes);
    int blocks = 0, mismatches = 0;
    std::array<int, 9> modes{};
    for (int by = 0; by < src.height / 4; ++by) {
      for (int bx = 0; bx < src.width / 4; ++bx) {
        bool same = true;
        for (int t = 0; t < 16; ++t) {
          const size_t at = (static_cast<size_t>(by * 4 + t / 4) * static_cast<size_t>(src.width) +
                             static_cast<size_t>(bx * 4 + t % 4)) *
                            4;
          same = same && std::memcmp(&mine[at], &m.rgba[at], 4) == 0;
        }
        const size_t n =
            static_cast<size_t>(by) * static_cast<size_t>(src.width / 4) + static_cast<size_t>(bx);
        ++modes[static_cast<size_t>(
            Bc7Decoder::mode_of(std::span<const uint8_t, 16>(e.bytes.data() + 16 * n, 16)))];
        ++blocks;
        mismatches += same ? 0 : 1;
      }
    }
    const double p = psnr(mine, src.rgba);
    const double p_fast =
        psnr(texsim_decode(bc7_encode(src, FileBlockFormat::Bc7Unorm, Bc7Quality::Fast).bytes,
                           src.width, src.height),
             src.rgba);
    // Mesa's own encoder on the same image, for scale.
    MesaImage in;
    in.width = src.width;
    in.height = src.height;
    in.rgba = src.rgba;
    const std::vector<uint8_t> theirs = mesa().encode_blocks(kGlBptcUnorm, in);
    const double p_mesa = psnr(texsim_decode(theirs, src.width, src.height), src.rgba);
    EXPECT_EQ(mismatches, 0) << c.texture;
    EXPECT_GT(p, c.floor) << c.texture;
    EXPECT_GT(modes[5] + modes[6], 0);
    std::printf(
        "BC7_UNORM %s %dx%d: %d blocks, %d mismatches, modes 5/6 %d/%d, PSNR %.2f dB "
        "(fast %.2f dB, Mesa's encoder %.2f dB), %.3f s\n",
        c.texture, c.side, c.side, blocks, mismatches, modes[5], modes[6], p, p_fast, p_mesa, secs);
  }
}

// The encoder's reconstruction is the decoder's on every block it makes; normal beats fast
// and picks both modes.
TEST(Bc7Encoder, ReconstructionIsTheDecodersAndNormalBeatsFast) {
  const Rgba8Image src = load_crop("/usr/share/glmark2/textures/desktop-window.png", 128, 128);
  ASSERT_EQ(src.width, 128);
  double err[2] = {0, 0};
  std::array<int, 9> modes{};
  for (const Bc7Quality q : {Bc7Quality::Fast, Bc7Quality::Normal}) {
    const EncodedLevel e = bc7_encode(src, FileBlockFormat::Bc7Unorm, q);
    const std::vector<uint8_t> dec = texsim_decode(e.bytes, 128, 128);
    for (size_t n = 0; n < e.bytes.size() / 16; ++n) {
      Bc7Block b{};
      std::memcpy(b.data(), e.bytes.data() + 16 * n, 16);
      if (q == Bc7Quality::Normal) ++modes[static_cast<size_t>(Bc7Decoder::mode_of(b))];
      Bc7Pixels mine{};
      ASSERT_TRUE(bc7_reconstruct(b, &mine));
      const size_t bx = n % 32, by = n / 32;
      for (size_t t = 0; t < 16; ++t) {
        const size_t at = ((by * 4 + t / 4) * 128 + bx * 4 + t % 4) * 4;
        ASSERT_EQ(std::memcmp(mine[t].data(), &dec[at], 4), 0) << "block " << n;
      }
    }
    for (size_t i = 0; i < dec.size(); ++i) {
      const double d = static_cast<double>(dec[i]) - src.rgba[i];
      err[q == Bc7Quality::Normal ? 1 : 0] += d * d;
    }
  }
  EXPECT_LT(err[1], err[0]);
  EXPECT_GT(modes[5], 0);
  EXPECT_GT(modes[6], 0);
}

TEST(Bc7Encoder, OtherFormatsAndBadImagesAreRefused) {
  const Rgba8Image img{4, 4, std::vector<uint8_t>(64, 9)};
  EXPECT_THROW((void)bc7_encode(img, FileBlockFormat::Bc7Srgb, Bc7Quality::Fast), InputError);
  EXPECT_THROW((void)bc7_encode(img, FileBlockFormat::Bc3Unorm, Bc7Quality::Fast), InputError);
  EXPECT_THROW((void)bc7_encode({3, 3, {}}, FileBlockFormat::Bc7Unorm, Bc7Quality::Fast),
               InputError);
  // A flat block is exact; a 6 x 5 image takes 2 x 2 blocks.
  const EncodedLevel flat = bc7_encode(img, FileBlockFormat::Bc7Unorm, Bc7Quality::Fast);
  Bc7Block b{};
  std::memcpy(b.data(), flat.bytes.data(), 16);
  Bc7Pixels px{};
  ASSERT_TRUE(bc7_reconstruct(b, &px));
  for (const auto& p : px) EXPECT_EQ(p[0], 9);
  const EncodedLevel odd = bc7_encode({6, 5, std::vector<uint8_t>(120, 200)},
                                      FileBlockFormat::Bc7Unorm, Bc7Quality::Normal);
  EXPECT_EQ(odd.bytes.size(), 64u);
  EXPECT_EQ(odd.provenance, "texsim bc7 encoder (modes 6 and 5, normal)");
}

// The figures of docs/compressed-files.md#encoders: whole textures, both qualities, against
// Mesa, and Mesa's own encoder's PSNR (run with --gtest_also_run_disabled_tests).
TEST(Bc7Encoder, DISABLED_MeasureWholeTextures) {
  if (!mesa().available()) GTEST_SKIP() << mesa().why_not();
  std::printf(
      "| texture | blocks | mismatches | PSNR fast | PSNR normal | PSNR Mesa | s fast | s normal "
      "|\n");
  for (const char* name :
       {"crate-base.png", "jellyfish-caustics-01.png", "desktop-window.png", "glyph-atlas.png"}) {
    const std::string path = std::string("/usr/share/glmark2/textures/") + name;
    png_image png{};
    png.version = PNG_IMAGE_VERSION;
    ASSERT_TRUE(png_image_begin_read_from_file(&png, path.c_str()));
    const Rgba8Image src =
        load_crop(path, static_cast<int>(png.width), static_cast<int>(png.height));
    png_image_free(&png);
    std::array<double, 2> p{}, secs{};
    int blocks = 0, mismatches = 0;
    for (size_t q = 0; q < 2; ++q) {
      const auto t0 = std::chrono::steady_clock::now();
      const EncodedLevel e = bc7_encode(src, FileBlockFormat::Bc7Unorm,
                                        q == 0 ? Bc7Quality::Fast : Bc7Quality::Normal);
      secs[q] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const std::vector<uint8_t> mine = texsim_decode(e.bytes, src.width, src.height);
      const MesaImage m = mesa().decode_blocks(kGlBptcUnorm, src.width, src.height, e.bytes);
      for (size_t b = 0; b < e.bytes.size() / 16; ++b) {
        const size_t bx = b % static_cast<size_t>(src.width / 4),
                     by = b / static_cast<size_t>(src.width / 4);
        bool same = true;
        for (size_t t = 0; t < 16; ++t) {
          const size_t at =
              ((by * 4 + t / 4) * static_cast<size_t>(src.width) + bx * 4 + t % 4) * 4;
          same = same && std::memcmp(&mine[at], &m.rgba[at], 4) == 0;
        }
        ++blocks;
        mismatches += same ? 0 : 1;
      }
      p[q] = psnr(mine, src.rgba);
    }
    MesaImage in;
    in.width = src.width;
    in.height = src.height;
    in.rgba = src.rgba;
    const double p_mesa = psnr(
        texsim_decode(mesa().encode_blocks(kGlBptcUnorm, in), src.width, src.height), src.rgba);
    EXPECT_EQ(mismatches, 0) << name;
    std::printf("| %s | %d | %d | %.2f | %.2f | %.2f | %.2f | %.2f |\n", name, blocks, mismatches,
                p[0], p[1], p_mesa, secs[0], secs[1]);
  }
}

}  // namespace
