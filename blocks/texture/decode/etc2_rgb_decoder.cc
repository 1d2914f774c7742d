#include "blocks/texture/decode/etc2_rgb_decoder.h"

#include <algorithm>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/texture/decode/etc_tables.h"

namespace texsim {

static_assert(Block<Etc2RgbDecoder>);

namespace {

using Mode = Etc2RgbDecoder::Mode;
using Texels8 = Etc2RgbDecoder::Texels8;
using Rgb = std::array<int, 3>;

using etc_tables::kDistances;
using etc_tables::kModifiers;

// The block as the spec's int64bit: q0 is the most significant byte.
uint64_t block_word(Etc2RgbDecoder::Block b) {
  uint64_t w = 0;
  for (uint8_t q : b) w = (w << 8) | q;
  return w;
}

// `n` bits of the word from bit `lo` up.
int bits(uint64_t w, int lo, int n) {
  return static_cast<int>((w >> lo) & ((uint64_t{1} << n) - 1));
}
int signed3(int v) { return v >= 4 ? v - 8 : v; }  // a 3-bit two's-complement field
// Widening by bit replication: the field's top bits repeated below it.
int extend4(int v) { return (v << 4) | v; }
int extend5(int v) { return (v << 3) | (v >> 2); }
int extend6(int v) { return (v << 2) | (v >> 4); }
int extend7(int v) { return (v << 1) | (v >> 6); }
uint8_t clamp255(int v) { return static_cast<uint8_t>(std::clamp(v, 0, 255)); }
Rgb extend4(Rgb c) { return {extend4(c[0]), extend4(c[1]), extend4(c[2])}; }
Rgb plus(Rgb c, int d) { return {c[0] + d, c[1] + d, c[2] + d}; }

// The 2-bit index of texel (x, y): texels are numbered column by column (i = x * 4 + y), the
// most significant bit at bit 16 + i, the least at bit i.
int texel_index(uint64_t w, int x, int y) {
  const int i = x * 4 + y;
  return (bits(w, 16 + i, 1) << 1) | bits(w, i, 1);
}

void put(Texels8& out, int x, int y, Rgb c, uint8_t alpha) {
  out[static_cast<size_t>(y) * 4 + static_cast<size_t>(x)] = {clamp255(c[0]), clamp255(c[1]),
                                                              clamp255(c[2]), alpha};
}

Mode select_mode(uint64_t w, bool punch_through) {
  if (!punch_through && bits(w, 33, 1) == 0) return Mode::Individual;
  const auto outside = [&](int lo) {
    const int s = bits(w, lo + 3, 5) + signed3(bits(w, lo, 3));
    return s < 0 || s > 31;
  };
  if (outside(56)) return Mode::T;
  if (outside(48)) return Mode::H;
  if (outside(40)) return Mode::Planar;
  return Mode::Differential;
}

// Individual and differential modes: two subblocks (2x4 side by side, or 4x2 one above the
// other when the flip bit 32 is set), each a base colour plus a modifier of its table.
void decode_subblocks(uint64_t w, Mode mode, bool opaque, Texels8& out) {
  std::array<Rgb, 2> base{};
  if (mode == Mode::Individual) {
    base[0] = extend4(Rgb{bits(w, 60, 4), bits(w, 52, 4), bits(w, 44, 4)});
    base[1] = extend4(Rgb{bits(w, 56, 4), bits(w, 48, 4), bits(w, 40, 4)});
  } else {
    for (int c = 0; c < 3; ++c) {
      const int lo = 56 - 8 * c;  // dR at 58-56, dG at 50-48, dB at 42-40
      const int v = bits(w, lo + 3, 5);
      base[0][static_cast<size_t>(c)] = extend5(v);
      base[1][static_cast<size_t>(c)] = extend5(v + signed3(bits(w, lo, 3)));
    }
  }
  const std::array<int, 2> table = {bits(w, 37, 3), bits(w, 34, 3)};
  const bool flip = bits(w, 32, 1) != 0;
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      const int idx = texel_index(w, x, y);
      if (!opaque && idx == 2) {
        put(out, x, y, {0, 0, 0}, 0);
        continue;
      }
      const size_t sub = (flip ? y : x) >= 2 ? 1 : 0;
      // Index 0: +a, 1: +b, 2: -a, 3: -b; without the opaque bit the a column is 0.
      int m = kModifiers[static_cast<size_t>(table[sub])][static_cast<size_t>(idx & 1)];
      if (!opaque && (idx & 1) == 0) m = 0;
      put(out, x, y, plus(base[sub], idx >= 2 ? -m : m), 255);
    }
  }
}

