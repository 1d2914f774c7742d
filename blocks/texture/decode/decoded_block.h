#pragma once
// What every block-compressed texel decoder (blocks/texture/decode/) returns: the texels of one
// block, row-major, each RGBA as the Khronos Data Format Specification's decoding gives it,
// rounded once to the nearest float (a UNORM/SNORM result is its exact value k / (2^n - 1)
// in float; a channel the format lacks has the spec's default: 0 for colour, 1 for alpha).
#include <array>
#include <cstdint>
#include <glm/vec4.hpp>

namespace texsim {

inline constexpr int kMaxBlockTexels = 12 * 12;  // ASTC 12x12, the largest 2-D block

struct DecodedBlock {
  int width = 0;   // texels per row of the block
  int height = 0;  // rows of the block
  std::array<glm::vec4, kMaxBlockTexels> texels{};
  const glm::vec4& at(int x, int y) const {
    return texels[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
  }
};

// A 4x4 block of 8-bit RGBA results (texel (x, y) at y * 4 + x), each channel c / 255 rounded
// once to float: the decoded block of the formats whose spec results are 8-bit codes.
inline DecodedBlock decoded_from_rgba8(const std::array<std::array<uint8_t, 4>, 16>& t) {
  DecodedBlock d;
  d.width = 4;
  d.height = 4;
  for (size_t i = 0; i < t.size(); ++i) {
    for (size_t c = 0; c < 4; ++c)
      d.texels[i][static_cast<int>(c)] = static_cast<float>(t[i][c]) / 255.0F;
  }
  return d;
}

}  // namespace texsim
