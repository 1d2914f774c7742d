#include "blocks/texture/decode/astc_partition.h"

#include <array>
#include <cstddef>

namespace texsim {

uint32_t astc_hash52(uint32_t p) {
  p ^= p >> 15;
  p -= p << 17;
  p += p << 7;
  p += p << 4;
  p ^= p >> 5;
  p += p << 16;
  p ^= p >> 7;
  p ^= p >> 3;
  p ^= p << 6;
  p ^= p >> 17;
  return p;
}

int astc_select_partition(int seed, int x, int y, int z, int partition_count, bool small_block) {
  if (small_block) {
    x <<= 1;
    y <<= 1;
    z <<= 1;
  }
  seed += (partition_count - 1) * 1024;
  const uint32_t rnum = astc_hash52(static_cast<uint32_t>(seed));
  // seed1..seed12 of the spec (index 0 = seed1); each is a 4-bit field, squared, shifted.
  std::array<uint32_t, 12> s = {
      rnum & 0xFU,         (rnum >> 4) & 0xFU,  (rnum >> 8) & 0xFU,
      (rnum >> 12) & 0xFU, (rnum >> 16) & 0xFU, (rnum >> 20) & 0xFU,
      (rnum >> 24) & 0xFU, (rnum >> 28) & 0xFU, (rnum >> 18) & 0xFU,
      (rnum >> 22) & 0xFU, (rnum >> 26) & 0xFU, ((rnum >> 30) | (rnum << 2)) & 0xFU};
  for (uint32_t& v : s) v *= v;  // fits in 8 bits, as the spec's uint8_t
  int sh1 = 0, sh2 = 0;
  if ((seed & 1) != 0) {
    sh1 = (seed & 2) != 0 ? 4 : 5;
    sh2 = partition_count == 3 ? 6 : 5;
  } else {
    sh1 = partition_count == 3 ? 6 : 5;
    sh2 = (seed & 2) != 0 ? 4 : 5;
  }
  const int sh3 = (seed & 0x10) != 0 ? sh1 : sh2;
  for (size_t i = 0; i < 8; ++i) s[i] >>= (i % 2 == 0) ? sh1 : sh2;
  for (size_t i = 8; i < 12; ++i) s[i] >>= sh3;
  const auto sx = static_cast<uint32_t>(x), sy = static_cast<uint32_t>(y);
  const auto sz = static_cast<uint32_t>(z);
  uint32_t a = s[0] * sx + s[1] * sy + s[10] * sz + (rnum >> 14);
  uint32_t b = s[2] * sx + s[3] * sy + s[11] * sz + (rnum >> 10);
  uint32_t c = s[4] * sx + s[5] * sy + s[8] * sz + (rnum >> 6);
  uint32_t d = s[6] * sx + s[7] * sy + s[9] * sz + (rnum >> 2);
  a &= 0x3FU;
  b &= 0x3FU;
  c &= 0x3FU;
  d &= 0x3FU;
  if (partition_count < 4) d = 0;
  if (partition_count < 3) c = 0;
  if (a >= b && a >= c && a >= d) return 0;
  if (b >= c && b >= d) return 1;
  if (c >= d) return 2;
  return 3;
}

}  // namespace texsim
