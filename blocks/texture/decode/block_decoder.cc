#include "blocks/texture/decode/block_decoder.h"

#include <span>
#include <stdexcept>

#include "blocks/texture/decode/astc_decoder.h"
#include "blocks/texture/decode/bc1_decoder.h"
#include "blocks/texture/decode/bc2_decoder.h"
#include "blocks/texture/decode/bc3_decoder.h"
#include "blocks/texture/decode/bc4_decoder.h"
#include "blocks/texture/decode/bc5_decoder.h"
#include "blocks/texture/decode/bc7_decoder.h"
#include "blocks/texture/decode/eac_decoder.h"
#include "blocks/texture/decode/eac_rg_decoder.h"
#include "blocks/texture/decode/etc2_rgb_decoder.h"
#include "blocks/texture/decode/etc2_rgba_decoder.h"

namespace texsim {

namespace {

// Calls fn with the decoder block of format f.
template <class Fn>
auto with_decoder(CompressedFormat f, Fn&& fn) {
  using CF = CompressedFormat;
  switch (f) {
    case CF::Bc1Rgb:
      return fn(Bc1Decoder({false}));
    case CF::Bc1Rgba:
      return fn(Bc1Decoder({true}));
    case CF::Bc2:
      return fn(Bc2Decoder());
    case CF::Bc3:
      return fn(Bc3Decoder());
    case CF::Bc4:
      return fn(Bc4Decoder({false}));
    case CF::Bc4Snorm:
      return fn(Bc4Decoder({true}));
    case CF::Bc5:
      return fn(Bc5Decoder({false}));
    case CF::Bc5Snorm:
      return fn(Bc5Decoder({true}));
    case CF::Bc7:
      return fn(Bc7Decoder());
    case CF::Etc2Rgb8:
      return fn(Etc2RgbDecoder({false}));
    case CF::Etc2Rgb8A1:
      return fn(Etc2RgbDecoder({true}));
    case CF::Etc2Rgba8:
      return fn(Etc2RgbaDecoder());
    case CF::EacR11:
      return fn(EacDecoder({false}));
    case CF::EacR11Snorm:
      return fn(EacDecoder({true}));
    case CF::EacRg11:
      return fn(EacRgDecoder({false}));
    case CF::EacRg11Snorm:
      return fn(EacRgDecoder({true}));
    default:
      break;
  }
  const CompressedFormatInfo& i = format_info(f);
  if (i.family == CodecFamily::Astc) {
    AstcDecoder::Config c;
    c.block_width = i.block_w;
    c.block_height = i.block_h;
    return fn(AstcDecoder(c));
  }
  throw std::logic_error("no decoder for " + std::string(to_string(f)));  // unreachable
}

}  // namespace

std::string decoder_arithmetic(CompressedFormat f) {
  return with_decoder(f, [](const auto& d) { return d.arithmetic(); });
}

DecodedBlock decode_block(CompressedFormat f, const uint8_t* block) {
  return with_decoder(f, [block](const auto& d) {
    using D = std::decay_t<decltype(d)>;
    return d.decode(std::span<const uint8_t, D::kBlockBytes>(block, D::kBlockBytes));
  });
}

OpCounts decoder_ops(CompressedFormat f) {
  return with_decoder(f, [](const auto& d) { return d.ops_per_item(); });
}

TimingSpec decoder_timing(CompressedFormat f, const TechTable& tech) {
  return with_decoder(f, [&tech](const auto& d) { return d.timing(tech); });
}

std::string decoder_name(CompressedFormat f) {
  // One row per format (a block's configurations, e.g. BC1 with alpha or an ASTC footprint,
  // cost differently): "decode.bc1_rgb", "decode.astc_6x6".
  return "decode." + std::string(to_string(f));
}

}  // namespace texsim
