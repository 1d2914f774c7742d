#include "blocks/texture/decode/astc_weights.h"

#include <array>

#include "blocks/texture/decode/astc_block_mode.h"

namespace texsim {

namespace {

struct WeightRangeRow {
  const char* b_pattern;  // the spec's B column (7 bits, most significant first); "" = none
  int c;                  // the spec's C column
};

// Trit/quint rows of the spec's weight unquantisation table, by weight range index; the
// ranges 0..2 and 0..4 (no low bits) use the spec's value tables instead.
constexpr std::array<WeightRangeRow, 12> kWeightRows = {{
    {"", 0},          // 0..1 (bits)
    {"", 0},          // 0..2 (table)
    {"", 0},          // 0..3 (bits)
    {"", 0},          // 0..4 (table)
    {"0000000", 50},  // 0..5
    {"", 0},          // 0..7 (bits)
    {"0000000", 28},  // 0..9
    {"b000b0b", 23},  // 0..11
    {"", 0},          // 0..15 (bits)
    {"b0000b0", 13},  // 0..19
    {"cb000cb", 11},  // 0..23
    {"", 0},          // 0..31 (bits)
}};

int pattern_value(const char* pattern, int m) {
  int v = 0;
  for (const char* p = pattern; *p != '\0'; ++p) {
    const int bit = *p == '0' ? 0 : (m >> (*p - 'a')) & 1;
    v = (v << 1) | bit;
  }
  return v;
}

// The unquantised value in 0..63, before the expansion to 0..64.
int unquantize_to_63(int value, int index) {
  const AstcRange r = astc_weight_range(index);
  if (!r.trit && !r.quint) {
    int out = 0, have = 0;  // bit replication to 6 bits
    while (have < 6) {
      out = (out << r.bits) | value;
      have += r.bits;
    }
    return out >> (have - 6);
  }
  if (r.bits == 0) {
    static constexpr std::array<int, 3> kTrits = {0, 32, 63};
    static constexpr std::array<int, 5> kQuints = {0, 16, 32, 47, 63};
    return r.trit ? kTrits[static_cast<size_t>(value)] : kQuints[static_cast<size_t>(value)];
  }
  const WeightRangeRow& row = kWeightRows[static_cast<size_t>(index)];
  const int d = value >> r.bits;
  const int m = value & ((1 << r.bits) - 1);
  const int a = (m & 1) != 0 ? 0x7F : 0;
  int unq = d * row.c + pattern_value(row.b_pattern, m);
  unq ^= a;
  return (a & 0x20) | (unq >> 2);
}

}  // namespace

int astc_unquantize_weight(int value, int index) {
  const int unq = unquantize_to_63(value, index);
  return unq > 32 ? unq + 1 : unq;
}

void astc_infill_weights(std::span<const int> grid, int grid_width, int grid_height,
                         int block_width, int block_height, std::span<int> out) {
  const int ds = (1024 + block_width / 2) / (block_width - 1);
  const int dt = (1024 + block_height / 2) / (block_height - 1);
  for (int y = 0; y < block_height; ++y) {
    const int gt = (dt * y * (grid_height - 1) + 32) >> 6;
    const int jt = gt >> 4, ft = gt & 0x0F;
    for (int x = 0; x < block_width; ++x) {
      const int gs = (ds * x * (grid_width - 1) + 32) >> 6;
      const int js = gs >> 4, fs = gs & 0x0F;
      const int v0 = js + jt * grid_width;
      // A neighbour outside the grid has weight 0 in the sum (its factor is 0: the fraction
      // along that axis is 0 at the grid's last row or column); it is never read.
      const auto at = [&](int i, bool inside) { return inside ? grid[static_cast<size_t>(i)] : 0; };
      const bool right = js + 1 < grid_width;
      const bool below = jt + 1 < grid_height;
      const int p00 = at(v0, true);
      const int p01 = at(v0 + 1, right);
      const int p10 = at(v0 + grid_width, below);
      const int p11 = at(v0 + grid_width + 1, right && below);
      const int w11 = (fs * ft + 8) >> 4;
      const int w10 = ft - w11;
      const int w01 = fs - w11;
      const int w00 = 16 - fs - ft + w11;
      const int texel = y * block_width + x;
      out[static_cast<size_t>(texel)] = (p00 * w00 + p01 * w01 + p10 * w10 + p11 * w11 + 8) >> 4;
    }
  }
}

}  // namespace texsim
