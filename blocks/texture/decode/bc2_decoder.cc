#include "blocks/texture/decode/bc2_decoder.h"

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/base/derive_timing.h"
#include "blocks/texture/decode/bc1_decoder.h"

namespace texsim {

static_assert(Block<Bc2Decoder>);

Bc2Decoder::Config Bc2Decoder::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"datapath"});
  Config c;
  c.datapath = parse_datapath(r, c.datapath);
  return c;
}

DecodedBlock Bc2Decoder::decode(std::span<const uint8_t, kBlockBytes> block) const {
  DecodedBlock out;
  Bc1Decoder::decode_colour(block.subspan<8, 8>(), false, false, out);
  for (size_t t = 0; t < 16; ++t) {
    const uint32_t a = (block[t / 2] >> (4 * (t % 2))) & 15U;
    out.texels[t].a = static_cast<float>(a) / 15.0F;
  }
  return out;
}

OpCounts Bc2Decoder::ops_per_item() const {
  OpCounts o = Bc1Decoder::colour_ops(false, false);
  o.mul += 16;  // each texel's alpha times 1/15
  return o;
}

TimingSpec Bc2Decoder::timing(const TechTable& tech) const {
  // The alpha path (one multiply) runs beside the colour path, which is longer.
  return derive_timing(tech, ops_per_item(), Bc1Decoder::colour_path(), cfg_.datapath);
}

}  // namespace texsim
