#include "pipeline/image_io/etc_encoder.h"

#include <cstring>

#include "blocks/base/input_error.h"

namespace texsim {

namespace {
constexpr int kMaxSide = 16384;

// The block's pixels from the padded image.
EtcPixels block_pixels(const Rgba8Image& img, int bx, int by) {
  EtcPixels px{};
  const auto row_bytes = static_cast<size_t>(img.width) * 4;
  for (size_t row = 0; row < 4; ++row) {
    const size_t from =
        (static_cast<size_t>(by) * 4 + row) * row_bytes + static_cast<size_t>(bx) * 16;
    for (size_t x = 0; x < 4; ++x)
      std::memcpy(px[row * 4 + x].data(), img.rgba.data() + from + x * 4, 4);
  }
  return px;
}

std::array<int, 16> channel(const EtcPixels& px, size_t k) {
  std::array<int, 16> v{};
  for (size_t i = 0; i < 16; ++i) v[i] = px[i][k];
  return v;
}

uint8_t* append(uint8_t* out, const EtcBlock& b) {
  std::memcpy(out, b.data(), b.size());
  return out + b.size();
}
}  // namespace

const char* etc_effort_name(EtcEffort e) { return e == EtcEffort::Fast ? "fast" : "normal"; }

EncodedLevel etc_encode(const Rgba8Image& img, FileBlockFormat format, EtcEffort effort) {
  const std::string who = "texsim etc encoder";
  check_encoder_input(img, who, kMaxSide);
  using F = FileBlockFormat;
  if (format != F::Etc2Rgb8 && format != F::Etc2Rgb8A1 && format != F::Etc2Rgba8 &&
      format != F::EacR11Unorm && format != F::EacRg11Unorm)
    throw InputError(who, std::string(format_name(format)) +
                              " is not encoded (ETC2_RGB8, ETC2_RGB8A1, ETC2_RGBA8, "
                              "EAC_R11_UNORM, EAC_RG11_UNORM are)");
  const Rgba8Image padded = padded_to_blocks(img, 4, 4);
  EncodedLevel out;
  out.format = format;
  out.width = img.width;
  out.height = img.height;
  const int bx = padded.width / 4, by = padded.height / 4;
  out.bytes.resize(static_cast<size_t>(bx) * static_cast<size_t>(by) *
                   static_cast<size_t>(format_block_bytes(format)));
  uint8_t* at = out.bytes.data();
  for (int y = 0; y < by; ++y) {
    for (int x = 0; x < bx; ++x) {
      const EtcPixels px = block_pixels(padded, x, y);
      switch (format) {
        case F::Etc2Rgb8:
        case F::Etc2Rgb8A1:
          at = append(at, etc_encode_rgb(px, format == F::Etc2Rgb8A1, effort));
          break;
        case F::Etc2Rgba8:  // the alpha block first
          at = append(at, eac_encode(channel(px, 3), EacKind::Alpha8, effort));
          at = append(at, etc_encode_rgb(px, false, effort));
          break;
        case F::EacRg11Unorm:  // red, then green
          at = append(at, eac_encode(channel(px, 0), EacKind::R11, effort));
          at = append(at, eac_encode(channel(px, 1), EacKind::R11, effort));
          break;
        default:  // EAC_R11_UNORM
          at = append(at, eac_encode(channel(px, 0), EacKind::R11, effort));
          break;
      }
    }
  }
  out.provenance = std::string("texsim etc encoder (") + format_name(format) + ", " +
                   etc_effort_name(effort) + ")";
  return out;
}

}  // namespace texsim
