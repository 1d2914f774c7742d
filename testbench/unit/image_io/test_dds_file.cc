// DDS files (pipeline/image_io/dds_file.h): every format round-trips through the writer and
// the reader with its mip chain, under the legacy and the DX10 header; the legacy FourCCs read
// as their formats; and every rule of the strict reader (sizes against the file, mip counts,
// unknown formats, headers that lie, cube maps, arrays, volumes) is an InputError naming the
// file and the reason.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "pipeline/image_io/dds_file.h"
#include "testbench/lib/compressed_image_checks.h"
#include "testbench/lib/error_of.h"
#include "testbench/lib/temp_dir.h"

namespace {

using namespace texsim;  // NOLINT(google-build-using-namespace)
using texsim::test::expect_same;
using texsim::test::set_u32;

constexpr FileBlockFormat kFormats[] = {
    FileBlockFormat::Bc1Unorm, FileBlockFormat::Bc1Srgb,  FileBlockFormat::Bc2Unorm,
    FileBlockFormat::Bc2Srgb,  FileBlockFormat::Bc3Unorm, FileBlockFormat::Bc3Srgb,
    FileBlockFormat::Bc4Unorm, FileBlockFormat::Bc4Snorm, FileBlockFormat::Bc5Unorm,
    FileBlockFormat::Bc5Snorm, FileBlockFormat::Bc7Unorm, FileBlockFormat::Bc7Srgb};

// An image of `format` with `levels` mip levels of pseudo-random blocks.
CompressedImage make_image(FileBlockFormat format, uint32_t w, uint32_t h, uint32_t levels) {
  CompressedImage img;
  img.format = format;
  img.width = w;
  img.height = h;
  img.block_bytes = format_block_bytes(format);
  uint32_t seed = 12345u + w * 31u + h;
  for (uint32_t i = 0; i < levels; ++i) {
    CompressedLevel l;
    l.width = mip_side(w, i);
    l.height = mip_side(h, i);
    l.bytes.resize(level_block_count(l.width, l.height, 4, 4) *
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

TEST(DdsFile, EveryFormatRoundTripsWithItsMipChain) {
  TempDir dir("dds_roundtrip");
  for (const FileBlockFormat f : kFormats) {
    for (const bool dx10 : {false, true}) {
      // 13 x 7: partial edge blocks; levels 13x7, 6x3, 3x1, 1x1.
      const CompressedImage img = make_image(f, 13, 7, 4);
      const std::string path =
          dir.file(std::string(format_name(f)) + (dx10 ? "_dx10" : "") + ".dds");
      write_dds_file(path, img, dx10);
      SCOPED_TRACE(path);
      expect_same(read_dds_file(path), img);
    }
  }
  EXPECT_EQ(dir.entries(), 24u);  // no temporary file left behind
}

TEST(DdsFile, OneLevelAndLargeSizesRoundTrip) {
  TempDir dir("dds_one");
  const CompressedImage img = make_image(FileBlockFormat::Bc3Unorm, 1, 1, 1);
  write_dds_file(dir.file("a.dds"), img);
  expect_same(read_dds_file(dir.file("a.dds")), img);
  const CompressedImage big = make_image(FileBlockFormat::Bc1Unorm, 1024, 4, 11);
  write_dds_file(dir.file("b.dds"), big);
  expect_same(read_dds_file(dir.file("b.dds")), big);
}

TEST(DdsFile, LegacyHeaderWhereItCanAndDx10ElseWhere) {
  const std::string legacy = dds_bytes(make_image(FileBlockFormat::Bc1Unorm, 8, 8, 1), false, "x");
  EXPECT_EQ(legacy.substr(84, 4), "DXT1");
  EXPECT_EQ(legacy.size(), 128u + 32u);
  const std::string srgb = dds_bytes(make_image(FileBlockFormat::Bc1Srgb, 8, 8, 1), false, "x");
  EXPECT_EQ(srgb.substr(84, 4), "DX10");
  EXPECT_EQ(srgb.size(), 148u + 32u);
  EXPECT_EQ(static_cast<uint8_t>(srgb[128]), 72);  // DXGI_FORMAT_BC1_UNORM_SRGB
}

TEST(DdsFile, LegacyFourCCsReadAsTheirFormats) {
  const struct {
    const char* code;
    FileBlockFormat format;
  } cases[] = {{"DXT1", FileBlockFormat::Bc1Unorm}, {"DXT3", FileBlockFormat::Bc2Unorm},
               {"DXT5", FileBlockFormat::Bc3Unorm}, {"ATI1", FileBlockFormat::Bc4Unorm},
               {"BC4U", FileBlockFormat::Bc4Unorm}, {"BC4S", FileBlockFormat::Bc4Snorm},
               {"ATI2", FileBlockFormat::Bc5Unorm}, {"BC5U", FileBlockFormat::Bc5Unorm},
               {"BC5S", FileBlockFormat::Bc5Snorm}};
  for (const auto& c : cases) {
    std::string s = dds_bytes(make_image(c.format, 8, 4, 1), false, "x");
    s.replace(84, 4, c.code);
    const CompressedImage img =
        parse_dds({reinterpret_cast<const uint8_t*>(s.data()), s.size()}, "mem.dds");
    EXPECT_EQ(img.format, c.format) << c.code;
    EXPECT_EQ(img.levels.at(0).bytes.size(), static_cast<size_t>(format_block_bytes(c.format)) * 2);
  }
}

// The InputError message of reading `bytes` from a file, "" if none.
std::string read_error(const TempDir& dir, const std::string& bytes) {
  const std::string path = dir.file("bad.dds");
  write_bytes(path, bytes);
  return error_of([&] { read_dds_file(path); });
}

std::string good(FileBlockFormat f = FileBlockFormat::Bc1Unorm, bool dx10 = false,
                 uint32_t levels = 3) {
  return dds_bytes(make_image(f, 16, 8, levels), dx10, "x");
}

struct BadCase {
  const char* name;
  std::string bytes;
  const char* reason;
};

std::vector<BadCase> bad_cases() {
  std::vector<BadCase> v;
  auto with = [](std::string s, size_t at, uint32_t value) {
    set_u32(s, at, value);
    return s;
  };
  const std::string g = good(), gx = good(FileBlockFormat::Bc7Unorm, true);
  v.push_back({"truncated", g.substr(0, g.size() - 1), "truncated"});
  v.push_back({"trailing", g + "x", "1 trailing bytes"});
  v.push_back({"short", g.substr(0, 100), "shorter than a DDS header"});
  v.push_back({"empty", "", "shorter than a DDS header"});
  v.push_back({"magic", with(g, 0, 0x20534444u + 1), "not a DDS file"});
  v.push_back({"header size", with(g, 4, 100), "header size is 100"});
  v.push_back({"pixel format size", with(g, 76, 24), "pixel format size is 24"});
  v.push_back({"no fourcc", with(g, 80, 0x40), "uncompressed pixel format"});
  v.push_back({"unknown fourcc", with(g, 84, 0x32545844u), "unknown FourCC 'DXT2'"});
  v.push_back({"binary fourcc", with(g, 84, 7), "unknown FourCC 0x00000007"});
  v.push_back({"mip count", with(g, 28, 6), "mip count 6 is more than a 16 x 8 image has (5)"});
  v.push_back({"mips beyond file", with(g, 28, 4), "truncated"});
  v.push_back({"zero width", with(g, 16, 0), "has no texels"});
  v.push_back({"huge size", with(g, 16, 0xffffffffu), "header gives level 0 64 bytes"});
  v.push_back({"huge no linear size", with(with(g, 8, 0x1007), 16, 0xffffffffu), "truncated"});
  v.push_back({"linear size", with(g, 20, 12345), "header gives level 0 12345 bytes"});
  v.push_back({"cube", with(g, 112, 0x200 | 0xfc00), "cube maps are not supported"});
  v.push_back({"volume", with(g, 112, 0x200000), "volume textures are not supported"});
  v.push_back({"depth", with(with(g, 8, 0x800000 | 0x1007), 24, 4), "volume textures"});
  v.push_back({"dx10 cut", gx.substr(0, 140), "file ends inside the DX10 header"});
  v.push_back({"dxgi unknown", with(gx, 128, 28), "DXGI format 28 is not a supported"});
  v.push_back({"dxgi typeless", with(gx, 128, 70), "TYPELESS"});
  v.push_back({"dxgi bc6h", with(gx, 128, 95), "BC6H"});
  v.push_back({"dx10 cube", with(gx, 136, 4), "cube maps are not supported"});
  v.push_back({"dx10 1d", with(gx, 132, 2), "resource dimension 2 is not a 2-D texture"});
  v.push_back({"dx10 volume", with(gx, 132, 4), "volume textures are not supported"});
  v.push_back({"dx10 array", with(gx, 140, 6), "array size 6: texture arrays"});
  v.push_back({"dx10 array 0", with(gx, 140, 0), "array size 0"});
  v.push_back({"dx10 trailing", gx + "abcd", "4 trailing bytes"});
  return v;
}

TEST(DdsFile, EveryBadInputIsAnErrorNamingTheFileAndTheReason) {
  TempDir dir("dds_bad");
  const std::string path = dir.file("bad.dds");
  for (const BadCase& c : bad_cases()) {
    const std::string e = read_error(dir, c.bytes);
    EXPECT_NE(e.find(path), std::string::npos) << c.name << ": " << e;
    EXPECT_NE(e.find(c.reason), std::string::npos) << c.name << ": " << e;
  }
}

TEST(DdsFile, GoodBasesOfTheBadCasesRead) {  // so each bad case fails for its own reason
  TempDir dir("dds_good");
  EXPECT_EQ(read_error(dir, good()), "");
  EXPECT_EQ(read_error(dir, good(FileBlockFormat::Bc7Unorm, true)), "");
}

TEST(DdsFile, MissingFileIsAnInputError) {
  TempDir dir("dds_missing");
  const std::string e = error_of([&] { read_dds_file(dir.file("none.dds")); });
  EXPECT_NE(e.find(dir.file("none.dds")), std::string::npos) << e;
}

TEST(DdsFile, WriterRefusesInconsistentImages) {
  TempDir dir("dds_write_bad");
  const std::string path = dir.file("out.dds");
  CompressedImage img = make_image(FileBlockFormat::Bc1Unorm, 16, 16, 2);
  img.levels[1].bytes.pop_back();
  EXPECT_NE(error_of([&] { write_dds_file(path, img); }).find("level 1 holds 31 bytes"),
            std::string::npos);
  img = make_image(FileBlockFormat::Bc1Unorm, 16, 16, 2);
  img.levels[1].width = 7;
  EXPECT_NE(error_of([&] { write_dds_file(path, img); }).find("not half the size"),
            std::string::npos);
  img = make_image(FileBlockFormat::Bc1Unorm, 2, 2, 2);
  img.levels.push_back(img.levels[1]);
  EXPECT_NE(error_of([&] { write_dds_file(path, img); }).find("3 levels, more than"),
            std::string::npos);
  img = make_image(FileBlockFormat::Bc1Unorm, 4, 4, 1);
  img.format = FileBlockFormat::Astc;
  img.block_bytes = 16;
  img.levels[0].bytes.resize(16);
  EXPECT_NE(error_of([&] { write_dds_file(path, img); }).find("ASTC"), std::string::npos);
  EXPECT_EQ(dir.entries(), 0u);
}

}  // namespace
