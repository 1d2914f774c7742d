#include "blocks/texture/decode/astc_endpoints.h"

#include <algorithm>

namespace texsim {

namespace {

struct ColorRangeRow {
  AstcRange range;
  const char* b_pattern;  // the spec's B column, most significant bit first
  int c;                  // the spec's C column
};

// The rows of the spec's colour unquantisation table, and the power-of-two ranges (C = 0).
// Pattern letters name the value's low bits: a = bit 0, b = bit 1, ...
constexpr std::array<ColorRangeRow, kAstcColorRanges> kColorRanges = {{
    {{1, true, false}, "000000000", 204},  // 0..5
    {{3, false, false}, "", 0},            // 0..7
    {{1, false, true}, "000000000", 113},  // 0..9
    {{2, true, false}, "b000b0bb0", 93},   // 0..11
    {{4, false, false}, "", 0},            // 0..15
    {{2, false, true}, "b0000bb00", 54},   // 0..19
    {{3, true, false}, "cb000cbcb", 44},   // 0..23
    {{5, false, false}, "", 0},            // 0..31
    {{3, false, true}, "cb0000cbc", 26},   // 0..39
    {{4, true, false}, "dcb000dcb", 22},   // 0..47
    {{6, false, false}, "", 0},            // 0..63
    {{4, false, true}, "dcb0000dc", 13},   // 0..79
    {{5, true, false}, "edcb000ed", 11},   // 0..95
    {{7, false, false}, "", 0},            // 0..127
    {{5, false, true}, "edcb0000e", 6},    // 0..159
    {{6, true, false}, "fedcb000f", 5},    // 0..191
    {{8, false, false}, "", 0},            // 0..255
}};

// The value of a bit pattern (MSB first) whose letters select bits of `m`.
int pattern_value(const char* pattern, int m) {
  int v = 0;
  for (const char* p = pattern; *p != '\0'; ++p) {
    const int bit = *p == '0' ? 0 : (m >> (*p - 'a')) & 1;
    v = (v << 1) | bit;
  }
  return v;
}

// Replicates the `bits`-bit value `v` into `to` bits (MSB first).
int replicate(int v, int bits, int to) {
  int out = 0;
  int have = 0;
  while (have < to) {
    out = (out << bits) | v;
    have += bits;
  }
  return out >> (have - to);
}

void bit_transfer_signed(int& a, int& b) {
  b >>= 1;
  b |= a & 0x80;
  a >>= 1;
  a &= 0x3F;
  if ((a & 0x20) != 0) a -= 0x40;
}

std::array<int, 4> blue_contract(int r, int g, int b, int a) {
  return {(r + b) >> 1, (g + b) >> 1, b, a};
}

std::array<int, 4> clamp_unorm8(std::array<int, 4> c) {
  for (int& x : c) x = std::clamp(x, 0, 255);
  return c;
}

// Modes 8 and 12: direct, with blue contraction when the second endpoint is the darker one.
AstcEndpoints direct_rgba(std::span<const int> v, int a0, int a1) {
  const int s0 = v[0] + v[2] + v[4];
  const int s1 = v[1] + v[3] + v[5];
  if (s1 >= s0) return {{v[0], v[2], v[4], a0}, {v[1], v[3], v[5], a1}};
  return {blue_contract(v[1], v[3], v[5], a1), blue_contract(v[0], v[2], v[4], a0)};
}

// Modes 9 and 13: base + signed offset, alpha pair (a0, a1) already bit-transferred.
AstcEndpoints offset_rgba(std::span<const int> values, int a0, int a1) {
  int v0 = values[0], v1 = values[1], v2 = values[2], v3 = values[3];
  int v4 = values[4], v5 = values[5];
  bit_transfer_signed(v1, v0);
  bit_transfer_signed(v3, v2);
  bit_transfer_signed(v5, v4);
  AstcEndpoints e;
  if (v1 + v3 + v5 >= 0) {
    e = {{v0, v2, v4, a0}, {v0 + v1, v2 + v3, v4 + v5, a0 + a1}};
  } else {
    e = {blue_contract(v0 + v1, v2 + v3, v4 + v5, a0 + a1), blue_contract(v0, v2, v4, a0)};
  }
  return {clamp_unorm8(e.e0), clamp_unorm8(e.e1)};
}

}  // namespace

AstcRange astc_color_range(int index) { return kColorRanges[static_cast<size_t>(index)].range; }

int astc_select_color_range(int value_count, int available_bits) {
  for (int i = kAstcColorRanges - 1; i >= 0; --i) {
    if (astc_color_range(i).sequence_bits(value_count) <= available_bits) return i;
  }
  return -1;
}

int astc_unquantize_color(int value, int index) {
  const ColorRangeRow& row = kColorRanges[static_cast<size_t>(index)];
  const int n = row.range.bits;
  if (!row.range.trit && !row.range.quint) return replicate(value, n, 8);
  const int d = value >> n;              // the trit or quint
  const int m = value & ((1 << n) - 1);  // the low bits
  const int a = (m & 1) != 0 ? 0x1FF : 0;
  const int b = pattern_value(row.b_pattern, m);
  int unq = d * row.c + b;
  unq ^= a;
  return (a & 0x80) | (unq >> 2);
}

bool astc_is_ldr_endpoint_mode(int cem) {
  switch (cem) {
    case 0:
    case 1:
    case 4:
    case 5:
    case 6:
    case 8:
    case 9:
    case 10:
    case 12:
    case 13:
      return true;
    default:
      return false;
  }
}

AstcEndpoints astc_decode_ldr_endpoints(int cem, std::span<const int> v) {
  switch (cem) {
    case 0:
      return {{v[0], v[0], v[0], 0xFF}, {v[1], v[1], v[1], 0xFF}};
    case 1: {
      const int l0 = (v[0] >> 2) | (v[1] & 0xC0);
      const int l1 = std::min(l0 + (v[1] & 0x3F), 0xFF);
      return {{l0, l0, l0, 0xFF}, {l1, l1, l1, 0xFF}};
    }
    case 4:
      return {{v[0], v[0], v[0], v[2]}, {v[1], v[1], v[1], v[3]}};
    case 5: {
      int v0 = v[0], v1 = v[1], v2 = v[2], v3 = v[3];
      bit_transfer_signed(v1, v0);
      bit_transfer_signed(v3, v2);
      return {clamp_unorm8({v0, v0, v0, v2}), clamp_unorm8({v0 + v1, v0 + v1, v0 + v1, v2 + v3})};
    }
    case 6:
      return {{(v[0] * v[3]) >> 8, (v[1] * v[3]) >> 8, (v[2] * v[3]) >> 8, 0xFF},
              {v[0], v[1], v[2], 0xFF}};
    case 8:
      return direct_rgba(v, 0xFF, 0xFF);
    case 9:
      return offset_rgba(v, 0xFF, 0);
    case 10:
      return {{(v[0] * v[3]) >> 8, (v[1] * v[3]) >> 8, (v[2] * v[3]) >> 8, v[4]},
              {v[0], v[1], v[2], v[5]}};
    case 12:
      return direct_rgba(v, v[6], v[7]);
    case 13: {
      int v6 = v[6], v7 = v[7];
      bit_transfer_signed(v7, v6);
      return offset_rgba(v, v6, v7);
    }
    default:
      return {};  // an HDR mode: the caller gives the error colour instead
  }
}

}  // namespace texsim
