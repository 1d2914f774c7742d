#pragma once
// Fixed<I, F>: the fixed-point number type shared by the C++ block models and the RTL.
// Semantics are documented in docs/number-formats.md; tests in testbench/unit/base/test_fixed.cc.
//
// A value is an integer `raw` scaled by 2^-F. I counts the integer bits *including* the sign
// bit for signed types, so Fixed<I, F, Signedness::Signed> is the hardware type sI.F with
// I + F bits in all: range [-2^(I-1), 2^(I-1) - 2^-F]. Unsigned: [0, 2^I - 2^-F].
// Every operation that can lose precision rounds with the type's Rounding mode; every result
// that does not fit is saturated or wrapped according to the type's Overflow mode.
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace texsim {

// 128-bit intermediate for exact products and quotients (GCC/Clang extension).
__extension__ typedef __int128 wide_int;

enum class Signedness { Signed, Unsigned };

enum class Rounding {
  Floor,       // drop the low bits (two's-complement truncation: toward -inf)
  TowardZero,  // sign-magnitude truncation
  HalfUp,      // add half an LSB, then floor (the cheapest hardware rounding)
  HalfEven,    // round to nearest, ties to even (IEEE default)
};

enum class Overflow {
  Saturate,  // clamp to the representable range
  Wrap,      // keep the low I+F bits (two's complement), as a plain adder does
};

namespace fixed_detail {

// Shifts `v` right by `s` bits (s >= 0) rounding per `r`. Uses wide_int so that products of
// two 62-bit operands never overflow before rounding.
constexpr wide_int shift_round(wide_int v, int s, Rounding r) {
  if (s <= 0) return v << (-s);
  const wide_int one = 1;
  const wide_int floor_q = v >> s;          // arithmetic shift: floor
  const wide_int rem = v - (floor_q << s);  // in [0, 2^s)
  const wide_int half = one << (s - 1);
  switch (r) {
    case Rounding::Floor:
      return floor_q;
    case Rounding::TowardZero:
      return (v < 0 && rem != 0) ? floor_q + 1 : floor_q;
    case Rounding::HalfUp:
      return rem >= half ? floor_q + 1 : floor_q;
    case Rounding::HalfEven:
      if (rem > half) return floor_q + 1;
      if (rem < half) return floor_q;
      return (floor_q & 1) ? floor_q + 1 : floor_q;
  }
  return floor_q;
}

}  // namespace fixed_detail

template <int I, int F, Signedness S = Signedness::Signed, Rounding R = Rounding::HalfEven,
          Overflow O = Overflow::Saturate>
class Fixed {
  static_assert(I >= 0 && F >= 0 && I + F >= 1 && I + F <= 62, "Fixed<I,F>: 1..62 bits");
  static_assert(S == Signedness::Unsigned || I >= 1, "signed Fixed needs a sign bit in I");

 public:
  static constexpr int kIntBits = I;
  static constexpr int kFracBits = F;
  static constexpr int kBits = I + F;
  static constexpr bool kSigned = S == Signedness::Signed;
  static constexpr Rounding kRounding = R;
  static constexpr Overflow kOverflow = O;
  static constexpr int64_t kRawMax =
      kSigned ? (int64_t{1} << (kBits - 1)) - 1 : (int64_t{1} << kBits) - 1;
  static constexpr int64_t kRawMin = kSigned ? -(int64_t{1} << (kBits - 1)) : 0;

  constexpr Fixed() = default;

  // Conversions from real numbers round per R and saturate/wrap per O. NaN converts to 0
  // (hardware has no NaN; the blocks reject NaN inputs before they get here).
  constexpr Fixed(double x) : raw_(from_real(x)) {}  // NOLINT: implicit, like a hardware cast
  constexpr Fixed(int x) : raw_(fit(static_cast<wide_int>(x) << F)) {}  // NOLINT

  static constexpr Fixed from_raw(int64_t raw) {
    Fixed f;
    f.raw_ = fit(raw);
    return f;
  }
  static constexpr Fixed max() { return from_raw(kRawMax); }
  static constexpr Fixed min() { return from_raw(kRawMin); }
  static constexpr double lsb() { return 1.0 / static_cast<double>(int64_t{1} << F); }

  constexpr int64_t raw() const { return raw_; }
  constexpr double to_double() const { return static_cast<double>(raw_) * lsb(); }
  constexpr explicit operator double() const { return to_double(); }
  constexpr explicit operator float() const { return static_cast<float>(to_double()); }

  friend constexpr Fixed operator+(Fixed a, Fixed b) {
    return from_wide(static_cast<wide_int>(a.raw_) + b.raw_);
  }
  friend constexpr Fixed operator-(Fixed a, Fixed b) {
    return from_wide(static_cast<wide_int>(a.raw_) - b.raw_);
  }
  constexpr Fixed operator-() const { return from_wide(-static_cast<wide_int>(raw_)); }
  // Full-precision product (2F fraction bits), then one rounding back to F bits.
  friend constexpr Fixed operator*(Fixed a, Fixed b) {
    const wide_int p = static_cast<wide_int>(a.raw_) * b.raw_;
    return from_wide(fixed_detail::shift_round(p, F, R));
  }
  // Quotient rounded per R. Division by zero saturates to the signed extreme (or max for
  // 0/0), as a restoring divider with saturation logic does; callers guard where it matters.
  friend constexpr Fixed operator/(Fixed a, Fixed b) {
    if (b.raw_ == 0) {
      return a.raw_ < 0 ? from_raw(kRawMin) : from_raw(kRawMax);
    }
    // Two extra guard bits give the rounding its information: q = a·2^(F+2)/b, then round.
    wide_int num = static_cast<wide_int>(a.raw_) << (F + 2);
    wide_int den = b.raw_;
    if (den < 0) {
      num = -num;
      den = -den;
    }
    wide_int q = num / den;  // toward zero
    const wide_int rem = num - q * den;
    if (rem != 0 && num < 0) q -= 1;  // make it floor; sticky bit below
    const bool sticky = rem != 0;
    // q now = floor(exact·4); rounding with the sticky bit:
    const wide_int floor_q = q >> 2;
    const int guard = static_cast<int>(q & 3);
    wide_int r = floor_q;
    switch (R) {
      case Rounding::Floor:
        break;
      case Rounding::TowardZero:
        if (num < 0 && (guard != 0 || sticky)) r = floor_q + 1;
        break;
      case Rounding::HalfUp:
        if (guard >= 2) r = floor_q + 1;
        break;
      case Rounding::HalfEven:
        // Above half, or exactly half (no sticky bit) with an odd quotient: round up.
        if (guard > 2 || (guard == 2 && (sticky || (floor_q & 1) != 0))) r = floor_q + 1;
        break;
    }
    return from_wide(r);
  }
  constexpr Fixed& operator+=(Fixed b) { return *this = *this + b; }
  constexpr Fixed& operator-=(Fixed b) { return *this = *this - b; }
  constexpr Fixed& operator*=(Fixed b) { return *this = *this * b; }
  constexpr Fixed& operator/=(Fixed b) { return *this = *this / b; }

  friend constexpr bool operator==(Fixed a, Fixed b) { return a.raw_ == b.raw_; }
  friend constexpr auto operator<=>(Fixed a, Fixed b) { return a.raw_ <=> b.raw_; }

  // Name in the project's notation, e.g. "s3.12" or "u0.16".
  static std::string name() {
    return std::string(kSigned ? "s" : "u") + std::to_string(I) + "." + std::to_string(F);
  }

 private:
  static constexpr int64_t fit(wide_int v) {
    if constexpr (O == Overflow::Saturate) {
      if (v > kRawMax) return kRawMax;
      if (v < kRawMin) return kRawMin;
      return static_cast<int64_t>(v);
    } else {
      const wide_int mask = (static_cast<wide_int>(1) << kBits) - 1;
      wide_int w = v & mask;
      if (kSigned && (w >> (kBits - 1)) != 0) w -= (static_cast<wide_int>(1) << kBits);
      return static_cast<int64_t>(w);
    }
  }
  static constexpr Fixed from_wide(wide_int v) {
    Fixed f;
    f.raw_ = fit(v);
    return f;
  }
  static constexpr int64_t from_real(double x) {
    if (x != x) return 0;
    const double scaled = x * static_cast<double>(int64_t{1} << F);
    // Outside ±2^62 the value saturates (or wraps modulo 2^bits, which is 0 there).
    constexpr double kLimit = 4.611686018427387904e18;
    if (scaled >= kLimit) return O == Overflow::Saturate ? kRawMax : 0;
    if (scaled <= -kLimit) return O == Overflow::Saturate ? kRawMin : 0;
    double r = 0;
    switch (R) {
      case Rounding::Floor:
        r = std::floor(scaled);
        break;
      case Rounding::TowardZero:
        r = std::trunc(scaled);
        break;
      case Rounding::HalfUp:
        r = std::floor(scaled + 0.5);
        break;
      case Rounding::HalfEven:
        r = std::nearbyint(scaled);
        break;  // default FE mode: ties-even
    }
    return fit(static_cast<wide_int>(r));
  }

  int64_t raw_ = 0;
};

// Free helpers so templated functional cores can treat float, double and Fixed alike.
template <class T>
constexpr double to_double(T x) {
  if constexpr (requires { x.to_double(); })
    return x.to_double();
  else
    return static_cast<double>(x);
}

template <class T>
struct is_fixed : std::false_type {};
template <int I, int F, Signedness S, Rounding R, Overflow O>
struct is_fixed<Fixed<I, F, S, R, O>> : std::true_type {};
template <class T>
inline constexpr bool is_fixed_v = is_fixed<T>::value;

// Name of a number format for reports: "float", "double", or Fixed::name().
template <class T>
std::string format_name() {
  if constexpr (is_fixed_v<T>)
    return T::name();
  else if constexpr (std::is_same_v<T, float>)
    return "float";
  else if constexpr (std::is_same_v<T, double>)
    return "double";
  else if constexpr (std::is_same_v<T, long double>)
    return "long double";
  else
    return "unknown";
}

}  // namespace texsim
