#include "pipeline/image_io/ktx_file.h"

#include <array>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"
#include "pipeline/image_io/dds_file.h"

namespace texsim {

namespace {

// The KTX 1.1 identifier: «KTX 11»\r\n\x1A\n.
constexpr std::array<uint8_t, 12> kIdentifier = {0xAB, 0x4B, 0x54, 0x58, 0x20, 0x31,
                                                 0x31, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
constexpr size_t kHeaderBytes = 64;  // the identifier and 13 32-bit fields
constexpr uint32_t kEndianness = 0x04030201, kEndiannessSwapped = 0x01020304;
// OpenGL base internal formats (GL/glcorearb.h).
constexpr uint32_t kGlRed = 0x1903, kGlRg = 0x8227, kGlRgb = 0x1907, kGlRgba = 0x1908;

struct KtxFormat {
  uint32_t gl;  // glInternalFormat
  FileBlockFormat format;
  int block_w, block_h;
  uint32_t base;  // glBaseInternalFormat written
};

// The compressed internal formats read (EXT_texture_compression_s3tc, EXT_texture_sRGB,
// ARB_texture_compression_rgtc, ARB_texture_compression_bptc, OpenGL 4.3's ETC2 / EAC,
// KHR_texture_compression_astc_ldr).
std::vector<KtxFormat> make_formats() {
  using F = FileBlockFormat;
  std::vector<KtxFormat> v = {
      {0x83F0, F::Bc1RgbUnorm, 4, 4, kGlRgb}, {0x83F1, F::Bc1Unorm, 4, 4, kGlRgba},
      {0x83F2, F::Bc2Unorm, 4, 4, kGlRgba},   {0x83F3, F::Bc3Unorm, 4, 4, kGlRgba},
      {0x8C4C, F::Bc1RgbSrgb, 4, 4, kGlRgb},  {0x8C4D, F::Bc1Srgb, 4, 4, kGlRgba},
      {0x8C4E, F::Bc2Srgb, 4, 4, kGlRgba},    {0x8C4F, F::Bc3Srgb, 4, 4, kGlRgba},
      {0x8DBB, F::Bc4Unorm, 4, 4, kGlRed},    {0x8DBC, F::Bc4Snorm, 4, 4, kGlRed},
      {0x8DBD, F::Bc5Unorm, 4, 4, kGlRg},     {0x8DBE, F::Bc5Snorm, 4, 4, kGlRg},
      {0x8E8C, F::Bc7Unorm, 4, 4, kGlRgba},   {0x8E8D, F::Bc7Srgb, 4, 4, kGlRgba},
      {0x9270, F::EacR11Unorm, 4, 4, kGlRed}, {0x9271, F::EacR11Snorm, 4, 4, kGlRed},
      {0x9272, F::EacRg11Unorm, 4, 4, kGlRg}, {0x9273, F::EacRg11Snorm, 4, 4, kGlRg},
      {0x9274, F::Etc2Rgb8, 4, 4, kGlRgb},    {0x9275, F::Etc2Rgb8Srgb, 4, 4, kGlRgb},
      {0x9276, F::Etc2Rgb8A1, 4, 4, kGlRgba}, {0x9277, F::Etc2Rgb8A1Srgb, 4, 4, kGlRgba},
      {0x9278, F::Etc2Rgba8, 4, 4, kGlRgba},  {0x9279, F::Etc2Rgba8Srgb, 4, 4, kGlRgba},
  };
  // GL_COMPRESSED_RGBA_ASTC_4x4_KHR (0x93B0) ... 12x12 (0x93BD); the sRGB ones from 0x93D0.
  static constexpr int kAstc[14][2] = {{4, 4},  {5, 4},   {5, 5},   {6, 5},  {6, 6},
                                       {8, 5},  {8, 6},   {8, 8},   {10, 5}, {10, 6},
                                       {10, 8}, {10, 10}, {12, 10}, {12, 12}};
  for (uint32_t i = 0; i < 14; ++i) {
    v.push_back({0x93B0 + i, F::Astc, kAstc[i][0], kAstc[i][1], kGlRgba});
    v.push_back({0x93D0 + i, F::AstcSrgb, kAstc[i][0], kAstc[i][1], kGlRgba});
  }
  return v;
}
const std::vector<KtxFormat>& formats() {
  static const std::vector<KtxFormat> v = make_formats();
  return v;
}

std::string hex(uint32_t v) {
  char s[16];
  std::snprintf(s, sizeof s, "0x%04X", v);
  return s;
}
uint32_t get_u32(std::span<const uint8_t> b, size_t at) {
  return static_cast<uint32_t>(b[at]) | static_cast<uint32_t>(b[at + 1]) << 8 |
         static_cast<uint32_t>(b[at + 2]) << 16 | static_cast<uint32_t>(b[at + 3]) << 24;
}
void put_u32(std::string& s, uint32_t v) {
  for (int i = 0; i < 4; ++i) s += static_cast<char>(v >> (8 * i));
}
// Bytes that take `n` up to a multiple of 4.
uint64_t pad4(uint64_t n) { return (4 - n % 4) % 4; }

// The header's fields after the endianness, in file order.
struct Header {
  uint32_t gl_type, gl_type_size, gl_format, gl_internal, gl_base, width, height, depth, array,
      faces, mips, kv_bytes;
};

Header read_header(std::span<const uint8_t> b, const std::string& where) {
  if (b.size() < kHeaderBytes)
    throw InputError(where, "file of " + std::to_string(b.size()) +
                                " bytes is shorter than a KTX header (64 bytes)");
  for (size_t i = 0; i < kIdentifier.size(); ++i) {
    if (b[i] != kIdentifier[i]) throw InputError(where, "not a KTX 1 file (no KTX 11 identifier)");
  }
  const uint32_t endian = get_u32(b, 12);
  if (endian == kEndiannessSwapped)
    throw InputError(where,
                     "big-endian KTX file (endianness 0x01020304 read little-endian): only "
                     "little-endian files are read");
  if (endian != kEndianness)
    throw InputError(where, "endianness field is " + hex(endian) + ", not 0x04030201");
  Header h{};
  std::array<uint32_t*, 12> f = {&h.gl_type, &h.gl_type_size, &h.gl_format, &h.gl_internal,
                                 &h.gl_base, &h.width,        &h.height,    &h.depth,
                                 &h.array,   &h.faces,        &h.mips,      &h.kv_bytes};
  for (size_t i = 0; i < f.size(); ++i) *f[i] = get_u32(b, 16 + 4 * i);
  return h;
}

// The header's format and shape checks; the format read.
KtxFormat check_header(const Header& h, const std::string& where) {
  if (h.gl_type != 0 || h.gl_format != 0)
    throw InputError(where, "glType " + hex(h.gl_type) + ", glFormat " + hex(h.gl_format) +
                                ": uncompressed textures are not read (block-compressed ones "
                                "have glType = glFormat = 0)");
  if (h.gl_type_size != 1)
    throw InputError(
        where, "glTypeSize is " + std::to_string(h.gl_type_size) + ", not 1 (compressed textures)");
  const KtxFormat* fmt = nullptr;
  for (const KtxFormat& k : formats()) {
    if (k.gl == h.gl_internal) fmt = &k;
  }
  if (!fmt)
    throw InputError(where, "glInternalFormat " + hex(h.gl_internal) +
                                " is not a supported block-compressed format (BC1-BC5, BC7, "
                                "ETC2 / EAC, 2-D LDR ASTC)");
  if (h.faces != 1)
    throw InputError(where, "numberOfFaces " + std::to_string(h.faces) +
                                ": cube maps are not supported (one face only)");
  if (h.array != 0)
    throw InputError(where, "numberOfArrayElements " + std::to_string(h.array) +
                                ": texture arrays are not supported (0, one 2-D texture)");
  if (h.depth != 0)
    throw InputError(where, "pixelDepth " + std::to_string(h.depth) +
                                ": 3-D textures are not supported (0, a 2-D texture)");
  if (h.width == 0 || h.height == 0)
    throw InputError(where, "image size " + std::to_string(h.width) + " x " +
                                std::to_string(h.height) +
                                " has no texels (1-D textures are not supported)");
  const uint32_t levels = h.mips == 0 ? 1 : h.mips;  // 0: one level, the rest to be generated
  if (levels > max_mip_levels(h.width, h.height))
    throw InputError(where, "numberOfMipmapLevels " + std::to_string(levels) + " is more than a " +
                                std::to_string(h.width) + " x " + std::to_string(h.height) +
                                " image has (" + std::to_string(max_mip_levels(h.width, h.height)) +
                                ")");
  return *fmt;
}

// Walks the key/value pairs (each a 32-bit size, its bytes and padding to 4) within their
// `size` bytes at `at`.
void check_key_values(std::span<const uint8_t> b, uint64_t at, uint64_t size,
                      const std::string& where) {
  if (size > b.size() - at)
    throw InputError(where, "key/value data of " + std::to_string(size) +
                                " bytes runs past the end of the file");
  const uint64_t end = at + size;
  while (at < end) {
    if (end - at < 4)
      throw InputError(where,
                       "key/value data ends inside a pair's size at byte " + std::to_string(at));
    const uint64_t n = get_u32(b, static_cast<size_t>(at));
    at += 4;
    if (n > end - at || pad4(n) > end - at - n)
      throw InputError(where, "key/value pair of " + std::to_string(n) + " bytes at byte " +
                                  std::to_string(at - 4) + " runs past the key/value data");
    at += n + pad4(n);
  }
}

}  // namespace

CompressedImage parse_ktx(std::span<const uint8_t> b, const std::string& where) {
  const Header h = read_header(b, where);
  const KtxFormat fmt = check_header(h, where);
  check_key_values(b, kHeaderBytes, h.kv_bytes, where);
  CompressedImage img;
  img.format = fmt.format;
  img.width = h.width;
  img.height = h.height;
  img.block_w = fmt.block_w;
  img.block_h = fmt.block_h;
  img.block_bytes = format_block_bytes(fmt.format);
  uint64_t at = kHeaderBytes + uint64_t{h.kv_bytes};
  const uint32_t levels = h.mips == 0 ? 1 : h.mips;
  for (uint32_t i = 0; i < levels; ++i) {
    const std::string level = "level " + std::to_string(i);
    if (b.size() - at < 4)
      throw InputError(where, "truncated: " + level + "'s imageSize at byte " + std::to_string(at) +
                                  " is past the end of the file");
    const uint64_t size = get_u32(b, static_cast<size_t>(at));
    at += 4;
    CompressedLevel l;
    l.width = mip_side(h.width, i);
    l.height = mip_side(h.height, i);
    const uint64_t want = level_block_count(l.width, l.height, fmt.block_w, fmt.block_h) *
                          static_cast<uint64_t>(img.block_bytes);
    if (size != want)
      throw InputError(where, level + " (" + std::to_string(l.width) + " x " +
                                  std::to_string(l.height) + "): imageSize " +
                                  std::to_string(size) + ", its blocks take " +
                                  std::to_string(want));
    if (size + pad4(size) > b.size() - at)
      throw InputError(where, "truncated: " + level + " takes " + std::to_string(size) +
                                  " bytes, the file holds " + std::to_string(b.size() - at) +
                                  " after its imageSize");
    l.bytes.assign(b.begin() + static_cast<std::ptrdiff_t>(at),
                   b.begin() + static_cast<std::ptrdiff_t>(at + size));
    at += size + pad4(size);  // mipPadding (cubePadding is none: one face)
    img.levels.push_back(std::move(l));
  }
  if (at != b.size())
    throw InputError(where, std::to_string(b.size() - at) + " trailing bytes after the " +
                                std::to_string(levels) + " level(s) the header describes");
  return img;
}

CompressedImage read_ktx_file(const std::string& path) {
  const std::string s = read_input_file(path, "KTX file", kMaxCompressedInput);
  return parse_ktx({reinterpret_cast<const uint8_t*>(s.data()), s.size()}, path);
}

std::string ktx_bytes(const CompressedImage& img, const std::string& where) {
  check_compressed_image(img, where);
  const KtxFormat* fmt = nullptr;
  for (const KtxFormat& k : formats()) {
    if (k.format == img.format && k.block_w == img.block_w && k.block_h == img.block_h) fmt = &k;
  }
  if (!fmt) throw InputError(where, "cannot write: " + img.format_label() + " has no KTX format");
  std::string s(kIdentifier.begin(), kIdentifier.end());
  for (uint32_t v : {kEndianness, 0U, 1U, 0U, fmt->gl, fmt->base, img.width, img.height, 0U, 0U, 1U,
                     static_cast<uint32_t>(img.levels.size()), 0U})
    put_u32(s, v);
  for (const CompressedLevel& l : img.levels) {
    if (l.bytes.size() > UINT32_MAX)
      throw InputError(where, "cannot write: a level of more than 4 GiB (imageSize is 32-bit)");
    put_u32(s, static_cast<uint32_t>(l.bytes.size()));
    s.append(reinterpret_cast<const char*>(l.bytes.data()), l.bytes.size());
    s.append(static_cast<size_t>(pad4(l.bytes.size())), '\0');
  }
  return s;
}

void write_ktx_file(const std::string& path, const CompressedImage& img) {
  write_file_atomic(path, ktx_bytes(img, path));
}

}  // namespace texsim
