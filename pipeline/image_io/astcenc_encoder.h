#pragma once
// ASTC blocks from Arm's astcenc codec library (Debian's libastcenc-dev 4.2), in process: one
// codec context per footprint, preset and colour profile, made on first use and kept for the
// process's life (making a context builds astcenc's block-mode and partition tables, which
// costs more than encoding a small mip level). The bytes equal those of the astcenc 4.2
// command-line tool run with the same options (test_encoders checks it).
#include <string>

#include "pipeline/image_io/encoder_input.h"

namespace texsim {

enum class AstcPreset { Fastest, Fast, Medium, Thorough };  // -fastest ... -thorough

// "fastest", "fast", "medium", "thorough".
const char* astc_preset_name(AstcPreset p);

struct AstcencOptions {
  int block_w = 6, block_h = 6;  // one of ASTC's 14 2-D footprints, 4x4 to 12x12
  AstcPreset preset = AstcPreset::Medium;
  bool srgb = false;  // the LDR sRGB profile (astcenc -cs) instead of linear LDR (-cl)
};

// Encodes `img` (padded to whole blocks first, encoder_input.h) on astcenc_threads() threads
// (astcenc's output does not depend on its thread count). A footprint
// that is not ASTC's, an image too large, or an error from the codec throws InputError naming
// "astcenc" and the codec's own message.
EncodedLevel astcenc_encode(const Rgba8Image& img, const AstcencOptions& options);
// The threads one encode uses, for the whole process (`texsim run --threads`; default 1).
void set_astcenc_threads(int threads);
int astcenc_threads();

}  // namespace texsim