// T and H modes: four paint colours from two 4-bit base colours and a distance.
void decode_paint(uint64_t w, Mode mode, bool opaque, Texels8& out) {
  std::array<Rgb, 4> paint{};
  if (mode == Mode::T) {
    const Rgb c1 =
        extend4(Rgb{(bits(w, 59, 2) << 2) | bits(w, 56, 2), bits(w, 52, 4), bits(w, 48, 4)});
    const Rgb c2 = extend4(Rgb{bits(w, 44, 4), bits(w, 40, 4), bits(w, 36, 4)});
    const int d = kDistances[static_cast<size_t>((bits(w, 34, 2) << 1) | bits(w, 32, 1))];
    paint = {c1, plus(c2, d), c2, plus(c2, -d)};
  } else {
    const Rgb c1 = extend4(Rgb{bits(w, 59, 4), (bits(w, 56, 3) << 1) | bits(w, 52, 1),
                               (bits(w, 51, 1) << 3) | bits(w, 47, 3)});
    const Rgb c2 = extend4(Rgb{bits(w, 43, 4), bits(w, 39, 4), bits(w, 35, 4)});
    // The distance index's least significant bit is the ordering of the base colours.
    const auto value = [](const Rgb& c) { return (c[0] << 16) + (c[1] << 8) + c[2]; };
    const int order = value(c1) >= value(c2) ? 1 : 0;
    const int d =
        kDistances[static_cast<size_t>((bits(w, 34, 1) << 2) | (bits(w, 32, 1) << 1) | order)];
    paint = {plus(c1, d), plus(c1, -d), plus(c2, d), plus(c2, -d)};
  }
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      const int idx = texel_index(w, x, y);
      if (!opaque && idx == 2) {
        put(out, x, y, {0, 0, 0}, 0);
      } else {
        put(out, x, y, paint[static_cast<size_t>(idx)], 255);
      }
    }
  }
}

// Planar mode: colours O, H and V (RGB 676) and the plane through them, rounded
// (ties up) and clamped: (x (H - O) + y (V - O) + 4 O + 2) >> 2. Always opaque.
void decode_planar(uint64_t w, Texels8& out) {
  const Rgb o = {extend6(bits(w, 57, 6)), extend7((bits(w, 56, 1) << 6) | bits(w, 49, 6)),
                 extend6((bits(w, 48, 1) << 5) | (bits(w, 43, 2) << 3) | bits(w, 39, 3))};
  const Rgb h = {extend6((bits(w, 34, 5) << 1) | bits(w, 32, 1)), extend7(bits(w, 25, 7)),
                 extend6(bits(w, 19, 6))};
  const Rgb v = {extend6(bits(w, 13, 6)), extend7(bits(w, 6, 7)), extend6(bits(w, 0, 6))};
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      Rgb c{};
      for (size_t k = 0; k < 3; ++k) {
        // An arithmetic shift of the signed sum: floor((s + 2) / 4).
        c[k] = (x * (h[k] - o[k]) + y * (v[k] - o[k]) + 4 * o[k] + 2) >> 2;
      }
      put(out, x, y, c, 255);
    }
  }
}

}  // namespace

Etc2RgbDecoder::Config Etc2RgbDecoder::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"punch_through", "datapath"});
  Config c;
  c.punch_through = r.get_bool("punch_through", c.punch_through);
  c.datapath = parse_datapath(r, c.datapath);
  return c;
}

Etc2RgbDecoder::Mode Etc2RgbDecoder::mode(Block block) const {
  return select_mode(block_word(block), cfg_.punch_through);
}

Etc2RgbDecoder::Texels8 Etc2RgbDecoder::decode_rgba8(Block block) const {
  const uint64_t w = block_word(block);
  const Mode m = select_mode(w, cfg_.punch_through);
  // Without punch-through every block is opaque; with it, bit 33 says so.
  const bool opaque = !cfg_.punch_through || bits(w, 33, 1) != 0;
  Texels8 out{};
  switch (m) {
    case Mode::Individual:
    case Mode::Differential:
      decode_subblocks(w, m, opaque, out);
      break;
    case Mode::T:
    case Mode::H:
      decode_paint(w, m, opaque, out);
      break;
    case Mode::Planar:
      decode_planar(w, out);  // opaque even when the opaque bit is 0 (the spec's rule)
      break;
  }
  return out;
}

DecodedBlock Etc2RgbDecoder::decode(Block block) const {
  return decoded_from_rgba8(decode_rgba8(block));
}

OpCounts Etc2RgbDecoder::ops_per_item() const {
  OpCounts o;
  // Mode selection: R + dR, G + dG, B + dB (also the differential mode's second base colour)
  // and their range checks.
  o.add += 3;
  o.cmp += 3;
  // Individual / differential: the two table codewords' (a, b), each texel's modifier
  // select, base + modifier per channel, clamp.
  o.lut += 2;
  o.cmp += 16;
  o.add += 48;
  o.cmp += 48;
  // T / H: the distance, the H ordering compare, four paint colours (base ± d) and their
  // clamps, each texel's paint select.
  o.lut += 1;
  o.cmp += 1;
  o.add += 12;
  o.cmp += 12;
  o.cmp += 16;
  // Planar: H - O and V - O, their triples (2d + d), x (H - O) + y (V - O) + (4 O + 2) per
  // texel and channel, clamp.
  o.add += 6 + 6 + 96;
  o.cmp += 48;
  // Each texel channel's result from the mode's datapath.
  o.cmp += 48;
  // Punch-through: the transparent index check per texel.
  if (cfg_.punch_through) o.cmp += 16;
  return o;
}

TimingSpec Etc2RgbDecoder::timing(const TechTable& t) const {
  // The longest of two chains: planar (difference, triple, two adds, clamp, mode select) and
  // H (ordering compare, distance look-up, base ± d, clamp, paint select, mode select).
  OpCounts planar;
  planar.add = 4;
  planar.cmp = 2;
  OpCounts h;
  h.cmp = 4;
  h.lut = 1;
  h.add = 1;
  const double path = std::max(t.path_latency(planar), t.path_latency(h));
  return derive_timing(t, ops_per_item(), path, cfg_.datapath);
}

}  // namespace texsim
