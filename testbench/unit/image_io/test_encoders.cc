// Block encoders (pipeline/image_io/{squish,nvtt,astcenc}_encoder.h) on a real texture
// (glmark2-data's crate-base.png, with a synthetic alpha ramp): each produces the block count
// of its format for every quality option, including sizes that are not whole blocks; the
// padding is the edge texels' (a padded image encodes to the same bytes); libsquish's own
// decompressor gives back the input within a loose bound (a sanity check, not a conformance
// test); the levels round-trip through the DDS and .astc writers; DDS files that nvtt itself
// writes, with full mip chains, pass the strict reader; astcenc's library gives the bytes of
// astcenc's command-line tool; bad input is an InputError.
#include <gtest/gtest.h>
#include <nvtt/nvtt.h>
#include <squish.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/base/shell_quote.h"
#include "pipeline/image_io/astc_file.h"
#include "pipeline/image_io/astcenc_encoder.h"
#include "pipeline/image_io/dds_file.h"
#include "pipeline/image_io/encoded_level_cache.h"
#include "pipeline/image_io/nvtt_encoder.h"
#include "pipeline/image_io/png_file.h"
#include "pipeline/image_io/squish_encoder.h"
#include "testbench/lib/error_of.h"
#include "testbench/lib/temp_dir.h"

namespace {

using namespace texsim;  // NOLINT(google-build-using-namespace)

const char* const kTexture = "/usr/share/glmark2/textures/crate-base.png";

// A w x h crop of crate-base.png at (x0, y0), alpha a ramp across it.
Rgba8Image crate(int x0, int y0, int w, int h) {
  static const PngImage png = [] {
    std::ifstream in(kTexture, std::ios::binary);
    const std::vector<uint8_t> file{std::istreambuf_iterator<char>(in),
                                    std::istreambuf_iterator<char>()};
    PngImage p;
    std::string error;
    EXPECT_EQ(read_png_rgb8(file.data(), file.size(), 4096, &p, &error), PngRead::Ok) << error;
    return p;
  }();
  Rgba8Image img;
  if (png.width < x0 + w || png.height < y0 + h) return img;
  img.width = w;
  img.height = h;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const uint8_t* p = png.rgb.data() + (static_cast<size_t>(y0 + y) * png.width + x0 + x) * 3;
      img.rgba.insert(img.rgba.end(), {p[0], p[1], p[2], static_cast<uint8_t>(x * 255 / w)});
    }
  }
  return img;
}

size_t blocks(const Rgba8Image& img, int bw, int bh) {
  return static_cast<size_t>(level_block_count(static_cast<uint64_t>(img.width),
                                               static_cast<uint64_t>(img.height), bw, bh));
}

// Mean absolute difference per channel between the image and squish's decoding of `bytes`
// (`channels`: 3 ignores alpha).
double squish_error(const Rgba8Image& img, const std::vector<uint8_t>& bytes, int flags,
                    int channels) {
  std::vector<uint8_t> back(img.rgba.size());
  squish::DecompressImage(back.data(), img.width, img.height, bytes.data(), flags);
  double sum = 0;
  size_t n = 0;
  for (size_t i = 0; i < back.size(); ++i) {
    if (static_cast<int>(i % 4) >= channels) continue;
    sum += std::abs(static_cast<int>(back[i]) - static_cast<int>(img.rgba[i]));
    ++n;
  }
  return sum / static_cast<double>(n);
}

TEST(Encoders, RealTextureIsOnDisk) {
  ASSERT_TRUE(std::ifstream(kTexture).good()) << kTexture << " (package glmark2-data)";
}

Rgba8Image opaque_copy(Rgba8Image img) {
  for (size_t i = 3; i < img.rgba.size(); i += 4) img.rgba[i] = 255;
  return img;
}

