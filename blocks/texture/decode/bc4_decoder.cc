#include "blocks/texture/decode/bc4_decoder.h"

#include <algorithm>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/base/derive_timing.h"

namespace texsim {

static_assert(Block<Bc4Decoder>);

Bc4Decoder::Config Bc4Decoder::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"snorm", "datapath"});
  Config c;
  c.snorm = r.get_bool("snorm", c.snorm);
  c.datapath = parse_datapath(r, c.datapath);
  return c;
}

std::array<float, 16> Bc4Decoder::decode_channel(std::span<const uint8_t, kBlockBytes> block,
                                                 bool snorm) {
  // Stored endpoints (signed for SNORM) decide the mode; the values use -128 as -127, since
  // the DFS maps -128 to -1.0 = -127 / 127 and interpolates the mapped values.
  int32_t s0 = block[0];
  int32_t s1 = block[1];
  if (snorm) {
    s0 = s0 >= 128 ? s0 - 256 : s0;  // two's complement
    s1 = s1 >= 128 ? s1 - 256 : s1;
  }
  const int32_t e0 = std::max(s0, -127);
  const int32_t e1 = std::max(s1, -127);
  const int32_t scale = snorm ? 127 : 255;  // denominator of an endpoint
  std::array<int32_t, 8> num{};             // entry k is num[k] / den[k]
  std::array<int32_t, 8> den{};
  num[0] = e0;
  num[1] = e1;
  den[0] = den[1] = scale;
  if (s0 > s1) {
    for (int k = 1; k <= 6; ++k) {  // ((7 - k)·e0 + k·e1) / 7
      num[static_cast<size_t>(k) + 1] = (7 - k) * e0 + k * e1;
      den[static_cast<size_t>(k) + 1] = 7 * scale;
    }
  } else {
    for (int k = 1; k <= 4; ++k) {  // ((5 - k)·e0 + k·e1) / 5
      num[static_cast<size_t>(k) + 1] = (5 - k) * e0 + k * e1;
      den[static_cast<size_t>(k) + 1] = 5 * scale;
    }
    num[6] = snorm ? -1 : 0;  // min
    num[7] = 1;               // max
    den[6] = den[7] = 1;
  }
  std::array<float, 8> pal{};
  for (size_t k = 0; k < 8; ++k) {
    // Integers below 2^24: one correctly rounded division is the exact value rounded once.
    pal[k] = static_cast<float>(num[k]) / static_cast<float>(den[k]);
  }
  uint64_t bits = 0;
  for (int b = 5; b >= 0; --b) bits = (bits << 8) | block[2 + static_cast<size_t>(b)];
  std::array<float, 16> out{};
  for (int t = 0; t < 16; ++t) out[static_cast<size_t>(t)] = pal[(bits >> (3 * t)) & 7U];
  return out;
}

DecodedBlock Bc4Decoder::decode(std::span<const uint8_t, kBlockBytes> block) const {
  DecodedBlock out;
  out.width = kBlockSize;
  out.height = kBlockSize;
  const auto red = decode_channel(block, cfg_.snorm);
  for (size_t t = 0; t < 16; ++t) out.texels[t] = {red[t], 0.0F, 0.0F, 1.0F};
  return out;
}

OpCounts Bc4Decoder::channel_ops(bool snorm) {
  OpCounts o;
  o.cmp = 1;              // red0 > red1
  if (snorm) o.cmp += 2;  // -128 -> -127 on each endpoint
  // Weighted sums: each of the six sevenths and four fifths is a shift-add of two constant
  // multiples (2 adds), then the mode's choice of entries 2..7.
  o.add = uint64_t{2} * (6 + 4);
  o.cmp += 6;
  o.mul = 8;    // each palette entry times the constant reciprocal of its denominator
  o.cmp += 16;  // per texel, an 8:1 select of the palette
  return o;
}

OpCounts Bc4Decoder::channel_path(bool snorm) {
  OpCounts p;
  p.add = 2;              // weighted sum
  p.cmp = snorm ? 3 : 2;  // (SNORM clamp), mode select, texel select
  p.mul = 1;              // normalisation
  return p;
}

TimingSpec Bc4Decoder::timing(const TechTable& tech) const {
  return derive_timing(tech, ops_per_item(), channel_path(cfg_.snorm), cfg_.datapath);
}

}  // namespace texsim
