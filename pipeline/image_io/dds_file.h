#pragma once
// DDS files of block-compressed 2-D textures (docs/compressed-files.md#dds): the legacy
// header's FourCCs DXT1, DXT3, DXT5, ATI1, BC4U, BC4S, ATI2, BC5U, BC5S and the DX10
// extension header's DXGI formats BC1-BC3 UNORM and UNORM_SRGB, BC4-BC5 UNORM and SNORM, BC7
// UNORM and UNORM_SRGB; one 2-D texture with its mip chain. Cube maps, arrays, volumes and
// every other format are refused. The reader is strict: each size, block count and mip count
// must agree with the file's size to the byte, or it throws InputError naming the file and
// what is wrong.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "pipeline/image_io/compressed_image.h"

namespace texsim {

// Largest DDS or .astc file the readers take (docs/cli.md#input-limits).
inline constexpr uint64_t kMaxCompressedInput = uint64_t{1} << 30;

// Reads the DDS file at `path` (opened with open_input_file).
CompressedImage read_dds_file(const std::string& path);
// The same rules on bytes in memory; `where` names them in errors.
CompressedImage parse_dds(std::span<const uint8_t> bytes, const std::string& where);

// The DDS bytes of `img`: the legacy FourCC header for the formats it can name (BC1-BC3 UNORM,
// BC4 and BC5), the DX10 header for the others or when `dx10` is set. Throws InputError
// naming `where` for an inconsistent image or an ASTC one.
std::string dds_bytes(const CompressedImage& img, bool dx10, const std::string& where);
// Writes them to `path` atomically (a temporary file renamed into place).
void write_dds_file(const std::string& path, const CompressedImage& img, bool dx10 = false);

}  // namespace texsim