TEST(SquishEncoder, EveryFormatAndFitGivesItsBlocksAndDecodesBackClosely) {
  const Rgba8Image img = crate(100, 200, 64, 48);
  const Rgba8Image opaque = opaque_copy(img);
  const struct {
    FileBlockFormat format;
    int flag, channels;
    size_t block_bytes;
  } formats[] = {{FileBlockFormat::Bc1Unorm, squish::kDxt1, 3, 8},
                 {FileBlockFormat::Bc2Unorm, squish::kDxt3, 4, 16},
                 {FileBlockFormat::Bc3Unorm, squish::kDxt5, 4, 16}};
  for (const auto& f : formats) {
    for (const SquishFit fit :
         {SquishFit::Range, SquishFit::Cluster, SquishFit::IterativeCluster}) {
      // BC1 gets the opaque image: below alpha 128 libsquish picks transparent black.
      const Rgba8Image& in = f.channels == 3 ? opaque : img;
      const EncodedLevel e = squish_encode(in, f.format, fit);
      SCOPED_TRACE(e.provenance);
      EXPECT_EQ(e.bytes.size(), blocks(img, 4, 4) * f.block_bytes);
      EXPECT_LT(squish_error(in, e.bytes, f.flag, f.channels), 8.0);
      EXPECT_NE(e.provenance.find("libsquish 1.15"), std::string::npos);
      EXPECT_NE(e.provenance.find(format_name(f.format)), std::string::npos);
    }
  }
  EXPECT_NE(squish_encode(img, FileBlockFormat::Bc1Unorm, SquishFit::IterativeCluster)
                .provenance.find("kColourIterativeClusterFit"),
            std::string::npos);
}

TEST(SquishEncoder, EdgeBlocksArePaddedWithTheEdgeTexels) {
  const Rgba8Image img = crate(7, 9, 13, 6);  // 4 x 2 blocks, the last column and row partial
  const Rgba8Image padded = padded_to_blocks(img, 4, 4);
  ASSERT_EQ(padded.width, 16);
  ASSERT_EQ(padded.height, 8);
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 16; ++x) {
      const size_t sx = static_cast<size_t>(x < 13 ? x : 12),
                   sy = static_cast<size_t>(y < 6 ? y : 5);
      for (size_t c = 0; c < 4; ++c) {
        ASSERT_EQ(padded.rgba[(static_cast<size_t>(y) * 16 + static_cast<size_t>(x)) * 4 + c],
                  img.rgba[(sy * 13 + sx) * 4 + c]);
      }
    }
  }
  const EncodedLevel a = squish_encode(img, FileBlockFormat::Bc3Unorm, SquishFit::Cluster);
  const EncodedLevel b = squish_encode(padded, FileBlockFormat::Bc3Unorm, SquishFit::Cluster);
  EXPECT_EQ(a.bytes.size(), 8u * 16u);
  EXPECT_EQ(a.bytes, b.bytes);
  // The encoder's block-by-block loop gives what libsquish's own CompressImage does.
  std::vector<uint8_t> whole(a.bytes.size());
  squish::CompressImage(padded.rgba.data(), 16, 8, whole.data(),
                        squish::kDxt5 | squish::kColourClusterFit);
  EXPECT_EQ(a.bytes, whole);
  EXPECT_EQ(a.width, 13);
  EXPECT_EQ(a.height, 6);
}

TEST(NvttEncoder, EveryFormatAndQualityGivesItsBlocks) {
  const Rgba8Image img = crate(300, 40, 50, 30);  // 13 x 8 blocks, partial edges
  const Rgba8Image opaque = opaque_copy(img);
  const struct {
    FileBlockFormat format;
    int squish_flag, channels;
    size_t block_bytes;
  } formats[] = {{FileBlockFormat::Bc1Unorm, squish::kDxt1, 3, 8},
                 {FileBlockFormat::Bc2Unorm, squish::kDxt3, 4, 16},
                 {FileBlockFormat::Bc3Unorm, squish::kDxt5, 4, 16},
                 {FileBlockFormat::Bc4Unorm, 0, 0, 8},
                 {FileBlockFormat::Bc5Unorm, 0, 0, 16}};
  for (const auto& f : formats) {
    for (const NvttQuality q :
         {NvttQuality::Fastest, NvttQuality::Normal, NvttQuality::Production}) {
      const Rgba8Image& in = f.channels == 3 ? opaque : img;
      const EncodedLevel e = nvtt_encode(in, f.format, q);
      SCOPED_TRACE(e.provenance);
      EXPECT_EQ(e.bytes.size(), blocks(img, 4, 4) * f.block_bytes);
      EXPECT_NE(e.provenance.find("NVIDIA Texture Tools 2.0."), std::string::npos);
      if (f.squish_flag == 0) continue;
      const Rgba8Image padded = padded_to_blocks(in, 4, 4);
      EXPECT_LT(squish_error(padded, e.bytes, f.squish_flag, f.channels), 8.0);
    }
  }
}

