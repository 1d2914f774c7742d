#include "blocks/texture/decode/eac_rg_decoder.h"

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<EacRgDecoder>);

std::array<EacRgDecoder::Values11, 2> EacRgDecoder::decode_rg11(Block block) const {
  return {channel_.decode_r11(block.subspan<0, 8>()), channel_.decode_r11(block.subspan<8, 8>())};
}

DecodedBlock EacRgDecoder::decode(Block block) const {
  const std::array<Values11, 2> v = decode_rg11(block);
  const bool snorm = config().snorm;
  DecodedBlock d;
  d.width = kBlockWidth;
  d.height = kBlockHeight;
  for (size_t i = 0; i < v[0].size(); ++i) {
    d.texels[i] = {EacDecoder::to_float(v[0][i], snorm), EacDecoder::to_float(v[1][i], snorm), 0.0F,
                   1.0F};
  }
  return d;
}

TimingSpec EacRgDecoder::timing(const TechTable& t) const {
  // The two channels side by side: one channel's chain, twice its operators.
  return derive_timing(t, ops_per_item(), channel_.critical_path(), config().datapath);
}

}  // namespace texsim
