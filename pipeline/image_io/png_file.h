#pragma once
// PNG files through libpng, without OpenImageIO: the 8-bit RGB images texsim writes (image,
// reference, error maps) and the 8-bit RGB PNGs it reads back (reference frames). The reader
// takes only the PNGs whose pixels OpenImageIO would return unchanged (no alpha to associate,
// no 16-bit conversion); every other file goes to OpenImageIO, so that decoded pixels never
// depend on which library read them.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace texsim {

// Writes `height` rows of `width` RGB8 pixels (top row first) as a PNG to `path`, in place
// (callers write a temporary file and rename it). `fast`: zlib level 1 and no row filters, for
// very large images. Returns "" or the reason it failed (the OS's, when it has one).
std::string write_png_rgb8(const std::string& path, int width, int height, const uint8_t* rgb,
                           bool fast);

// The same for `height` rows of `width` RGBA8 pixels (8-bit RGB with alpha, zlib level 6),
// for tools that take RGBA images (the astcenc encoder's input).
std::string write_png_rgba8(const std::string& path, int width, int height, const uint8_t* rgba);

// Whether the bytes start with the PNG signature.
bool is_png(const uint8_t* data, size_t size);

struct PngImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // 3 bytes per pixel, top row first
};

enum class PngRead {
  Ok,          // decoded into the image
  NotHandled,  // not a PNG, or one with alpha, transparency, grey or 16-bit samples
  Failed,      // a PNG of the handled kinds that is damaged or too large: the reason in `error`
};

// Decodes an 8-bit RGB PNG, or a palette PNG without transparency, of at most `max_side`
// pixels per side from memory.
PngRead read_png_rgb8(const uint8_t* data, size_t size, int max_side, PngImage* out,
                      std::string* error);

}  // namespace texsim
