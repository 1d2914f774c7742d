#pragma once
// The texel formats a texture may be stored in (docs/formats.md): what one texel takes in
// memory (the bytes the caches and DRAM move) and the value the unit reads back, converted by
// the rules of the Vulkan specification's "Format conversion" chapter.
//  - Loading encodes a float RGBA value into the format: UNORM clamps to [0, 1] and rounds
//    c = round(f · (2^b − 1)), SNORM clamps to [−1, 1] and rounds c = round(f · (2^(b−1) − 1))
//    (nearest, halves away from zero; NaN gives 0); 16-bit floats round to nearest even
//    (overflow to infinity, NaN kept); 32-bit floats are kept.
//  - Reading decodes: UNORM c / (2^b − 1), SNORM max(c / (2^(b−1) − 1), −1), sRGB colour
//    channels through the sRGB EOTF to linear (before any filtering, as the spec requires),
//    halves exactly; each result rounded once to float. Channels a format lacks read as 0
//    (colour) and 1 (alpha); a depth format's value is in red.
#include <cstdint>
#include <glm/vec4.hpp>
#include <optional>
#include <string>
#include <string_view>

namespace texsim {

enum class StorageFormat {
  R8Unorm,
  Rg8Unorm,
  Rgba8Unorm,
  R8Snorm,
  Rg8Snorm,
  Rgba8Snorm,
  Srgb8A8,
  Rgb565,
  Rgba4444,
  Rgb5A1,
  Rgb10A2,
  R16f,
  Rg16f,
  Rgba16f,
  R32f,
  Rg32f,
  Rgba32f,
  D16,
  D32f,
  kCount
};

enum class ChannelCoding { Unorm, Snorm, Srgb, Float16, Float32 };

struct StorageFormatInfo {
  std::string_view name;  // the scene's `format = "…"` value
  int bytes = 0;          // bytes per texel in memory
  int channels = 0;       // stored channels (R, RG, RGB or RGBA)
  int bits[4] = {};       // bits of each stored channel
  ChannelCoding coding = ChannelCoding::Unorm;
  bool depth = false;
};

const StorageFormatInfo& format_info(StorageFormat f);
inline std::string_view to_string(StorageFormat f) { return format_info(f).name; }
// The format named `name`, or nothing.
std::optional<StorageFormat> storage_format_from_name(std::string_view name);
// Every format's name, comma-separated (for messages).
std::string storage_format_names();

// The value a texel of `f` reads back after loading `in` (encode, then decode).
glm::vec4 convert_texel(StorageFormat f, const glm::vec4& in);
// The value a border texel of a texture stored in `f` reads (Vulkan "Texel Replacement", then
// "Conversion to RGBA"): the sampler's float border colour as given (linear also for sRGB
// formats: no EOTF), clamped to the range of a normalised format's channels, and the channels
// the format lacks substituted as for any texel (0 for colour, 1 for alpha).
glm::vec4 border_texel(StorageFormat f, const glm::vec4& border);
// True when every value the format decodes to is a multiple of 1/255 in [0, 1] (R8, RG8 and
// RGBA8 UNORM): the texture keeps its 8-bit store, and the unit's 8-bit kernels serve it.
bool decodes_to_bytes(StorageFormat f);

// IEEE binary16 conversions: to half rounds to nearest even (overflow to infinity, NaN stays a
// quiet NaN); from half is exact.
uint16_t half_from_float(float f);
float float_from_half(uint16_t h);
// The sRGB EOTF of an 8-bit code, rounded once to float.
float srgb_to_linear(uint8_t code);
// The sRGB EOTF of a value in [0, 1] (clamped; NaN gives 0), in double rounded once to float.
float srgb_eotf(float c);
// The inverse: the sRGB OETF of a linear value in [0, 1] (clamped; NaN gives 0), in double
// rounded once to float (a linear border colour taken to the encoded values an sRGB texture's
// filter sums when it decodes after filtering).
float srgb_oetf(float linear);
// The 8-bit code whose srgb_to_linear() is nearest to `linear` (exact for every value
// srgb_to_linear() gives: the table is strictly increasing).
uint8_t srgb_code(float linear);

}  // namespace texsim
