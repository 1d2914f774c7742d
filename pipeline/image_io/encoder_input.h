#pragma once
// What the block encoders (squish_encoder.h, nvtt_encoder.h, astcenc_encoder.h) take and
// give: one level of RGBA8 texels in, that level's blocks out. Every encoder is handed the
// image padded to whole blocks by replicating the last column and row (padded_to_blocks), so
// the texels of an edge block beyond the image repeat the edge texels whichever encoder runs.
#include <cstdint>
#include <string>
#include <vector>

#include "pipeline/image_io/compressed_image.h"

namespace texsim {

struct Rgba8Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  // 4 bytes per texel, R G B A, top row first
};

struct EncodedLevel {
  FileBlockFormat format = FileBlockFormat::Bc1Unorm;
  int width = 0, height = 0;  // of the image given (not padded)
  int block_w = 4, block_h = 4;
  std::vector<uint8_t> bytes;  // ceil(w / block_w) x ceil(h / block_h) blocks, row-major
  std::string provenance;      // encoder, its version and the options used
};

// Throws InputError naming `who` unless the image has texels, at most `max_side` per side, and
// exactly width x height x 4 bytes.
void check_encoder_input(const Rgba8Image& img, const std::string& who, int max_side);
// The image widened to a multiple of bw and heightened to a multiple of bh, the new texels
// copies of the last column's and then the last row's.
Rgba8Image padded_to_blocks(const Rgba8Image& img, int bw, int bh);
// The level as a one-level CompressedImage (for the DDS and .astc writers).
CompressedImage as_compressed_image(const EncodedLevel& level);

}  // namespace texsim
