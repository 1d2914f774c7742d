#include "pipeline/image_io/dds_file.h"

#include <array>
#include <cstdio>
#include <optional>
#include <vector>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"

namespace texsim {

namespace {

// Sizes and flags of the DDS header (Microsoft's DDS_HEADER, DDS_PIXELFORMAT and
// DDS_HEADER_DXT10); offsets below are from the start of the file.
constexpr size_t kMagicBytes = 4, kHeaderBytes = 124, kPixelFormatBytes = 32, kDx10Bytes = 20;
constexpr uint32_t kFlagCaps = 0x1, kFlagHeight = 0x2, kFlagWidth = 0x4, kFlagPixelFormat = 0x1000;
constexpr uint32_t kFlagMipCount = 0x20000, kFlagLinearSize = 0x80000, kFlagDepth = 0x800000;
constexpr uint32_t kPfFourCC = 0x4;
constexpr uint32_t kCapsComplex = 0x8, kCapsTexture = 0x1000, kCapsMipmap = 0x400000;
constexpr uint32_t kCaps2Cubemap = 0x200, kCaps2Volume = 0x200000;
constexpr uint32_t kDx10Texture2D = 3, kDx10MiscCube = 0x4;

constexpr uint32_t fourcc(const char (&s)[5]) {
  return static_cast<uint32_t>(static_cast<uint8_t>(s[0])) |
         static_cast<uint32_t>(static_cast<uint8_t>(s[1])) << 8 |
         static_cast<uint32_t>(static_cast<uint8_t>(s[2])) << 16 |
         static_cast<uint32_t>(static_cast<uint8_t>(s[3])) << 24;
}

struct FourCCFormat {
  uint32_t code;
  FileBlockFormat format;
};
constexpr std::array<FourCCFormat, 9> kFourCCs = {{
    {fourcc("DXT1"), FileBlockFormat::Bc1Unorm},
    {fourcc("DXT3"), FileBlockFormat::Bc2Unorm},
    {fourcc("DXT5"), FileBlockFormat::Bc3Unorm},
    {fourcc("ATI1"), FileBlockFormat::Bc4Unorm},
    {fourcc("BC4U"), FileBlockFormat::Bc4Unorm},
    {fourcc("BC4S"), FileBlockFormat::Bc4Snorm},
    {fourcc("ATI2"), FileBlockFormat::Bc5Unorm},
    {fourcc("BC5U"), FileBlockFormat::Bc5Unorm},
    {fourcc("BC5S"), FileBlockFormat::Bc5Snorm},
}};

struct DxgiFormat {
  uint32_t code;
  FileBlockFormat format;
};
// DXGI_FORMAT values (dxgiformat.h).
constexpr std::array<DxgiFormat, 12> kDxgiFormats = {{
    {71, FileBlockFormat::Bc1Unorm},
    {72, FileBlockFormat::Bc1Srgb},
    {74, FileBlockFormat::Bc2Unorm},
    {75, FileBlockFormat::Bc2Srgb},
    {77, FileBlockFormat::Bc3Unorm},
    {78, FileBlockFormat::Bc3Srgb},
    {80, FileBlockFormat::Bc4Unorm},
    {81, FileBlockFormat::Bc4Snorm},
    {83, FileBlockFormat::Bc5Unorm},
    {84, FileBlockFormat::Bc5Snorm},
    {98, FileBlockFormat::Bc7Unorm},
    {99, FileBlockFormat::Bc7Srgb},
}};

uint32_t get_u32(std::span<const uint8_t> b, size_t at) {
  return static_cast<uint32_t>(b[at]) | static_cast<uint32_t>(b[at + 1]) << 8 |
         static_cast<uint32_t>(b[at + 2]) << 16 | static_cast<uint32_t>(b[at + 3]) << 24;
}
void put_u32(std::string& s, size_t at, uint32_t v) {
  for (size_t i = 0; i < 4; ++i) s[at + i] = static_cast<char>(v >> (8 * i));
}

// A FourCC as text for messages: its printable characters, or its value in hex.
std::string fourcc_text(uint32_t code) {
  std::string s;
  for (int i = 0; i < 4; ++i) {
    const auto c = static_cast<char>(code >> (8 * i));
    if (c < 0x20 || c > 0x7e) {
      char hex[16];
      std::snprintf(hex, sizeof hex, "0x%08x", code);
      return hex;
    }
    s += c;
  }
  return "'" + s + "'";
}

// Why a DXGI format that is not read here is refused.
std::string dxgi_refusal(uint32_t code) {
  const std::string n = std::to_string(code);
  if (code == 70 || code == 73 || code == 76 || code == 79 || code == 82 || code == 97)
    return "DXGI format " + n + " is a TYPELESS BC format (how to read it is not in the file)";
  if (code >= 94 && code <= 96) return "DXGI format " + n + " (BC6H) is not supported";
  return "DXGI format " + n + " is not a supported block-compressed format (BC1-BC5, BC7)";
}

// The format named by the pixel format and the DX10 header (when there is one); `data_at`
// receives where the blocks start.
FileBlockFormat read_format(std::span<const uint8_t> b, const std::string& where, size_t* data_at) {
  if (get_u32(b, 76) != kPixelFormatBytes)
    throw InputError(where, "pixel format size is " + std::to_string(get_u32(b, 76)) + ", not " +
                                std::to_string(kPixelFormatBytes));
  if ((get_u32(b, 80) & kPfFourCC) == 0)
    throw InputError(where,
                     "uncompressed pixel format (no FourCC): only block-compressed "
                     "formats are read");
  const uint32_t code = get_u32(b, 84);
  *data_at = kMagicBytes + kHeaderBytes;
  if (code != fourcc("DX10")) {
    for (const FourCCFormat& f : kFourCCs)
      if (f.code == code) return f.format;
    throw InputError(where, "unknown FourCC " + fourcc_text(code) +
                                " (read: DXT1, DXT3, DXT5, ATI1, BC4U, BC4S, ATI2, BC5U, BC5S, "
                                "DX10)");
  }
  if (b.size() < *data_at + kDx10Bytes)
    throw InputError(where,
                     "file ends inside the DX10 header (" + std::to_string(b.size()) + " bytes)");
  const size_t h = *data_at;
  *data_at += kDx10Bytes;
  const uint32_t dxgi = get_u32(b, h), dim = get_u32(b, h + 4);
  const uint32_t misc = get_u32(b, h + 8), array = get_u32(b, h + 12);
  if (misc & kDx10MiscCube) throw InputError(where, "cube maps are not supported");
  if (dim != kDx10Texture2D)
    throw InputError(where, "resource dimension " + std::to_string(dim) +
                                " is not a 2-D texture (1-D and volume textures are not "
                                "supported)");
  if (array != 1)
    throw InputError(where, "array size " + std::to_string(array) +
                                ": texture arrays are not supported (one 2-D texture only)");
  for (const DxgiFormat& f : kDxgiFormats)
    if (f.code == dxgi) return f.format;
  throw InputError(where, dxgi_refusal(dxgi));
}

}  // namespace

CompressedImage parse_dds(std::span<const uint8_t> b, const std::string& where) {
  if (b.size() < kMagicBytes + kHeaderBytes)
    throw InputError(where, "file of " + std::to_string(b.size()) +
                                " bytes is shorter than a DDS header (128 bytes)");
  if (get_u32(b, 0) != fourcc("DDS ")) throw InputError(where, "not a DDS file (no 'DDS ' magic)");
  if (get_u32(b, 4) != kHeaderBytes)
    throw InputError(where, "header size is " + std::to_string(get_u32(b, 4)) + ", not 124");
  const uint32_t flags = get_u32(b, 8), height = get_u32(b, 12), width = get_u32(b, 16);
  const uint32_t linear = get_u32(b, 20), depth = get_u32(b, 24), mips = get_u32(b, 28);
  const uint32_t caps2 = get_u32(b, 112);
  if (caps2 & kCaps2Cubemap) throw InputError(where, "cube maps are not supported");
  if ((caps2 & kCaps2Volume) || ((flags & kFlagDepth) && depth > 1))
    throw InputError(where, "volume textures are not supported");
  if (width == 0 || height == 0)
    throw InputError(where, "image size " + std::to_string(width) + " x " + std::to_string(height) +
                                " has no texels");
  size_t at = 0;
  CompressedImage img;
  img.format = read_format(b, where, &at);
  img.width = width;
  img.height = height;
  img.block_bytes = format_block_bytes(img.format);
  // A mip count of 0 (or no DDSD_MIPMAPCOUNT flag with a 0 count) is one level.
  const uint32_t count = mips == 0 ? 1 : mips;
  if (count > max_mip_levels(width, height))
    throw InputError(where, "mip count " + std::to_string(count) + " is more than a " +
                                std::to_string(width) + " x " + std::to_string(height) +
                                " image has (" + std::to_string(max_mip_levels(width, height)) +
                                ")");
  uint64_t total = 0;
  std::vector<uint64_t> sizes;
  for (uint32_t i = 0; i < count; ++i) {
    sizes.push_back(level_block_count(mip_side(width, i), mip_side(height, i), 4, 4) *
                    static_cast<uint64_t>(img.block_bytes));
    total += sizes.back();
  }
  if ((flags & kFlagLinearSize) && linear != sizes[0])
    throw InputError(where, "header gives level 0 " + std::to_string(linear) +
                                " bytes, its blocks take " + std::to_string(sizes[0]));
  const uint64_t have = b.size() - at;
  if (have < total)
    throw InputError(where, "truncated: " + std::to_string(count) + " level(s) of " +
                                img.format_label() + " take " + std::to_string(total) +
                                " bytes, the file holds " + std::to_string(have));
  if (have > total)
    throw InputError(where, std::to_string(have - total) + " trailing bytes after the " +
                                std::to_string(count) + " level(s) the header describes");
  for (uint32_t i = 0; i < count; ++i) {
    CompressedLevel l;
    l.width = mip_side(width, i);
    l.height = mip_side(height, i);
    l.bytes.assign(b.begin() + static_cast<std::ptrdiff_t>(at),
                   b.begin() + static_cast<std::ptrdiff_t>(at + sizes[i]));
    at += sizes[i];
    img.levels.push_back(std::move(l));
  }
  return img;
}

CompressedImage read_dds_file(const std::string& path) {
  const std::string s = read_input_file(path, "DDS file", kMaxCompressedInput);
  return parse_dds({reinterpret_cast<const uint8_t*>(s.data()), s.size()}, path);
}

std::string dds_bytes(const CompressedImage& img, bool dx10, const std::string& where) {
  check_compressed_image(img, where);
  if (is_astc(img.format))
    throw InputError(where, "cannot write: ASTC is not stored in DDS files here");
  if (is_etc(img.format) || img.format == FileBlockFormat::Bc1RgbUnorm ||
      img.format == FileBlockFormat::Bc1RgbSrgb)
    throw InputError(where, std::string("cannot write: ") + format_name(img.format) +
                                " is not stored in DDS files (KTX files hold it)");
  std::optional<uint32_t> legacy;
  for (const FourCCFormat& f : kFourCCs)
    if (f.format == img.format && f.code != fourcc("ATI1") && f.code != fourcc("ATI2"))
      legacy = f.code;
  if (dx10) legacy.reset();
  uint32_t dxgi = 0;
  for (const DxgiFormat& f : kDxgiFormats)
    if (f.format == img.format) dxgi = f.code;
  const auto levels = static_cast<uint32_t>(img.levels.size());
  std::string s(kMagicBytes + kHeaderBytes + (legacy ? 0 : kDx10Bytes), '\0');
  put_u32(s, 0, fourcc("DDS "));
  put_u32(s, 4, kHeaderBytes);
  put_u32(s, 8,
          kFlagCaps | kFlagHeight | kFlagWidth | kFlagPixelFormat | kFlagLinearSize |
              (levels > 1 ? kFlagMipCount : 0));
  put_u32(s, 12, img.height);
  put_u32(s, 16, img.width);
  put_u32(s, 20, static_cast<uint32_t>(img.levels[0].bytes.size()));
  put_u32(s, 28, levels > 1 ? levels : 0);
  put_u32(s, 76, kPixelFormatBytes);
  put_u32(s, 80, kPfFourCC);
  put_u32(s, 84, legacy ? *legacy : fourcc("DX10"));
  put_u32(s, 108, kCapsTexture | (levels > 1 ? kCapsComplex | kCapsMipmap : 0));
  if (!legacy) {
    const size_t h = kMagicBytes + kHeaderBytes;
    put_u32(s, h, dxgi);
    put_u32(s, h + 4, kDx10Texture2D);
    put_u32(s, h + 12, 1);  // array size
  }
  for (const CompressedLevel& l : img.levels)
    s.append(reinterpret_cast<const char*>(l.bytes.data()), l.bytes.size());
  return s;
}

void write_dds_file(const std::string& path, const CompressedImage& img, bool dx10) {
  write_file_atomic(path, dds_bytes(img, dx10, path));
}

}  // namespace texsim