// Per block of a padded image, whether a BC4 block's two endpoint bytes are near the block's
// smallest and largest value of `channel` (the red channel for BC4 and BC5's first half, green
// for BC5's second): a sanity check of which channel nvtt encodes, not a decoder.
double endpoints_matching(const Rgba8Image& padded, const std::vector<uint8_t>& bytes,
                          size_t stride, size_t offset, size_t channel) {
  const int bx = padded.width / 4, by = padded.height / 4;
  int good = 0;
  for (int b = 0; b < bx * by; ++b) {
    int lo = 255, hi = 0;
    for (int t = 0; t < 16; ++t) {
      const int x = (b % bx) * 4 + t % 4, y = (b / bx) * 4 + t / 4;
      const int v = padded.rgba[static_cast<size_t>(y * padded.width + x) * 4 + channel];
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    const int e0 = bytes[static_cast<size_t>(b) * stride + offset];
    const int e1 = bytes[static_cast<size_t>(b) * stride + offset + 1];
    if (std::abs(std::min(e0, e1) - lo) <= 24 && std::abs(std::max(e0, e1) - hi) <= 24) ++good;
  }
  return good / static_cast<double>(bx * by);
}

TEST(NvttEncoder, Bc4IsTheRedChannelAndBc5RedAndGreen) {
  Rgba8Image img = crate(0, 0, 64, 64);
  for (size_t i = 0; i < img.rgba.size(); i += 4) img.rgba[i + 2] = 0;  // blue unlike the others
  const EncodedLevel bc4 = nvtt_encode(img, FileBlockFormat::Bc4Unorm, NvttQuality::Normal);
  EXPECT_GT(endpoints_matching(img, bc4.bytes, 8, 0, 0), 0.9);
  const EncodedLevel bc5 = nvtt_encode(img, FileBlockFormat::Bc5Unorm, NvttQuality::Normal);
  EXPECT_GT(endpoints_matching(img, bc5.bytes, 16, 0, 0), 0.9);
  EXPECT_GT(endpoints_matching(img, bc5.bytes, 16, 8, 1), 0.9);
}

TEST(AstcencEncoder, BlockSizesAndPresetsGiveTheirBlocks) {
  const Rgba8Image img = crate(10, 10, 50, 37);
  const struct {
    int bw, bh;
    AstcPreset preset;
  } cases[] = {{4, 4, AstcPreset::Fastest},
               {6, 6, AstcPreset::Fast},
               {8, 5, AstcPreset::Medium},
               {12, 12, AstcPreset::Thorough},
               {10, 8, AstcPreset::Fastest}};
  for (const auto& c : cases) {
    AstcencOptions o;
    o.block_w = c.bw;
    o.block_h = c.bh;
    o.preset = c.preset;
    const EncodedLevel e = astcenc_encode(img, o);
    SCOPED_TRACE(e.provenance);
    EXPECT_EQ(e.format, FileBlockFormat::Astc);
    EXPECT_EQ(e.block_w, c.bw);
    EXPECT_EQ(e.block_h, c.bh);
    EXPECT_EQ(e.bytes.size(), blocks(img, c.bw, c.bh) * 16);
    EXPECT_NE(e.provenance.find("libastcenc 4.2"), std::string::npos);
    EXPECT_NE(e.provenance.find(std::string("-") + astc_preset_name(c.preset)), std::string::npos);
  }
  AstcencOptions srgb;
  srgb.srgb = true;
  EXPECT_NE(astcenc_encode(img, srgb).provenance.find("-cs 6x6"), std::string::npos);
}

// The library, as texsim calls it, against the command-line tool on the same padded image: the
// same bytes for each profile, footprint and preset (a wrongly configured context — another
// preset, profile or flag — changes blocks of a real texture).
TEST(AstcencEncoder, LibraryGivesTheCommandLineToolsBytes) {
  if (::access("/usr/bin/astcenc", X_OK) != 0) GTEST_SKIP() << "/usr/bin/astcenc (package astcenc)";
  TempDir dir("astcenc_cli");
  const Rgba8Image img = crate(40, 60, 48, 40);
  const std::string png = dir.file("in.png");
  ASSERT_EQ(write_png_rgba8(png, img.width, img.height, img.rgba.data()), "");
  const struct {
    int bw, bh;
    AstcPreset preset;
    bool srgb;
  } cases[] = {{4, 4, AstcPreset::Fastest, false},
               {6, 5, AstcPreset::Medium, false},
               {8, 8, AstcPreset::Fast, true}};
  for (const auto& c : cases) {
    AstcencOptions o;
    o.block_w = c.bw;
    o.block_h = c.bh;
    o.preset = c.preset;
    o.srgb = c.srgb;
    const EncodedLevel lib = astcenc_encode(img, o);
    SCOPED_TRACE(lib.provenance);
    const std::string out = dir.file("out.astc");
    std::string cmd = "/usr/bin/astcenc ";
    cmd.append(c.srgb ? "-cs " : "-cl ").append(shell_quote(png)).append(" ");
    cmd.append(shell_quote(out)).append(" ");
    cmd.append(std::to_string(c.bw)).append("x").append(std::to_string(c.bh)).append(" -");
    cmd.append(astc_preset_name(c.preset)).append(" -j 1 -silent >/dev/null 2>&1");
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;  // NOLINT(cert-env33-c): the test's own command
    EXPECT_EQ(read_astc_file(out).levels.at(0).bytes, lib.bytes);
  }
}

// Every thread of the context joins an image (`texsim run --threads`): the blocks are those
// of one thread.
TEST(AstcencEncoder, ThreadsGiveTheBytesOfOne) {
  const Rgba8Image img = crate(40, 60, 96, 64);
  AstcencOptions o;
  o.block_w = o.block_h = 4;
  o.preset = AstcPreset::Fastest;
  const int before = astcenc_threads();
  set_astcenc_threads(1);
  const EncodedLevel one = astcenc_encode(img, o);
  set_astcenc_threads(3);
  EXPECT_EQ(astcenc_threads(), 3);
  const EncodedLevel three = astcenc_encode(img, o);
  set_astcenc_threads(before);
  EXPECT_EQ(one.bytes, three.bytes);
  EXPECT_EQ(one.provenance, three.provenance);
}

TEST(AstcencEncoder, NotAFootprintIsAClearError) {
  const Rgba8Image img = crate(0, 0, 8, 8);
  AstcencOptions o;
  o.block_w = 7;
  const std::string e = error_of([&] { astcenc_encode(img, o); });
  EXPECT_NE(e.find("astcenc: block size 7x6 is not an ASTC 2-D footprint"), std::string::npos) << e;
}

TEST(Encoders, BadInputIsAnInputError) {
  Rgba8Image img = crate(0, 0, 8, 8);
  img.rgba.pop_back();
  EXPECT_NE(error_of([&] {
              squish_encode(img, FileBlockFormat::Bc1Unorm, SquishFit::Cluster);
            }).find("8 x 8 RGBA8 texels take 256"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              nvtt_encode(img, FileBlockFormat::Bc1Unorm, NvttQuality::Normal);
            }).find("take 256"),
            std::string::npos);
  EXPECT_NE(error_of([&] { astcenc_encode(img, AstcencOptions{}); }).find("take 256"),
            std::string::npos);
  const Rgba8Image empty;
  EXPECT_NE(error_of([&] {
              squish_encode(empty, FileBlockFormat::Bc1Unorm, SquishFit::Range);
            }).find("image size 0 x 0"),
            std::string::npos);
  const Rgba8Image ok = crate(0, 0, 8, 8);
  EXPECT_NE(error_of([&] {
              squish_encode(ok, FileBlockFormat::Bc4Unorm, SquishFit::Range);
            }).find("BC4_UNORM is not encoded"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              nvtt_encode(ok, FileBlockFormat::Bc7Unorm, NvttQuality::Normal);
            }).find("BC7_UNORM is not encoded"),
            std::string::npos);
}

