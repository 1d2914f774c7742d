#include "pipeline/image_io/squish_encoder.h"

#include <squish.h>

#include <array>
#include <cstring>

#include "blocks/base/input_error.h"

#ifndef TEXSIM_SQUISH_VERSION
#define TEXSIM_SQUISH_VERSION "unknown"
#endif

namespace texsim {

namespace {
constexpr int kMaxSide = 16384;

int fit_flag(SquishFit fit) {
  switch (fit) {
    case SquishFit::Range:
      return squish::kColourRangeFit;
    case SquishFit::Cluster:
      return squish::kColourClusterFit;
    case SquishFit::IterativeCluster:
      return squish::kColourIterativeClusterFit;
  }
  return squish::kColourClusterFit;
}

const char* fit_flag_name(SquishFit fit) {
  switch (fit) {
    case SquishFit::Range:
      return "kColourRangeFit";
    case SquishFit::Cluster:
      return "kColourClusterFit";
    case SquishFit::IterativeCluster:
      return "kColourIterativeClusterFit";
  }
  return "?";
}
}  // namespace

const char* squish_fit_name(SquishFit fit) {
  switch (fit) {
    case SquishFit::Range:
      return "range";
    case SquishFit::Cluster:
      return "cluster";
    case SquishFit::IterativeCluster:
      return "iterative-cluster";
  }
  return "?";
}

EncodedLevel squish_encode(const Rgba8Image& img, FileBlockFormat format, SquishFit fit) {
  const std::string who = "libsquish encoder";
  check_encoder_input(img, who, kMaxSide);
  int kind = 0;
  if (format == FileBlockFormat::Bc1Unorm) kind = squish::kDxt1;
  if (format == FileBlockFormat::Bc2Unorm) kind = squish::kDxt3;
  if (format == FileBlockFormat::Bc3Unorm) kind = squish::kDxt5;
  if (kind == 0)
    throw InputError(who, std::string(format_name(format)) +
                              " is not encoded (BC1_UNORM, BC2_UNORM, BC3_UNORM are)");
  const Rgba8Image padded = padded_to_blocks(img, 4, 4);
  const int flags = kind | fit_flag(fit);
  EncodedLevel out;
  out.format = format;
  out.width = img.width;
  out.height = img.height;
  const size_t block_bytes = static_cast<size_t>(format_block_bytes(format));
  const int bx = padded.width / 4, by = padded.height / 4;
  out.bytes.resize(static_cast<size_t>(bx) * static_cast<size_t>(by) * block_bytes);
  // Block by block on the calling thread (CompressImage would start OpenMP's threads, which
  // compete with the simulator's own).
  const auto row_bytes = static_cast<size_t>(padded.width) * 4;
  std::array<uint8_t, 64> texels{};
  uint8_t* block = out.bytes.data();
  for (int y = 0; y < by; ++y) {
    for (int x = 0; x < bx; ++x) {
      for (size_t row = 0; row < 4; ++row) {
        const size_t from =
            (static_cast<size_t>(y) * 4 + row) * row_bytes + static_cast<size_t>(x) * 16;
        std::memcpy(texels.data() + row * 16, padded.rgba.data() + from, 16);
      }
      squish::Compress(texels.data(), block, flags);
      block += block_bytes;
    }
  }
  out.provenance = std::string("libsquish ") + TEXSIM_SQUISH_VERSION + " (" + format_name(format) +
                   ", " + fit_flag_name(fit) + ")";
  return out;
}

}  // namespace texsim
