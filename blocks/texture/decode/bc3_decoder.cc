#include "blocks/texture/decode/bc3_decoder.h"

#include <algorithm>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/base/derive_timing.h"
#include "blocks/texture/decode/bc1_decoder.h"
#include "blocks/texture/decode/bc4_decoder.h"

namespace texsim {

static_assert(Block<Bc3Decoder>);

Bc3Decoder::Config Bc3Decoder::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"datapath"});
  Config c;
  c.datapath = parse_datapath(r, c.datapath);
  return c;
}

DecodedBlock Bc3Decoder::decode(std::span<const uint8_t, kBlockBytes> block) const {
  DecodedBlock out;
  Bc1Decoder::decode_colour(block.subspan<8, 8>(), false, false, out);
  const auto alpha = Bc4Decoder::decode_channel(block.first<8>(), false);
  for (size_t t = 0; t < 16; ++t) out.texels[t].a = alpha[t];
  return out;
}

OpCounts Bc3Decoder::ops_per_item() const {
  return Bc1Decoder::colour_ops(false, false) + Bc4Decoder::channel_ops(false);
}

TimingSpec Bc3Decoder::timing(const TechTable& tech) const {
  // Colour and alpha run side by side: the longer of the two paths.
  const double path = std::max(tech.path_latency(Bc1Decoder::colour_path()),
                               tech.path_latency(Bc4Decoder::channel_path(false)));
  return derive_timing(tech, ops_per_item(), path, cfg_.datapath);
}

}  // namespace texsim