TEST(Encoders, LevelsRoundTripThroughTheFileWriters) {
  TempDir dir("encoders_files");
  const Rgba8Image img = crate(200, 200, 30, 22);
  const EncodedLevel bc3 = squish_encode(img, FileBlockFormat::Bc3Unorm, SquishFit::Cluster);
  write_dds_file(dir.file("a.dds"), as_compressed_image(bc3));
  const CompressedImage dds = read_dds_file(dir.file("a.dds"));
  EXPECT_EQ(dds.width, 30u);
  EXPECT_EQ(dds.height, 22u);
  EXPECT_EQ(dds.levels.at(0).bytes, bc3.bytes);
  const EncodedLevel bc5 = nvtt_encode(img, FileBlockFormat::Bc5Unorm, NvttQuality::Fastest);
  write_dds_file(dir.file("b.dds"), as_compressed_image(bc5), true);
  EXPECT_EQ(read_dds_file(dir.file("b.dds")).levels.at(0).bytes, bc5.bytes);
  const EncodedLevel astc = astcenc_encode(img, AstcencOptions{});
  write_astc_file(dir.file("c.astc"), as_compressed_image(astc));
  const CompressedImage back = read_astc_file(dir.file("c.astc"));
  EXPECT_EQ(back.width, 30u);
  EXPECT_EQ(back.levels.at(0).bytes, astc.bytes);
}

