#pragma once
// texsim's own ETC2 / EAC encoder (Debian has none): every 4x4 block through
// etc_block_encoder.h's mode search, the block of least squared error kept.
#include <string>

#include "pipeline/image_io/encoder_input.h"
#include "pipeline/image_io/etc_block_encoder.h"

namespace texsim {

// "fast", "normal".
const char* etc_effort_name(EtcEffort e);

// Encodes `img` (padded to whole blocks first, encoder_input.h) as ETC2_RGB8, ETC2_RGB8A1
// (alpha < 128 transparent), ETC2_RGBA8 (RGB and an 8-bit EAC alpha), EAC_R11_UNORM (red) or
// EAC_RG11_UNORM (red, green); any other format (the sRGB and SNORM ones included), or a bad
// image, throws InputError.
EncodedLevel etc_encode(const Rgba8Image& img, FileBlockFormat format, EtcEffort effort);

}  // namespace texsim
