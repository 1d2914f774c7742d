#include "blocks/texture/decode/astc_block_mode.h"

#include <array>

namespace texsim {

AstcRange astc_weight_range(int index) {
  // {bits, trit, quint} in the order of ρ = 2..7, then again with P = 1.
  static constexpr std::array<AstcRange, 12> kRanges = {{
      {1, false, false},  // 0..1
      {0, true, false},   // 0..2
      {2, false, false},  // 0..3
      {0, false, true},   // 0..4
      {1, true, false},   // 0..5
      {3, false, false},  // 0..7
      {1, false, true},   // 0..9
      {2, true, false},   // 0..11
      {4, false, false},  // 0..15
      {2, false, true},   // 0..19
      {3, true, false},   // 0..23
      {5, false, false},  // 0..31
  }};
  return kRanges[static_cast<size_t>(index)];
}

AstcBlockMode astc_decode_block_mode(uint32_t mode, int block_width, int block_height) {
  const auto bit = [mode](int i) { return static_cast<int>((mode >> i) & 1U); };
  const auto field = [mode](int lo, int n) {
    return static_cast<int>((mode >> lo) & ((1U << n) - 1U));
  };
  AstcBlockMode m;
  if ((mode & 0x1FFU) == 0x1FCU) {
    m.kind = AstcBlockMode::Kind::VoidExtent;
    return m;
  }
  int rho = 0, w = 0, h = 0;
  bool dual = bit(10) != 0;
  bool high_precision = bit(9) != 0;
  const int a = field(5, 2);  // bits 6..5
  const int b = field(7, 2);  // bits 8..7
  if (field(0, 2) != 0) {
    rho = (bit(1) << 2) | (bit(0) << 1) | bit(4);
    switch (field(2, 2)) {
      case 0:
        w = b + 4;
        h = a + 2;
        break;
      case 1:
        w = b + 8;
        h = a + 2;
        break;
      case 2:
        w = a + 2;
        h = b + 8;
        break;
      default:
        if (bit(8) == 0) {
          w = a + 2;
          h = bit(7) + 6;
        } else {
          w = bit(7) + 2;
          h = a + 2;
        }
        break;
    }
  } else {
    if (field(0, 4) == 0) return m;  // bits 3..0 = 0000: reserved
    rho = (bit(3) << 2) | (bit(2) << 1) | bit(4);
    switch (b) {
      case 0:
        w = 12;
        h = a + 2;
        break;
      case 1:
        w = a + 2;
        h = 12;
        break;
      case 2:
        w = a + 6;
        h = field(9, 2) + 6;
        dual = false;  // bits 10..9 hold the height here
        high_precision = false;
        break;
      default:
        if (bit(6) != 0) return m;  // bits 8..6 = 111 (not a void extent): reserved
        w = bit(5) != 0 ? 10 : 6;
        h = bit(5) != 0 ? 6 : 10;
        break;
    }
  }
  m.grid_width = w;
  m.grid_height = h;
  m.dual_plane = dual;
  m.weight_range = rho - 2 + (high_precision ? 6 : 0);
  m.weight_count = w * h * (dual ? 2 : 1);
  m.weight_bits = astc_weight_range(m.weight_range).sequence_bits(m.weight_count);
  if (m.weight_count > 64 || m.weight_bits < 24 || m.weight_bits > 96 || w > block_width ||
      h > block_height) {
    return m;  // kind stays Reserved
  }
  m.kind = AstcBlockMode::Kind::Normal;
  return m;
}

}  // namespace texsim
