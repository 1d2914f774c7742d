// ETC2 / EAC decoders (blocks/texture/decode/): directed blocks of every mode with values
// worked out from the Khronos Data Format Specification 1.3 tables, and every block of real
// textures (encoded in every mode by etc_encode_rgb_mode / eac_encode_mode) and of random bytes
// decoded by Mesa (llvmpipe's glGetTexImage of glCompressedTexImage2D) as the independent decoder:
// 0 mismatches.
#include <gtest/gtest.h>
#include <png.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <random>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "blocks/texture/decode/eac_decoder.h"
#include "blocks/texture/decode/eac_rg_decoder.h"
#include "blocks/texture/decode/etc2_rgb_decoder.h"
#include "blocks/texture/decode/etc2_rgba_decoder.h"
#include "pipeline/image_io/etc_block_encoder.h"
#include "pipeline/reference/mesa_peer.h"

namespace {

using namespace texsim;  // NOLINT(google-build-using-namespace)
using Mode = Etc2RgbDecoder::Mode;

// ---------------------------------------------------------------------------------------------
// Hand-built blocks

// A block from the spec's 64-bit word (q0 the most significant byte).
std::array<uint8_t, 8> block_of(uint64_t w) {
  std::array<uint8_t, 8> b{};
  for (size_t i = 0; i < 8; ++i) b[i] = static_cast<uint8_t>(w >> (56 - 8 * i));
  return b;
}
void put(uint64_t& w, int lo, int n, uint64_t v) {
  const uint64_t mask = ((uint64_t{1} << n) - 1) << lo;
  w = (w & ~mask) | ((v << lo) & mask);
}
// The 2-bit ETC index of texel (x, y): msb at bit 16 + (x * 4 + y), lsb at bit x * 4 + y.
void put_index(uint64_t& w, int x, int y, int idx) {
  put(w, 16 + x * 4 + y, 1, static_cast<uint64_t>(idx >> 1));
  put(w, x * 4 + y, 1, static_cast<uint64_t>(idx & 1));
}
// The 3-bit EAC index of texel (x, y) at bits 47 - 3 (x * 4 + y) down.
void put_eac_index(uint64_t& w, int x, int y, int idx) {
  put(w, 45 - 3 * (x * 4 + y), 3, static_cast<uint64_t>(idx));
}
using Rgba8 = std::array<uint8_t, 4>;
Rgba8 texel(const Etc2RgbDecoder::Texels8& t, int x, int y) {
  return t[static_cast<size_t>(y) * 4 + static_cast<size_t>(x)];
}
Rgba8 rgba(int r, int g, int b, int a = 255) {
  return {static_cast<uint8_t>(r), static_cast<uint8_t>(g), static_cast<uint8_t>(b),
          static_cast<uint8_t>(a)};
}

const Etc2RgbDecoder kRgb;
const Etc2RgbDecoder kRgbA1({true, Datapath::Spatial});

TEST(Etc2Rgb, IndividualModeExtendsFourBitsAndAddsTheTableModifier) {
  // R1 = 14, R2 = 3, G1 = 3, G2 = 8, B1 = 8, B2 = 15 (the spec's example: 238, 51, 136),
  // table 1 = 2 (±9, ±29), table 2 = 7 (±47, ±183), diff bit 0, flip 0 (2x4 side by side).
  uint64_t w = 0xE3388F0000000000ULL;
  put(w, 37, 3, 2);
  put(w, 34, 3, 7);
  put_index(w, 0, 0, 1);  // +b = +29: 238 + 29 = 267 clamps to 255
  put_index(w, 3, 3, 3);  // -b = -183 on (51, 136, 255)
  put_index(w, 1, 2, 2);  // -a = -9
  const auto b = block_of(w);
  EXPECT_EQ(kRgb.mode(b), Mode::Individual);
  const auto t = kRgb.decode_rgba8(b);
  EXPECT_EQ(texel(t, 0, 0), rgba(255, 80, 165));
  EXPECT_EQ(texel(t, 1, 0), rgba(247, 60, 145));  // index 0: +a = +9
  EXPECT_EQ(texel(t, 1, 2), rgba(229, 42, 127));
  EXPECT_EQ(texel(t, 2, 0), rgba(98, 183, 255));  // subblock 2: (51, 136, 255) + 47
  EXPECT_EQ(texel(t, 3, 3), rgba(0, 0, 72));
  // Flip 1: the subblocks are the top and bottom 4x2 halves.
  put(w, 32, 1, 1);
  const auto f = kRgb.decode_rgba8(block_of(w));
  EXPECT_EQ(texel(f, 3, 0), rgba(247, 60, 145));
  EXPECT_EQ(texel(f, 0, 3), rgba(98, 183, 255));
  // The float result is the 8-bit one / 255.
  EXPECT_EQ(kRgb.decode(block_of(w)).at(0, 3), glm::vec4(98 / 255.0F, 183 / 255.0F, 1.0F, 1.0F));
}

TEST(Etc2Rgb, DifferentialModeAddsTheThreeBitDeltas) {
  // The spec's example: R = 28, dR = -4 (231, 198); G = 4, dG = 2 (33, 49); B = 3, dB = 0
  // (24, 24). Tables 0 (±2, ±8) and 1 (±5, ±17), flip 1.
  uint64_t w = 0;
  put(w, 59, 5, 28);
  put(w, 56, 3, 4);  // -4
  put(w, 51, 5, 4);
  put(w, 48, 3, 2);
  put(w, 43, 5, 3);
  put(w, 40, 3, 0);
  put(w, 37, 3, 0);
  put(w, 34, 3, 1);
  put(w, 33, 1, 1);
  put(w, 32, 1, 1);
  put_index(w, 2, 0, 3);  // -8
  put_index(w, 2, 3, 1);  // +17
  const auto b = block_of(w);
  EXPECT_EQ(kRgb.mode(b), Mode::Differential);
  const auto t = kRgb.decode_rgba8(b);
  EXPECT_EQ(texel(t, 0, 0), rgba(233, 35, 26));
  EXPECT_EQ(texel(t, 2, 0), rgba(223, 25, 16));
  EXPECT_EQ(texel(t, 0, 2), rgba(203, 54, 29));
  EXPECT_EQ(texel(t, 2, 3), rgba(215, 66, 41));
}

TEST(Etc2Rgb, ModeSelectionAtTheEdgesOfTheFiveBitRange) {
  const auto mode_for = [](int r, int dr, int g, int dg, int b, int db) {
    uint64_t w = 0;
    put(w, 59, 5, static_cast<uint64_t>(r));
    put(w, 56, 3, static_cast<uint64_t>(dr & 7));
    put(w, 51, 5, static_cast<uint64_t>(g));
    put(w, 48, 3, static_cast<uint64_t>(dg & 7));
    put(w, 43, 5, static_cast<uint64_t>(b));
    put(w, 40, 3, static_cast<uint64_t>(db & 7));
    put(w, 33, 1, 1);
    return kRgb.mode(block_of(w));
  };
  EXPECT_EQ(mode_for(31, 0, 0, 0, 0, 0), Mode::Differential);
  EXPECT_EQ(mode_for(28, 3, 1, -1, 4, -4), Mode::Differential);
  EXPECT_EQ(mode_for(31, 1, 0, 0, 0, 0), Mode::T);
  EXPECT_EQ(mode_for(0, -1, 0, 0, 0, 0), Mode::T);
  EXPECT_EQ(mode_for(0, -1, 31, 3, 0, -4), Mode::T);  // R first
  EXPECT_EQ(mode_for(5, 0, 29, 3, 0, 0), Mode::H);
  EXPECT_EQ(mode_for(5, 0, 2, -3, 0, -4), Mode::H);  // G before B
  EXPECT_EQ(mode_for(5, 0, 2, 0, 0, -1), Mode::Planar);
  EXPECT_EQ(mode_for(5, 0, 2, 0, 30, 2), Mode::Planar);
}

// T block: base 1 = (13, 2, 5) -> (221, 34, 85), base 2 = (8, 0, 15) -> (136, 0, 255),
// distance index (da = 2, db = 1) = 5 -> 32; texels (0..3, 0) take indices 0..3.
uint64_t t_block() {
  uint64_t w = 0;
  put(w, 61, 3, 7);  // free bits: R = 11111 = 31 ...
  put(w, 59, 2, 3);  // R1a
  put(w, 58, 1, 0);  // ... dR = 001: 31 + 1 overflows
  put(w, 56, 2, 1);  // R1b
  put(w, 52, 4, 2);
  put(w, 48, 4, 5);
  put(w, 44, 4, 8);
  put(w, 40, 4, 0);
  put(w, 36, 4, 15);
  put(w, 34, 2, 2);
  put(w, 33, 1, 1);
  put(w, 32, 1, 1);
  for (int x = 0; x < 4; ++x) put_index(w, x, 0, x);
  return w;
}

TEST(Etc2Rgb, TModePaintColoursFromTheDistanceTableClamped) {
  const auto b = block_of(t_block());
  EXPECT_EQ(kRgb.mode(b), Mode::T);
  const auto t = kRgb.decode_rgba8(b);
  EXPECT_EQ(texel(t, 0, 0), rgba(221, 34, 85));   // paint 0: base 1
  EXPECT_EQ(texel(t, 1, 0), rgba(168, 32, 255));  // paint 1: base 2 + 32, 287 clamped
  EXPECT_EQ(texel(t, 2, 0), rgba(136, 0, 255));   // paint 2: base 2
  EXPECT_EQ(texel(t, 3, 0), rgba(104, 0, 223));   // paint 3: base 2 - 32, -32 clamped
  EXPECT_EQ(texel(t, 0, 1), rgba(221, 34, 85));
}

// H block of base colours c1, c2 (4-bit fields) and (da, db); texels (0..3, 0) take indices
// 0..3. The free bits are chosen for these fields: G1b = 0, B1a = 1, B1b = 001 and dR < 0.
uint64_t h_block(std::array<int, 3> c1, std::array<int, 3> c2, int da, int db) {
  uint64_t w = 0;
  put(w, 59, 4, static_cast<uint64_t>(c1[0]));
  put(w, 56, 3, static_cast<uint64_t>(c1[1] >> 1));
  put(w, 52, 1, static_cast<uint64_t>(c1[1] & 1));
  put(w, 51, 1, static_cast<uint64_t>(c1[2] >> 3));
  put(w, 47, 3, static_cast<uint64_t>(c1[2] & 7));
  put(w, 43, 4, static_cast<uint64_t>(c2[0]));
  put(w, 39, 4, static_cast<uint64_t>(c2[1]));
  put(w, 35, 4, static_cast<uint64_t>(c2[2]));
  put(w, 34, 1, static_cast<uint64_t>(da));
  put(w, 33, 1, 1);
  put(w, 32, 1, static_cast<uint64_t>(db));
  put(w, 50, 1, 1);  // dG = -4 with G = 1: H (R = 5 + dR stays in range)
  for (int x = 0; x < 4; ++x) put_index(w, x, 0, x);
  return w;
}

TEST(Etc2Rgb, HModeDistanceIndexTakesItsLowBitFromTheColourOrder) {
  // c1 = (5, 10, 9) -> (85, 170, 153) >= c2 = (5, 10, 8) -> (85, 170, 136): index 101b = 5,
  // distance 32.
  const auto b = block_of(h_block({5, 10, 9}, {5, 10, 8}, 1, 0));
  ASSERT_EQ(kRgb.mode(b), Mode::H);
  const auto t = kRgb.decode_rgba8(b);
  EXPECT_EQ(texel(t, 0, 0), rgba(117, 202, 185));
  EXPECT_EQ(texel(t, 1, 0), rgba(53, 138, 121));
  EXPECT_EQ(texel(t, 2, 0), rgba(117, 202, 168));
  EXPECT_EQ(texel(t, 3, 0), rgba(53, 138, 104));
  // The same colours the other way round: c1 < c2, index 100b = 4, distance 23.
  const auto s = kRgb.decode_rgba8(block_of(h_block({5, 10, 8}, {5, 10, 9}, 1, 0)));
  EXPECT_EQ(texel(s, 0, 0), rgba(108, 193, 159));
  EXPECT_EQ(texel(s, 1, 0), rgba(62, 147, 113));
  EXPECT_EQ(texel(s, 2, 0), rgba(108, 193, 176));
  EXPECT_EQ(texel(s, 3, 0), rgba(62, 147, 130));
  // Equal colours count as c1 >= c2; (da, db) = (0, 0): index 1, distance 6. Clamping at both
  // ends with (15, 0, 9) and distance 64 (index 7).
  const auto e = kRgb.decode_rgba8(block_of(h_block({5, 10, 9}, {5, 10, 9}, 0, 0)));
  EXPECT_EQ(texel(e, 0, 0), rgba(91, 176, 159));
  const auto c = kRgb.decode_rgba8(block_of(h_block({15, 0, 9}, {1, 0, 9}, 1, 1)));
  EXPECT_EQ(texel(c, 0, 0), rgba(255, 64, 217));
  EXPECT_EQ(texel(c, 1, 0), rgba(191, 0, 89));
  EXPECT_EQ(texel(c, 3, 0), rgba(0, 0, 89));
}

// Planar block of 8-bit-extended O, H, V from 6/7/6-bit fields, with the free bits set for
// planar (R, G in range, B + dB < 0).
uint64_t planar_block(std::array<int, 3> o, std::array<int, 3> h, std::array<int, 3> v) {
  uint64_t w = 0;
  put(w, 57, 6, static_cast<uint64_t>(o[0]));
  put(w, 56, 1, static_cast<uint64_t>(o[1] >> 6));
  put(w, 49, 6, static_cast<uint64_t>(o[1] & 63));
  put(w, 48, 1, static_cast<uint64_t>(o[2] >> 5));
  put(w, 43, 2, static_cast<uint64_t>((o[2] >> 3) & 3));
  put(w, 39, 3, static_cast<uint64_t>(o[2] & 7));
  put(w, 34, 5, static_cast<uint64_t>(h[0] >> 1));
  put(w, 33, 1, 1);
  put(w, 32, 1, static_cast<uint64_t>(h[0] & 1));
  put(w, 25, 7, static_cast<uint64_t>(h[1]));
  put(w, 19, 6, static_cast<uint64_t>(h[2]));
  put(w, 13, 6, static_cast<uint64_t>(v[0]));
  put(w, 6, 7, static_cast<uint64_t>(v[1]));
  put(w, 0, 6, static_cast<uint64_t>(v[2]));
  // Free bits 63, 55, 47-45, 42: the first choice that selects planar.
  for (uint32_t combo = 0; combo < 64; ++combo) {
    uint64_t t = w;
    const std::array<int, 6> free = {63, 55, 47, 46, 45, 42};
    for (size_t k = 0; k < free.size(); ++k) put(t, free[k], 1, (combo >> k) & 1);
    if (kRgb.mode(block_of(t)) == Mode::Planar) return t;
  }
  ADD_FAILURE() << "no free bits select planar";
  return w;
}

TEST(Etc2Rgb, PlanarModeExtrapolatesRoundsTiesUpAndClamps) {
  // R: O = 255, H = V = 0; G: O = 0, H = V = 255 (7-bit 127); B: O = 130 (6-bit 32),
  // H = 125 (31), V = 255 (63).
  const auto b = block_of(planar_block({63, 0, 32}, {0, 127, 31}, {0, 127, 63}));
  ASSERT_EQ(kRgb.mode(b), Mode::Planar);
  const auto t = kRgb.decode_rgba8(b);
  EXPECT_EQ(texel(t, 0, 0), rgba(255, 0, 130));
  EXPECT_EQ(texel(t, 1, 1)[0], 128);  // (1022 - 510) / 4
  EXPECT_EQ(texel(t, 3, 3)[0], 0);    // -508 / 4 clamped
  EXPECT_EQ(texel(t, 3, 3)[1], 255);  // 1532 / 4 clamped
  EXPECT_EQ(texel(t, 1, 0)[1], 64);   // 257 / 4 rounds down
  EXPECT_EQ(texel(t, 2, 0)[2], 128);  // 127.5: a tie goes to the larger integer
  // Every texel against the spec's first form, in doubles: x (H - O) / 4 + y (V - O) / 4 + O,
  // rounded half up and clamped.
  const std::array<std::array<int, 3>, 3> ohv = {{{255, 0, 130}, {0, 255, 125}, {0, 255, 255}}};
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      for (size_t k = 0; k < 3; ++k) {
        const double f =
            x * (ohv[1][k] - ohv[0][k]) / 4.0 + y * (ohv[2][k] - ohv[0][k]) / 4.0 + ohv[0][k];
        const int want = std::clamp(static_cast<int>(std::floor(f + 0.5)), 0, 255);
        EXPECT_EQ(texel(t, x, y)[k], want) << x << "," << y << " channel " << k;
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Punch-through alpha

TEST(Etc2Rgb8A1, OpaqueBitClearMakesIndexTwoTransparentAndZeroesTheSmallModifiers) {
  // The differential block above, opaque bit (33) cleared: index 0 adds 0, 1 adds +b, 2 is
  // transparent black, 3 adds -b.
  uint64_t w = 0;
  put(w, 59, 5, 28);
  put(w, 56, 3, 4);
  put(w, 51, 5, 4);
  put(w, 48, 3, 2);
  put(w, 43, 5, 3);
  put(w, 37, 3, 0);
  put(w, 34, 3, 1);
  put(w, 32, 1, 1);
  for (int x = 0; x < 4; ++x) put_index(w, x, 0, x);
  const auto clear = kRgbA1.decode_rgba8(block_of(w));
  EXPECT_EQ(kRgbA1.mode(block_of(w)), Mode::Differential);
  EXPECT_EQ(texel(clear, 0, 0), rgba(231, 33, 24));
  EXPECT_EQ(texel(clear, 1, 0), rgba(239, 41, 32));
  EXPECT_EQ(texel(clear, 2, 0), rgba(0, 0, 0, 0));
  EXPECT_EQ(texel(clear, 3, 0), rgba(223, 25, 16));
  EXPECT_EQ(kRgbA1.decode(block_of(w)).at(2, 0), glm::vec4(0, 0, 0, 0));
  // Opaque bit set: the RGB ETC2 tables, alpha 255.
  put(w, 33, 1, 1);
  const auto set = kRgbA1.decode_rgba8(block_of(w));
  EXPECT_EQ(texel(set, 0, 0), rgba(233, 35, 26));
  EXPECT_EQ(texel(set, 2, 0), rgba(229, 31, 22));
  EXPECT_EQ(set, kRgb.decode_rgba8(block_of(w)));
  // Without punch-through, bit 33 = 0 is the individual mode.
  put(w, 33, 1, 0);
  EXPECT_EQ(kRgb.mode(block_of(w)), Mode::Individual);
}

TEST(Etc2Rgb8A1, TAndHModesMakeIndexTwoTransparentPlanarStaysOpaque) {
  uint64_t t = t_block();
  put(t, 33, 1, 0);
  const auto tt = kRgbA1.decode_rgba8(block_of(t));
  EXPECT_EQ(texel(tt, 1, 0), rgba(168, 32, 255));
  EXPECT_EQ(texel(tt, 2, 0), rgba(0, 0, 0, 0));
  EXPECT_EQ(texel(tt, 3, 0), rgba(104, 0, 223));
  uint64_t h = h_block({5, 10, 9}, {5, 10, 8}, 1, 0);
  put(h, 33, 1, 0);
  ASSERT_EQ(kRgbA1.mode(block_of(h)), Mode::H);
  const auto ht = kRgbA1.decode_rgba8(block_of(h));
  EXPECT_EQ(texel(ht, 2, 0), rgba(0, 0, 0, 0));
  EXPECT_EQ(texel(ht, 3, 0), rgba(53, 138, 104));
  // Planar with the opaque bit clear decodes as with it set.
  uint64_t p = planar_block({63, 0, 32}, {0, 127, 31}, {0, 127, 63});
  const auto opaque = kRgbA1.decode_rgba8(block_of(p));
  put(p, 33, 1, 0);
  ASSERT_EQ(kRgbA1.mode(block_of(p)), Mode::Planar);
  EXPECT_EQ(kRgbA1.decode_rgba8(block_of(p)), opaque);
  for (const auto& px : opaque) EXPECT_EQ(px[3], 255);
}

// ---------------------------------------------------------------------------------------------
// EAC

// An EAC word: base codeword, multiplier, table, every texel index `idx`.
uint64_t eac_block(int base, int mult, int table, int idx) {
  uint64_t w = 0;
  put(w, 56, 8, static_cast<uint64_t>(base & 0xFF));
  put(w, 52, 4, static_cast<uint64_t>(mult));
  put(w, 48, 4, static_cast<uint64_t>(table));
  for (int i = 0; i < 16; ++i) put_eac_index(w, i / 4, i % 4, idx);
  return w;
}

const EacDecoder kR11;
const EacDecoder kSignedR11({true, Datapath::Spatial});

TEST(EacR11, SpecExamplesWithAndWithoutTheMultiplier) {
  // base 103, table 13 (-1 -2 -3 -10 0 1 2 9), index 3 (-10), multiplier 2: 828 - 160 = 668.
  EXPECT_EQ(kR11.decode_r11(block_of(eac_block(103, 2, 13, 3)))[5], 668);
  EXPECT_EQ(kR11.decode(block_of(eac_block(103, 2, 13, 3))).at(1, 1).x, 668 / 2047.0F);
  // Multiplier 0 stands for 1/8: 828 - 10 = 818.
  EXPECT_EQ(kR11.decode_r11(block_of(eac_block(103, 0, 13, 3)))[0], 818);
  // Clamping to 0..2047: 255 * 8 + 4 + 14 * 15 * 8, and 0 * 8 + 4 - 15 * 15 * 8.
  EXPECT_EQ(kR11.decode_r11(block_of(eac_block(255, 15, 0, 7)))[0], 2047);
  EXPECT_EQ(kR11.decode(block_of(eac_block(255, 15, 0, 7))).at(0, 0), glm::vec4(1, 0, 0, 1));
  EXPECT_EQ(kR11.decode_r11(block_of(eac_block(0, 15, 0, 3)))[0], 0);
  // Indices by position: texel b (x 0, y 1) at bits 44-42.
  uint64_t w = eac_block(100, 1, 13, 4);  // all 0 modifiers: 804
  put(w, 42, 3, 7);                       // b: +9 * 8
  const auto v = kR11.decode_r11(block_of(w));
  EXPECT_EQ(v[0], 804);
  EXPECT_EQ(v[4], 876);  // row-major (0, 1)
}

TEST(EacR11, SignedBaseMinus128IsMinus127AndResultsClampToPlusMinus1023) {
  // The spec's example: base 60, table 13, index 3, multiplier 2: 480 - 160 = 320; multiplier
  // 0: 480 - 10 = 470 (the spec's text says base 65 there but computes with 60).
  EXPECT_EQ(kSignedR11.decode_r11(block_of(eac_block(60, 2, 13, 3)))[0], 320);
  EXPECT_EQ(kSignedR11.decode_r11(block_of(eac_block(60, 0, 13, 3)))[0], 470);
  // No +4 in the signed form: base -5, modifier 0.
  EXPECT_EQ(kSignedR11.decode_r11(block_of(eac_block(-5, 1, 13, 4)))[0], -40);
  // -128 reads as -127: -1016 with a 0 modifier, as -127 gives.
  EXPECT_EQ(kSignedR11.decode_r11(block_of(eac_block(-128, 1, 13, 4)))[0], -1016);
  EXPECT_EQ(kSignedR11.decode_r11(block_of(eac_block(-127, 1, 13, 4)))[0], -1016);
  // -1016 - 10 = -1026 clamps to -1023 (never -1024): exactly -1.0.
  const auto low = block_of(eac_block(-128, 0, 13, 3));
  EXPECT_EQ(kSignedR11.decode_r11(low)[0], -1023);
  EXPECT_EQ(kSignedR11.decode(low).at(0, 0).x, -1.0F);
  EXPECT_EQ(kSignedR11.decode_r11(block_of(eac_block(127, 15, 0, 7)))[0], 1023);
  EXPECT_EQ(kSignedR11.decode(block_of(eac_block(60, 2, 13, 3))).at(3, 3).x, 320 / 1023.0F);
}

TEST(EacRg11, RedFromTheFirstEightBytesGreenFromTheSecond) {
  std::array<uint8_t, 16> b{};
  const auto r = block_of(eac_block(103, 2, 13, 3));
  const auto g = block_of(eac_block(103, 0, 13, 3));
  std::copy(r.begin(), r.end(), b.begin());
  std::copy(g.begin(), g.end(), b.begin() + 8);
  const EacRgDecoder rg;
  const DecodedBlock d = rg.decode(b);
  EXPECT_EQ(d.at(2, 1), glm::vec4(668 / 2047.0F, 818 / 2047.0F, 0, 1));
  const EacRgDecoder srg({true, Datapath::Spatial});
  EXPECT_EQ(srg.decode_rg11(b)[0][0], 664);  // signed: 103 * 8 - 160, no +4
}

TEST(Etc2Rgba8, AlphaIsEightBitEacWithMultiplierZeroGivingTheBase) {
  std::array<uint8_t, 16> b{};
  const auto a = block_of(eac_block(103, 2, 13, 3));  // 103 - 20 = 83
  const auto c = block_of(t_block());
  std::copy(a.begin(), a.end(), b.begin());
  std::copy(c.begin(), c.end(), b.begin() + 8);
  const Etc2RgbaDecoder rgba8;
  const auto t = rgba8.decode_rgba8(b);
  EXPECT_EQ(texel(t, 1, 0), rgba(168, 32, 255, 83));
  EXPECT_EQ(texel(t, 2, 0), rgba(136, 0, 255, 83));
  const auto z = block_of(eac_block(103, 0, 13, 3));  // 0 x modifier: 103
  std::copy(z.begin(), z.end(), b.begin());
  EXPECT_EQ(rgba8.decode_rgba8(b)[0][3], 103);
  const auto hi = block_of(eac_block(250, 3, 0, 7));  // 250 + 42 clamps to 255
  std::copy(hi.begin(), hi.end(), b.begin());
  EXPECT_EQ(rgba8.decode(b).at(0, 0).w, 1.0F);
}

TEST(EtcDecoders, BlockCostsAndNames) {
  const TechTable tech = TechTable::defaults();
  const OpCounts eac = kR11.ops_per_item();
  EXPECT_EQ(eac.add, 16u);
  EXPECT_EQ(eac.mul, 8u);
  EXPECT_EQ(eac.lut, 1u);
  EXPECT_EQ(eac.cmp, 33u);
  EXPECT_EQ(kSignedR11.ops_per_item().cmp, 34u);
  EXPECT_EQ(EacRgDecoder().ops_per_item(), eac * 2);
  EXPECT_EQ(kRgbA1.ops_per_item().cmp, kRgb.ops_per_item().cmp + 16);
  EXPECT_EQ(Etc2RgbaDecoder().ops_per_item().mul, 8u);
  for (const TimingSpec& t : {kRgb.timing(tech), kRgbA1.timing(tech), kR11.timing(tech),
                              EacRgDecoder().timing(tech), Etc2RgbaDecoder().timing(tech)}) {
    EXPECT_EQ(t.ii, 1u);
    EXPECT_GE(t.latency, 1u);
    EXPECT_GT(t.area, 0.0);
  }
  // The default table's figures in docs/derivations/etc2-eac.md §6.
  EXPECT_EQ(kRgb.timing(tech).latency, 7u);
  EXPECT_DOUBLE_EQ(kRgb.timing(tech).area, 279.0);
  EXPECT_DOUBLE_EQ(kRgbA1.timing(tech).area, 287.0);
  EXPECT_EQ(Etc2RgbaDecoder().timing(tech).latency, 8u);
  EXPECT_DOUBLE_EQ(Etc2RgbaDecoder().timing(tech).area, 379.0);
  EXPECT_EQ(kR11.timing(tech).latency, 8u);
  EXPECT_DOUBLE_EQ(kR11.timing(tech).area, 100.5);
  EXPECT_DOUBLE_EQ(EacRgDecoder({true, Datapath::Spatial}).timing(tech).area, 202.0);
  const EacDecoder shared({false, Datapath::Shared});
  EXPECT_EQ(shared.timing(tech).ii, 33u);  // the 33 compares through one comparator
  EXPECT_EQ(kRgb.name(), "texture.etc2_rgb8");
  EXPECT_EQ(kRgbA1.name(), "texture.etc2_rgb8a1");
  EXPECT_EQ(kSignedR11.name(), "texture.eac_r11_snorm");
  EXPECT_FALSE(kRgb.arithmetic().empty());
}

// ---------------------------------------------------------------------------------------------
// Every block of real textures and of random bytes against Mesa

// OpenGL enums (GL/glcorearb.h).
constexpr uint32_t kGlR11Eac = 0x9270, kGlSignedR11Eac = 0x9271, kGlRg11Eac = 0x9272,
                   kGlSignedRg11Eac = 0x9273, kGlRgb8Etc2 = 0x9274, kGlRgb8A1Etc2 = 0x9276,
                   kGlRgba8Etc2Eac = 0x9278;
constexpr uint32_t kGlRed = 0x1903, kGlRg = 0x8227, kGlRgba = 0x1908;
constexpr uint32_t kGlUnsignedByte = 0x1401, kGlShort = 0x1402, kGlUnsignedShort = 0x1403;

struct Image {
  std::string name;
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;
};

// A PNG as 8-bit RGBA (libpng's simplified reader: grey, palette and RGB files get alpha 255).
Image load_rgba(const std::string& path) {
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&img, path.c_str())) return {};
  img.format = PNG_FORMAT_RGBA;
  Image out{path.substr(path.rfind('/') + 1), static_cast<int>(img.width),
            static_cast<int>(img.height), std::vector<uint8_t>(PNG_IMAGE_SIZE(img))};
  if (!png_image_finish_read(&img, nullptr, out.rgba.data(), 0, nullptr)) return {};
  return out;
}

// glmark2-data's and matplotlib's sample pictures: photographs, a glyph atlas with
// transparency, logos with alpha edges.
const std::vector<Image>& textures() {
  static const std::vector<Image> images = [] {
    std::vector<Image> v;
    for (const char* p :
         {"/usr/share/glmark2/textures/crate-base.png", "/usr/share/glmark2/textures/nasa1.png",
          "/usr/share/glmark2/textures/glyph-atlas.png",
          "/usr/share/matplotlib/mpl-data/sample_data/logo2.png",
          "/usr/share/matplotlib/mpl-data/sample_data/Minduka_Present_Blue_Pack.png"}) {
      Image i = load_rgba(p);
      if (i.width >= 4 && i.height >= 4) v.push_back(std::move(i));
    }
    return v;
  }();
  return images;
}

EtcPixels pixels(const Image& img, int bx, int by) {
  EtcPixels px{};
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      const size_t i = (static_cast<size_t>(by * 4 + y) * static_cast<size_t>(img.width) +
                        static_cast<size_t>(bx * 4 + x)) *
                       4;
      for (size_t k = 0; k < 4; ++k)
        px[static_cast<size_t>(y) * 4 + static_cast<size_t>(x)][k] = img.rgba[i + k];
    }
  }
  return px;
}

