#include "blocks/texture/decode/bc7_decoder.h"

#include <array>
#include <bit>
#include <utility>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/base/derive_timing.h"
#include "blocks/texture/decode/bc7_tables.h"

namespace texsim {

static_assert(Block<Bc7Decoder>);

namespace {

// The mode parameters of DFS table "Mode-dependent BPTC parameters".
struct ModeInfo {
  int subsets;         // NS
  int partition_bits;  // PB
  int rotation_bits;   // RB
  int selection_bits;  // ISB
  int colour_bits;     // CB
  int alpha_bits;      // AB
  int endpoint_pbits;  // EPB: one p-bit per endpoint
  int shared_pbits;    // SPB: one p-bit per subset
  int index_bits;      // IB
  int secondary_bits;  // IB2
};
constexpr std::array<ModeInfo, 8> kModes = {{
    {3, 4, 0, 0, 4, 0, 1, 0, 3, 0},
    {2, 6, 0, 0, 6, 0, 0, 1, 3, 0},
    {3, 6, 0, 0, 5, 0, 0, 0, 2, 0},
    {2, 6, 0, 0, 7, 0, 1, 0, 2, 0},
    {1, 0, 2, 1, 5, 6, 0, 0, 2, 3},
    {1, 0, 2, 0, 7, 8, 0, 0, 2, 2},
    {1, 0, 0, 0, 7, 7, 1, 0, 4, 0},
    {2, 6, 0, 0, 5, 5, 1, 0, 2, 0},
}};

// The 6-bit interpolation weights of 2-, 3- and 4-bit indices (DFS "BPTC interpolation
// factors").
constexpr std::array<uint8_t, 4> kWeights2 = {0, 21, 43, 64};
constexpr std::array<uint8_t, 8> kWeights3 = {0, 9, 18, 27, 37, 46, 55, 64};
constexpr std::array<uint8_t, 16> kWeights4 = {0,  4,  9,  13, 17, 21, 26, 30,
                                               34, 38, 43, 47, 51, 55, 60, 64};

uint32_t weight(int bits, uint32_t index) {
  if (bits == 2) return kWeights2[index & 3U];
  if (bits == 3) return kWeights3[index & 7U];
  return kWeights4[index & 15U];
}

// Reads fields of the 128-bit little-endian block from bit 0 upwards. Every mode's fields sum
// to exactly 128 bits; a read past the end would return zeros.
class BitReader {
 public:
  explicit BitReader(std::span<const uint8_t, 16> b) : bytes_(b) {}
  uint32_t read(int n) {
    uint32_t v = 0;
    for (int i = 0; i < n; ++i, ++pos_) {
      if (pos_ < 128) v |= ((bytes_[static_cast<size_t>(pos_ / 8)] >> (pos_ % 8)) & 1U) << i;
    }
    return v;
  }
  int pos() const { return pos_; }

 private:
  std::span<const uint8_t, 16> bytes_;
  int pos_ = 0;
};

// A `bits`-wide endpoint value to 8 bits: shifted to the top and its top bits replicated into
// the rest (4 <= bits <= 8).
uint32_t expand_to_8(uint32_t v, int bits) {
  if (bits >= 8) return v;
  return (v << (8 - bits)) | (v >> (2 * bits - 8));
}

// Endpoint channels: [subset * 2 + endpoint][channel], 8 bits each.
using Endpoints = std::array<std::array<uint32_t, 4>, 6>;

Endpoints read_endpoints(const ModeInfo& m, BitReader& br) {
  const int count = 2 * m.subsets;
  Endpoints e{};
  for (int c = 0; c < 3; ++c) {
    for (int i = 0; i < count; ++i)
      e[static_cast<size_t>(i)][static_cast<size_t>(c)] = br.read(m.colour_bits);
  }
  for (int i = 0; i < count; ++i) e[static_cast<size_t>(i)][3] = br.read(m.alpha_bits);
  std::array<uint32_t, 6> pbit{};
  if (m.endpoint_pbits != 0) {
    for (int i = 0; i < count; ++i) pbit[static_cast<size_t>(i)] = br.read(1);
  } else if (m.shared_pbits != 0) {
    for (int s = 0; s < m.subsets; ++s) {
      const uint32_t p = br.read(1);  // subset s's two endpoints share it
      pbit[2 * static_cast<size_t>(s)] = pbit[2 * static_cast<size_t>(s) + 1] = p;
    }
  }
  const bool has_pbit = m.endpoint_pbits != 0 || m.shared_pbits != 0;
  for (int i = 0; i < count; ++i) {
    auto& ep = e[static_cast<size_t>(i)];
    for (size_t c = 0; c < 4; ++c) {
      const int bits = c < 3 ? m.colour_bits : m.alpha_bits;
      if (bits == 0) {  // no alpha in the mode: 255
        ep[c] = 255;
        continue;
      }
      uint32_t v = ep[c];
      int width = bits;
      if (has_pbit) {  // the p-bit goes below the stored bits
        v = (v << 1) | pbit[static_cast<size_t>(i)];
        ++width;
      }
      ep[c] = expand_to_8(v, width);
    }
  }
  return e;
}

// Subset of texel t and whether t is the anchor of its subset.
struct TexelSubset {
  int subset;
  bool anchor;
};
TexelSubset subset_of(int subsets, uint32_t partition, int t) {
  const auto p = static_cast<size_t>(partition & 63U);
  const auto ti = static_cast<size_t>(t);
  if (subsets == 2) {
    const int s = bc7::kBc7Partition2[p][ti];
    return {s, t == 0 || t == bc7::kBc7Anchor2[p]};
  }
  if (subsets == 3) {
    const int s = bc7::kBc7Partition3[p][ti];
    return {s, t == 0 || t == bc7::kBc7Anchor3Second[p] || t == bc7::kBc7Anchor3Third[p]};
  }
  return {0, t == 0};
}

uint32_t interpolate(uint32_t e0, uint32_t e1, uint32_t w) {
  return ((64 - w) * e0 + w * e1 + 32) >> 6;
}

}  // namespace

Bc7Decoder::Config Bc7Decoder::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"datapath"});
  Config c;
  c.datapath = parse_datapath(r, c.datapath);
  return c;
}

