#pragma once
// Height fields stored as NumPy .npz archives (a zip of .npy arrays), e.g. the sample DEM
// jacksboro_fault_dem.npz of Debian's python-matplotlib-data: the first 2-D array of the
// archive (int16/int32/uint16/float32/float64, C order, little-endian), row 0 at texel row 0.
// Heights are normalised to [0, 1] (lowest valid height 0, highest 1) and stored as a grey
// Rgba32f texture. No-data: non-finite values and the integer type's minimum (e.g. -32768,
// the usual int16 void) read as the lowest valid height (0); a field with no valid height is
// all 0 (docs/scenes.md#terrain-flyovers).
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/texture/memory/texture_memory.h"

namespace texsim {

struct NpzHeightField {
  int width = 0, height = 0;
  std::vector<double> h;    // normalised heights, row-major
  uint64_t no_data = 0;     // values replaced by the fallback
  double min = 0, max = 0;  // the valid range before normalising (file units)
  std::string array;        // the archive member read, e.g. "elevation.npy"
};

// Limits (docs/cli.md#input-limits): the archive's size, checked before it is read; a
// member's declared uncompressed size, checked before it is inflated; each side of the array.
// The estimated memory of the field and its texture is also checked against
// scene_memory_limit() (--max-memory) before the array is inflated.
inline constexpr uint64_t kMaxNpzBytes = uint64_t{1} << 28;
inline constexpr int kMaxNpzSide = 8192;

// Reads `path`; throws InputError naming the file on any problem. Its .npy header is parsed
// as the dictionary it is (keys descr, fortran_order and shape, each once, nothing else;
// versions 1.0, 2.0 and 3.0). Heights of ±inf are refused; NaN is no-data.
NpzHeightField read_npz_height_field(const std::string& path);
// One .npy array's bytes (`where` names it in errors): the field, or width 0 when the array
// is not 2-D. The fuzz harness's and the tests' entry.
NpzHeightField parse_npy_height_field(const std::string& bytes, const std::string& where);
// The field as a grey texture with its MIP chain (relief and normals read level 0).
Texture npz_height_texture(const std::string& path);
bool is_npz_source(const std::string& source);

}  // namespace texsim