// A compressed image: bw x bh blocks of `block_bytes`, row by row.
struct Compressed {
  int bw = 0, bh = 0;
  size_t block_bytes = 8;
  std::vector<uint8_t> data;
  template <size_t N>
  std::span<const uint8_t, N> block(int bx, int by) const {
    return std::span<const uint8_t, N>(
        data.data() +
            (static_cast<size_t>(by) * static_cast<size_t>(bw) + static_cast<size_t>(bx)) * N,
        N);
  }
};

// The image's blocks, each made of `make(pixels, bx, by)`'s bytes.
Compressed encode(const Image& img, size_t block_bytes,
                  const std::function<std::vector<uint8_t>(const EtcPixels&, int, int)>& make) {
  Compressed c{img.width / 4, img.height / 4, block_bytes, {}};
  for (int by = 0; by < c.bh; ++by) {
    for (int bx = 0; bx < c.bw; ++bx) {
      const std::vector<uint8_t> b = make(pixels(img, bx, by), bx, by);
      c.data.insert(c.data.end(), b.begin(), b.end());
    }
  }
  return c;
}

// 64 x 64 blocks of random bytes.
Compressed random_blocks(size_t block_bytes, uint64_t seed) {
  std::mt19937_64 rng(seed);
  Compressed c{64, 64, block_bytes, std::vector<uint8_t>(4096 * block_bytes)};
  for (uint8_t& b : c.data) b = static_cast<uint8_t>(rng() >> 56);
  return c;
}

