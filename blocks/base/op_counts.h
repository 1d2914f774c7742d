#pragma once
// Operation counts by kind: the unit of cost that every block reports (docs/architecture.md).
// Plain uint64_t members so counting on the hot path is one add, never a string look-up.
#include <array>
#include <cstdint>
#include <string_view>

namespace texsim {

enum class OpKind : int { Add, Mul, Div, Rcp, Sqrt, Lut, Cmp, Mem, kCount };
inline constexpr int kOpKinds = static_cast<int>(OpKind::kCount);

// Report names of the kinds (keys of blocks.<name>.ops.<kind> in report.json).
inline constexpr std::array<std::string_view, kOpKinds> kOpKindNames = {
    "add", "mul", "div", "rcp", "sqrt", "lut", "cmp", "mem"};

struct OpCounts {
  uint64_t add = 0;   // add / subtract / accumulate
  uint64_t mul = 0;   // multiply
  uint64_t div = 0;   // divide
  uint64_t rcp = 0;   // reciprocal
  uint64_t sqrt = 0;  // square root
  uint64_t lut = 0;   // exp/log2/transcendental or any table look-up
  uint64_t cmp = 0;   // compare, min/max, select, clamp
  uint64_t mem = 0;   // memory reads (texels, weight-map entries)

  constexpr uint64_t get(OpKind k) const {
    switch (k) {
      case OpKind::Add:
        return add;
      case OpKind::Mul:
        return mul;
      case OpKind::Div:
        return div;
      case OpKind::Rcp:
        return rcp;
      case OpKind::Sqrt:
        return sqrt;
      case OpKind::Lut:
        return lut;
      case OpKind::Cmp:
        return cmp;
      case OpKind::Mem:
        return mem;
      case OpKind::kCount:
        break;
    }
    return 0;
  }
  constexpr uint64_t& at(OpKind k) {
    switch (k) {
      case OpKind::Add:
        return add;
      case OpKind::Mul:
        return mul;
      case OpKind::Div:
        return div;
      case OpKind::Rcp:
        return rcp;
      case OpKind::Sqrt:
        return sqrt;
      case OpKind::Lut:
        return lut;
      case OpKind::Cmp:
        return cmp;
      case OpKind::Mem:
        return mem;
      case OpKind::kCount:
        break;
    }
    return mem;
  }
  // Arithmetic operations (everything but memory reads).
  constexpr uint64_t arithmetic() const { return add + mul + div + rcp + sqrt + lut + cmp; }
  constexpr uint64_t total() const { return arithmetic() + mem; }

  constexpr OpCounts& operator+=(const OpCounts& o) {
    add += o.add;
    mul += o.mul;
    div += o.div;
    rcp += o.rcp;
    sqrt += o.sqrt;
    lut += o.lut;
    cmp += o.cmp;
    mem += o.mem;
    return *this;
  }
  friend constexpr OpCounts operator+(OpCounts a, const OpCounts& b) { return a += b; }
  friend constexpr OpCounts operator*(OpCounts a, uint64_t n) {
    a.add *= n;
    a.mul *= n;
    a.div *= n;
    a.rcp *= n;
    a.sqrt *= n;
    a.lut *= n;
    a.cmp *= n;
    a.mem *= n;
    return a;
  }
  friend constexpr bool operator==(const OpCounts&, const OpCounts&) = default;
};

}  // namespace texsim
