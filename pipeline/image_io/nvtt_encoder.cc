#include "pipeline/image_io/nvtt_encoder.h"

#include <nvtt/nvtt.h>

#include <utility>
#include <vector>

#include "blocks/base/input_error.h"

namespace texsim {

namespace {
constexpr int kMaxSide = 16384;

// Collects the blocks nvtt writes; with the file header off, everything written is blocks.
struct MemoryOutput : nvtt::OutputHandler {
  std::vector<uint8_t> bytes;
  void beginImage(int, int, int, int, int, int) override {}
  bool writeData(const void* data, int size) override {
    if (size < 0) return false;
    const auto* p = static_cast<const uint8_t*>(data);
    bytes.insert(bytes.end(), p, p + size);
    return true;
  }
};

struct ErrorRecord : nvtt::ErrorHandler {
  std::string message;
  void error(nvtt::Error e) override {
    if (message.empty()) message = nvtt::errorString(e);
  }
};

bool nvtt_format(FileBlockFormat f, nvtt::Format* out) {
  switch (f) {
    case FileBlockFormat::Bc1Unorm:
      *out = nvtt::Format_BC1;
      return true;
    case FileBlockFormat::Bc2Unorm:
      *out = nvtt::Format_BC2;
      return true;
    case FileBlockFormat::Bc3Unorm:
      *out = nvtt::Format_BC3;
      return true;
    case FileBlockFormat::Bc4Unorm:
      *out = nvtt::Format_BC4;
      return true;
    case FileBlockFormat::Bc5Unorm:
      *out = nvtt::Format_BC5;
      return true;
    default:
      return false;
  }
}

nvtt::Quality nvtt_quality(NvttQuality q) {
  switch (q) {
    case NvttQuality::Fastest:
      return nvtt::Quality_Fastest;
    case NvttQuality::Normal:
      return nvtt::Quality_Normal;
    case NvttQuality::Production:
      return nvtt::Quality_Production;
  }
  return nvtt::Quality_Normal;
}

// The release (from the library file's name at configure time) and what the library says:
// nvtt::version() is 200 for every 2.0.x.
std::string version_text() {
#ifdef TEXSIM_NVTT_VERSION
  const std::string release = TEXSIM_NVTT_VERSION;
#else
  const std::string release = "2.0.x";
#endif
  return release + " (nvtt::version() " + std::to_string(nvtt::version()) + ")";
}
}  // namespace

const char* nvtt_quality_name(NvttQuality q) {
  switch (q) {
    case NvttQuality::Fastest:
      return "fastest";
    case NvttQuality::Normal:
      return "normal";
    case NvttQuality::Production:
      return "production";
  }
  return "?";
}

EncodedLevel nvtt_encode(const Rgba8Image& img, FileBlockFormat format, NvttQuality quality) {
  const std::string who = "NVIDIA Texture Tools encoder";
  check_encoder_input(img, who, kMaxSide);
  nvtt::Format nf{};
  if (!nvtt_format(format, &nf))
    throw InputError(
        who, std::string(format_name(format)) + " is not encoded (BC1_UNORM to BC5_UNORM are)");
  const Rgba8Image padded = padded_to_blocks(img, 4, 4);
  std::vector<uint8_t> bgra(padded.rgba);  // nvtt's one input format is BGRA8
  for (size_t i = 0; i + 3 < bgra.size(); i += 4) std::swap(bgra[i], bgra[i + 2]);
  // nvtt 2.0.8 encodes BC4 from the alpha channel; BC4 is red, so red goes there.
  if (format == FileBlockFormat::Bc4Unorm)
    for (size_t i = 0; i + 3 < bgra.size(); i += 4) bgra[i + 3] = bgra[i + 2];

  nvtt::InputOptions in;
  in.setTextureLayout(nvtt::TextureType_2D, padded.width, padded.height);
  in.setFormat(nvtt::InputFormat_BGRA_8UB);
  in.setMipmapGeneration(false);
  if (!in.setMipmapData(bgra.data(), padded.width, padded.height))
    throw InputError(who, "the library refused the image");
  nvtt::CompressionOptions co;
  co.setFormat(nf);
  co.setQuality(nvtt_quality(quality));
  MemoryOutput sink;
  ErrorRecord errors;
  nvtt::OutputOptions oo;
  oo.setOutputHeader(false);
  oo.setOutputHandler(&sink);
  oo.setErrorHandler(&errors);
  nvtt::Compressor compressor;
  compressor.enableCudaAcceleration(false);
  if (!compressor.process(in, co, oo) || !errors.message.empty())
    throw InputError(
        who, "compression failed: " +
                 (errors.message.empty() ? std::string("no reason given") : errors.message));
  EncodedLevel out;
  out.format = format;
  out.width = img.width;
  out.height = img.height;
  const uint64_t want =
      level_block_count(static_cast<uint64_t>(img.width), static_cast<uint64_t>(img.height), 4, 4) *
      static_cast<uint64_t>(format_block_bytes(format));
  if (sink.bytes.size() != want)
    throw InputError(who, "produced " + std::to_string(sink.bytes.size()) + " bytes, " +
                              std::to_string(want) + " expected");
  out.bytes = std::move(sink.bytes);
  out.provenance = "NVIDIA Texture Tools " + version_text() + " (" + format_name(format) +
                   ", Quality_" +
                   (quality == NvttQuality::Fastest  ? "Fastest"
                    : quality == NvttQuality::Normal ? "Normal"
                                                     : "Production") +
                   ", CPU)";
  return out;
}

}  // namespace texsim