EtcMode mode_at(int bx, int by) { return static_cast<EtcMode>((bx + by) % 5); }
std::vector<uint8_t> vec(const std::array<uint8_t, 8>& a) { return {a.begin(), a.end()}; }
std::array<int, 16> channel(const EtcPixels& px, size_t k, int offset) {
  std::array<int, 16> v{};
  for (size_t i = 0; i < 16; ++i) v[i] = std::clamp(px[i][k] + offset, -127, 255);
  return v;
}

// Expected values of one block in the read-back's units: texel (row-major) x channel.
using Expected = std::array<std::array<int, 4>, 16>;

struct Tally {
  int blocks = 0;
  int mismatches = 0;  // blocks with any texel channel unlike Mesa's
  std::string first;
};

// Mesa's decoding of the whole image, read back as `channels` values of T per texel, against
// `expect(bx, by)`.
template <class T>
Tally compare(const MesaPeer& peer, const Compressed& c, uint32_t gl_format, uint32_t read_format,
              int channels, const std::function<Expected(int, int)>& expect) {
  const uint32_t type = std::is_same_v<T, uint8_t>    ? kGlUnsignedByte
                        : std::is_same_v<T, uint16_t> ? kGlUnsignedShort
                                                      : kGlShort;
  const int width = c.bw * 4;
  const std::vector<uint8_t> bytes =
      peer.decode_compressed(gl_format, width, c.bh * 4, c.data, read_format, type,
                             sizeof(T) * static_cast<size_t>(channels));
  std::vector<T> mesa(bytes.size() / sizeof(T));
  std::memcpy(mesa.data(), bytes.data(), mesa.size() * sizeof(T));
  Tally t;
  for (int by = 0; by < c.bh; ++by) {
    for (int bx = 0; bx < c.bw; ++bx) {
      const Expected want = expect(bx, by);
      ++t.blocks;
      bool same = true;
      for (int i = 0; i < 16; ++i) {
        const size_t at = (static_cast<size_t>(by * 4 + i / 4) * static_cast<size_t>(width) +
                           static_cast<size_t>(bx * 4 + i % 4)) *
                          static_cast<size_t>(channels);
        for (int k = 0; k < channels; ++k) {
          const int got = mesa[at + static_cast<size_t>(k)];
          const int w = want[static_cast<size_t>(i)][static_cast<size_t>(k)];
          if (got == w) continue;
          if (same && t.first.empty()) {
            t.first = "block (" + std::to_string(bx) + ", " + std::to_string(by) + ") texel " +
                      std::to_string(i) + " channel " + std::to_string(k) + ": Mesa " +
                      std::to_string(got) + ", texsim " + std::to_string(w);
          }
          same = false;
        }
      }
      if (!same) ++t.mismatches;
    }
  }
  return t;
}

