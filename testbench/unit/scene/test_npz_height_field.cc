// NumPy .npz height fields (DEMs): the first 2-D array of a stored or deflated zip, normalised
// to [0, 1]; no-data (the int16 minimum, NaN) reads as the lowest height; a missing file names
// itself and the package; the shipped DEM scene's file when installed.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <zlib.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "blocks/base/input_error.h"
#include "pipeline/scene/npz_height_field.h"
#include "pipeline/scene/scene_memory.h"
#include "pipeline/scene/texture_loader.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

void put(std::string& b, uint32_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) b.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}

std::string npy(const std::string& descr, const std::string& shape, const std::string& data) {
  std::string hdr = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': " + shape + ", }";
  while ((10 + hdr.size() + 1) % 64 != 0) hdr.push_back(' ');
  hdr.push_back('\n');
  std::string b = "\x93NUMPY";
  b.push_back(1);
  b.push_back(0);
  put(b, static_cast<uint32_t>(hdr.size()), 2);
  return b + hdr + data;
}

std::string raw_deflate(const std::string& in) {
  z_stream s{};
  deflateInit2(&s, Z_DEFAULT_COMPRESSION, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY);
  std::string out(in.size() + 1024, '\0');
  s.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
  s.avail_in = static_cast<uInt>(in.size());
  s.next_out = reinterpret_cast<Bytef*>(out.data());
  s.avail_out = static_cast<uInt>(out.size());
  deflate(&s, Z_FINISH);
  out.resize(s.total_out);
  deflateEnd(&s);
  return out;
}

// A zip of (name, bytes) members, deflated or stored.
std::string zip(const std::vector<std::pair<std::string, std::string>>& files, bool deflated) {
  std::string body, dir;
  for (const auto& [name, data] : files) {
    const std::string packed = deflated ? raw_deflate(data) : data;
    const auto offset = static_cast<uint32_t>(body.size());
    const uint32_t method = deflated ? 8 : 0;
    put(body, 0x04034b50U, 4);
    put(body, 20, 2);
    put(body, 0, 2);
    put(body, method, 2);
    put(body, 0, 4);  // time, date
    put(body, 0, 4);  // crc (not checked)
    put(body, static_cast<uint32_t>(packed.size()), 4);
    put(body, static_cast<uint32_t>(data.size()), 4);
    put(body, static_cast<uint32_t>(name.size()), 2);
    put(body, 0, 2);
    body += name + packed;
    put(dir, 0x02014b50U, 4);
    put(dir, 20, 2);
    put(dir, 20, 2);
    put(dir, 0, 2);
    put(dir, method, 2);
    put(dir, 0, 4);
    put(dir, 0, 4);
    put(dir, static_cast<uint32_t>(packed.size()), 4);
    put(dir, static_cast<uint32_t>(data.size()), 4);
    put(dir, static_cast<uint32_t>(name.size()), 2);
    put(dir, 0, 2);
    put(dir, 0, 2);
    put(dir, 0, 2);
    put(dir, 0, 2);
    put(dir, 0, 4);
    put(dir, offset, 4);
    dir += name;
  }
  std::string z = body + dir;
  put(z, 0x06054b50U, 4);
  put(z, 0, 4);
  put(z, static_cast<uint32_t>(files.size()), 2);
  put(z, static_cast<uint32_t>(files.size()), 2);
  put(z, static_cast<uint32_t>(dir.size()), 4);
  put(z, static_cast<uint32_t>(body.size()), 4);
  put(z, 0, 2);
  return z;
}

std::string write_temp(const std::string& name, const std::string& bytes) {
  std::string p = (std::filesystem::temp_directory_path() / name).string();
  std::ofstream(p, std::ios::binary) << bytes;
  return p;
}

