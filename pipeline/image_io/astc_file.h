#pragma once
// .astc files (docs/compressed-files.md#astc): the 16-byte header of the ASTC encoders (magic
// 0x5CA1AB13, block footprint x/y/z, 24-bit x/y/z sizes, all little-endian) and one level of
// 16-byte blocks, row-major. Only 2-D images are taken: a 3-D block footprint or a z size
// other than 1 is refused, as is a footprint ASTC does not define. The block count must match
// the file's size to the byte, or the reader throws InputError naming the file and the
// reason.
#include <cstdint>
#include <span>
#include <string>

#include "pipeline/image_io/compressed_image.h"

namespace texsim {

// Reads the .astc file at `path` (opened with open_input_file).
CompressedImage read_astc_file(const std::string& path);
// The same rules on bytes in memory; `where` names them in errors.
CompressedImage parse_astc(std::span<const uint8_t> bytes, const std::string& where);

// The .astc bytes of a one-level ASTC image; InputError naming `where` for any other image.
std::string astc_bytes(const CompressedImage& img, const std::string& where);
// Writes them to `path` atomically.
void write_astc_file(const std::string& path, const CompressedImage& img);

// Whether the footprint is one of ASTC's 14 2-D block sizes (4x4 ... 12x12).
bool is_astc_2d_footprint(int bw, int bh);

}  // namespace texsim