Expected from_rgba8(const Etc2RgbDecoder::Texels8& t) {
  Expected e{};
  for (size_t i = 0; i < 16; ++i) {
    for (size_t k = 0; k < 4; ++k) e[i][k] = t[i][k];
  }
  return e;
}
// The spec's extension of an 11-bit result to 16 bits (what Mesa stores and reads back).
int unorm16(int v) { return (v << 5) + (v >> 6); }
int snorm16(int v) { return v >= 0 ? (v << 5) + (v >> 5) : -(((-v) << 5) + ((-v) >> 5)); }

#define REQUIRE_MESA(peer) \
  if (!(peer).available()) GTEST_SKIP() << (peer).why_not()

const MesaPeer& mesa() {
  static const MesaPeer peer(MesaDriver::Llvmpipe);
  return peer;
}

// The RGB(A) ETC2 side: every block of every texture with the modes in turn, then random ones;
// each mode must occur in both sets.
void check_rgb(const Etc2RgbDecoder& dec, uint32_t gl_format) {
  const bool punch = dec.config().punch_through;
  const auto expect = [&](const Compressed& c) {
    return [&dec, &c](int bx, int by) { return from_rgba8(dec.decode_rgba8(c.block<8>(bx, by))); };
  };
  const auto modes_of = [&](const Compressed& c) {
    std::array<int, 5> n{};
    for (int by = 0; by < c.bh; ++by) {
      for (int bx = 0; bx < c.bw; ++bx) ++n[static_cast<size_t>(dec.mode(c.block<8>(bx, by)))];
    }
    return n;
  };
  std::array<int, 5> image_modes{};
  int transparent_blocks = 0;
  ASSERT_FALSE(textures().empty());
  for (const Image& img : textures()) {
    const Compressed c = encode(img, 8, [&](const EtcPixels& px, int bx, int by) {
      return vec(etc_encode_rgb_mode(px, mode_at(bx, by), punch));
    });
    const Tally t = compare<uint8_t>(mesa(), c, gl_format, kGlRgba, 4, expect(c));
    EXPECT_EQ(t.mismatches, 0) << dec.name() << " " << img.name << ": " << t.first;
    const std::array<int, 5> m = modes_of(c);
    for (size_t k = 0; k < 5; ++k) image_modes[k] += m[k];
    for (int by = 0; by < c.bh; ++by) {
      for (int bx = 0; bx < c.bw; ++bx)
        transparent_blocks += punch && (c.block<8>(bx, by)[3] & 2) == 0;
    }
    std::printf("%s %s: %d blocks, %d mismatches\n", dec.name().c_str(), img.name.c_str(), t.blocks,
                t.mismatches);
  }
  const Compressed r = random_blocks(8, punch ? 2 : 1);
  const Tally t = compare<uint8_t>(mesa(), r, gl_format, kGlRgba, 4, expect(r));
  EXPECT_EQ(t.mismatches, 0) << dec.name() << " random: " << t.first;
  const std::array<int, 5> rm = modes_of(r);
  std::printf(
      "%s random: %d blocks, %d mismatches; modes I/D/T/H/P images %d/%d/%d/%d/%d random "
      "%d/%d/%d/%d/%d\n",
      dec.name().c_str(), t.blocks, t.mismatches, image_modes[0], image_modes[1], image_modes[2],
      image_modes[3], image_modes[4], rm[0], rm[1], rm[2], rm[3], rm[4]);
  for (size_t k = punch ? 1 : 0; k < 5; ++k) {
    EXPECT_GT(image_modes[k], 0) << "mode " << k;
    EXPECT_GT(rm[k], 0) << "mode " << k;
  }
  if (punch) {
    EXPECT_GT(transparent_blocks, 0);
  }
}

