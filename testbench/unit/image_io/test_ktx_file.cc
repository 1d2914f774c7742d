// KTX 1.1 files (pipeline/image_io/ktx_file.h): every format family (BC1-BC5, BC7, ETC2 / EAC,
// ASTC of several footprints, sRGB ones) round-trips through the writer and the reader with
// its mip chain; the header holds the spec's values; key/value data is skipped; and every rule
// of the strict reader (truncation, endianness, imageSize, mip count, faces, array elements,
// depth, unknown formats, uncompressed textures, key/value bounds, trailing bytes) is an
// InputError naming the file and the reason. A texture of a KTX file loads as a scene texture
// with its format.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "pipeline/image_io/ktx_file.h"
#include "pipeline/scene/compressed_loader.h"
#include "testbench/lib/compressed_image_checks.h"
#include "testbench/lib/error_of.h"
#include "testbench/lib/temp_dir.h"

namespace {

using namespace texsim;  // NOLINT(google-build-using-namespace)
using texsim::test::expect_same;
using texsim::test::set_u32;

// An image of `format` (block footprint bw x bh) with `levels` mip levels of pseudo-random
// blocks.
CompressedImage make_image(FileBlockFormat format, uint32_t w, uint32_t h, uint32_t levels,
                           int bw = 4, int bh = 4) {
  CompressedImage img;
  img.format = format;
  img.width = w;
  img.height = h;
  img.block_w = bw;
  img.block_h = bh;
  img.block_bytes = format_block_bytes(format);
  uint32_t seed = 777u + w * 31u + h;
  for (uint32_t i = 0; i < levels; ++i) {
    CompressedLevel l;
    l.width = mip_side(w, i);
    l.height = mip_side(h, i);
    l.bytes.resize(level_block_count(l.width, l.height, bw, bh) *
                   static_cast<uint64_t>(img.block_bytes));
    for (uint8_t& b : l.bytes) {
      seed = seed * 1664525u + 1013904223u;
      b = static_cast<uint8_t>(seed >> 24);
    }
    img.levels.push_back(std::move(l));
  }
  return img;
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}
uint32_t get_u32(const std::string& s, size_t at) {
  uint32_t v = 0;
  for (size_t i = 0; i < 4; ++i)
    v |= static_cast<uint32_t>(static_cast<uint8_t>(s[at + i])) << (8 * i);
  return v;
}

TEST(KtxFile, EveryFormatFamilyRoundTripsWithItsMipChain) {
  using F = FileBlockFormat;
  TempDir dir("ktx_roundtrip");
  struct Case {
    F format;
    int bw, bh;
  };
  const std::vector<Case> cases = {
      {F::Bc1Unorm, 4, 4},      {F::Bc1RgbUnorm, 4, 4},  {F::Bc1RgbSrgb, 4, 4},
      {F::Bc2Srgb, 4, 4},       {F::Bc3Unorm, 4, 4},     {F::Bc4Snorm, 4, 4},
      {F::Bc5Unorm, 4, 4},      {F::Bc7Unorm, 4, 4},     {F::Bc7Srgb, 4, 4},
      {F::Etc2Rgb8, 4, 4},      {F::Etc2Rgb8Srgb, 4, 4}, {F::Etc2Rgb8A1, 4, 4},
      {F::Etc2Rgba8Srgb, 4, 4}, {F::EacR11Unorm, 4, 4},  {F::EacR11Snorm, 4, 4},
      {F::EacRg11Unorm, 4, 4},  {F::EacRg11Snorm, 4, 4}, {F::Astc, 4, 4},
      {F::Astc, 6, 5},          {F::Astc, 12, 12},       {F::AstcSrgb, 8, 8},
      {F::AstcSrgb, 10, 6},
  };
  for (const Case& c : cases) {
    // 13 x 7: partial edge blocks; levels 13x7, 6x3, 3x1, 1x1.
    const CompressedImage img = make_image(c.format, 13, 7, 4, c.bw, c.bh);
    const std::string path = dir.file(img.format_label() + ".ktx");
    write_ktx_file(path, img);
    SCOPED_TRACE(path);
    expect_same(read_ktx_file(path), img);
  }
  EXPECT_EQ(dir.entries(), cases.size());  // no temporary file left behind
}

TEST(KtxFile, HeaderHoldsTheSpecsValues) {
  const std::string s = ktx_bytes(make_image(FileBlockFormat::Etc2Rgb8, 8, 4, 2), "x");
  EXPECT_EQ(s.substr(0, 12), std::string("\xABKTX 11\xBB\r\n\x1A\n"));
  EXPECT_EQ(get_u32(s, 12), 0x04030201u);
  EXPECT_EQ(get_u32(s, 16), 0u);       // glType
  EXPECT_EQ(get_u32(s, 20), 1u);       // glTypeSize
  EXPECT_EQ(get_u32(s, 24), 0u);       // glFormat
  EXPECT_EQ(get_u32(s, 28), 0x9274u);  // GL_COMPRESSED_RGB8_ETC2
  EXPECT_EQ(get_u32(s, 32), 0x1907u);  // GL_RGB
  EXPECT_EQ(get_u32(s, 36), 8u);
  EXPECT_EQ(get_u32(s, 40), 4u);
  EXPECT_EQ(get_u32(s, 52), 1u);   // faces
  EXPECT_EQ(get_u32(s, 56), 2u);   // levels
  EXPECT_EQ(get_u32(s, 64), 16u);  // level 0: 2 blocks of 8 bytes
  EXPECT_EQ(s.size(), 64u + 4 + 16 + 4 + 8);
  const std::string astc = ktx_bytes(make_image(FileBlockFormat::AstcSrgb, 12, 12, 1, 12, 12), "x");
  EXPECT_EQ(get_u32(astc, 28), 0x93DDu);  // GL_COMPRESSED_SRGB8_ALPHA8_ASTC_12x12_KHR
  // A file with one key/value pair and numberOfMipmapLevels 0 (one level) reads.
  std::string kv = ktx_bytes(make_image(FileBlockFormat::Bc4Unorm, 4, 4, 1), "x");
  set_u32(kv, 56, 0);
  const std::string pair = std::string("\x0b\0\0\0KTXorient\0\0\0\0", 16);  // 11 bytes + pad 1
  set_u32(kv, 60, static_cast<uint32_t>(pair.size()));
  kv.insert(64, pair);
  const CompressedImage img =
      parse_ktx({reinterpret_cast<const uint8_t*>(kv.data()), kv.size()}, "kv.ktx");
  EXPECT_EQ(img.format, FileBlockFormat::Bc4Unorm);
  EXPECT_EQ(img.levels.size(), 1u);
}

// The InputError message of reading `bytes` from a file, "" if none.
std::string read_error(const TempDir& dir, const std::string& bytes) {
  const std::string path = dir.file("bad.ktx");
  write_bytes(path, bytes);
  return error_of([&] { read_ktx_file(path); });
}

std::string good() { return ktx_bytes(make_image(FileBlockFormat::Bc7Unorm, 16, 8, 3), "x"); }

TEST(KtxFile, EveryBadHeaderGivesItsMessage) {
  TempDir dir("ktx_bad");
  const auto with = [](size_t at, uint32_t v) {
    std::string s = good();
    set_u32(s, at, v);
    return s;
  };
  std::string not_ktx = good();
  not_ktx[1] = 'X';
  std::string swapped = with(12, 0x01020304);
  const struct {
    std::string bytes, message;
  } cases[] = {
      {good().substr(0, 40), "40 bytes is shorter than a KTX header (64 bytes)"},
      {not_ktx, "not a KTX 1 file"},
      {swapped, "big-endian KTX file"},
      {with(12, 7), "endianness field is 0x0007, not 0x04030201"},
      {with(16, 0x1401), "glType 0x1401, glFormat 0x0000: uncompressed textures are not read"},
      {with(24, 0x1908), "uncompressed textures are not read"},
      {with(20, 4), "glTypeSize is 4, not 1"},
      {with(28, 0x8D64), "glInternalFormat 0x8D64 is not a supported block-compressed format"},
      {with(52, 6), "numberOfFaces 6: cube maps are not supported"},
      {with(48, 2), "numberOfArrayElements 2: texture arrays are not supported"},
      {with(44, 1), "pixelDepth 1: 3-D textures are not supported"},
      {with(40, 0), "image size 16 x 0 has no texels"},
      {with(56, 6), "numberOfMipmapLevels 6 is more than a 16 x 8 image has (5)"},
      {with(60, 4096), "key/value data of 4096 bytes runs past the end of the file"},
      {with(64, 127), "level 0 (16 x 8): imageSize 127, its blocks take 128"},
      {with(64 + 4 + 128, 16), "level 1 (8 x 4): imageSize 16, its blocks take 32"},
      {good().substr(0, good().size() - 5), "truncated: level 2 takes 16 bytes"},
      {good().substr(0, 64 + 4 + 128 + 2), "truncated: level 1's imageSize at byte 196"},
      {good() + "abc", "3 trailing bytes after the 3 level(s) the header describes"},
  };
  for (const auto& c : cases) {
    const std::string msg = read_error(dir, c.bytes);
    EXPECT_NE(msg.find(dir.file("bad.ktx") + ": "), std::string::npos) << msg;
    EXPECT_NE(msg.find(c.message), std::string::npos) << "want: " << c.message << "\ngot:  " << msg;
  }
  // Key/value pairs must stay inside their data.
  std::string kv = good();
  set_u32(kv, 60, 8);
  kv.insert(64, std::string("\x09\0\0\0abcd", 8));  // a pair of 9 bytes in 4
  EXPECT_NE(read_error(dir, kv).find("key/value pair of 9 bytes at byte 64 runs past"),
            std::string::npos)
      << read_error(dir, kv);
}

TEST(KtxFile, TheWriterRefusesWhatKtxCannotHold) {
  CompressedImage bad = make_image(FileBlockFormat::Astc, 8, 8, 1, 4, 4);
  bad.block_w = 7;  // not an ASTC footprint
  bad.block_h = 7;
  bad.levels[0].bytes.resize(level_block_count(8, 8, 7, 7) * 16);
  EXPECT_NE(error_of([&] { (void)ktx_bytes(bad, "out.ktx"); }).find("has no KTX format"),
            std::string::npos);
  CompressedImage wrong = make_image(FileBlockFormat::Bc1Unorm, 8, 8, 2);
  wrong.levels[1].bytes.pop_back();
  EXPECT_NE(error_of([&] { (void)ktx_bytes(wrong, "out.ktx"); }).find("cannot write"),
            std::string::npos);
}

TEST(KtxFile, ASceneTextureLoadsFromAKtxFile) {
  TempDir dir("ktx_scene");
  const std::string path = dir.file("t.ktx");
  write_ktx_file(path, make_image(FileBlockFormat::Etc2Rgba8, 16, 8, 2));
  ASSERT_TRUE(is_compressed_file(path));
  ASSERT_TRUE(is_compressed_file(dir.file("T.KTX")));
  const Texture t = load_compressed_file(path);
  EXPECT_EQ(t.width(0), 16);
  EXPECT_EQ(t.levels(), 2);
  ASSERT_NE(t.blocks(), nullptr);
  EXPECT_EQ(t.blocks()->format, CompressedFormat::Etc2Rgba8);
  EXPECT_EQ(t.blocks()->provenance, "file t.ktx (ETC2_RGBA8)");
}

// The fuzz harness's seeds (testbench/fuzz/corpus/ktx) read, but for those named *_refused.
TEST(KtxFile, TheFuzzSeedsReadOrAreRefusedAsNamed) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(std::string(TEXSIM_SOURCE_DIR) +
                                                           "/testbench/fuzz/corpus/ktx")) {
    const std::string path = e.path().string();
    const bool refused = path.find("_refused") != std::string::npos;
    EXPECT_EQ(error_of([&] { (void)read_ktx_file(path); }).empty(), !refused) << path;
    ++n;
  }
  EXPECT_GE(n, 5);
}

}  // namespace
