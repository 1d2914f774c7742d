// BC7 decoder (blocks/texture/decode/bc7_decoder.h): directed cases from the Khronos Data
// Format Specification 1.3 §BPTC. No library on the system decodes BC7, so every case is built
// by hand: a builder writes the fields in the spec's order (mode, partition, rotation, index
// selection, colour, alpha, p-bits, primary and secondary indices, with one bit less at each
// subset's anchor) and must fill exactly 128 bits; the expected texels follow from the spec's
// formulas (bit replication, the weight table, ((64 - w)·E0 + w·E1 + 32) >> 6, rotation). Cases
// that poke bits at the positions of the spec's bit-layout table check the field order
// independently of the builder. Then Mesa's BPTC codec (llvmpipe, through the EGL peer) is the
// independent decoder: random blocks of every mode, and every block of real textures that Mesa
// itself compressed, must decode to the same 8-bit values (BC7 is integer-exact: texsim's
// k / 255 times 255 is Mesa's k).
#include <gtest/gtest.h>
#include <png.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "blocks/base/tech_table.h"
#include "blocks/texture/decode/bc7_decoder.h"
#include "blocks/texture/decode/bc7_tables.h"
#include "pipeline/reference/mesa_peer.h"

namespace texsim {
namespace {

using Block = std::array<uint8_t, 16>;

class BlockWriter {
 public:
  void put(uint32_t v, int bits) {
    for (int i = 0; i < bits; ++i, ++pos_) {
      ASSERT_LT(pos_, 128);
      if ((v >> i) & 1U)
        block_[static_cast<size_t>(pos_ / 8)] |= static_cast<uint8_t>(1U << (pos_ % 8));
    }
  }
  int pos() const { return pos_; }
  const Block& block() const { return block_; }