TEST(EtcMesa, Rgb8EveryBlockOfTexturesAndRandomBlocks) {
  REQUIRE_MESA(mesa());
  check_rgb(kRgb, kGlRgb8Etc2);
}

TEST(EtcMesa, Rgb8A1EveryBlockOfTexturesAndRandomBlocks) {
  REQUIRE_MESA(mesa());
  check_rgb(kRgbA1, kGlRgb8A1Etc2);
}

TEST(EtcMesa, Rgba8EveryBlockOfTexturesAndRandomBlocks) {
  REQUIRE_MESA(mesa());
  const Etc2RgbaDecoder dec;
  const auto expect = [&](const Compressed& c) {
    return [&dec, &c](int bx, int by) { return from_rgba8(dec.decode_rgba8(c.block<16>(bx, by))); };
  };
  for (const Image& img : textures()) {
    const Compressed c = encode(img, 16, [](const EtcPixels& px, int bx, int by) {
      std::vector<uint8_t> b =
          vec(eac_encode_mode(channel(px, 3, 0), EacKind::Alpha8, (bx + by) % 7 == 0));
      const std::vector<uint8_t> rgb = vec(etc_encode_rgb_mode(px, mode_at(bx, by), false));
      b.insert(b.end(), rgb.begin(), rgb.end());
      return b;
    });
    const Tally t = compare<uint8_t>(mesa(), c, kGlRgba8Etc2Eac, kGlRgba, 4, expect(c));
    EXPECT_EQ(t.mismatches, 0) << img.name << ": " << t.first;
    std::printf("%s %s: %d blocks, %d mismatches\n", dec.name().c_str(), img.name.c_str(), t.blocks,
                t.mismatches);
  }
  const Compressed r = random_blocks(16, 3);
  const Tally t = compare<uint8_t>(mesa(), r, kGlRgba8Etc2Eac, kGlRgba, 4, expect(r));
  EXPECT_EQ(t.mismatches, 0) << "random: " << t.first;
  std::printf("%s random: %d blocks, %d mismatches\n", dec.name().c_str(), t.blocks, t.mismatches);
}

