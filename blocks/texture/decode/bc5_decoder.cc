#include "blocks/texture/decode/bc5_decoder.h"

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/base/derive_timing.h"
#include "blocks/texture/decode/bc4_decoder.h"

namespace texsim {

static_assert(Block<Bc5Decoder>);

Bc5Decoder::Config Bc5Decoder::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"snorm", "datapath"});
  Config c;
  c.snorm = r.get_bool("snorm", c.snorm);
  c.datapath = parse_datapath(r, c.datapath);
  return c;
}

DecodedBlock Bc5Decoder::decode(std::span<const uint8_t, kBlockBytes> block) const {
  DecodedBlock out;
  out.width = 4;
  out.height = 4;
  const auto red = Bc4Decoder::decode_channel(block.first<8>(), cfg_.snorm);
  const auto green = Bc4Decoder::decode_channel(block.last<8>(), cfg_.snorm);
  for (size_t t = 0; t < 16; ++t) out.texels[t] = {red[t], green[t], 0.0F, 1.0F};
  return out;
}

OpCounts Bc5Decoder::ops_per_item() const { return Bc4Decoder::channel_ops(cfg_.snorm) * 2; }

TimingSpec Bc5Decoder::timing(const TechTable& tech) const {
  // The two channels run side by side.
  return derive_timing(tech, ops_per_item(), Bc4Decoder::channel_path(cfg_.snorm), cfg_.datapath);
}

}  // namespace texsim
