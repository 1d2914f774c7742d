#pragma once
// The block-compressed texel formats (docs/formats.md#block-compressed-formats): block size,
// bytes per block, and what a decoded texel takes where a cache holds decoded texels.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace texsim {

enum class CompressedFormat {
  Bc1Rgb,
  Bc1Rgba,
  Bc2,
  Bc3,
  Bc4,
  Bc4Snorm,
  Bc5,
  Bc5Snorm,
  Bc7,
  Etc2Rgb8,
  Etc2Rgb8A1,
  Etc2Rgba8,
  EacR11,
  EacR11Snorm,
  EacRg11,
  EacRg11Snorm,
  Astc4x4,
  Astc5x4,
  Astc5x5,
  Astc6x5,
  Astc6x6,
  Astc8x5,
  Astc8x6,
  Astc8x8,
  Astc10x5,
  Astc10x6,
  Astc10x8,
  Astc10x10,
  Astc12x10,
  Astc12x12,
  kCount
};

inline constexpr int kCompressedFormats = static_cast<int>(CompressedFormat::kCount);
// A count per compressed format (e.g. blocks decoded), indexed by the format.
using PerCompressedFormat = std::array<uint64_t, kCompressedFormats>;

enum class CodecFamily { Bc, Etc, Astc };

struct CompressedFormatInfo {
  std::string_view name;  // the scene's `compress = { format = "…" }` value
  CodecFamily family = CodecFamily::Bc;
  int block_w = 4, block_h = 4;
  int block_bytes = 8;
  // Bytes of one decoded texel where a cache holds decoded texels: 4 for 8-bit RGBA results,
  // 2 and 4 for one and two channels of up to 16 bits (BC4/5, EAC), 8 for ASTC's 16-bit RGBA.
  int decoded_bytes = 4;
};

const CompressedFormatInfo& format_info(CompressedFormat f);
inline std::string_view to_string(CompressedFormat f) { return format_info(f).name; }
std::optional<CompressedFormat> compressed_format_from_name(std::string_view name);
std::string compressed_format_names();

}  // namespace texsim
