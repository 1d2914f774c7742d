#include "pipeline/image_io/astc_file.h"

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"
#include "pipeline/image_io/dds_file.h"

namespace texsim {

namespace {

constexpr size_t kHeaderBytes = 16;
constexpr uint32_t kMagic = 0x5CA1AB13;
constexpr int kBlockBytes = 16;

uint32_t get_le(std::span<const uint8_t> b, size_t at, int n) {
  uint32_t v = 0;
  for (int i = 0; i < n; ++i) v |= static_cast<uint32_t>(b[at + static_cast<size_t>(i)]) << (8 * i);
  return v;
}
void put_le(std::string& s, uint32_t v, int n) {
  for (int i = 0; i < n; ++i) s += static_cast<char>(v >> (8 * i));
}

}  // namespace

bool is_astc_2d_footprint(int bw, int bh) {
  static constexpr int kFootprints[14][2] = {{4, 4},  {5, 4},   {5, 5},   {6, 5},  {6, 6},
                                             {8, 5},  {8, 6},   {8, 8},   {10, 5}, {10, 6},
                                             {10, 8}, {10, 10}, {12, 10}, {12, 12}};
  for (const auto& f : kFootprints)
    if (f[0] == bw && f[1] == bh) return true;
  return false;
}

CompressedImage parse_astc(std::span<const uint8_t> b, const std::string& where) {
  if (b.size() < kHeaderBytes)
    throw InputError(where, "file of " + std::to_string(b.size()) +
                                " bytes is shorter than the .astc header (16 bytes)");
  if (get_le(b, 0, 4) != kMagic) throw InputError(where, "not an .astc file (no magic 0x5CA1AB13)");
  const int bw = b[4], bh = b[5], bd = b[6];
  const uint32_t w = get_le(b, 7, 3), h = get_le(b, 10, 3), d = get_le(b, 13, 3);
  const std::string footprint =
      std::to_string(bw) + "x" + std::to_string(bh) + "x" + std::to_string(bd);
  if (bd > 1) throw InputError(where, "3-D block footprint " + footprint + " is not supported");
  if (bd != 1 || !is_astc_2d_footprint(bw, bh))
    throw InputError(where, "block footprint " + footprint + " is not an ASTC 2-D block size");
  if (d > 1)
    throw InputError(where, "z size " + std::to_string(d) + ": 3-D images are not supported");
  if (w == 0 || h == 0 || d == 0)
    throw InputError(where, "image size " + std::to_string(w) + " x " + std::to_string(h) + " x " +
                                std::to_string(d) + " has no texels");
  const uint64_t want = level_block_count(w, h, bw, bh) * kBlockBytes;
  const uint64_t have = b.size() - kHeaderBytes;
  if (have < want)
    throw InputError(where, "truncated: " + std::to_string(w) + " x " + std::to_string(h) +
                                " texels in " + std::to_string(bw) + "x" + std::to_string(bh) +
                                " blocks take " + std::to_string(want) + " bytes, the file holds " +
                                std::to_string(have));
  if (have > want)
    throw InputError(where, std::to_string(have - want) + " trailing bytes after the " +
                                std::to_string(want / kBlockBytes) +
                                " blocks the header describes");
  CompressedImage img;
  img.format = FileBlockFormat::Astc;
  img.width = w;
  img.height = h;
  img.block_w = bw;
  img.block_h = bh;
  img.block_bytes = kBlockBytes;
  CompressedLevel l;
  l.width = w;
  l.height = h;
  l.bytes.assign(b.begin() + kHeaderBytes, b.end());
  img.levels.push_back(std::move(l));
  return img;
}

CompressedImage read_astc_file(const std::string& path) {
  const std::string s = read_input_file(path, ".astc file", kMaxCompressedInput);
  return parse_astc({reinterpret_cast<const uint8_t*>(s.data()), s.size()}, path);
}

std::string astc_bytes(const CompressedImage& img, const std::string& where) {
  if (img.format != FileBlockFormat::Astc)
    throw InputError(where, std::string("cannot write: ") + format_name(img.format) +
                                " is not stored in .astc files");
  if (!is_astc_2d_footprint(img.block_w, img.block_h))
    throw InputError(where, "cannot write: " + img.format_label() + " is not an ASTC block size");
  if (img.levels.size() != 1) throw InputError(where, "cannot write: .astc files hold one level");
  if (img.width >= (1u << 24) || img.height >= (1u << 24))
    throw InputError(where, "cannot write: sizes are 24-bit in .astc files");
  check_compressed_image(img, where);
  std::string s;
  put_le(s, kMagic, 4);
  put_le(s, static_cast<uint32_t>(img.block_w), 1);
  put_le(s, static_cast<uint32_t>(img.block_h), 1);
  put_le(s, 1, 1);
  put_le(s, img.width, 3);
  put_le(s, img.height, 3);
  put_le(s, 1, 3);
  const auto& bytes = img.levels[0].bytes;
  s.append(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  return s;
}

void write_astc_file(const std::string& path, const CompressedImage& img) {
  write_file_atomic(path, astc_bytes(img, path));
}

}  // namespace texsim
