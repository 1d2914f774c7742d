#pragma once
// texsim's own BC7 encoder (Debian has none), written from the Khronos Data Format
// Specification's BC7 description. Two of the eight modes:
//  - mode 6: one subset, RGBA 7.7.7.7 endpoints with a p-bit each, 4-bit indices; endpoints
//    from the block's principal axis (RGBA), then least-squares passes given the indices;
//  - mode 5 (quality "normal"): RGB 7.7.7 and alpha 8-bit endpoints, 2-bit colour and alpha
//    indices, each of the four channel rotations tried.
// The block of least squared error (RGBA) under the encoder's own reconstruction
// (bc7_reconstruct) is kept. Not a hardware block.
#include <array>
#include <cstdint>

#include "pipeline/image_io/encoder_input.h"

namespace texsim {

// 16 RGBA8 pixels of a 4x4 block, row-major.
using Bc7Pixels = std::array<std::array<uint8_t, 4>, 16>;
using Bc7Block = std::array<uint8_t, 16>;

enum class Bc7Quality {
  Fast,    // mode 6, one least-squares pass
  Normal,  // mode 6 with three passes, and mode 5 in each rotation
};
// "fast", "normal".
const char* bc7_quality_name(Bc7Quality q);

// The block of least squared error among the modes `q` tries.
Bc7Block bc7_encode_block(const Bc7Pixels& px, Bc7Quality q);
// The 16 RGBA8 pixels (row-major) of a mode 5 or mode 6 block; false for other modes.
bool bc7_reconstruct(const Bc7Block& b, Bc7Pixels* out);

// Encodes `img` (padded to whole blocks first, encoder_input.h) as BC7_UNORM; any other
// format, or a bad image, throws InputError.
EncodedLevel bc7_encode(const Rgba8Image& img, FileBlockFormat format, Bc7Quality q);

}  // namespace texsim