int Bc7Decoder::mode_of(std::span<const uint8_t, kBlockBytes> block) {
  if (block[0] == 0) return kReservedMode;
  return std::countr_zero(static_cast<unsigned>(block[0]));
}

DecodedBlock Bc7Decoder::decode(std::span<const uint8_t, kBlockBytes> block) const {
  DecodedBlock out;
  out.width = kBlockSize;
  out.height = kBlockSize;
  const int mode = mode_of(block);
  if (mode == kReservedMode) return out;  // every channel of every texel 0
  const ModeInfo& m = kModes[static_cast<size_t>(mode)];
  BitReader br(block);
  br.read(mode + 1);
  const uint32_t partition = br.read(m.partition_bits);
  const uint32_t rotation = br.read(m.rotation_bits);
  const uint32_t selection = br.read(m.selection_bits);
  const Endpoints e = read_endpoints(m, br);
  std::array<TexelSubset, 16> sub{};
  std::array<uint32_t, 16> primary{};
  std::array<uint32_t, 16> secondary{};
  for (int t = 0; t < 16; ++t) {
    sub[static_cast<size_t>(t)] = subset_of(m.subsets, partition, t);
    primary[static_cast<size_t>(t)] =
        br.read(sub[static_cast<size_t>(t)].anchor ? m.index_bits - 1 : m.index_bits);
  }
  if (m.secondary_bits != 0) {
    for (int t = 0; t < 16; ++t)
      secondary[static_cast<size_t>(t)] = br.read(t == 0 ? m.secondary_bits - 1 : m.secondary_bits);
  }
  for (size_t t = 0; t < 16; ++t) {
    // Colour from the secondary indices when the selection bit is set; alpha from the
    // secondary ones when there are some and the selection bit is clear.
    uint32_t wc = weight(m.index_bits, primary[t]);
    uint32_t wa = wc;
    if (m.secondary_bits != 0) {
      const uint32_t w2 = weight(m.secondary_bits, secondary[t]);
      if (selection != 0) {
        wc = w2;
      } else {
        wa = w2;
      }
    }
    const auto& e0 = e[2 * static_cast<size_t>(sub[t].subset)];
    const auto& e1 = e[2 * static_cast<size_t>(sub[t].subset) + 1];
    std::array<uint32_t, 4> v{};
    for (size_t c = 0; c < 4; ++c) v[c] = interpolate(e0[c], e1[c], c < 3 ? wc : wa);
    if (rotation != 0) std::swap(v[3], v[rotation - 1]);  // 1: A<->R, 2: A<->G, 3: A<->B
    for (int c = 0; c < 4; ++c)
      out.texels[t][c] = static_cast<float>(v[static_cast<size_t>(c)]) / 255.0F;
  }
  return out;
}

OpCounts Bc7Decoder::ops_per_item() const {
  constexpr uint64_t kTexels = 16;
  constexpr uint64_t kChannels = 4;
  OpCounts o;
  o.lut = 1 + 1;                     // mode (lowest set bit of byte 0), partition and anchor tables
  o.cmp = kTexels * 2;               // per texel, its position against the two anchors: its offset
  o.lut += kTexels * 2;              // per texel, the weights of its primary and secondary index
  o.cmp += kTexels * 2;              // per texel, the index selection bit's swap of the two weights
  o.cmp += kTexels * kChannels;      // per texel and channel, the endpoint pair of its subset
  o.add += kTexels * 2;              // 64 - w, colour and alpha weight
  o.mul += kTexels * kChannels * 2;  // (64 - w)·E0 and w·E1 per channel
  o.add += kTexels * kChannels * 2;  // their sum and the rounding 32
  o.cmp += kTexels * kChannels;      // rotation: per texel and channel, a 2:1 select
  o.mul += kTexels * kChannels;      // each 8-bit result times 1/255
  return o;
}

OpCounts Bc7Decoder::critical_path() {
  OpCounts p;
  p.lut = 2;   // mode, then partition and anchors
  p.cmp = 3;   // index offset, subset's endpoints, rotation
  p.lut += 1;  // weight
  p.mul = 2;   // w·E1, then the normalisation
  p.add = 2;   // sum, rounding
  return p;
}

TimingSpec Bc7Decoder::timing(const TechTable& tech) const {
  return derive_timing(tech, ops_per_item(), critical_path(), cfg_.datapath);
}

}  // namespace texsim
