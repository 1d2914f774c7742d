#pragma once
// ASTC integer sequence encoding (Khronos Data Format Specification 1.3, "Integer Sequence
// Encoding"; docs/derivations/astc.md §3): sequences of values in a range 0..(k·2^n − 1),
// k = 1, 3 or 5, packed as n low bits per value plus five trits in 8 bits or three quints in
// 7 bits. The 128 bits of one block are read through AstcBits, which returns 0 past the end.
#include <array>
#include <cstdint>
#include <span>

namespace texsim {

// The 128 bits of one block, bit 0 = bit 0 of byte 0 (little-endian, as the spec labels them).
class AstcBits {
 public:
  explicit AstcBits(std::span<const uint8_t, 16> block);
  AstcBits(uint64_t lo, uint64_t hi) : lo_(lo), hi_(hi) {}
  // Bits [pos, pos + count) as an unsigned value, count ≤ 32; bits at 128 or above read 0.
  uint32_t get(int pos, int count) const;
  // The block with its bit order reversed (bit i becomes bit 127 − i): the weight stream,
  // which grows down from bit 127, read upwards.
  AstcBits reversed() const;

 private:
  uint64_t lo_ = 0, hi_ = 0;
};

// One range of the integer sequence encoding: `bits` low bits plus at most one trit or quint.
struct AstcRange {
  int bits = 0;
  bool trit = false;
  bool quint = false;
  // Values in the range: (1, 3 or 5) · 2^bits.
  int size() const { return (trit ? 3 : quint ? 5 : 1) << bits; }
  // Bits that `count` values of this range take: ⌈8·count/5⌉ for trits, ⌈7·count/3⌉ for
  // quints, plus count·bits.
  int sequence_bits(int count) const;
};

inline constexpr int kAstcMaxSequence = 64;  // the most values a sequence holds (weights)

// The five trits packed in the 8 bits T (the spec's bit-manipulation procedure).
std::array<int, 5> astc_unpack_trits(uint32_t t);
// The three quints packed in the 7 bits Q.
std::array<int, 3> astc_unpack_quints(uint32_t q);

// Decodes `count` values (≤ kAstcMaxSequence) of `range` from `bits` starting at bit `start`:
// out[i] = (trit or quint)·2^n + low bits. Only the sequence's own sequence_bits(count) bits
// are read; the unused high bits of a last partial trit/quint group are taken as 0.
void astc_decode_sequence(const AstcBits& bits, int start, int count, AstcRange range,
                          std::span<int> out);

}  // namespace texsim
