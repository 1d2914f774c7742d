#pragma once
// KTX 1.1 files of block-compressed 2-D textures (docs/compressed-files.md#ktx): the 12-byte
// identifier, the 52-byte little-endian header (endianness 0x04030201; big-endian files are
// refused), key/value data (skipped), then per mip level its imageSize and its blocks, each
// level padded to 4 bytes. glType and glFormat 0 (compressed); glInternalFormat one of the
// BC1-BC5 and BC7 formats (sRGB ones included), ETC2 / EAC, or 2-D LDR ASTC (UNORM and sRGB,
// the 14 footprints). One 2-D texture with its mip chain: pixelDepth 0, numberOfArrayElements
// 0 and numberOfFaces 1, anything else refused. The reader is strict: every size must agree
// with the file to the byte, or it throws InputError naming the file and what is wrong.
// Block rows are taken in file order, the first the image's top (as DDS).
#include <cstdint>
#include <span>
#include <string>

#include "pipeline/image_io/compressed_image.h"

namespace texsim {

// Reads the KTX file at `path` (opened with open_input_file, at most kMaxCompressedInput).
CompressedImage read_ktx_file(const std::string& path);
// The same rules on bytes in memory; `where` names them in errors.
CompressedImage parse_ktx(std::span<const uint8_t> bytes, const std::string& where);

// The KTX bytes of `img` (no key/value data). Throws InputError naming `where` for an
// inconsistent image.
std::string ktx_bytes(const CompressedImage& img, const std::string& where);
// Writes them to `path` atomically (a temporary file renamed into place).
void write_ktx_file(const std::string& path, const CompressedImage& img);

}  // namespace texsim
