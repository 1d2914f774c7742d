#include "pipeline/image_io/compressed_image.h"

#include <bit>

#include "blocks/base/input_error.h"

namespace texsim {

const char* format_name(FileBlockFormat f) {
  switch (f) {
    case FileBlockFormat::Bc1Unorm:
      return "BC1_UNORM";
    case FileBlockFormat::Bc1Srgb:
      return "BC1_UNORM_SRGB";
    case FileBlockFormat::Bc1RgbUnorm:
      return "BC1_RGB_UNORM";
    case FileBlockFormat::Bc1RgbSrgb:
      return "BC1_RGB_UNORM_SRGB";
    case FileBlockFormat::Bc2Unorm:
      return "BC2_UNORM";
    case FileBlockFormat::Bc2Srgb:
      return "BC2_UNORM_SRGB";
    case FileBlockFormat::Bc3Unorm:
      return "BC3_UNORM";
    case FileBlockFormat::Bc3Srgb:
      return "BC3_UNORM_SRGB";
    case FileBlockFormat::Bc4Unorm:
      return "BC4_UNORM";
    case FileBlockFormat::Bc4Snorm:
      return "BC4_SNORM";
    case FileBlockFormat::Bc5Unorm:
      return "BC5_UNORM";
    case FileBlockFormat::Bc5Snorm:
      return "BC5_SNORM";
    case FileBlockFormat::Bc7Unorm:
      return "BC7_UNORM";
    case FileBlockFormat::Bc7Srgb:
      return "BC7_UNORM_SRGB";
    case FileBlockFormat::Etc2Rgb8:
      return "ETC2_RGB8";
    case FileBlockFormat::Etc2Rgb8Srgb:
      return "ETC2_RGB8_SRGB";
    case FileBlockFormat::Etc2Rgb8A1:
      return "ETC2_RGB8A1";
    case FileBlockFormat::Etc2Rgb8A1Srgb:
      return "ETC2_RGB8A1_SRGB";
    case FileBlockFormat::Etc2Rgba8:
      return "ETC2_RGBA8";
    case FileBlockFormat::Etc2Rgba8Srgb:
      return "ETC2_RGBA8_SRGB";
    case FileBlockFormat::EacR11Unorm:
      return "EAC_R11_UNORM";
    case FileBlockFormat::EacR11Snorm:
      return "EAC_R11_SNORM";
    case FileBlockFormat::EacRg11Unorm:
      return "EAC_RG11_UNORM";
    case FileBlockFormat::EacRg11Snorm:
      return "EAC_RG11_SNORM";
    case FileBlockFormat::Astc:
      return "ASTC";
    case FileBlockFormat::AstcSrgb:
      return "ASTC_SRGB";
  }
  return "unknown";
}

int format_block_bytes(FileBlockFormat f) {
  switch (f) {
    case FileBlockFormat::Bc1Unorm:
    case FileBlockFormat::Bc1Srgb:
    case FileBlockFormat::Bc1RgbUnorm:
    case FileBlockFormat::Bc1RgbSrgb:
    case FileBlockFormat::Bc4Unorm:
    case FileBlockFormat::Bc4Snorm:
    case FileBlockFormat::Etc2Rgb8:
    case FileBlockFormat::Etc2Rgb8Srgb:
    case FileBlockFormat::Etc2Rgb8A1:
    case FileBlockFormat::Etc2Rgb8A1Srgb:
    case FileBlockFormat::EacR11Unorm:
    case FileBlockFormat::EacR11Snorm:
      return 8;
    default:
      return 16;
  }
}

bool is_astc(FileBlockFormat f) {
  return f == FileBlockFormat::Astc || f == FileBlockFormat::AstcSrgb;
}

bool is_etc(FileBlockFormat f) {
  return f >= FileBlockFormat::Etc2Rgb8 && f <= FileBlockFormat::EacRg11Snorm;
}

std::string CompressedImage::format_label() const {
  if (!is_astc(format)) return format_name(format);
  return std::string(format_name(format)) + " " + std::to_string(block_w) + "x" +
         std::to_string(block_h);
}

uint64_t level_block_count(uint64_t w, uint64_t h, int bw, int bh) {
  const auto ubw = static_cast<uint64_t>(bw), ubh = static_cast<uint64_t>(bh);
  return ((w + ubw - 1) / ubw) * ((h + ubh - 1) / ubh);
}

uint32_t max_mip_levels(uint64_t w, uint64_t h) {
  const uint64_t side = w > h ? w : h;
  return side == 0 ? 0 : static_cast<uint32_t>(std::bit_width(side));
}

uint32_t mip_side(uint32_t n, uint32_t i) {
  if (i >= 32) return 1;
  const uint32_t s = n >> i;
  return s == 0 ? 1 : s;
}

void check_compressed_image(const CompressedImage& img, const std::string& where) {
  auto fail = [&](const std::string& what) { throw InputError(where, "cannot write: " + what); };
  if (img.width == 0 || img.height == 0) fail("the image has no texels");
  if (img.levels.empty()) fail("the image has no levels");
  if (img.levels.size() > max_mip_levels(img.width, img.height))
    fail(std::to_string(img.levels.size()) + " levels, more than a " + std::to_string(img.width) +
         " x " + std::to_string(img.height) + " image has");
  if (is_astc(img.format)) {
    if (img.block_w < 4 || img.block_w > 12 || img.block_h < 4 || img.block_h > 12)
      fail("ASTC block footprint out of range");
  } else if (img.block_w != 4 || img.block_h != 4) {
    fail("BC, ETC2 and EAC formats have 4x4 blocks");
  }
  if (img.block_bytes != format_block_bytes(img.format))
    fail("block bytes do not match " + std::string(format_name(img.format)));
  for (size_t i = 0; i < img.levels.size(); ++i) {
    const CompressedLevel& l = img.levels[i];
    const auto li = static_cast<uint32_t>(i);
    if (l.width != mip_side(img.width, li) || l.height != mip_side(img.height, li))
      fail("level " + std::to_string(i) + " is not half the size of the one above");
    const uint64_t want = level_block_count(l.width, l.height, img.block_w, img.block_h) *
                          static_cast<uint64_t>(img.block_bytes);
    if (l.bytes.size() != want)
      fail("level " + std::to_string(i) + " holds " + std::to_string(l.bytes.size()) +
           " bytes, its blocks take " + std::to_string(want));
  }
}

}  // namespace texsim
