#include "blocks/texture/decode/compressed_format.h"

#include <array>

namespace texsim {

namespace {

using F = CodecFamily;
constexpr std::array<CompressedFormatInfo, static_cast<size_t>(CompressedFormat::kCount)> kInfo = {{
    {"bc1_rgb", F::Bc, 4, 4, 8, 4},
    {"bc1_rgba", F::Bc, 4, 4, 8, 4},
    {"bc2", F::Bc, 4, 4, 16, 4},
    {"bc3", F::Bc, 4, 4, 16, 4},
    {"bc4", F::Bc, 4, 4, 8, 2},
    {"bc4_snorm", F::Bc, 4, 4, 8, 2},
    {"bc5", F::Bc, 4, 4, 16, 4},
    {"bc5_snorm", F::Bc, 4, 4, 16, 4},
    {"bc7", F::Bc, 4, 4, 16, 4},
    {"etc2_rgb8", F::Etc, 4, 4, 8, 4},
    {"etc2_rgb8a1", F::Etc, 4, 4, 8, 4},
    {"etc2_rgba8", F::Etc, 4, 4, 16, 4},
    {"eac_r11", F::Etc, 4, 4, 8, 2},
    {"eac_r11_snorm", F::Etc, 4, 4, 8, 2},
    {"eac_rg11", F::Etc, 4, 4, 16, 4},
    {"eac_rg11_snorm", F::Etc, 4, 4, 16, 4},
    {"astc_4x4", F::Astc, 4, 4, 16, 8},
    {"astc_5x4", F::Astc, 5, 4, 16, 8},
    {"astc_5x5", F::Astc, 5, 5, 16, 8},
    {"astc_6x5", F::Astc, 6, 5, 16, 8},
    {"astc_6x6", F::Astc, 6, 6, 16, 8},
    {"astc_8x5", F::Astc, 8, 5, 16, 8},
    {"astc_8x6", F::Astc, 8, 6, 16, 8},
    {"astc_8x8", F::Astc, 8, 8, 16, 8},
    {"astc_10x5", F::Astc, 10, 5, 16, 8},
    {"astc_10x6", F::Astc, 10, 6, 16, 8},
    {"astc_10x8", F::Astc, 10, 8, 16, 8},
    {"astc_10x10", F::Astc, 10, 10, 16, 8},
    {"astc_12x10", F::Astc, 12, 10, 16, 8},
    {"astc_12x12", F::Astc, 12, 12, 16, 8},
}};

}  // namespace

const CompressedFormatInfo& format_info(CompressedFormat f) {
  return kInfo[static_cast<size_t>(f)];
}

std::optional<CompressedFormat> compressed_format_from_name(std::string_view name) {
  for (size_t i = 0; i < kInfo.size(); ++i) {
    if (kInfo[i].name == name) return static_cast<CompressedFormat>(i);
  }
  return std::nullopt;
}

std::string compressed_format_names() {
  std::string s;
  for (const auto& f : kInfo) {
    if (!s.empty()) s += ", ";
    s += f.name;
  }
  return s;
}

}  // namespace texsim
