#include "blocks/texture/decode/bc1_decoder.h"

#include <array>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/base/derive_timing.h"

namespace texsim {

static_assert(Block<Bc1Decoder>);

namespace {

// One palette entry as exact rationals: channel c is num[c] / den[c].
struct Rational3 {
  std::array<uint32_t, 3> num{};
  std::array<uint32_t, 3> den{1, 1, 1};
};

// The channels of an RGB565 value: R in bits 15..11, G in 10..5, B in 4..0.
std::array<uint32_t, 3> channels565(uint32_t c) { return {c >> 11, (c >> 5) & 63U, c & 31U}; }
constexpr std::array<uint32_t, 3> kMax565 = {31, 63, 31};

}  // namespace

Bc1Decoder::Config Bc1Decoder::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"alpha", "datapath"});
  Config c;
  c.alpha = r.get_bool("alpha", c.alpha);
  c.datapath = parse_datapath(r, c.datapath);
  return c;
}

void Bc1Decoder::decode_colour(std::span<const uint8_t, kBlockBytes> block, bool three_colour_mode,
                               bool alpha_punch_through, DecodedBlock& out) {
  const uint32_t colour0 = block[0] | (uint32_t{block[1]} << 8);
  const uint32_t colour1 = block[2] | (uint32_t{block[3]} << 8);
  const uint32_t bits = block[4] | (uint32_t{block[5]} << 8) | (uint32_t{block[6]} << 16) |
                        (uint32_t{block[7]} << 24);
  const bool four = !three_colour_mode || colour0 > colour1;
  const auto e0 = channels565(colour0);
  const auto e1 = channels565(colour1);
  std::array<Rational3, 4> pal{};
  for (size_t c = 0; c < 3; ++c) {
    pal[0].num[c] = e0[c];
    pal[0].den[c] = kMax565[c];
    pal[1].num[c] = e1[c];
    pal[1].den[c] = kMax565[c];
    if (four) {  // exact thirds of the two endpoints
      pal[2].num[c] = 2 * e0[c] + e1[c];
      pal[3].num[c] = e0[c] + 2 * e1[c];
      pal[2].den[c] = pal[3].den[c] = 3 * kMax565[c];
    } else {  // the exact half, and black
      pal[2].num[c] = e0[c] + e1[c];
      pal[2].den[c] = 2 * kMax565[c];
      pal[3].num[c] = 0;
    }
  }
  std::array<glm::vec4, 4> colours{};
  for (size_t i = 0; i < 4; ++i) {
    for (int c = 0; c < 3; ++c) {
      const auto ci = static_cast<size_t>(c);
      // Two integers below 2^24: one correctly rounded division is the exact value rounded once.
      colours[i][c] = static_cast<float>(pal[i].num[ci]) / static_cast<float>(pal[i].den[ci]);
    }
    colours[i].a = 1.0F;
  }
  if (!four && alpha_punch_through) colours[3].a = 0.0F;
  out.width = kBlockSize;
  out.height = kBlockSize;
  for (int t = 0; t < 16; ++t) {
    const uint32_t code = (bits >> (2 * t)) & 3U;
    out.texels[static_cast<size_t>(t)] = colours[code];
  }
}

DecodedBlock Bc1Decoder::decode(std::span<const uint8_t, kBlockBytes> block) const {
  DecodedBlock out;
  decode_colour(block, true, cfg_.alpha, out);
  return out;
}

OpCounts Bc1Decoder::colour_ops(bool three_colour_mode, bool alpha_out) {
  OpCounts o;
  // Per channel: 2c0+c1 and c0+2c1 (the doubling is wiring), and c0+c1 in the three-colour
  // mode, then the mode's choice of entries 2 and 3.
  o.add = uint64_t{3} * (three_colour_mode ? 3 : 2);
  if (three_colour_mode) {
    o.cmp = 1 + 3 * 2;  // colour0 > colour1, and the two entry selects per channel
  }
  o.mul = uint64_t{4} * 3;  // each palette channel times the constant reciprocal of its denominator
  // Per texel, a 4:1 select of the palette per output channel (alpha only when it varies).
  o.cmp += uint64_t{16} * (alpha_out ? 4 : 3);
  return o;
}

OpCounts Bc1Decoder::colour_path() {
  OpCounts p;
  p.add = 1;  // palette sum
  p.cmp = 2;  // mode select of the entry, texel select
  p.mul = 1;  // normalisation
  return p;
}

TimingSpec Bc1Decoder::timing(const TechTable& tech) const {
  return derive_timing(tech, ops_per_item(), colour_path(), cfg_.datapath);
}

}  // namespace texsim