// The DDS file nvtt writes itself (header and every mip level, made by nvtt from the image).
std::string nvtt_dds_file(const Rgba8Image& img, nvtt::Format format) {
  struct Sink : nvtt::OutputHandler {
    std::string bytes;
    void beginImage(int, int, int, int, int, int) override {}
    bool writeData(const void* data, int size) override {
      bytes.append(static_cast<const char*>(data), static_cast<size_t>(size));
      return true;
    }
  } sink;
  std::vector<uint8_t> bgra(img.rgba);
  for (size_t i = 0; i + 3 < bgra.size(); i += 4) std::swap(bgra[i], bgra[i + 2]);
  nvtt::InputOptions in;
  in.setTextureLayout(nvtt::TextureType_2D, img.width, img.height);
  in.setMipmapData(bgra.data(), img.width, img.height);
  in.setMipmapGeneration(true);
  nvtt::CompressionOptions co;
  co.setFormat(format);
  co.setQuality(nvtt::Quality_Normal);
  nvtt::OutputOptions oo;
  oo.setOutputHandler(&sink);
  nvtt::Compressor c;
  c.enableCudaAcceleration(false);
  EXPECT_TRUE(c.process(in, co, oo));
  return sink.bytes;
}

TEST(NvttEncoder, DdsFilesNvttWritesPassTheStrictReader) {
  const struct {
    nvtt::Format nvtt;
    FileBlockFormat format;
  } formats[] = {{nvtt::Format_BC1, FileBlockFormat::Bc1Unorm},
                 {nvtt::Format_BC2, FileBlockFormat::Bc2Unorm},
                 {nvtt::Format_BC3, FileBlockFormat::Bc3Unorm},
                 {nvtt::Format_BC5, FileBlockFormat::Bc5Unorm}};
  const Rgba8Image odd = crate(60, 60, 50, 30), whole = opaque_copy(crate(60, 60, 48, 32));
  for (const auto& f : formats) {
    const std::string file = nvtt_dds_file(odd, f.nvtt);
    const CompressedImage img =
        parse_dds({reinterpret_cast<const uint8_t*>(file.data()), file.size()}, "nvtt's DDS");
    EXPECT_EQ(img.format, f.format);
    EXPECT_EQ(img.levels.size(), 6u);  // 50x30 ... 1x1
    // Level 0 of whole blocks is what nvtt_encode gives for the same image.
    const std::string file0 = nvtt_dds_file(whole, f.nvtt);
    const CompressedImage img0 =
        parse_dds({reinterpret_cast<const uint8_t*>(file0.data()), file0.size()}, "nvtt's DDS");
    EXPECT_EQ(img0.levels.at(0).bytes, nvtt_encode(whole, f.format, NvttQuality::Normal).bytes)
        << format_name(f.format);
  }
}

}  // namespace

// The encoded-level cache (encoded_level_cache.h): an entry round-trips byte for byte; a
// second cache over the same directory serves the level from disk without encoding, with the
// same blocks and provenance; a damaged, truncated or foreign entry is refused with its reason,
// removed and encoded again; the key changes with any texel, the identity and the size.
namespace {

EncodedLevel fake_level(int w, int h, uint8_t fill) {
  EncodedLevel l;
  l.format = FileBlockFormat::Bc1Unorm;
  l.width = w;
  l.height = h;
  l.bytes.assign(static_cast<size_t>((w + 3) / 4) * static_cast<size_t>((h + 3) / 4) * 8, fill);
  l.provenance = "test encoder (fill " + std::to_string(fill) + ")";
  return l;
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& path, const std::string& b) {
  std::ofstream(path, std::ios::binary).write(b.data(), static_cast<std::streamsize>(b.size()));
}

}  // namespace