 private:
  Block block_{};
  int pos_ = 0;
};

// The spec's "Mode-dependent BPTC parameters" (NS, PB, RB, ISB, CB, AB, EPB, SPB, IB, IB2),
// written out again here so the builder does not share the decoder's table.
struct Mode {
  int ns, pb, rb, isb, cb, ab, epb, spb, ib, ib2;
};
constexpr std::array<Mode, 8> kMode = {{{3, 4, 0, 0, 4, 0, 1, 0, 3, 0},
                                        {2, 6, 0, 0, 6, 0, 0, 1, 3, 0},
                                        {3, 6, 0, 0, 5, 0, 0, 0, 2, 0},
                                        {2, 6, 0, 0, 7, 0, 1, 0, 2, 0},
                                        {1, 0, 2, 1, 5, 6, 0, 0, 2, 3},
                                        {1, 0, 2, 0, 7, 8, 0, 0, 2, 2},
                                        {1, 0, 0, 0, 7, 7, 1, 0, 4, 0},
                                        {2, 6, 0, 0, 5, 5, 1, 0, 2, 0}}};

// The fields of one block.
struct Fields {
  int mode = 0;
  uint32_t partition = 0, rotation = 0, isb = 0;
  std::array<std::array<uint32_t, 4>, 6> ep{};  // [subset·2 + endpoint][R, G, B, A], stored bits
  std::array<uint32_t, 6> pbit{};               // per endpoint (EPB) or per subset (SPB)
  std::array<uint32_t, 16> idx{};               // primary
  std::array<uint32_t, 16> idx2{};              // secondary
};

int subset_of(const Fields& f, int t) {
  const auto p = static_cast<size_t>(f.partition);
  if (kMode[static_cast<size_t>(f.mode)].ns == 2)
    return bc7::kBc7Partition2[p][static_cast<size_t>(t)];
  if (kMode[static_cast<size_t>(f.mode)].ns == 3)
    return bc7::kBc7Partition3[p][static_cast<size_t>(t)];
  return 0;
}
bool is_anchor(const Fields& f, int t) {
  const auto p = static_cast<size_t>(f.partition);
  switch (kMode[static_cast<size_t>(f.mode)].ns) {
    case 2:
      return t == 0 || t == bc7::kBc7Anchor2[p];
    case 3:
      return t == 0 || t == bc7::kBc7Anchor3Second[p] || t == bc7::kBc7Anchor3Third[p];
    default:
      return t == 0;
  }
}

Block build(const Fields& f) {
  const Mode& m = kMode[static_cast<size_t>(f.mode)];
  BlockWriter w;
  w.put(1U << f.mode, f.mode + 1);
  w.put(f.partition, m.pb);
  w.put(f.rotation, m.rb);
  w.put(f.isb, m.isb);
  const int eps = 2 * m.ns;
  for (size_t c = 0; c < 3; ++c) {
    for (int e = 0; e < eps; ++e) w.put(f.ep[static_cast<size_t>(e)][c], m.cb);
  }
  for (int e = 0; e < eps; ++e) w.put(f.ep[static_cast<size_t>(e)][3], m.ab);
  for (int e = 0; e < eps * m.epb; ++e) w.put(f.pbit[static_cast<size_t>(e)], 1);
  for (int s = 0; s < m.ns * m.spb; ++s) w.put(f.pbit[static_cast<size_t>(s)], 1);
  for (int t = 0; t < 16; ++t)
    w.put(f.idx[static_cast<size_t>(t)], is_anchor(f, t) ? m.ib - 1 : m.ib);
  for (int t = 0; t < 16 && m.ib2 > 0; ++t)
    w.put(f.idx2[static_cast<size_t>(t)], t == 0 ? m.ib2 - 1 : m.ib2);
  EXPECT_EQ(w.pos(), 128) << "mode " << f.mode << " fields must fill the block";
  return w.block();
}

// The spec's formulas for one texel, from the fields.
uint32_t endpoint8(const Fields& f, int e, int c) {
  const Mode& m = kMode[static_cast<size_t>(f.mode)];
  const int bits = c < 3 ? m.cb : m.ab;
  if (bits == 0) return 255;
  uint32_t v = f.ep[static_cast<size_t>(e)][static_cast<size_t>(c)];
  int width = bits;
  if (m.epb != 0 || m.spb != 0) {
    v = (v << 1) | f.pbit[static_cast<size_t>(m.epb != 0 ? e : e / 2)];
    ++width;
  }
  while (width < 8) {  // replicate the top bits below
    const int take = std::min(width, 8 - width);
    v = (v << take) | (v >> (width - take));
    width += take;
  }
  return v;
}
uint32_t weight_of(int bits, uint32_t i) {
  static constexpr std::array<uint32_t, 4> w2 = {0, 21, 43, 64};
  static constexpr std::array<uint32_t, 8> w3 = {0, 9, 18, 27, 37, 46, 55, 64};
  static constexpr std::array<uint32_t, 16> w4 = {0,  4,  9,  13, 17, 21, 26, 30,
                                                  34, 38, 43, 47, 51, 55, 60, 64};
  return bits == 2 ? w2[i] : bits == 3 ? w3[i] : w4[i];
}
std::array<uint32_t, 4> expected_texel(const Fields& f, int t) {
  const Mode& m = kMode[static_cast<size_t>(f.mode)];
  const int s = subset_of(f, t);
  const auto ti = static_cast<size_t>(t);
  uint32_t wc = weight_of(m.ib, f.idx[ti]);
  uint32_t wa = wc;
  if (m.ib2 > 0) {
    if (f.isb != 0) {
      wc = weight_of(m.ib2, f.idx2[ti]);
    } else {
      wa = weight_of(m.ib2, f.idx2[ti]);
    }
  }
  std::array<uint32_t, 4> v{};
  for (int c = 0; c < 4; ++c) {
    const uint32_t w = c < 3 ? wc : wa;
    v[static_cast<size_t>(c)] =
        ((64 - w) * endpoint8(f, 2 * s, c) + w * endpoint8(f, 2 * s + 1, c) + 32) >> 6;
  }
  if (f.rotation != 0) std::swap(v[3], v[f.rotation - 1]);
  return v;
}

void expect_decodes_as_spec(const Fields& f) {
  const DecodedBlock d = Bc7Decoder().decode(build(f));
  ASSERT_EQ(d.width, 4);
  for (int t = 0; t < 16; ++t) {
    const auto e = expected_texel(f, t);
    const glm::vec4 want(static_cast<float>(e[0]) / 255.0F, static_cast<float>(e[1]) / 255.0F,
                         static_cast<float>(e[2]) / 255.0F, static_cast<float>(e[3]) / 255.0F);
    EXPECT_EQ(d.texels[static_cast<size_t>(t)], want) << "mode " << f.mode << " texel " << t;
  }
}

// Random fields of `mode` that fit their widths (anchors one bit narrower).
Fields random_fields(int mode, std::mt19937& rng) {
  const Mode& m = kMode[static_cast<size_t>(mode)];
  Fields f;
  f.mode = mode;
  auto bits = [&](int n) { return n == 0 ? 0U : static_cast<uint32_t>(rng()) & ((1U << n) - 1); };
  f.partition = bits(m.pb);
  f.rotation = bits(m.rb);
  f.isb = bits(m.isb);
  for (auto& e : f.ep) e = {bits(m.cb), bits(m.cb), bits(m.cb), bits(m.ab)};
  for (auto& p : f.pbit) p = bits(1);
  for (int t = 0; t < 16; ++t) {
    f.idx[static_cast<size_t>(t)] = bits(is_anchor(f, t) ? m.ib - 1 : m.ib);
    f.idx2[static_cast<size_t>(t)] = bits(t == 0 ? m.ib2 - 1 : m.ib2);
  }
  return f;
}

TEST(Bc7Decoder, ModeIsTheLowestSetBitOfByteZero) {
  Block b{};
  EXPECT_EQ(Bc7Decoder::mode_of(b), Bc7Decoder::kReservedMode);
  for (int m = 0; m < 8; ++m) {
    b[0] = static_cast<uint8_t>(1U << m);
    EXPECT_EQ(Bc7Decoder::mode_of(b), m);
    b[0] = static_cast<uint8_t>(0xFFU << m);  // the bits above do not matter
    EXPECT_EQ(Bc7Decoder::mode_of(b), m);
  }
}

TEST(Bc7Decoder, ReservedModeIsZeroInEveryChannel) {
  Block b{};
  for (size_t i = 1; i < 16; ++i) b[i] = static_cast<uint8_t>(0x5A + i);
  const DecodedBlock d = Bc7Decoder().decode(b);
  EXPECT_EQ(d.width, 4);
  EXPECT_EQ(d.height, 4);
  for (int t = 0; t < 16; ++t) EXPECT_EQ(d.texels[static_cast<size_t>(t)], glm::vec4(0, 0, 0, 0));
}

TEST(Bc7Decoder, Mode6EndpointPbitsAndFourBitWeights) {
  // R0 = 100 with p-bit 1 -> 201, R1 = 20 with p-bit 0 -> 40 (7 bits + p-bit: no replication).
  Fields f;
  f.mode = 6;
  f.ep[0] = {100, 0, 127, 64};
  f.ep[1] = {20, 127, 0, 64};
  f.pbit = {1, 0};
  for (int t = 0; t < 16; ++t)
    f.idx[static_cast<size_t>(t)] = static_cast<uint32_t>(t == 0 ? 7 : t);
  const DecodedBlock d = Bc7Decoder().decode(build(f));
  // Texel 0 (the anchor, 3 stored bits) index 7, weight 30: (34·201 + 30·40 + 32) >> 6 = 126.
  EXPECT_EQ(d.at(0, 0).r, 126.0F / 255.0F);
  EXPECT_EQ(d.at(3, 3).r, 40.0F / 255.0F);   // index 15, weight 64: E1
  EXPECT_EQ(d.at(1, 0).r, 191.0F / 255.0F);  // index 1, weight 4: (60·201 + 4·40 + 32) >> 6
  EXPECT_EQ(d.at(3, 3).g, 254.0F / 255.0F);  // G1 = 127 with p-bit 0 -> 254
  EXPECT_EQ(d.at(3, 3).a, 128.0F / 255.0F);  // A1 = 64 with p-bit 0 -> 128
  expect_decodes_as_spec(f);
}

TEST(Bc7Decoder, Mode6FieldPositionsOfTheSpecLayout) {
  // Mode 6: R0 in bits 7..13, R1 in 14..20, EPB0 in bit 63, EPB1 in bit 64, IB from bit 65.
  Block b{};
  b[0] = 1U << 6;
  b[0] |= 0x80;     // R0 bit 0 (block bit 7)
  b[2] |= 1U << 4;  // R1 bit 6 (block bit 20): R1 = 64, with p-bit 0 -> 128
  b[7] |= 0x80;     // block bit 63: EPB0
  const DecodedBlock d = Bc7Decoder().decode(b);
  // All indices 0: E0. R0 = 1, p = 1 -> 3; G0 = 0, p = 1 -> 1; A0 = 0, p = 1 -> 1.
  EXPECT_EQ(d.at(2, 2), glm::vec4(3.0F / 255.0F, 1.0F / 255.0F, 1.0F / 255.0F, 1.0F / 255.0F));
  b[8] |= 0x02;  // block bit 65: texel 0's index bit 0 -> index 1, weight 4
  const DecodedBlock d1 = Bc7Decoder().decode(b);
  EXPECT_EQ(d1.at(0, 0).r, static_cast<float>((60 * 3 + 4 * 128 + 32) >> 6) / 255.0F);  // 11
  EXPECT_EQ(d1.at(1, 0), d.at(1, 0));
}

TEST(Bc7Decoder, Mode5RotationAndSecondaryAlphaIndices) {
  Fields f;
  f.mode = 5;
  f.ep[0] = {127, 0, 64, 255};
  f.ep[1] = {0, 127, 64, 0};
  for (int t = 0; t < 16; ++t) {
    f.idx[static_cast<size_t>(t)] = static_cast<uint32_t>(t % (t == 0 ? 2 : 4));
    f.idx2[static_cast<size_t>(t)] = static_cast<uint32_t>((t / 4) % (t == 0 ? 2 : 4));
  }
  for (uint32_t r = 0; r < 4; ++r) {
    f.rotation = r;
    expect_decodes_as_spec(f);
  }
  // Rotation 1 swaps A and R: texel (1, 0) has colour index 1 (weight 21) and alpha index 0;
  // R0 = 127 (7 bits) -> 255, R1 = 0, A0 = 255.
  f.rotation = 1;
  const DecodedBlock d = Bc7Decoder().decode(build(f));
  EXPECT_EQ(d.at(1, 0).r, 1.0F);  // the alpha of index 0: A0 = 255
  EXPECT_EQ(d.at(1, 0).a, static_cast<float>((43 * 255 + 21 * 0 + 32) >> 6) / 255.0F);
}

TEST(Bc7Decoder, Mode4IndexSelectionSwapsColourAndAlphaIndices) {
  std::mt19937 rng(4);
  for (int i = 0; i < 50; ++i) {
    Fields f = random_fields(4, rng);
    f.isb = static_cast<uint32_t>(i % 2);
    expect_decodes_as_spec(f);
  }
  // Colour from the 3-bit secondary index when ISB = 1: texel 5 with idx2 = 7 is E1's colour.
  Fields f;
  f.mode = 4;
  f.isb = 1;
  f.ep[0] = {0, 0, 0, 0};
  f.ep[1] = {31, 31, 31, 63};
  f.idx2[5] = 7;
  f.idx[5] = 0;
  const DecodedBlock d = Bc7Decoder().decode(build(f));
  EXPECT_EQ(d.at(1, 1), glm::vec4(1, 1, 1, 0));
  f.isb = 0;  // now colour from the 2-bit primary (0) and alpha from the secondary (7)
  const DecodedBlock d0 = Bc7Decoder().decode(build(f));
  EXPECT_EQ(d0.at(1, 1), glm::vec4(0, 0, 0, 1));
}

TEST(Bc7Decoder, Mode1SharedPbitsPerSubset) {
  // Partition 13 of two subsets: rows 0..1 subset 0, rows 2..3 subset 1 (anchor 15).
  Fields f;
  f.mode = 1;
  f.partition = 13;
  f.ep[0] = {0, 0, 0, 0};
  f.ep[1] = {0, 0, 0, 0};
  f.ep[2] = {63, 63, 63, 0};
  f.ep[3] = {63, 63, 63, 0};
  f.pbit = {0, 1};  // subset 0: p 0; subset 1: p 1
  const DecodedBlock d = Bc7Decoder().decode(build(f));
  EXPECT_EQ(d.at(0, 0), glm::vec4(0, 0, 0, 1));
  EXPECT_EQ(d.at(0, 3), glm::vec4(1, 1, 1, 1));  // 63 with p 1 = 127 -> 255
  f.pbit = {1, 0};
  const DecodedBlock d2 = Bc7Decoder().decode(build(f));
  // 0 with p 1 = 1 (7 bits) -> 2 | 0 = 2; 63 with p 0 = 126 -> 252 | 1 = 253.
  EXPECT_EQ(d2.at(0, 0).r, 2.0F / 255.0F);
  EXPECT_EQ(d2.at(0, 3).r, 253.0F / 255.0F);
  // Mode 1's shared p-bits are block bits 80 and 81.
  Block b{};
  b[0] = 2;
  b[10] = 0x02;  // bit 81: subset 1's p-bit
  const DecodedBlock d3 = Bc7Decoder().decode(b);
  EXPECT_EQ(d3.at(0, 0).r, 0.0F);           // partition 0: texel 0 in subset 0
  EXPECT_EQ(d3.at(3, 0).r, 2.0F / 255.0F);  // texel 3 in subset 1
}

TEST(Bc7Decoder, Mode2SpecExampleTexelNineAtBits115And116) {
  // DFS 1.3's example: mode 2, partition 6, texel (1, 2) = index 9 is in subset 1 and its two
  // index bits are block bits 115 and 116.
  Fields f;
  f.mode = 2;
  f.partition = 6;
  f.ep[2] = {0, 0, 0, 0};
  f.ep[3] = {31, 31, 31, 0};
  Block b = build(f);
  const DecodedBlock before = Bc7Decoder().decode(b);
  EXPECT_EQ(subset_of(f, 9), 1);
  b[115 / 8] |= static_cast<uint8_t>(1U << (115 % 8));
  b[116 / 8] |= static_cast<uint8_t>(1U << (116 % 8));
  const DecodedBlock after = Bc7Decoder().decode(b);
  for (int t = 0; t < 16; ++t) {
    if (t == 9) continue;
    EXPECT_EQ(after.texels[static_cast<size_t>(t)], before.texels[static_cast<size_t>(t)]) << t;
  }
  EXPECT_EQ(after.at(1, 2), glm::vec4(1, 1, 1, 1));  // index 3: E1 of subset 1
  EXPECT_EQ(before.at(1, 2), glm::vec4(0, 0, 0, 1));
}

TEST(Bc7Decoder, AnchorIndicesOfTwoAndThreeSubsetPartitions) {
  // Partitions whose second/third-subset anchors are not 15: the anchor's index has one bit
  // less, so the anchor's largest index reaches E1 of its subset only with the top bit clear.
  std::mt19937 rng(7);
  for (int mode : {0, 1, 2, 3, 7}) {
    const int parts = kMode[static_cast<size_t>(mode)].pb == 4 ? 16 : 64;
    for (int p = 0; p < parts; ++p) {
      Fields f = random_fields(mode, rng);
      f.partition = static_cast<uint32_t>(p);
      const Mode& m = kMode[static_cast<size_t>(mode)];
      for (int t = 0; t < 16; ++t) {  // anchors at their largest value, others random
        if (is_anchor(f, t)) f.idx[static_cast<size_t>(t)] = (1U << (m.ib - 1)) - 1;
      }
      expect_decodes_as_spec(f);
    }
  }
}

TEST(Bc7Decoder, EveryModeWithRandomFields) {
  std::mt19937 rng(1);
  for (int mode = 0; mode < 8; ++mode) {
    for (int i = 0; i < 200; ++i) expect_decodes_as_spec(random_fields(mode, rng));
  }
}

TEST(Bc7Decoder, PartitionTablesAgreeWithTheirAnchors) {
  for (size_t p = 0; p < 64; ++p) {
    EXPECT_EQ(bc7::kBc7Partition2[p][0], 0);
    EXPECT_EQ(bc7::kBc7Partition2[p][bc7::kBc7Anchor2[p]], 1) << p;
    EXPECT_EQ(bc7::kBc7Partition3[p][0], 0);
    EXPECT_EQ(bc7::kBc7Partition3[p][bc7::kBc7Anchor3Second[p]], 1) << p;
    EXPECT_EQ(bc7::kBc7Partition3[p][bc7::kBc7Anchor3Third[p]], 2) << p;
  }
  // Spot values of the spec's tables: 2-subset partition 13 = rows 0000/0000/1111/1111 as
  // printed, 3-subset partition 6 row 2 = 1 1 1 1.
  EXPECT_EQ(bc7::kBc7Partition2[13],
            (std::array<uint8_t, 16>{0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1}));
  EXPECT_EQ(bc7::kBc7Anchor2[17], 2);
  EXPECT_EQ(bc7::kBc7Anchor3Second[59], 13);
  EXPECT_EQ(bc7::kBc7Anchor3Third[38], 9);
}

TEST(Bc7Decoder, AnyBytesDecodeWithinRange) {
  std::mt19937 rng(3);
  for (int i = 0; i < 4000; ++i) {
    Block b{};
    for (auto& x : b) x = static_cast<uint8_t>(rng());
    const DecodedBlock d = Bc7Decoder().decode(b);
    for (int t = 0; t < 16; ++t) {
      for (int c = 0; c < 4; ++c) {
        const float v = d.texels[static_cast<size_t>(t)][c];
        ASSERT_TRUE(v >= 0.0F && v <= 1.0F);
        // Every value is k / 255.
        ASSERT_EQ(static_cast<float>(std::lround(v * 255.0F)) / 255.0F, v);
      }
    }
  }
}

TEST(Bc7Decoder, CostsAndTiming) {
  const Bc7Decoder dec;
  const OpCounts o = dec.ops_per_item();
  EXPECT_EQ(o.mul, 192u);
  EXPECT_EQ(o.add, 160u);
  EXPECT_EQ(o.cmp, 192u);
  EXPECT_EQ(o.lut, 34u);
  const TimingSpec t = dec.timing(TechTable::defaults());
  EXPECT_EQ(t.ii, 1u);
  EXPECT_EQ(t.latency, 17u);         // lut 3·2 + cmp 3·1 + mul 2·3 + add 2·1 (critical_path())
  EXPECT_DOUBLE_EQ(t.area, 1928.0);  // docs/derivations/bc-formats.md §7
  EXPECT_EQ(dec.name(), "texture.decode.bc7");
}

// ---------------------------------------------------------------------------------------------
// Mesa's BPTC decoder as the independent reference

constexpr uint32_t kGlBptcUnorm = 0x8E8C;  // GL_COMPRESSED_RGBA_BPTC_UNORM

#define SKIP_WITHOUT_MESA(peer) \
  if (!(peer).available()) GTEST_SKIP() << (peer).why_not()

// Blocks laid out `blocks_per_row` wide, compared texel by texel with Mesa's read-back.
// Returns the number of differing channel values; counts each block's mode in `modes`.
size_t compare_with_mesa(const std::vector<uint8_t>& blocks, int blocks_per_row,
                         const MesaImage& mesa, std::array<size_t, 9>& modes) {
  size_t differ = 0;
  const Bc7Decoder dec;
  const size_t n = blocks.size() / 16;
  for (size_t i = 0; i < n; ++i) {
    const std::span<const uint8_t, 16> blk(blocks.data() + 16 * i, 16);
    ++modes[static_cast<size_t>(Bc7Decoder::mode_of(blk))];
    const DecodedBlock d = dec.decode(blk);
    const size_t bx = i % static_cast<size_t>(blocks_per_row);
    const size_t by = i / static_cast<size_t>(blocks_per_row);
    for (size_t t = 0; t < 16; ++t) {
      const size_t x = 4 * bx + t % 4;
      const size_t y = 4 * by + t / 4;
      for (int c = 0; c < 4; ++c) {
        const long k = std::lround(d.texels[t][c] * 255.0F);
        const uint8_t m =
            mesa.rgba[(y * static_cast<size_t>(mesa.width) + x) * 4 + static_cast<size_t>(c)];
        if (k != m && differ++ == 0) {
          ADD_FAILURE() << "block " << i << " (mode " << Bc7Decoder::mode_of(blk) << ") texel " << t
                        << " channel " << c << ": texsim " << k << ", Mesa " << int{m};
        }
      }
    }
  }
  return differ;
}

TEST(Bc7Decoder, MatchesMesaOnRandomBlocksOfEveryMode) {
  const MesaPeer mesa(MesaDriver::Llvmpipe);
  SKIP_WITHOUT_MESA(mesa);
  std::mt19937 rng(11);
  constexpr int kPerMode = 1024;
  constexpr int kRow = 64;  // blocks per row of the texture
  std::vector<uint8_t> blocks;
  for (int mode = 0; mode < 8; ++mode) {
    for (int i = 0; i < kPerMode; ++i) {
      const Block b = build(random_fields(mode, rng));
      blocks.insert(blocks.end(), b.begin(), b.end());
    }
  }
  const int rows = 8 * kPerMode / kRow;
  const MesaImage img = mesa.decode_blocks(kGlBptcUnorm, 4 * kRow, 4 * rows, blocks);
  std::array<size_t, 9> modes{};
  EXPECT_EQ(compare_with_mesa(blocks, kRow, img, modes), 0u) << mesa.renderer();
  for (int m = 0; m < 8; ++m) EXPECT_EQ(modes[static_cast<size_t>(m)], size_t{kPerMode});
}

TEST(Bc7Decoder, ReservedModeAgainstMesa) {
  // DFS 1.3: all four channels 0. Mesa's decoder is compared here and its answer recorded.
  const MesaPeer mesa(MesaDriver::Llvmpipe);
  SKIP_WITHOUT_MESA(mesa);
  std::vector<uint8_t> blocks(16, 0);
  for (size_t i = 1; i < 16; ++i) blocks[i] = static_cast<uint8_t>(0x37 * i);
  const MesaImage img = mesa.decode_blocks(kGlBptcUnorm, 4, 4, blocks);
  std::array<size_t, 9> modes{};
  EXPECT_EQ(compare_with_mesa(blocks, 1, img, modes), 0u);
}

// An RGBA8 PNG cropped to whole 4x4 blocks.
MesaImage load_rgba(const std::string& path) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  MesaImage out;
  if (png_image_begin_read_from_file(&png, path.c_str()) == 0) return out;
  png.format = PNG_FORMAT_RGBA;
  std::vector<uint8_t> px(PNG_IMAGE_SIZE(png));
  if (png_image_finish_read(&png, nullptr, px.data(), 0, nullptr) == 0) return out;
  out.width = static_cast<int>(png.width) / 4 * 4;
  out.height = static_cast<int>(png.height) / 4 * 4;
  const size_t stride = PNG_IMAGE_ROW_STRIDE(png);
  for (int y = 0; y < out.height; ++y) {
    const auto* row = px.data() + static_cast<size_t>(y) * stride;
    out.rgba.insert(out.rgba.end(), row, row + 4 * static_cast<size_t>(out.width));
  }
  return out;
}

TEST(Bc7Decoder, MatchesMesaOnEveryBlockOfRealTexturesMesaCompressed) {
  const MesaPeer mesa(MesaDriver::Llvmpipe);
  SKIP_WITHOUT_MESA(mesa);
  for (const char* path :
       {"/usr/share/glmark2/textures/jellyfish256.png",
        "/usr/share/glmark2/textures/crate-base.png",
        "/usr/share/glmark2/textures/desktop-shadow.png",
        "/usr/share/matplotlib/mpl-data/sample_data/Minduka_Present_Blue_Pack.png",
        "/usr/share/matplotlib/mpl-data/sample_data/logo2.png"}) {
    const MesaImage src = load_rgba(path);
    ASSERT_GT(src.width, 0) << "cannot read " << path;
    const std::vector<uint8_t> blocks = mesa.encode_blocks(kGlBptcUnorm, src);
    const int per_row = src.width / 4;
    ASSERT_EQ(blocks.size(),
              static_cast<size_t>(per_row) * static_cast<size_t>(src.height / 4) * 16);
    const MesaImage img = mesa.decode_blocks(kGlBptcUnorm, src.width, src.height, blocks);
    std::array<size_t, 9> modes{};
    const size_t differ = compare_with_mesa(blocks, per_row, img, modes);
    std::printf("BC7  Mesa     %-30s blocks %6zu differ %zu modes",
                std::string(path).substr(std::string(path).rfind('/') + 1).c_str(),
                blocks.size() / 16, differ);
    for (size_t m = 0; m < 9; ++m) std::printf(" %zu", modes[m]);
    std::printf("\n");
    EXPECT_EQ(differ, 0u) << path;
  }
}

}  // namespace
}  // namespace texsim
