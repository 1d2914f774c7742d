// .astc files (pipeline/image_io/astc_file.h): every 2-D footprint round-trips through the
// writer and the reader; every rule of the strict reader (magic, footprints, 3-D blocks and
// images, sizes against the file) is an InputError naming the file and the reason.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "pipeline/image_io/astc_file.h"
#include "testbench/lib/error_of.h"
#include "testbench/lib/temp_dir.h"

namespace {

using namespace texsim;  // NOLINT(google-build-using-namespace)

CompressedImage make_astc(int bw, int bh, uint32_t w, uint32_t h) {
  CompressedImage img;
  img.format = FileBlockFormat::Astc;
  img.width = w;
  img.height = h;
  img.block_w = bw;
  img.block_h = bh;
  img.block_bytes = 16;
  CompressedLevel l;
  l.width = w;
  l.height = h;
  l.bytes.resize(level_block_count(w, h, bw, bh) * 16);
  uint32_t seed = 777u + w;
  for (uint8_t& b : l.bytes) {
    seed = seed * 1664525u + 1013904223u;
    b = static_cast<uint8_t>(seed >> 24);
  }
  img.levels.push_back(std::move(l));
  return img;
}

TEST(AstcFile, EveryFootprintRoundTrips) {
  const int footprints[14][2] = {{4, 4}, {5, 4},  {5, 5},  {6, 5},  {6, 6},   {8, 5},   {8, 6},
                                 {8, 8}, {10, 5}, {10, 6}, {10, 8}, {10, 10}, {12, 10}, {12, 12}};
  TempDir dir("astc_roundtrip");
  for (const auto& f : footprints) {
    const CompressedImage img = make_astc(f[0], f[1], 37, 19);
    const std::string path = dir.file(img.format_label() + ".astc");
    write_astc_file(path, img);
    const CompressedImage back = read_astc_file(path);
    EXPECT_EQ(back.format, FileBlockFormat::Astc);
    EXPECT_EQ(back.block_w, f[0]);
    EXPECT_EQ(back.block_h, f[1]);
    EXPECT_EQ(back.width, 37u);
    EXPECT_EQ(back.height, 19u);
    ASSERT_EQ(back.levels.size(), 1u);
    EXPECT_EQ(back.levels[0].bytes, img.levels[0].bytes) << path;
  }
  EXPECT_EQ(dir.entries(), 14u);
}

TEST(AstcFile, HeaderLayout) {
  const std::string s = astc_bytes(make_astc(8, 5, 0x012345, 0x000102), "x");
  const uint8_t want[16] = {0x13, 0xAB, 0xA1, 0x5C, 8, 5, 1, 0x45,
                            0x23, 0x01, 0x02, 0x01, 0, 1, 0, 0};
  for (size_t i = 0; i < 16; ++i) EXPECT_EQ(static_cast<uint8_t>(s[i]), want[i]) << i;
  // ceil(0x12345 / 8) x ceil(258 / 5) blocks
  EXPECT_EQ(s.size(), 16u + uint64_t{(0x12345 + 7) / 8} * ((0x102 + 4) / 5) * 16);
}

void set(std::string& s, size_t at, int n, uint32_t v) {
  for (int i = 0; i < n; ++i) s[at + static_cast<size_t>(i)] = static_cast<char>(v >> (8 * i));
}

TEST(AstcFile, EveryBadInputIsAnErrorNamingTheFileAndTheReason) {
  TempDir dir("astc_bad");
  const std::string path = dir.file("bad.astc");
  const std::string g = astc_bytes(make_astc(6, 6, 20, 13), "x");  // 4 x 3 blocks
  auto with = [](std::string s, size_t at, int n, uint32_t v) {
    set(s, at, n, v);
    return s;
  };
  const struct {
    const char* name;
    std::string bytes;
    const char* reason;
  } cases[] = {
      {"truncated", g.substr(0, g.size() - 1), "truncated: 20 x 13 texels in 6x6 blocks take 192"},
      {"trailing", g + "zz", "2 trailing bytes after the 12 blocks"},
      {"short", g.substr(0, 15), "shorter than the .astc header"},
      {"magic", with(g, 0, 4, 0x5CA1AB14), "no magic 0x5CA1AB13"},
      {"3-D block", with(g, 6, 1, 3), "3-D block footprint 6x6x3 is not supported"},
      {"zero z block", with(g, 6, 1, 0), "block footprint 6x6x0 is not an ASTC 2-D block size"},
      {"bad footprint", with(g, 4, 1, 7), "block footprint 7x6x1 is not an ASTC 2-D"},
      {"3x3", with(with(g, 4, 1, 3), 5, 1, 3), "block footprint 3x3x1"},
      {"z size", with(g, 13, 3, 2), "z size 2: 3-D images are not supported"},
      {"zero z", with(g, 13, 3, 0), "has no texels"},
      {"zero x", with(g, 7, 3, 0), "image size 0 x 13 x 1 has no texels"},
      {"huge", with(g, 7, 3, 0xffffff), "truncated"},
  };
  for (const auto& c : cases) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << c.bytes;
    const std::string e = error_of([&] { read_astc_file(path); });
    EXPECT_NE(e.find(path), std::string::npos) << c.name << ": " << e;
    EXPECT_NE(e.find(c.reason), std::string::npos) << c.name << ": " << e;
  }
  std::ofstream(path, std::ios::binary | std::ios::trunc) << g;  // the base reads
  EXPECT_EQ(error_of([&] { read_astc_file(path); }), "");
}

TEST(AstcFile, WriterRefusesWhatTheFormatCannotHold) {
  TempDir dir("astc_write_bad");
  const std::string path = dir.file("out.astc");
  CompressedImage img = make_astc(6, 6, 12, 12);
  img.format = FileBlockFormat::Bc3Unorm;
  EXPECT_NE(error_of([&] { write_astc_file(path, img); }).find("BC3_UNORM is not stored"),
            std::string::npos);
  img = make_astc(7, 6, 14, 12);
  EXPECT_NE(error_of([&] { write_astc_file(path, img); }).find("not an ASTC block size"),
            std::string::npos);
  img = make_astc(4, 4, 8, 8);
  img.width = 1u << 24;
  EXPECT_NE(error_of([&] { write_astc_file(path, img); }).find("24-bit"), std::string::npos);
  img = make_astc(4, 4, 8, 8);
  img.levels.push_back(img.levels[0]);
  img.levels[1].width = img.levels[1].height = 4;
  img.levels[1].bytes.resize(16);
  EXPECT_NE(error_of([&] { write_astc_file(path, img); }).find("one level"), std::string::npos);
  EXPECT_EQ(dir.entries(), 0u);
}

}  // namespace