TEST(EncodedLevelCache, EntriesRoundTripAndRefuseDamage) {
  const Rgba8Image img = crate(0, 0, 9, 6);
  const EncodedLevelKey key = encoded_level_key("squish range bc1_rgb", img);
  const EncodedLevel l = fake_level(9, 6, 0x5A);
  const std::string e = encode_level_entry(key, l);
  const EncodedLevel back = decode_level_entry(e, "x.level", &key);
  EXPECT_EQ(back.bytes, l.bytes);
  EXPECT_EQ(back.provenance, l.provenance);
  EXPECT_EQ(back.width, 9);
  EXPECT_EQ(encode_level_entry(key, back), e);
  std::string flipped = e;
  flipped[e.size() - 1] ^= 1;
  EXPECT_NE(error_of([&] { decode_level_entry(flipped, "x.level", &key); }).find("CRC-64"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              decode_level_entry(e.substr(0, e.size() - 8), "x.level", &key);
            }).find("header says"),
            std::string::npos);
  EXPECT_NE(
      error_of([&] { decode_level_entry(e.substr(0, 40), "x.level", &key); }).find("shorter than"),
      std::string::npos);
  EncodedLevelKey other = key;
  other[0] ^= 1;
  EXPECT_NE(error_of([&] { decode_level_entry(e, "x.level", &other); }).find("key"),
            std::string::npos);
  // Keys: another texel, identity or size gives another key.
  Rgba8Image img2 = img;
  img2.rgba[17] ^= 1;
  EXPECT_NE(encoded_level_key("squish range bc1_rgb", img2), key);
  EXPECT_NE(encoded_level_key("squish cluster bc1_rgb", img), key);
  Rgba8Image img3 = img;
  img3.width = 6;
  img3.height = 9;
  EXPECT_NE(encoded_level_key("squish range bc1_rgb", img3), key);
}

TEST(EncodedLevelCache, DiskServesLaterProcessesAndDamageIsEncodedAgain) {
  TempDir dir("encoded_cache");
  const Rgba8Image img = crate(8, 8, 16, 12);
  const EncodedLevelKey key = encoded_level_key("test", img);
  int encodes = 0;
  const auto encode = [&] {
    ++encodes;
    return squish_encode(img, FileBlockFormat::Bc1Unorm, SquishFit::Range);
  };
  EncodedLevelCache::forget_memory();
  EncodedLevelCache cache(dir.file("encoded"), uint64_t{1} << 20);
  const char* where = "?";
  const EncodedLevel first = cache.get(key, encode, &where);
  EXPECT_STREQ(where, "");
  EXPECT_EQ(cache.get(key, encode, &where).bytes, first.bytes);
  EXPECT_STREQ(where, "memory");
  EncodedLevelCache::forget_memory();  // as a new process
  const EncodedLevel again = cache.get(key, encode, &where);
  EXPECT_STREQ(where, "disk");
  EXPECT_EQ(again.bytes, first.bytes);
  EXPECT_EQ(again.provenance, first.provenance);
  EXPECT_EQ(encodes, 1);
  // A damaged entry: refused, removed, encoded again, and stored whole.
  std::string b = file_bytes(cache.entry_path(key));
  b[b.size() / 2] ^= 0x10;
  write_bytes(cache.entry_path(key), b);
  EncodedLevelCache::forget_memory();
  EXPECT_EQ(cache.get(key, encode, &where).bytes, first.bytes);
  EXPECT_STREQ(where, "");
  EXPECT_EQ(encodes, 2);
  EncodedLevelCache::forget_memory();
  cache.get(key, encode, &where);
  EXPECT_STREQ(where, "disk");
  // Not a regular file where the entry should be: refused by the common opener, encoded again.
  std::filesystem::remove(cache.entry_path(key));
  std::filesystem::create_directory(cache.entry_path(key));
  EncodedLevelCache::forget_memory();
  EXPECT_EQ(cache.get(key, encode, &where).bytes, first.bytes);
  EXPECT_STREQ(where, "");
  EXPECT_EQ(encodes, 3);
  EXPECT_TRUE(std::filesystem::is_regular_file(cache.entry_path(key)));
  // No disk layer: every new process encodes.
  EncodedLevelCache none("", 0);
  EncodedLevelCache::forget_memory();
  none.get(key, encode, &where);
  EXPECT_STREQ(where, "");
  EXPECT_EQ(encodes, 4);
  EncodedLevelCache::forget_memory();
}
