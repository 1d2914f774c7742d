#include "pipeline/image_io/encoder_input.h"

#include <cstring>

#include "blocks/base/input_error.h"

namespace texsim {

void check_encoder_input(const Rgba8Image& img, const std::string& who, int max_side) {
  if (img.width <= 0 || img.height <= 0 || img.width > max_side || img.height > max_side)
    throw InputError(who, "image size " + std::to_string(img.width) + " x " +
                              std::to_string(img.height) + " is not 1.." +
                              std::to_string(max_side) + " per side");
  const size_t want = static_cast<size_t>(img.width) * static_cast<size_t>(img.height) * 4;
  if (img.rgba.size() != want)
    throw InputError(who, "image holds " + std::to_string(img.rgba.size()) + " bytes, " +
                              std::to_string(img.width) + " x " + std::to_string(img.height) +
                              " RGBA8 texels take " + std::to_string(want));
}

Rgba8Image padded_to_blocks(const Rgba8Image& img, int bw, int bh) {
  Rgba8Image out;
  out.width = (img.width + bw - 1) / bw * bw;
  out.height = (img.height + bh - 1) / bh * bh;
  if (out.width == img.width && out.height == img.height) return img;
  const auto src_row = static_cast<size_t>(img.width) * 4;
  const auto dst_row = static_cast<size_t>(out.width) * 4;
  out.rgba.resize(dst_row * static_cast<size_t>(out.height));
  for (int y = 0; y < out.height; ++y) {
    const int sy = y < img.height ? y : img.height - 1;
    const uint8_t* src = img.rgba.data() + static_cast<size_t>(sy) * src_row;
    uint8_t* dst = out.rgba.data() + static_cast<size_t>(y) * dst_row;
    std::memcpy(dst, src, src_row);
    for (size_t x = src_row; x < dst_row; x += 4) std::memcpy(dst + x, src + src_row - 4, 4);
  }
  return out;
}

CompressedImage as_compressed_image(const EncodedLevel& level) {
  CompressedImage img;
  img.format = level.format;
  img.width = static_cast<uint32_t>(level.width);
  img.height = static_cast<uint32_t>(level.height);
  img.block_w = level.block_w;
  img.block_h = level.block_h;
  img.block_bytes = format_block_bytes(level.format);
  CompressedLevel l;
  l.width = img.width;
  l.height = img.height;
  l.bytes = level.bytes;
  img.levels.push_back(std::move(l));
  return img;
}

}  // namespace texsim
