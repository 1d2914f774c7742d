#include "blocks/texture/decode/astc_integer_sequence.h"

namespace texsim {

AstcBits::AstcBits(std::span<const uint8_t, 16> block) {
  for (int i = 7; i >= 0; --i) {
    lo_ = (lo_ << 8) | block[static_cast<size_t>(i)];
    hi_ = (hi_ << 8) | block[static_cast<size_t>(i) + 8];
  }
}

uint32_t AstcBits::get(int pos, int count) const {
  if (count <= 0 || pos < 0 || pos >= 128) return 0;
  uint64_t v = 0;
  if (pos < 64) {
    v = lo_ >> pos;
    if (pos > 0) v |= hi_ << (64 - pos);
  } else {
    v = hi_ >> (pos - 64);
  }
  return static_cast<uint32_t>(v & ((uint64_t{1} << count) - 1U));
}

AstcBits AstcBits::reversed() const {
  uint64_t lo = 0, hi = 0;
  for (int i = 0; i < 64; ++i) {
    lo = (lo << 1) | ((hi_ >> i) & 1U);
    hi = (hi << 1) | ((lo_ >> i) & 1U);
  }
  return {lo, hi};
}

int AstcRange::sequence_bits(int count) const {
  int n = count * bits;
  if (trit) n += (8 * count + 4) / 5;
  if (quint) n += (7 * count + 2) / 3;
  return n;
}

std::array<int, 5> astc_unpack_trits(uint32_t t) {
  const auto bit = [](uint32_t v, int i) { return static_cast<int>((v >> i) & 1U); };
  const auto field = [](uint32_t v, int hi, int lo) {
    return static_cast<int>((v >> lo) & ((1U << (hi - lo + 1)) - 1U));
  };
  int t4 = 0, t3 = 0, t2 = 0, t1 = 0, t0 = 0;
  uint32_t c = 0;
  if (field(t, 4, 2) == 7) {
    c = static_cast<uint32_t>((field(t, 7, 5) << 2) | field(t, 1, 0));
    t4 = t3 = 2;
  } else {
    c = static_cast<uint32_t>(field(t, 4, 0));
    if (field(t, 6, 5) == 3) {
      t4 = 2;
      t3 = bit(t, 7);
    } else {
      t4 = bit(t, 7);
      t3 = field(t, 6, 5);
    }
  }
  if (field(c, 1, 0) == 3) {
    t2 = 2;
    t1 = bit(c, 4);
    t0 = (bit(c, 3) << 1) | (bit(c, 2) & ~bit(c, 3) & 1);
  } else if (field(c, 3, 2) == 3) {
    t2 = 2;
    t1 = 2;
    t0 = field(c, 1, 0);
  } else {
    t2 = bit(c, 4);
    t1 = field(c, 3, 2);
    t0 = (bit(c, 1) << 1) | (bit(c, 0) & ~bit(c, 1) & 1);
  }
  return {t0, t1, t2, t3, t4};
}

std::array<int, 3> astc_unpack_quints(uint32_t q) {
  const auto bit = [](uint32_t v, int i) { return static_cast<int>((v >> i) & 1U); };
  const auto field = [](uint32_t v, int hi, int lo) {
    return static_cast<int>((v >> lo) & ((1U << (hi - lo + 1)) - 1U));
  };
  int q2 = 0, q1 = 0, q0 = 0;
  if (field(q, 2, 1) == 3 && field(q, 6, 5) == 0) {
    const int q0b = bit(q, 0);
    q2 = (q0b << 2) | ((bit(q, 4) & ~q0b & 1) << 1) | (bit(q, 3) & ~q0b & 1);
    q1 = q0 = 4;
  } else {
    uint32_t c = 0;
    if (field(q, 2, 1) == 3) {
      q2 = 4;
      // C = { Q[4:3], ~Q[6:5], Q[0] }
      c = static_cast<uint32_t>((field(q, 4, 3) << 3) | ((~field(q, 6, 5) & 3) << 1) | bit(q, 0));
    } else {
      q2 = field(q, 6, 5);
      c = static_cast<uint32_t>(field(q, 4, 0));
    }
    if (field(c, 2, 0) == 5) {
      q1 = 4;
      q0 = field(c, 4, 3);
    } else {
      q1 = field(c, 4, 3);
      q0 = field(c, 2, 0);
    }
  }
  return {q0, q1, q2};
}

void astc_decode_sequence(const AstcBits& bits, int start, int count, AstcRange range,
                          std::span<int> out) {
  const int end = start + range.sequence_bits(count);
  // A read of the sequence: bits past its end are the zero padding of a partial group.
  const auto read = [&](int pos, int n) -> uint32_t {
    if (n <= 0 || pos >= end) return 0;
    const int avail = end - pos < n ? end - pos : n;
    return bits.get(pos, avail);
  };
  const int n = range.bits;
  const int group = range.trit ? 5 : range.quint ? 3 : 1;
  // Bits of a trit/quint group after each value's low bits (the spec's packing tables).
  static constexpr int kTritBits[5] = {2, 2, 1, 2, 1};
  static constexpr int kQuintBits[3] = {3, 2, 2};
  int pos = start;
  for (int g = 0; g * group < count; ++g) {
    std::array<uint32_t, 5> low{};
    uint32_t packed = 0;
    int packed_bits = 0;
    for (int j = 0; j < group; ++j) {
      low[static_cast<size_t>(j)] = read(pos, n);
      pos += n;
      const int extra = range.trit ? kTritBits[j] : range.quint ? kQuintBits[j] : 0;
      packed |= read(pos, extra) << packed_bits;
      packed_bits += extra;
      pos += extra;
    }
    std::array<int, 5> high{};
    if (range.trit) {
      high = astc_unpack_trits(packed);
    } else if (range.quint) {
      const auto q = astc_unpack_quints(packed);
      high = {q[0], q[1], q[2], 0, 0};
    }
    for (int j = 0; j < group && g * group + j < count; ++j) {
      const int k = g * group + j;
      out[static_cast<size_t>(k)] =
          (high[static_cast<size_t>(j)] << n) | static_cast<int>(low[static_cast<size_t>(j)]);
    }
  }
}

}  // namespace texsim
