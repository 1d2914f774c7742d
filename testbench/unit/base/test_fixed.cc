// Semantics of Fixed<I,F>: rounding modes, saturation and wrap, products and quotients,
// checked against exact rational arithmetic done in long double / integers.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "rtl_model/number/fixed.h"

namespace texsim {
namespace {

using S4_8 = Fixed<4, 8>;  // s4.8: [-8, 8 - 1/256]
using U0_8 = Fixed<0, 8, Signedness::Unsigned>;

TEST(Fixed, RangeAndName) {
  EXPECT_EQ(S4_8::name(), "s4.8");
  EXPECT_EQ(U0_8::name(), "u0.8");
  EXPECT_DOUBLE_EQ(S4_8::max().to_double(), 8.0 - 1.0 / 256);
  EXPECT_DOUBLE_EQ(S4_8::min().to_double(), -8.0);
  EXPECT_DOUBLE_EQ(U0_8::max().to_double(), 255.0 / 256);
  EXPECT_DOUBLE_EQ(U0_8::min().to_double(), 0.0);
}

TEST(Fixed, ConversionRoundingModes) {
  const double lsb = 1.0 / 256;
  // x = 2.5 LSB and -2.5 LSB exercise every mode's tie and sign handling.
  const double p = 2.5 * lsb, n = -2.5 * lsb;
  EXPECT_EQ((Fixed<4, 8, Signedness::Signed, Rounding::Floor>(p).raw()), 2);
  EXPECT_EQ((Fixed<4, 8, Signedness::Signed, Rounding::Floor>(n).raw()), -3);
  EXPECT_EQ((Fixed<4, 8, Signedness::Signed, Rounding::TowardZero>(n).raw()), -2);
  EXPECT_EQ((Fixed<4, 8, Signedness::Signed, Rounding::HalfUp>(p).raw()), 3);
  EXPECT_EQ((Fixed<4, 8, Signedness::Signed, Rounding::HalfUp>(n).raw()), -2);
  EXPECT_EQ((Fixed<4, 8, Signedness::Signed, Rounding::HalfEven>(p).raw()), 2);
  EXPECT_EQ((Fixed<4, 8, Signedness::Signed, Rounding::HalfEven>(3.5 * lsb).raw()), 4);
  EXPECT_EQ((Fixed<4, 8, Signedness::Signed, Rounding::HalfEven>(n).raw()), -2);
}

TEST(Fixed, SaturationAndWrap) {
  EXPECT_EQ(S4_8(100.0), S4_8::max());
  EXPECT_EQ(S4_8(-100.0), S4_8::min());
  EXPECT_EQ(S4_8(7.5) + S4_8(7.5), S4_8::max());
  EXPECT_EQ(U0_8(0.25) - U0_8(0.5), U0_8::min());
  EXPECT_EQ(S4_8(std::nan("")).raw(), 0);
  EXPECT_EQ(S4_8(INFINITY), S4_8::max());
  using W = Fixed<4, 8, Signedness::Signed, Rounding::HalfEven, Overflow::Wrap>;
  // 7.5 + 1 = 8.5 wraps to 8.5 - 16 = -7.5 in a 12-bit two's-complement adder.
  EXPECT_DOUBLE_EQ((W(7.5) + W(1.0)).to_double(), -7.5);
}

// Products and quotients are the exact result rounded once: check every mode against
// exact integer arithmetic on random operands.
template <Rounding R>
void check_mul_div(std::mt19937& rng) {
  using T = Fixed<8, 10, Signedness::Signed, R>;
  std::uniform_int_distribution<int64_t> d(-(1 << 15), (1 << 15));
  for (int i = 0; i < 20000; ++i) {
    const T a = T::from_raw(d(rng)), b = T::from_raw(d(rng));
    const long double lsb = 1.0L / 1024;
    auto round_ref = [](long double q) -> long double {
      switch (R) {
        case Rounding::Floor:
          return std::floor(q);
        case Rounding::TowardZero:
          return std::trunc(q);
        case Rounding::HalfUp:
          return std::floor(q + 0.5L);
        case Rounding::HalfEven: {
          const long double f = std::floor(q), rem = q - f;
          if (rem > 0.5L) return f + 1;
          if (rem < 0.5L) return f;
          return std::fmod(f, 2.0L) == 0 ? f : f + 1;
        }
      }
      return q;
    };
    auto clamp = [](long double r) {
      return std::min<long double>(std::max<long double>(r, T::kRawMin), T::kRawMax);
    };
    const long double prod = static_cast<long double>(a.raw()) * b.raw() * lsb;  // in LSBs
    ASSERT_EQ((a * b).raw(), static_cast<int64_t>(clamp(round_ref(prod))))
        << a.to_double() << " * " << b.to_double();
    if (b.raw() != 0) {
      const long double quo = static_cast<long double>(a.raw()) / b.raw() * 1024.0L;
      ASSERT_EQ((a / b).raw(), static_cast<int64_t>(clamp(round_ref(quo))))
          << a.to_double() << " / " << b.to_double();
    }
  }
}

TEST(Fixed, MulDivRoundOnceEveryMode) {
  std::mt19937 rng(7);
  check_mul_div<Rounding::Floor>(rng);
  check_mul_div<Rounding::TowardZero>(rng);
  check_mul_div<Rounding::HalfUp>(rng);
  check_mul_div<Rounding::HalfEven>(rng);
}

TEST(Fixed, DivisionByZeroSaturates) {
  EXPECT_EQ(S4_8(1.0) / S4_8(0.0), S4_8::max());
  EXPECT_EQ(S4_8(-1.0) / S4_8(0.0), S4_8::min());
}

TEST(Fixed, ConversionErrorIsHalfLsbWhenRounding) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(-7.9, 7.9);
  for (int i = 0; i < 10000; ++i) {
    const double x = d(rng);
    EXPECT_LE(std::abs(S4_8(x).to_double() - x), 0.5 / 256 + 1e-15);
    EXPECT_LT(std::abs(Fixed<4, 8, Signedness::Signed, Rounding::Floor>(x).to_double() - x),
              1.0 / 256);
  }
}

}  // namespace
}  // namespace texsim
