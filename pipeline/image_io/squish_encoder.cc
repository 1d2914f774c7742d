#include "pipeline/image_io/squish_encoder.h"

#include <squish.h>

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

EncodedLevel squish_encode(const Rgba8Image& img, CompressedFormat format, SquishFit fit) {
  const std::string who = "libsquish encoder";
  check_encoder_input(img, who, kMaxSide);
  int kind = 0;
  if (format == CompressedFormat::Bc1Unorm) kind = squish::kDxt1;
  if (format == CompressedFormat::Bc2Unorm) kind = squish::kDxt3;
  if (format == CompressedFormat::Bc3Unorm) kind = squish::kDxt5;
  if (kind == 0)
    throw InputError(who, std::string(format_name(format)) +
                              " is not encoded (BC1_UNORM, BC2_UNORM, BC3_UNORM are)");
  const Rgba8Image padded = padded_to_blocks(img, 4, 4);
  const int flags = kind | fit_flag(fit);
  EncodedLevel out;
  out.format = format;
  out.width = img.width;
  out.height = img.height;
  out.bytes.resize(
      static_cast<size_t>(squish::GetStorageRequirements(padded.width, padded.height, flags)));
  squish::CompressImage(padded.rgba.data(), padded.width, padded.height, out.bytes.data(), flags);
  out.provenance = std::string("libsquish ") + TEXSIM_SQUISH_VERSION + " (" + format_name(format) +
                   ", " + fit_flag_name(fit) + ")";
  return out;
}

}  // namespace texsim
