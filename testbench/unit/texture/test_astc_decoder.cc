// AstcDecoder's directed tests: the spec's corner cases worked by hand (trit and quint
// unpacking, integer sequences, unquantisation, block modes, void extents, the error colour
// of every illegal encoding, the partition hash, weight infill, dual planes with each
// component selector, HDR endpoint modes in the LDR profile). The comparisons with the ARM
// reference codec are test_astc_textures.cc and test_astc_random.cc.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <numeric>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "blocks/base/tech_table.h"
#include "blocks/texture/decode/astc_block_mode.h"
#include "blocks/texture/decode/astc_decoder.h"
#include "blocks/texture/decode/astc_endpoints.h"
#include "blocks/texture/decode/astc_integer_sequence.h"
#include "blocks/texture/decode/astc_partition.h"
#include "blocks/texture/decode/astc_weights.h"

namespace texsim {
namespace {

using Block = std::array<uint8_t, 16>;
const glm::vec4 kMagenta(1, 0, 1, 1);

void set_bits(Block& b, int pos, int count, uint64_t v) {
  for (int i = 0; i < count; ++i) {
    const auto byte = static_cast<size_t>((pos + i) / 8);
    const auto mask = static_cast<uint8_t>(1U << ((pos + i) % 8));
    b[byte] = static_cast<uint8_t>(((v >> i) & 1U) != 0 ? (b[byte] | mask) : (b[byte] & ~mask));
  }
}

// Stored weight k (of `bits` bits) in the weight stream, which grows down from bit 127.
void set_weight(Block& b, int k, int bits, uint32_t v) {
  for (int j = 0; j < bits; ++j) set_bits(b, 127 - (k * bits + j), 1, (v >> j) & 1U);
}

AstcDecoder decoder(int w, int h, AstcDecoder::Mode mode = AstcDecoder::Mode::Unorm16) {
  AstcDecoder::Config c;
  c.block_width = w;
  c.block_height = h;
  c.mode = mode;
  return AstcDecoder(c);
}

// ---- Integer sequence encoding ----------------------------------------------------------
TEST(AstcIntegerSequence, TritsWorkedByHand) {
  // T = 000 111 00: T[4:2] = 111 → C = {T[7:5], T[1:0]} = 0, t4 = t3 = 2; then t2 = t1 = t0 = 0.
  EXPECT_EQ(astc_unpack_trits(0x1C), (std::array<int, 5>{0, 0, 0, 2, 2}));
  // T = 0xFF: C = 11111, t4 = t3 = 2; C[1:0] = 11 → t2 = 2, t1 = C4 = 1, t0 = {C3, C2&~C3} = 2.
  EXPECT_EQ(astc_unpack_trits(0xFF), (std::array<int, 5>{2, 1, 2, 2, 2}));
  EXPECT_EQ(astc_unpack_trits(0x00), (std::array<int, 5>{0, 0, 0, 0, 0}));
  // T = 0x13 = 000 10011: C = 10011, t4 = T7 = 0, t3 = T[6:5] = 0; C[1:0] = 11 → t2 = 2,
  // t1 = C4 = 1, t0 = {C3 = 0, C2 & ~C3 = 0} = 0.
  EXPECT_EQ(astc_unpack_trits(0x13), (std::array<int, 5>{0, 1, 2, 0, 0}));
  // Every combination of five trits has an encoding.
  std::set<std::array<int, 5>> seen;
  for (uint32_t t = 0; t < 256; ++t) seen.insert(astc_unpack_trits(t));
  EXPECT_EQ(seen.size(), 243U);
}

TEST(AstcIntegerSequence, QuintsWorkedByHand) {
  // Q = 00 00 11 0: Q[2:1] = 11, Q[6:5] = 00 → q2 = {Q0, Q4&~Q0, Q3&~Q0} = 0, q1 = q0 = 4.
  EXPECT_EQ(astc_unpack_quints(0x06), (std::array<int, 3>{4, 4, 0}));
  // Q = 0x7F: Q[2:1] = 11 → q2 = 4, C = {Q[4:3] = 11, ~Q[6:5] = 00, Q0 = 1} = 11001:
  // C[2:0] = 001 → q1 = C[4:3] = 3, q0 = 1.
  EXPECT_EQ(astc_unpack_quints(0x7F), (std::array<int, 3>{1, 3, 4}));
  // Q = 0x0D = 00 01 101: q2 = 0, C = 01101, C[2:0] = 101 → q1 = 4, q0 = C[4:3] = 1.
  EXPECT_EQ(astc_unpack_quints(0x0D), (std::array<int, 3>{1, 4, 0}));
  std::set<std::array<int, 3>> seen;
  for (uint32_t q = 0; q < 128; ++q) seen.insert(astc_unpack_quints(q));
  EXPECT_EQ(seen.size(), 125U);
}

TEST(AstcIntegerSequence, SequenceBits) {
  EXPECT_EQ((AstcRange{2, true, false}).sequence_bits(5), 18);  // 8 + 5·2
  EXPECT_EQ((AstcRange{2, true, false}).sequence_bits(2), 8);   // ⌈16/5⌉ + 4
  EXPECT_EQ((AstcRange{1, false, true}).sequence_bits(3), 10);  // 7 + 3
  EXPECT_EQ((AstcRange{1, false, true}).sequence_bits(4), 14);  // ⌈28/3⌉ + 4
  EXPECT_EQ((AstcRange{0, true, false}).sequence_bits(1), 2);   // ⌈8/5⌉
  EXPECT_EQ((AstcRange{5, false, false}).sequence_bits(16), 80);
}

// Packs five values of a trit range with n low bits as the spec's packing table lays them.
uint64_t pack_trits(const std::array<int, 5>& v, int n) {
  uint32_t t = 0;  // the T byte whose trits are v >> n (found among the 256)
  for (uint32_t c = 0; c < 256; ++c) {
    const auto tr = astc_unpack_trits(c);
    bool ok = true;
    for (size_t i = 0; i < 5; ++i) ok = ok && tr[i] == (v[i] >> n);
    if (ok) {
      t = c;
      break;
    }
  }
  static constexpr int kTBits[5] = {2, 2, 1, 2, 1};
  uint64_t out = 0;
  int pos = 0, tpos = 0;
  for (size_t i = 0; i < 5; ++i) {
    out |= static_cast<uint64_t>(v[i] & ((1 << n) - 1)) << pos;
    pos += n;
    out |= static_cast<uint64_t>((t >> tpos) & ((1U << kTBits[i]) - 1)) << pos;
    pos += kTBits[i];
    tpos += kTBits[i];
  }
  return out;
}

TEST(AstcIntegerSequence, DecodesTritSequence) {
  const std::array<int, 5> v = {5, 11, 0, 7, 2};  // range 0..11: one trit, two bits
  const uint64_t packed = pack_trits(v, 2);
  std::array<int, 5> out{};
  astc_decode_sequence(AstcBits(packed << 3, 0), 3, 5, AstcRange{2, true, false}, out);
  EXPECT_EQ(out, v);
  // Two values take 8 bits; whatever lies above them is not part of the sequence.
  std::array<int, 2> two{};
  const uint64_t low8 = packed & 0xFF;
  astc_decode_sequence(AstcBits(low8 | ~0xFFULL, ~0ULL), 0, 2, AstcRange{2, true, false}, two);
  std::array<int, 2> two_zero{};
  astc_decode_sequence(AstcBits(low8, 0), 0, 2, AstcRange{2, true, false}, two_zero);
  EXPECT_EQ(two, two_zero);
  EXPECT_EQ(two[0], 5);
  EXPECT_EQ(two[1], 11);
}

TEST(AstcIntegerSequence, DecodesQuintSequence) {
  // Range 0..9 (one quint, one bit): values 9, 4, 6 → quints (4, 2, 3), bits (1, 0, 0).
  uint32_t q = 0;
  for (uint32_t c = 0; c < 128; ++c) {
    if (astc_unpack_quints(c) == std::array<int, 3>{4, 2, 3}) q = c;
  }
  // m0, Q[2:0], m1, Q[4:3], m2, Q[6:5]
  const uint64_t packed = 1U | ((q & 7U) << 1) | (0U << 4) | (((q >> 3) & 3U) << 5) | (0U << 7) |
                          (((q >> 5) & 3U) << 8);
  std::array<int, 3> out{};
  astc_decode_sequence(AstcBits(packed, 0), 0, 3, AstcRange{1, false, true}, out);
  EXPECT_EQ(out, (std::array<int, 3>{9, 4, 6}));
}

TEST(AstcIntegerSequence, BitsReversed) {
  const AstcBits b(1, 0);
  EXPECT_EQ(b.reversed().get(127, 1), 1U);
  EXPECT_EQ(b.reversed().get(0, 1), 0U);
  EXPECT_EQ(AstcBits(0, 1ULL << 63).reversed().get(0, 1), 1U);
  EXPECT_EQ(b.get(126, 8), 0U);  // past bit 127 reads 0
}

// ---- Unquantisation ----------------------------------------------------------------------
TEST(AstcUnquantize, ColorWorkedByHand) {
  // 0..5: value 2 = trit 1, bit 0: D·C + B = 204, ^A = 204, >> 2 = 51; value 1: A = 0x1FF,
  // 0 ^ 0x1FF = 511 → 0x80 | 127 = 255. The whole range: {0, 255, 51, 204, 102, 153}.
  const std::array<int, 6> q6 = {0, 255, 51, 204, 102, 153};
  for (int v = 0; v < 6; ++v) EXPECT_EQ(astc_unquantize_color(v, 0), q6[size_t(v)]) << v;
  EXPECT_EQ(astc_unquantize_color(5, 1), 182);     // 0..7: 101 → 10110110
  EXPECT_EQ(astc_unquantize_color(200, 16), 200);  // 0..255 is the identity
  // Every range maps its ends to 0 and 255 and is monotonic in its unscrambled order.
  for (int r = 0; r < kAstcColorRanges; ++r) {
    std::set<int> values;
    for (int v = 0; v < astc_color_range(r).size(); ++v) {
      values.insert(astc_unquantize_color(v, r));
    }
    EXPECT_EQ(static_cast<int>(values.size()), astc_color_range(r).size()) << r;
    EXPECT_EQ(*values.begin(), 0);
    EXPECT_EQ(*values.rbegin(), 255);
  }
}

TEST(AstcUnquantize, WeightWorkedByHand) {
  // 0..5 (index 4): value 2 → 50 >> 2 = 12; value 3 (trit 1, bit 1) → (50 ^ 127) = 77 →
  // 0x20 | 19 = 51 → 52 after the expansion above 32; value 1 → 63 → 64.
  const std::array<int, 6> w6 = {0, 64, 12, 52, 25, 39};
  for (int v = 0; v < 6; ++v) EXPECT_EQ(astc_unquantize_weight(v, 4), w6[size_t(v)]) << v;
  EXPECT_EQ(astc_unquantize_weight(2, 1), 64);  // 0..2: {0, 32, 63} → 63 + 1
  EXPECT_EQ(astc_unquantize_weight(3, 3), 48);  // 0..4: 47 + 1
  EXPECT_EQ(astc_unquantize_weight(5, 5), 46);  // 0..7: 101 → 101101 = 45 → 46
  EXPECT_EQ(astc_unquantize_weight(1, 0), 64);  // 0..1
  for (int r = 0; r < 12; ++r) {
    std::set<int> values;
    for (int v = 0; v < astc_weight_range(r).size(); ++v) {
      values.insert(astc_unquantize_weight(v, r));
    }
    EXPECT_EQ(*values.begin(), 0);
    EXPECT_EQ(*values.rbegin(), 64);
  }
}

TEST(AstcUnquantize, ColorRangeSelection) {
  EXPECT_EQ(astc_select_color_range(8, 64), 16);  // 8 values of 8 bits
  EXPECT_EQ(astc_select_color_range(8, 63), 15);  // 0..191: 8·6 + ⌈64/5⌉ = 61
  EXPECT_EQ(astc_select_color_range(8, 21), 0);   // 0..5 needs ⌈13·8/5⌉ = 21
  EXPECT_EQ(astc_select_color_range(8, 20), -1);
}

// ---- Block mode --------------------------------------------------------------------------
TEST(AstcBlockMode, WorkedModes) {
  // 0x441: DP, A = 2, ρ = 2: a 4×4 grid of 0..1 weights on two planes.
  const AstcBlockMode m = astc_decode_block_mode(0x441, 4, 4);
  EXPECT_EQ(m.kind, AstcBlockMode::Kind::Normal);
  EXPECT_EQ(m.grid_width, 4);
  EXPECT_EQ(m.grid_height, 4);
  EXPECT_TRUE(m.dual_plane);
  EXPECT_EQ(m.weight_range, 0);
  EXPECT_EQ(m.weight_bits, 32);
  // 0x004: bits 1..0 = 00, 8..7 = 00 → 12 × (A + 2) = 12 × 2, ρ = 2.
  const AstcBlockMode wide = astc_decode_block_mode(0x004, 12, 12);
  EXPECT_EQ(wide.kind, AstcBlockMode::Kind::Normal);
  EXPECT_EQ(wide.grid_width, 12);
  EXPECT_EQ(wide.grid_height, 2);
  EXPECT_EQ(astc_decode_block_mode(0x1FC, 4, 4).kind, AstcBlockMode::Kind::VoidExtent);
  EXPECT_EQ(astc_decode_block_mode(0x7FC, 4, 4).kind, AstcBlockMode::Kind::VoidExtent);
}

TEST(AstcBlockMode, ReservedAndIllegalModes) {
  const auto reserved = [](uint32_t mode, int w, int h) {
    return astc_decode_block_mode(mode, w, h).kind == AstcBlockMode::Kind::Reserved;
  };
  EXPECT_TRUE(reserved(0x000, 12, 12));                  // bits 3..0 = 0000
  EXPECT_TRUE(reserved(0x600, 12, 12));                  // the same, any high bits
  EXPECT_TRUE(reserved(0x1C4, 12, 12));                  // bits 8..6 = 111, not a void extent
  EXPECT_TRUE(reserved(0x004, 4, 4));                    // a 12×2 grid on a 4×4 block
  EXPECT_TRUE(reserved(0x400 | 0x060 | 0x004, 12, 12));  // 12×5 on two planes: 120 weights
  EXPECT_TRUE(reserved(0x077, 12, 12));                  // 8×5 grid of 0..7: 120 bits > 96
  EXPECT_FALSE(reserved(0x065, 12, 12));                 // 8×5 grid of 0..1: 40 bits
  EXPECT_TRUE(reserved(0x041, 4, 4));                    // 4×4 grid of 0..1: 16 bits < 24
  EXPECT_FALSE(reserved(0x441, 4, 4));                   // the same on two planes: 32 bits
  // Every mode on every footprint: legal ones respect all the limits.
  for (int w : {4, 5, 6, 8, 10, 12}) {
    for (int h : {4, 5, 6, 8, 10, 12}) {
      for (uint32_t mode = 0; mode < 2048; ++mode) {
        const AstcBlockMode m = astc_decode_block_mode(mode, w, h);
        if (m.kind != AstcBlockMode::Kind::Normal) continue;
        EXPECT_LE(m.weight_count, 64);
        EXPECT_GE(m.weight_bits, 24);
        EXPECT_LE(m.weight_bits, 96);
        EXPECT_LE(m.grid_width, w);
        EXPECT_LE(m.grid_height, h);
      }
    }
  }
}

// ---- Void extent -------------------------------------------------------------------------
Block void_extent(uint16_t r, uint16_t g, uint16_t b, uint16_t a) {
  Block blk{};
  set_bits(blk, 0, 9, 0x1FC);
  set_bits(blk, 10, 2, 3);
  set_bits(blk, 12, 52, ~0ULL);  // no extent
  set_bits(blk, 64, 16, r);
  set_bits(blk, 80, 16, g);
  set_bits(blk, 96, 16, b);
  set_bits(blk, 112, 16, a);
  return blk;
}

TEST(AstcVoidExtent, LdrConstantColour) {
  const Block blk = void_extent(0x1234, 0xFFFF, 0x0000, 0x8000);
  AstcBlockInfo info;
  const DecodedBlock d = decoder(6, 5).decode(blk, &info);
  EXPECT_TRUE(info.void_extent);
  EXPECT_EQ(info.error, AstcError::None);
  EXPECT_EQ(d.width, 6);
  EXPECT_EQ(d.height, 5);
  for (int y = 0; y < 5; ++y) {
    for (int x = 0; x < 6; ++x) {
      EXPECT_EQ(d.at(x, y), glm::vec4(0x1234 / 65535.0F, 1.0F, 0.0F, 0x8000 / 65535.0F));
    }
  }
  // decode_float16: C / 65536 toward zero to 11 significant bits; 0xFFFF is 1.0.
  const DecodedBlock f = decoder(6, 5, AstcDecoder::Mode::Float16).decode(blk);
  EXPECT_EQ(f.at(0, 0), glm::vec4(0x1234 / 65536.0F, 1.0F, 0.0F, 0.5F));
  // decode_unorm8: the top 8 bits.
  const DecodedBlock u8 = decoder(6, 5, AstcDecoder::Mode::Unorm8).decode(blk);
  EXPECT_EQ(u8.at(5, 4), glm::vec4(0x12 / 255.0F, 1.0F, 0.0F, 0x80 / 255.0F));
}

TEST(AstcVoidExtent, Float16RoundsTowardZero) {
  // 0x1235 has 13 significant bits: the low two are dropped (0x1234); 3 is an FP16 denormal.
  const DecodedBlock f =
      decoder(4, 4, AstcDecoder::Mode::Float16).decode(void_extent(0x1235, 0xFFFE, 3, 0x7FF));
  EXPECT_EQ(f.at(0, 0).r, 0x1234 / 65536.0F);
  EXPECT_EQ(f.at(0, 0).g, 0xFFE0 / 65536.0F);
  EXPECT_EQ(f.at(0, 0).b, 3 / 65536.0F);
  EXPECT_EQ(f.at(0, 0).a, 0x7FF / 65536.0F);  // 11 bits: exact
}

TEST(AstcVoidExtent, IllegalOnesGiveTheErrorColour) {
  const AstcDecoder dec = decoder(4, 4);
  AstcBlockInfo info;
  Block hdr = void_extent(0x3C00, 0, 0, 0x3C00);
  set_bits(hdr, 9, 1, 1);
  EXPECT_EQ(dec.decode(hdr, &info).at(3, 3), kMagenta);
  EXPECT_EQ(info.error, AstcError::HdrVoidExtent);
  Block reserved_bits = void_extent(0, 0, 0, 0);
  set_bits(reserved_bits, 10, 2, 1);
  EXPECT_EQ(dec.decode(reserved_bits, &info).at(0, 0), kMagenta);
  EXPECT_EQ(info.error, AstcError::VoidExtentReservedBits);
  Block inverted = void_extent(0, 0, 0, 0);
  set_bits(inverted, 12, 13, 100);  // min s
  set_bits(inverted, 25, 13, 100);  // max s = min s
  EXPECT_EQ(dec.decode(inverted, &info).at(0, 0), kMagenta);
  EXPECT_EQ(info.error, AstcError::VoidExtentCoordinates);
  Block extent = void_extent(0, 0xFFFF, 0, 0xFFFF);
  set_bits(extent, 12, 13, 100);
  set_bits(extent, 25, 13, 200);
  set_bits(extent, 38, 13, 0);
  set_bits(extent, 51, 13, 8191);
  EXPECT_EQ(dec.decode(extent, &info).at(0, 0), glm::vec4(0, 1, 0, 1));
  EXPECT_EQ(info.error, AstcError::None);
}

// ---- Error colour of illegal blocks ------------------------------------------------------
TEST(AstcErrors, ReservedBlockMode) {
  AstcBlockInfo info;
  Block blk{};  // block mode 0: reserved
  const DecodedBlock d = decoder(12, 12).decode(blk, &info);
  EXPECT_EQ(info.error, AstcError::ReservedBlockMode);
  for (int i = 0; i < 144; ++i) EXPECT_EQ(d.texels[size_t(i)], kMagenta);
  set_bits(blk, 0, 11, 0x004);  // a 12×2 grid: legal on 12×12, too large for 8×8
  decoder(8, 8).decode(blk, &info);
  EXPECT_EQ(info.error, AstcError::ReservedBlockMode);
}

TEST(AstcErrors, DualPlaneWithFourPartitions) {
  Block blk{};
  set_bits(blk, 0, 11, 0x441);
  set_bits(blk, 11, 2, 3);
  AstcBlockInfo info;
  EXPECT_EQ(decoder(4, 4).decode(blk, &info).at(1, 2), kMagenta);
  EXPECT_EQ(info.error, AstcError::DualPlaneFourPartitions);
}

TEST(AstcErrors, TooManyColourValues) {
  Block blk{};
  set_bits(blk, 0, 11, 0x042);    // 4×4 grid of 0..3, one plane
  set_bits(blk, 11, 2, 3);        // 4 partitions
  set_bits(blk, 23, 6, 12 << 2);  // all of CEM 12: 32 integers
  AstcBlockInfo info;
  EXPECT_EQ(decoder(4, 4).decode(blk, &info).at(0, 0), kMagenta);
  EXPECT_EQ(info.error, AstcError::TooManyColorValues);
}

TEST(AstcErrors, TooFewColourBits) {
  Block blk{};
  set_bits(blk, 0, 11, 0x453);  // 4×4 grid of 0..7 on two planes: 96 weight bits
  set_bits(blk, 13, 4, 12);     // RGBA direct: 8 integers need ≥ 21 bits, 13 are left
  AstcBlockInfo info;
  EXPECT_EQ(decoder(4, 4).decode(blk, &info).at(0, 0), kMagenta);
  EXPECT_EQ(info.error, AstcError::TooFewColorBits);
  set_bits(blk, 13, 4, 0);  // luminance: 2 integers fit in 13 bits
  decoder(4, 4).decode(blk, &info);
  EXPECT_EQ(info.error, AstcError::None);
}

// ---- Partition hash ----------------------------------------------------------------------
TEST(AstcPartition, HashValues) {
  EXPECT_EQ(astc_hash52(0), 0U);  // every step keeps 0
  // Worked from the spec's hash52 pseudo-code in a separate transcription.
  EXPECT_EQ(astc_hash52(1), 0x0c46f563U);
  EXPECT_EQ(astc_hash52(1024), 0xbd3d4343U);
  EXPECT_EQ(astc_hash52(3072 + 1023), 0x85c559b5U);
}

std::string pattern(int seed, int parts, int w, int h) {
  std::string s;
  const bool small = w * h < 31;
  for (int y = 0; y < h; ++y) {
    if (y > 0) s += '|';
    for (int x = 0; x < w; ++x) s += char('0' + astc_select_partition(seed, x, y, 0, parts, small));
  }
  return s;
}

TEST(AstcPartition, Patterns) {
  // 4×4 (small block: coordinates doubled), from the same transcription.
  EXPECT_EQ(pattern(77, 2, 4, 4), "0011|0011|0001|0001");
  EXPECT_EQ(pattern(300, 3, 4, 4), "0000|0000|0001|0111");
  EXPECT_EQ(pattern(1023, 4, 4, 4), "3331|3333|2222|2333");
  EXPECT_EQ(pattern(513, 2, 4, 4), "1100|1000|0001|1111");
  // 8×6 (not small).
  EXPECT_EQ(pattern(77, 2, 8, 6), "00011111|00001111|00001111|00000111|00000111|00000011");
  EXPECT_EQ(pattern(1023, 4, 8, 6), "33333311|33333331|33333331|33333333|22222222|22222233");
}

// ---- Weight infill -----------------------------------------------------------------------
TEST(AstcWeights, InfillWorkedByHand) {
  // A 2×2 grid (0, 64 / 64, 0) on an 8×8 block: Ds = (1024 + 4) / 7 = 146.
  const std::array<int, 4> grid = {0, 64, 64, 0};
  std::array<int, 64> out{};
  astc_infill_weights(grid, 2, 2, 8, 8, out);
  const auto at = [&](int x, int y) {
    const int t = y * 8 + x;
    return out[static_cast<size_t>(t)];
  };
  EXPECT_EQ(at(0, 0), 0);
  EXPECT_EQ(at(7, 0), 64);
  EXPECT_EQ(at(0, 7), 64);
  EXPECT_EQ(at(7, 7), 0);
  // x = 3: cs = 438, gs = (438 + 32) >> 6 = 7; y = 0: ft = 0 → w00 = 9, w01 = 7:
  // (64·7 + 8) >> 4 = 28.
  EXPECT_EQ(at(3, 0), 28);
  // (3, 3): fs = ft = 7, w11 = (49 + 8) >> 4 = 3, w10 = w01 = 4, w00 = 5: (64·8 + 8) >> 4 = 32.
  EXPECT_EQ(at(3, 3), 32);
  // (4, 3): fs = 9 (cs = 584), ft = 7: w11 = 4, w10 = 3, w01 = 5, w00 = 4 → (64·8 + 8) >> 4.
  EXPECT_EQ(at(4, 3), 32);
}

TEST(AstcWeights, FullGridIsIdentityAndEdgesStayInside) {
  for (int bw : {4, 5, 6, 8, 10, 12}) {
    for (int bh : {4, 5, 6, 8, 10, 12}) {
      if (bw * bh <= 64) {
        std::vector<int> grid(static_cast<size_t>(bw * bh));
        std::iota(grid.begin(), grid.end(), 0);
        std::vector<int> out(grid.size());
        astc_infill_weights(grid, bw, bh, bw, bh, out);
        EXPECT_EQ(out, grid) << bw << "x" << bh;
      }
      // Where the grid position is on the last column/row, its fraction is 0: the weight
      // beyond the grid, which the infill does not read, has a zero factor.
      const int ds = (1024 + bw / 2) / (bw - 1);
      for (int gw = 2; gw <= bw; ++gw) {
        for (int x = 0; x < bw; ++x) {
          const int gs = (ds * x * (gw - 1) + 32) >> 6;
          EXPECT_LE(gs >> 4, gw - 1);
          if ((gs >> 4) == gw - 1) {
            EXPECT_EQ(gs & 0xF, 0);
          }
        }
      }
    }
  }
}

// ---- Dual plane --------------------------------------------------------------------------
// A 4×4 block, 4×4 grid of 0..1 weights on two planes, RGBA direct from (0,0,0,0) to
// (255,255,255,255), plane 0 weights `w0` and plane 1 weights `w1`, selector `ccs`.
Block dual_plane_block(int ccs, uint32_t w0, uint32_t w1) {
  Block blk{};
  set_bits(blk, 0, 11, 0x441);
  set_bits(blk, 13, 4, 12);
  const std::array<uint32_t, 8> v = {0, 255, 0, 255, 0, 255, 0, 255};
  for (int i = 0; i < 8; ++i) set_bits(blk, 17 + 8 * i, 8, v[size_t(i)]);
  set_bits(blk, 128 - 32 - 2, 2, static_cast<uint32_t>(ccs));
  for (int t = 0; t < 16; ++t) {
    set_weight(blk, 2 * t, 1, w0);
    set_weight(blk, 2 * t + 1, 1, w1);
  }
  return blk;
}

TEST(AstcDualPlane, EachComponentSelector) {
  const AstcDecoder dec = decoder(4, 4);
  for (int ccs = 0; ccs < 4; ++ccs) {
    AstcBlockInfo info;
    const DecodedBlock d = dec.decode(dual_plane_block(ccs, 0, 1), &info);
    EXPECT_EQ(info.error, AstcError::None);
    EXPECT_EQ(info.ccs, ccs);
    glm::vec4 want(0);
    want[ccs] = 1;
    for (int t = 0; t < 16; ++t) EXPECT_EQ(d.texels[size_t(t)], want) << ccs << " " << t;
    const DecodedBlock r = dec.decode(dual_plane_block(ccs, 1, 0));
    for (int t = 0; t < 16; ++t) EXPECT_EQ(r.texels[size_t(t)], glm::vec4(1) - want);
  }
}

// ---- HDR endpoint modes in the LDR profile -----------------------------------------------
TEST(AstcHdrEndpoints, OnlyTheHdrPartitionIsMagenta) {
  Block blk{};
  set_bits(blk, 0, 11, 0x042);        // 4×4 grid of 0..3: 32 weight bits, all weights 0
  set_bits(blk, 11, 2, 1);            // 2 partitions
  set_bits(blk, 13, 10, 77);          // pattern 0011|0011|0001|0001
  set_bits(blk, 23, 6, 0x09);         // classes 0/1: C0 = 0, C1 = 1, M0 = 00
  set_bits(blk, 128 - 32 - 2, 2, 3);  // M1 = 11: partition 1 uses CEM 7 (HDR)
  set_bits(blk, 29, 8, 10);           // partition 0, CEM 0: v0 = 10, v1 = 200
  set_bits(blk, 37, 8, 200);
  AstcBlockInfo info;
  const DecodedBlock d = decoder(4, 4).decode(blk, &info);
  EXPECT_EQ(info.cem[0], 0);
  EXPECT_EQ(info.cem[1], 7);
  EXPECT_EQ(info.error, AstcError::HdrEndpointMode);
  EXPECT_EQ(info.hdr_partitions, 2);
  const std::string parts = "0011001100010001";
  for (int t = 0; t < 16; ++t) {
    EXPECT_EQ(info.partition[size_t(t)], parts[size_t(t)] - '0');
    const float g = 10.0F / 255.0F;  // 10·257 / 65535
    EXPECT_EQ(d.texels[size_t(t)], parts[size_t(t)] == '1' ? kMagenta : glm::vec4(g, g, g, 1)) << t;
  }
  set_bits(blk, 11, 2, 0);   // one partition
  set_bits(blk, 13, 4, 15);  // HDR RGBA: every texel
  const DecodedBlock all = decoder(4, 4).decode(blk, &info);
  for (int t = 0; t < 16; ++t) EXPECT_EQ(all.texels[size_t(t)], kMagenta);
}

// ---- The block model ---------------------------------------------------------------------
TEST(AstcDecoderBlock, FootprintsAndCosts) {
  EXPECT_THROW(decoder(7, 7), std::invalid_argument);
  EXPECT_THROW(decoder(4, 12), std::invalid_argument);
  const AstcDecoder small = decoder(4, 4), large = decoder(12, 12);
  EXPECT_GT(large.ops_per_item().arithmetic(), small.ops_per_item().arithmetic());
  const TimingSpec t = large.timing(TechTable::defaults());
  EXPECT_GE(t.latency, 1U);
  EXPECT_EQ(t.ii, 1U);
  EXPECT_GT(t.area, 0.0);
  EXPECT_EQ(large.name(), "texture.astc_decoder");
  // The cost table of docs/derivations/astc.md §8 (default technology table, spatial).
  for (const auto& [w, h] : {std::pair{4, 4},
                             {5, 4},
                             {5, 5},
                             {6, 5},
                             {6, 6},
                             {8, 5},
                             {8, 6},
                             {8, 8},
                             {10, 5},
                             {10, 6},
                             {10, 8},
                             {10, 10},
                             {12, 10},
                             {12, 12}}) {
    const AstcDecoder d = decoder(w, h);
    const OpCounts o = d.ops_per_item();
    const TimingSpec s = d.timing(TechTable::defaults());
    std::printf("| %dx%d | %llu | %llu | %llu | %llu | %u | %u | %.0f |\n", w, h,
                static_cast<unsigned long long>(o.add), static_cast<unsigned long long>(o.mul),
                static_cast<unsigned long long>(o.lut), static_cast<unsigned long long>(o.cmp),
                s.latency, s.ii, s.area);
  }
}

}  // namespace
}  // namespace texsim