TEST(NpzHeightField, Int16WithNoDataDeflated) {
  std::string data;
  for (const int v : {100, 200, -32768, 300, 150, 100}) put(data, static_cast<uint16_t>(v), 2);
  const std::string p =
      write_temp("texsim_dem_i2.npz",
                 zip({{"x.npy", npy("<f8", "()", std::string(8, '\0'))},  // a scalar: skipped
                      {"elevation.npy", npy("<i2", "(2, 3)", data)}},
                     true));
  const NpzHeightField f = read_npz_height_field(p);
  EXPECT_EQ(f.array, "elevation.npy");
  ASSERT_EQ(f.width, 3);
  ASSERT_EQ(f.height, 2);
  EXPECT_EQ(f.no_data, 1u);
  EXPECT_DOUBLE_EQ(f.min, 100);
  EXPECT_DOUBLE_EQ(f.max, 300);
  const std::vector<double> want = {0, 0.5, 0, 1, 0.25, 0};  // no-data: the lowest height
  for (size_t i = 0; i < want.size(); ++i) EXPECT_DOUBLE_EQ(f.h[i], want[i]) << i;
  const Texture t = load_texture(p, "");
  EXPECT_EQ(t.width(0), 3);
  EXPECT_FLOAT_EQ(t.texel(0, 0, 1).r, 1.0F);
  EXPECT_FLOAT_EQ(t.texel(0, 2, 0).r, 0.0F);
}

TEST(NpzHeightField, Float32NaNStoredAndAllNoData) {
  std::string data;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const float v : {1.0F, nan, 3.0F, 2.0F}) {
    uint32_t bits = 0;
    std::memcpy(&bits, &v, 4);
    put(data, bits, 4);
  }
  const NpzHeightField f = read_npz_height_field(
      write_temp("texsim_dem_f4.npz", zip({{"topo.npy", npy("<f4", "(2, 2)", data)}}, false)));
  EXPECT_EQ(f.no_data, 1u);
  EXPECT_DOUBLE_EQ(f.h[0], 0);
  EXPECT_DOUBLE_EQ(f.h[1], 0);
  EXPECT_DOUBLE_EQ(f.h[2], 1);
  EXPECT_DOUBLE_EQ(f.h[3], 0.5);
  std::string voids;
  for (int i = 0; i < 4; ++i) put(voids, 0x8000, 2);
  const NpzHeightField v = read_npz_height_field(
      write_temp("texsim_dem_void.npz", zip({{"e.npy", npy("<i2", "(2, 2)", voids)}}, false)));
  EXPECT_EQ(v.no_data, 4u);
  for (const double h : v.h) EXPECT_EQ(h, 0.0);
}

TEST(NpzHeightField, ErrorsNameTheFile) {
  const std::string missing = "/nonexistent/texsim/jacksboro_fault_dem.npz";
  try {
    (void)load_texture(missing, "");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(missing), std::string::npos) << m;
    EXPECT_NE(m.find("python-matplotlib-data"), std::string::npos) << m;
  }
  const std::string one_d = write_temp(
      "texsim_dem_1d.npz", zip({{"a.npy", npy("<f8", "(1,)", std::string(8, 0))}}, false));
  EXPECT_THROW((void)read_npz_height_field(one_d), InputError);
  EXPECT_THROW((void)read_npz_height_field(write_temp("texsim_dem_bad.npz", "not a zip")),
               InputError);
}

// A .npy of any header text (version major.0), padded as numpy pads it.
std::string npy_raw(const std::string& dict, const std::string& data, int major = 1) {
  std::string hdr = dict;
  const size_t prefix = major == 1 ? 10 : 12;
  while ((prefix + hdr.size() + 1) % 64 != 0) hdr.push_back(' ');
  hdr.push_back('\n');
  std::string b = "\x93NUMPY";
  b.push_back(static_cast<char>(major));
  b.push_back(0);
  put(b, static_cast<uint32_t>(hdr.size()), major == 1 ? 2 : 4);
  return b + hdr + data;
}

