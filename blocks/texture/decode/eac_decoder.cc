#include "blocks/texture/decode/eac_decoder.h"

#include <algorithm>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/texture/decode/etc_tables.h"

namespace texsim {

static_assert(Block<EacDecoder>);

namespace {

using etc_tables::kEacModifiers;

// The block as the spec's int64bit: q0 is the most significant byte.
uint64_t block_word(EacDecoder::Block b) {
  uint64_t w = 0;
  for (uint8_t q : b) w = (w << 8) | q;
  return w;
}

// The fields of an EAC word: base codeword (bits 63-56), multiplier (55-52), table (51-48) and
// the modifier of texel (x, y), whose 3-bit index sits at bits 47-45 for a, 44-42 for b, ...
// (texels column by column: index i = x * 4 + y).
struct EacFields {
  uint64_t word;
  int base() const { return static_cast<int>(word >> 56); }
  int multiplier() const { return static_cast<int>((word >> 52) & 0xF); }
  int modifier(int x, int y) const {
    const int i = x * 4 + y;
    const auto index = static_cast<size_t>((word >> (45 - 3 * i)) & 7);
    return kEacModifiers[static_cast<size_t>((word >> 48) & 0xF)][index];
  }
};

}  // namespace

EacDecoder::Config EacDecoder::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"snorm", "datapath"});
  Config c;
  c.snorm = r.get_bool("snorm", c.snorm);
  c.datapath = parse_datapath(r, c.datapath);
  return c;
}

EacDecoder::Values11 EacDecoder::decode_r11(Block block) const {
  const EacFields f{block_word(block)};
  // UNORM: base * 8 + 4; SNORM: the base is two's complement, -128 read as -127, and no +4.
  int base = f.base() * 8 + 4;
  if (cfg_.snorm) base = std::max(static_cast<int>(static_cast<int8_t>(f.base())), -127) * 8;
  const int lo = cfg_.snorm ? -1023 : 0;
  const int hi = cfg_.snorm ? 1023 : 2047;
  const int mult = f.multiplier();
  Values11 out{};
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      const int m = f.modifier(x, y);
      // Multiplier 0 stands for 1/8: the modifier is added unscaled.
      const int v = base + (mult == 0 ? m : m * mult * 8);
      out[static_cast<size_t>(y) * 4 + static_cast<size_t>(x)] =
          static_cast<int16_t>(std::clamp(v, lo, hi));
    }
  }
  return out;
}

EacDecoder::Values8 EacDecoder::decode_alpha8(Block block) {
  const EacFields f{block_word(block)};
  Values8 out{};
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      const int v = f.base() + f.modifier(x, y) * f.multiplier();
      out[static_cast<size_t>(y) * 4 + static_cast<size_t>(x)] =
          static_cast<uint8_t>(std::clamp(v, 0, 255));
    }
  }
  return out;
}

DecodedBlock EacDecoder::decode(Block block) const {
  const Values11 v = decode_r11(block);
  DecodedBlock d;
  d.width = kBlockWidth;
  d.height = kBlockHeight;
  for (size_t i = 0; i < v.size(); ++i)
    d.texels[i] = {to_float(v[i], cfg_.snorm), 0.0F, 0.0F, 1.0F};
  return d;
}

OpCounts EacDecoder::ops_per_item() const {
  OpCounts o;
  o.lut = 1;                   // the table codeword selects one of 16 modifier rows
  o.mul = 8;                   // the row's 8 modifiers times the multiplier (4 x 4 bits)
  o.cmp = 1;                   // multiplier == 0
  o.cmp += 16;                 // each texel's 3-bit index selects its scaled modifier
  o.add = 16;                  // base + scaled modifier
  o.cmp += 16;                 // clamp to 11 bits
  if (cfg_.snorm) o.cmp += 1;  // base codeword -128 read as -127
  return o;
}

OpCounts EacDecoder::critical_path() const {
  OpCounts p;
  p.lut = 1;  // modifier row
  p.mul = 1;  // times the multiplier
  p.cmp = 2;  // per-texel select, then clamp
  p.add = 1;
  return p;
}

TimingSpec EacDecoder::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), critical_path(), cfg_.datapath);
}

}  // namespace texsim
