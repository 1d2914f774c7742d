#include "blocks/texture/decode/etc2_rgba_decoder.h"

#include <algorithm>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/texture/decode/eac_decoder.h"

namespace texsim {

static_assert(Block<Etc2RgbaDecoder>);

Etc2RgbaDecoder::Config Etc2RgbaDecoder::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"datapath"});
  Config c;
  c.datapath = parse_datapath(r, c.datapath);
  return c;
}

Etc2RgbaDecoder::Texels8 Etc2RgbaDecoder::decode_rgba8(Block block) const {
  Texels8 out = rgb_.decode_rgba8(block.subspan<8, 8>());
  const EacDecoder::Values8 alpha = EacDecoder::decode_alpha8(block.subspan<0, 8>());
  for (size_t i = 0; i < out.size(); ++i) out[i][3] = alpha[i];
  return out;
}

DecodedBlock Etc2RgbaDecoder::decode(Block block) const {
  return decoded_from_rgba8(decode_rgba8(block));
}

OpCounts Etc2RgbaDecoder::ops_per_item() const {
  // The alpha half is the R11 datapath without the multiplier-0 compare (0 x modifier is 0).
  OpCounts alpha = EacDecoder().ops_per_item();
  alpha.cmp -= 1;
  return rgb_.ops_per_item() + alpha;
}

TimingSpec Etc2RgbaDecoder::timing(const TechTable& t) const {
  // The two halves run side by side: the longer chain is the RGB one or the alpha one.
  const TimingSpec rgb = rgb_.timing(t);
  const double path =
      std::max(static_cast<double>(rgb.latency), t.path_latency(EacDecoder().critical_path()));
  return derive_timing(t, ops_per_item(), path, cfg_.datapath);
}

}  // namespace texsim