// The InputError message of parsing `b` as an .npy ("" if none).
std::string npy_error(const std::string& b) {
  try {
    (void)parse_npy_height_field(b, "a.npy");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string doubles(std::initializer_list<double> v) {
  std::string d;
  for (const double x : v) {
    uint64_t bits = 0;
    std::memcpy(&bits, &x, 8);
    put(d, static_cast<uint32_t>(bits), 4);
    put(d, static_cast<uint32_t>(bits >> 32), 4);
  }
  return d;
}

TEST(NpzHeightField, HeaderIsParsedAsADictionary) {
  const std::string four = std::string(8, '\0');
  // A key inside another key's string was taken as a key.
  EXPECT_EQ(npy_error(npy_raw("{'descr': '<i2', 'fortran_order': False, 'x': \"'shape': (1, 1)\"}",
                              four)),
            "a.npy: .npy header: unknown key 'x'");
  EXPECT_EQ(npy_error(npy_raw("{'descr': \"'shape': (1, 1),\", 'fortran_order': False}", four)),
            "a.npy: .npy header: no 'shape' key");
  EXPECT_EQ(
      npy_error(npy_raw(
          "{'descr': '<i2', 'fortran_order': False, 'shape': (1, 1), 'shape': (1, 1)}", four)),
      "a.npy: .npy header: key 'shape' appears twice");
  EXPECT_EQ(npy_error(npy_raw("{'descr': '<i2', 'fortran_order': 0, 'shape': (1, 1)}", four)),
            "a.npy: .npy header: fortran_order must be True or False");
  // Beyond 32 bits: accepted before (and the product wrapped).
  EXPECT_EQ(npy_error(npy_raw("{'descr': '<i2', 'fortran_order': False, 'shape': (4294967296, 1)}",
                              four)),
            "a.npy: .npy header: a shape dimension beyond 32 bits");
  EXPECT_EQ(
      npy_error(npy_raw("{'descr': '<i2', 'fortran_order': False, 'shape': (8193, 1)}", four)),
      "a.npy: shape (8193, 1): each side must be 1..8192");
  EXPECT_EQ(npy_error(npy_raw("{'descr': '<i2', 'fortran_order': False, 'shape': (2, 2)}",
                              std::string(7, '\0'))),
            "a.npy: truncated data");
  // Versions 2.0 and 3.0 (a 4-byte header length) are read; 9.0 is refused.
  const std::string dict = "{'descr': '<i2', 'fortran_order': False, 'shape': (2, 2), }";
  EXPECT_EQ(parse_npy_height_field(npy_raw(dict, four, 2), "a.npy").width, 2);
  EXPECT_EQ(parse_npy_height_field(npy_raw(dict, four, 3), "a.npy").height, 2);
  std::string v9 = npy_raw(dict, four);
  v9[6] = 9;
  EXPECT_EQ(npy_error(v9), "a.npy: .npy version 9.0 (1.0, 2.0 or 3.0 are read)");
  // Not 2-D: skipped (width 0), as in an archive.
  EXPECT_EQ(parse_npy_height_field(npy("<f8", "(1,)", std::string(8, '\0')), "a.npy").width, 0);
}

TEST(NpzHeightField, ExtremeHeightsNormaliseWithoutOverflow) {
  // ±1e308 became NaN (the span overflowed) and the run reported PSNR 999 dB.
  const NpzHeightField f =
      parse_npy_height_field(npy("<f8", "(2, 2)", doubles({-1e308, 1e308, 0, 1.7e308})), "a.npy");
  EXPECT_EQ(f.no_data, 0u);
  for (const double h : f.h) EXPECT_TRUE(h >= 0 && h <= 1) << h;
  EXPECT_DOUBLE_EQ(f.h[0], 0);
  EXPECT_DOUBLE_EQ(f.h[3], 1);
  EXPECT_NEAR(f.h[2], 0.5 / 1.35, 1e-12);  // (0 + 0.5e308) / (0.85e308 + 0.5e308)
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(npy_error(npy("<f8", "(1, 2)", doubles({0, -inf}))),
            "a.npy: height at row 0, column 1 is infinite (NaN marks no-data)");
}

TEST(NpzHeightField, SizesAreCheckedBeforeReadingOrInflating) {
  TempDir d("npz");
  // 8192 x 8192 float64 zeros declare 512 MiB: refused from the zip directory, before inflating.
  const std::string big = npy("<f8", "(8192, 8192)", std::string(4096, '\0'));
  std::string z = zip({{"e.npy", big}}, true);
  const uint32_t declared = 8192u * 8192u * 8u + static_cast<uint32_t>(big.size() - 4096);
  const size_t dir = z.find("PK\x01\x02");
  ASSERT_NE(dir, std::string::npos);
  for (int i = 0; i < 4; ++i)
    z[dir + 24 + static_cast<size_t>(i)] = static_cast<char>(declared >> (8 * i));
  std::string e;
  try {
    (void)read_npz_height_field(write_temp("texsim_dem_bomb.npz", z));
  } catch (const InputError& x) {
    e = x.what();
  }
  EXPECT_NE(e.find("declares 536871040 bytes uncompressed, more than the limit"), std::string::npos)
      << e;
  // float32 fits the archive limit: the memory estimate refuses it from the header alone.
  const std::string f4 = npy("<f4", "(8192, 8000)", std::string(70000, '\0'));
  std::string z4 = zip({{"e.npy", f4}}, true);
  const uint32_t declared4 = 8192u * 8000u * 4u + static_cast<uint32_t>(f4.size() - 70000);
  const size_t dir4 = z4.find("PK\x01\x02");
  for (int i = 0; i < 4; ++i)
    z4[dir4 + 24 + static_cast<size_t>(i)] = static_cast<char>(declared4 >> (8 * i));
  set_scene_memory_limit(uint64_t{1} << 30);
  e.clear();
  try {
    (void)read_npz_height_field(write_temp("texsim_dem_bomb4.npz", z4));
  } catch (const InputError& x) {
    e = x.what();
  }
  set_scene_memory_limit(UINT64_MAX);
  EXPECT_NE(e.find("a 8192 x 8000 height field would take an estimated"), std::string::npos) << e;
  // A file over 256 MiB is refused from its size (sparse here), not read whole first.
  const std::string huge = d.file("huge.npz");
  std::ofstream(huge).close();
  std::filesystem::resize_file(huge, uint64_t{3} << 30);
  EXPECT_THROW((void)read_npz_height_field(huge), InputError);
}

TEST(NpzHeightField, NotARegularFileIsAClearError) {
  TempDir d("npz");
  std::filesystem::create_directory(d.file("dir.npz"));
  ASSERT_EQ(::mkfifo(d.file("fifo.npz").c_str(), 0600), 0);  // blocked forever before
  for (const std::string& p : {d.file("dir.npz"), d.file("fifo.npz"), std::string("/dev/zero")}) {
    std::string e;
    try {
      (void)read_npz_height_field(p);
    } catch (const InputError& x) {
      e = x.what();
    }
    EXPECT_NE(e.find(p + ": cannot read"), std::string::npos) << e;
  }
}

TEST(NpzHeightField, ShippedSampleDem) {
  const std::string p = "/usr/share/matplotlib/mpl-data/sample_data/jacksboro_fault_dem.npz";
  if (!std::filesystem::exists(p)) GTEST_SKIP() << p << " not installed";
  const NpzHeightField f = read_npz_height_field(p);
  EXPECT_EQ(f.width, 403);
  EXPECT_EQ(f.height, 344);
  EXPECT_EQ(f.no_data, 0u);
  EXPECT_LT(f.min, f.max);
}

}  // namespace
}  // namespace texsim
