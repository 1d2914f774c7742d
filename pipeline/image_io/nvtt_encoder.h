#pragma once
// BC1-BC5 blocks from NVIDIA Texture Tools (Debian's libnvtt 2.0.8), on the CPU, collected in
// memory through its OutputHandler.
#include <string>

#include "pipeline/image_io/encoder_input.h"

namespace texsim {

enum class NvttQuality { Fastest, Normal, Production };

// "fastest", "normal", "production".
const char* nvtt_quality_name(NvttQuality q);

// Encodes `img` (padded to whole blocks first, encoder_input.h) as BC1_UNORM (opaque: alpha is
// ignored), BC2_UNORM, BC3_UNORM, BC4_UNORM (from the red channel) or BC5_UNORM (red and
// green). Any other format, a bad image or a failure the library reports throws InputError.
// No mipmaps are generated; CUDA is never used, so results do not depend on the machine's GPU.
EncodedLevel nvtt_encode(const Rgba8Image& img, FileBlockFormat format, NvttQuality quality);

}  // namespace texsim