// R11 / RG11 (unsigned, signed): the red (and green) channel of each texture, a quarter of
// the blocks with multiplier 0, then random blocks; Mesa keeps the spec's 16-bit extension.
void check_eac(bool snorm, int channels) {
  const EacDecoder r11({snorm, Datapath::Spatial});
  const EacRgDecoder rg11({snorm, Datapath::Spatial});
  const size_t bytes = channels == 1 ? 8 : 16;
  const uint32_t format = channels == 1 ? (snorm ? kGlSignedR11Eac : kGlR11Eac)
                                        : (snorm ? kGlSignedRg11Eac : kGlRg11Eac);
  const auto expect = [&](const Compressed& c) {
    return [&, snorm, channels](int bx, int by) {
      std::array<EacDecoder::Values11, 2> v{};
      if (channels == 1) {
        v[0] = r11.decode_r11(c.block<8>(bx, by));
      } else {
        v = rg11.decode_rg11(c.block<16>(bx, by));
      }
      Expected e{};
      for (size_t i = 0; i < 16; ++i) {
        for (size_t k = 0; k < static_cast<size_t>(channels); ++k)
          e[i][k] = snorm ? snorm16(v[k][i]) : unorm16(v[k][i]);
      }
      return e;
    };
  };
  const std::string name = channels == 1 ? r11.name() : rg11.name();
  const auto run = [&](const Compressed& c, const std::string& what) {
    const uint32_t read = channels == 1 ? kGlRed : kGlRg;
    const Tally t = snorm ? compare<int16_t>(mesa(), c, format, read, channels, expect(c))
                          : compare<uint16_t>(mesa(), c, format, read, channels, expect(c));
    EXPECT_EQ(t.mismatches, 0) << name << " " << what << ": " << t.first;
    std::printf("%s %s: %d blocks, %d mismatches\n", name.c_str(), what.c_str(), t.blocks,
                t.mismatches);
  };
  const EacKind kind = snorm ? EacKind::SignedR11 : EacKind::R11;
  const int offset = snorm ? -128 : 0;
  for (const Image& img : textures()) {
    run(encode(img, bytes,
               [&](const EtcPixels& px, int bx, int by) {
                 const bool zero = (bx * 3 + by) % 4 == 0;
                 std::vector<uint8_t> b = vec(eac_encode_mode(channel(px, 0, offset), kind, zero));
                 if (channels == 2) {
                   const auto g = eac_encode_mode(channel(px, 1, offset), kind, !zero);
                   b.insert(b.end(), g.begin(), g.end());
                 }
                 return b;
               }),
        img.name);
  }
  run(random_blocks(bytes, 10 + static_cast<uint64_t>(channels) * 2 + (snorm ? 1 : 0)), "random");
}

TEST(EtcMesa, R11EveryBlockOfTexturesAndRandomBlocks) {
  REQUIRE_MESA(mesa());
  check_eac(false, 1);
}
TEST(EtcMesa, SignedR11EveryBlockOfTexturesAndRandomBlocks) {
  REQUIRE_MESA(mesa());
  check_eac(true, 1);
}
TEST(EtcMesa, Rg11EveryBlockOfTexturesAndRandomBlocks) {
  REQUIRE_MESA(mesa());
  check_eac(false, 2);
}
TEST(EtcMesa, SignedRg11EveryBlockOfTexturesAndRandomBlocks) {
  REQUIRE_MESA(mesa());
  check_eac(true, 2);
}

}  // namespace
