#pragma once
// ASTC blocks from Arm's astcenc command-line encoder (Debian's astcenc 4.2, /usr/bin/astcenc):
// the image is written to a temporary RGBA PNG, astcenc is run on it (posix_spawn, no shell:
// every argument is one argv entry) and its .astc output is read back with the strict reader
// (astc_file.h). Temporary files are removed afterwards, and by the signal handler if the
// process is interrupted (temp_registry.h).
#include <string>

#include "pipeline/image_io/encoder_input.h"

namespace texsim {

enum class AstcPreset { Fastest, Fast, Medium, Thorough };  // -fastest ... -thorough

// "fastest", "fast", "medium", "thorough".
const char* astc_preset_name(AstcPreset p);

struct AstcencOptions {
  int block_w = 6, block_h = 6;  // one of ASTC's 14 2-D footprints, 4x4 to 12x12
  AstcPreset preset = AstcPreset::Medium;
  bool srgb = false;  // -cs (sRGB colour profile) instead of -cl (linear LDR)
  int threads = 1;    // -j: one thread by default, so tests share the machine politely
  std::string binary = "/usr/bin/astcenc";
};

// Encodes `img` (padded to whole blocks first, encoder_input.h). A missing binary, a run that
// fails (its exit status and the last lines it printed in the message) or output that does not
// match the request throws InputError naming the binary.
EncodedLevel astcenc_encode(const Rgba8Image& img, const AstcencOptions& options);

}  // namespace texsim
