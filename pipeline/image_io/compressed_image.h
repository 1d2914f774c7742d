#pragma once
// A block-compressed texture as the container files hold it (DDS, .astc, KTX): the format, the
// size of level 0, the block footprint and, per mip level, its size and its blocks' bytes
// (blocks row-major, ceil(w / block_w) x ceil(h / block_h) of them). The readers (dds_file.h,
// astc_file.h, ktx_file.h) check every size against the file; the encoders produce one level.
#include <cstdint>
#include <string>
#include <vector>

namespace texsim {

enum class FileBlockFormat {
  Bc1Unorm,  // BC1 with its 1-bit alpha (DDS, GL_COMPRESSED_RGBA_S3TC_DXT1_EXT)
  Bc1Srgb,
  Bc1RgbUnorm,  // BC1 read as opaque RGB (KTX's GL_COMPRESSED_RGB_S3TC_DXT1_EXT)
  Bc1RgbSrgb,
  Bc2Unorm,
  Bc2Srgb,
  Bc3Unorm,
  Bc3Srgb,
  Bc4Unorm,
  Bc4Snorm,
  Bc5Unorm,
  Bc5Snorm,
  Bc7Unorm,
  Bc7Srgb,
  Etc2Rgb8,
  Etc2Rgb8Srgb,
  Etc2Rgb8A1,
  Etc2Rgb8A1Srgb,
  Etc2Rgba8,
  Etc2Rgba8Srgb,
  EacR11Unorm,
  EacR11Snorm,
  EacRg11Unorm,
  EacRg11Snorm,
  Astc,      // 2-D LDR ASTC, any of the 14 2-D block footprints (block_w x block_h)
  AstcSrgb,  // the same with sRGB colours (KTX files name it; .astc files cannot)
};
// The enum's last value: stored formats above it are not formats (encoded_level_cache.cc).
inline constexpr FileBlockFormat kLastFileBlockFormat = FileBlockFormat::AstcSrgb;

// "BC1_UNORM", "BC7_UNORM_SRGB" (the DXGI spelling without the DXGI_FORMAT_ prefix),
// "ETC2_RGB8", "EAC_R11_SNORM", "ASTC", "ASTC_SRGB".
const char* format_name(FileBlockFormat f);
// Bytes per block: 8 for BC1 (either kind), BC4, ETC2 RGB8 / RGB8A1 and EAC R11, 16 for the others.
int format_block_bytes(FileBlockFormat f);
// Whether blocks of `f` are ASTC (any footprint, either colour space).
bool is_astc(FileBlockFormat f);
// Whether blocks of `f` are ETC2 or EAC (4x4 blocks).
bool is_etc(FileBlockFormat f);

struct CompressedLevel {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> bytes;  // the level's blocks, row-major
};

struct CompressedImage {
  FileBlockFormat format = FileBlockFormat::Bc1Unorm;
  uint32_t width = 0, height = 0;  // level 0
  int block_w = 4, block_h = 4;
  int block_bytes = 8;
  std::vector<CompressedLevel> levels;  // level 0 first

  // "BC1_UNORM", or "ASTC 6x6" / "ASTC_SRGB 6x6" with the footprint.
  std::string format_label() const;
};

// Blocks of a w x h level: ceil(w / bw) x ceil(h / bh) (64-bit: no overflow for 32-bit sizes).
uint64_t level_block_count(uint64_t w, uint64_t h, int bw, int bh);
// Most mip levels a w x h image has: floor(log2(max(w, h))) + 1 (down to 1 x 1).
uint32_t max_mip_levels(uint64_t w, uint64_t h);
// Size of mip level `i` of a side of `n` texels: max(1, n >> i).
uint32_t mip_side(uint32_t n, uint32_t i);

// Checks that an image is self-consistent (sizes of every level, the block bytes of its
// format, its levels halving from level 0) before a writer stores it: throws InputError naming
// `where` and what is wrong.
void check_compressed_image(const CompressedImage& img, const std::string& where);

}  // namespace texsim
