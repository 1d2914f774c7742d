#pragma once
// Shared parameters of the V(d) evaluator blocks (docs/derivations/vd-evaluators.md): σ, the seed's
// polynomial coefficients and breakpoints, and the number formats (widths, rounding,
// overflow) of every datapath variant. The C++ models and a later RTL version read the widths
// and coefficients from here only, so the two cannot drift apart.
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>

#include "rtl_model/number/fixed.h"
#include "rtl_model/number/number_format.h"

namespace texsim {

// V(d) = Φ(d/σ) with σ = 0.2 texel; the seed's approximations on d ∈ [0, 0.5] (METHODS §5.4).
struct VdSeedCoefficients {
  static constexpr double kSigma = 0.2;
  // 1/(σ√2) = 5/√2, to long double precision: Φ(d/σ) = erfc(−d·kInvSigmaSqrt2)/2.
  static constexpr long double kInvSigmaSqrt2 = 3.535533905932737622004221810524245196424L;
  // Coefficients in increasing powers of d.
  static constexpr std::array<double, 3> kP2 = {0.5, 2.151, -2.358};
  static constexpr std::array<double, 4> kP3 = {0.496, 2.288, -3.074, 0.956};
  // P1: segment k covers [break[k-1], break[k]) with value kP1[k][0] + kP1[k][1]·d.
  static constexpr std::array<long double, 2> kP1Break = {0.165L, 0.305L};
  static constexpr std::array<std::array<double, 2>, 3> kP1 = {
      {{0.506, 1.79}, {0.636, 1.008}, {0.853, 0.295}}};
  static constexpr double kDomainMax = 0.5;
};

enum class VdEvaluatorKind : int { Exact, P3, P2, P1 };
inline constexpr std::array<VdEvaluatorKind, 4> kVdEvaluatorKinds = {
    VdEvaluatorKind::Exact, VdEvaluatorKind::P3, VdEvaluatorKind::P2, VdEvaluatorKind::P1};
inline constexpr std::array<std::string_view, 4> kVdEvaluatorNames = {"exact", "p3", "p2", "p1"};
inline constexpr std::string_view vd_evaluator_name(VdEvaluatorKind k) {
  return kVdEvaluatorNames[static_cast<size_t>(k)];
}
// The seed's claimed maximum absolute error on [0, 0.5] (none for the exact evaluator).
inline std::optional<double> vd_seed_claim(VdEvaluatorKind k) {
  switch (k) {
    case VdEvaluatorKind::P3:
      return 5e-3;
    case VdEvaluatorKind::P2:
      return 7e-3;
    case VdEvaluatorKind::P1:
      return 1e-2;
    case VdEvaluatorKind::Exact:
      break;
  }
  return std::nullopt;
}

// ---- Number formats --------------------------------------------------------------------
// A format names the type of every signal of the datapath: In (d ∈ [0, 0.5]), SIn (signed d
// for the cut-off block), Coef (coefficients), Acc (Horner intermediates, products rounded
// into it) and Out (V or W).

template <class T>
struct VdFloatFormat {
  using In = T;
  using SIn = T;
  using Coef = T;
  using Acc = T;
  using Out = T;
  static std::string name() { return format_name<T>(); }
};

// Fixed-point datapath with `FIn` fraction bits on the input and `FC` on coefficients and
// results. Why these widths: d < 1 needs no integer bit (u0.FIn); the largest coefficient
// magnitude is 3.074 (P3) so coefficients and Horner intermediates need two integer bits plus
// a sign (s3.FC — an s2.x type would saturate 2.151, 2.288, 2.358 and 3.074); V and W lie in
// [0, 1.0005] (P1 reaches 1.0005 at d = 0.5) so the output is u1.FC. Rounding is HalfUp
// (add half an LSB, truncate: one constant into the product's adder tree); overflow
// saturates, although no signal overflows for d ∈ [0, 0.5] (tests check that).
template <int FIn, int FC>
struct VdFixedFormat {
  using In = Fixed<0, FIn, Signedness::Unsigned, Rounding::HalfUp, Overflow::Saturate>;
  using SIn = Fixed<1, FIn, Signedness::Signed, Rounding::HalfUp, Overflow::Saturate>;
  using Coef = Fixed<3, FC, Signedness::Signed, Rounding::HalfUp, Overflow::Saturate>;
  using Acc = Coef;
  using Out = Fixed<1, FC, Signedness::Unsigned, Rounding::HalfUp, Overflow::Saturate>;
  static std::string name() { return In::name() + "/" + Coef::name() + "/" + Out::name(); }
};

// u0.16 / s3.15 / u1.15: 18-bit coefficients fit the 18-bit port of FPGA DSP multipliers.
using VdFx16 = VdFixedFormat<16, 15>;
// u0.12 / s3.11 / u1.11: the narrowest format whose quantisation error stays well below the
// polynomials' own error (docs/derivations/vd-evaluators.md shows the measured knee).
using VdFx12 = VdFixedFormat<12, 11>;
// u0.8 / s3.7 / u1.7: a deliberately narrow format where quantisation dominates.
using VdFx8 = VdFixedFormat<8, 7>;

// The formats of the V(d) blocks (key "format"), by the registry type of their input d.
inline constexpr NumberFormatChoices<NumberFormat::Float, NumberFormat::Double, NumberFormat::Fx16,
                                     NumberFormat::Fx12, NumberFormat::Fx8>
    kVdFormats{{"float", "double", "fx16", "fx12", "fx8"}};
inline constexpr auto kVdFormatKinds = kVdFormats.kFormats;

// The datapath format (VdFloatFormat or VdFixedFormat) whose input is the registry type T.
template <class T>
struct VdFormatOf {
  using type = VdFloatFormat<T>;
};
template <int F>
struct VdFormatOf<Fixed<0, F, Signedness::Unsigned, Rounding::HalfUp, Overflow::Saturate>> {
  using type = VdFixedFormat<F, F - 1>;
};
static_assert(std::is_same_v<VdFormatOf<number_format_t<NumberFormat::Fx16>>::type, VdFx16>);
static_assert(std::is_same_v<VdFormatOf<number_format_t<NumberFormat::Fx12>>::type, VdFx12>);
static_assert(std::is_same_v<VdFormatOf<number_format_t<NumberFormat::Fx8>>::type, VdFx8>);

// Calls f(Format{}) with the V(d) datapath format of `k` (one of kVdFormats).
template <class F>
decltype(auto) visit_vd_format(NumberFormat k, F&& f) {
  return kVdFormats.visit(k, [&](auto d) { return f(typename VdFormatOf<decltype(d)>::type{}); });
}

// ---- Arithmetic on mixed formats ------------------------------------------------------
// Fixed's own operators need both operands in one format; a datapath with distinct input,
// coefficient and accumulator widths needs products and sums computed exactly and rounded
// once into the destination format, which is what a hardware multiplier/adder followed by a
// rounding stage does. For float/double the operations are the plain ones in `To`.
namespace vd_detail {

template <class To>
To from_wide(wide_int v, int frac_bits) {
  wide_int r = fixed_detail::shift_round(v, frac_bits - To::kFracBits, To::kRounding);
  if constexpr (To::kOverflow == Overflow::Saturate) {
    if (r > To::kRawMax) r = To::kRawMax;
    if (r < To::kRawMin) r = To::kRawMin;
    return To::from_raw(static_cast<int64_t>(r));
  } else {
    // C++20 integer conversion is modular: the low 64 bits survive, and from_raw keeps the
    // low I+F of them, as a plain adder does.
    return To::from_raw(static_cast<int64_t>(r));
  }
}

template <class To, class A>
To cast(A a) {
  if constexpr (is_fixed_v<To>) {
    static_assert(is_fixed_v<A>, "fixed destination needs a fixed source");
    return from_wide<To>(static_cast<wide_int>(a.raw()), A::kFracBits);
  } else {
    return static_cast<To>(a);
  }
}

template <class To, class A, class B>
To mul(A a, B b) {
  if constexpr (is_fixed_v<To>) {
    const wide_int p = static_cast<wide_int>(a.raw()) * static_cast<wide_int>(b.raw());
    return from_wide<To>(p, A::kFracBits + B::kFracBits);
  } else {
    return static_cast<To>(a) * static_cast<To>(b);
  }
}

template <class To, class A, class B>
To add(A a, B b) {
  if constexpr (is_fixed_v<To>) {
    constexpr int f = A::kFracBits > B::kFracBits ? A::kFracBits : B::kFracBits;
    const wide_int s = (static_cast<wide_int>(a.raw()) << (f - A::kFracBits)) +
                       (static_cast<wide_int>(b.raw()) << (f - B::kFracBits));
    return from_wide<To>(s, f);
  } else {
    return static_cast<To>(a) + static_cast<To>(b);
  }
}

template <class To, class A, class B>
To sub(A a, B b) {
  if constexpr (is_fixed_v<To>) {
    constexpr int f = A::kFracBits > B::kFracBits ? A::kFracBits : B::kFracBits;
    const wide_int s = (static_cast<wide_int>(a.raw()) << (f - A::kFracBits)) -
                       (static_cast<wide_int>(b.raw()) << (f - B::kFracBits));
    return from_wide<To>(s, f);
  } else {
    return static_cast<To>(a) - static_cast<To>(b);
  }
}

// Real value `x` rounded into T with T's rounding (coefficients, constants).
template <class T>
T quantize(long double x) {
  if constexpr (is_fixed_v<T>)
    return T(static_cast<double>(x));
  else
    return static_cast<T>(x);
}

// Smallest T value ≥ t: a comparator `d < ceil_to<T>(t)` then decides exactly as the real
// comparison `d < t` for every representable d (a threshold rounded down would send the one
// code between it and t to the wrong segment).
template <class T>
T ceil_to(long double t) {
  if constexpr (is_fixed_v<T>) {
    const long double scaled = std::ceil(t * std::ldexp(1.0L, T::kFracBits));
    return T::from_raw(static_cast<int64_t>(scaled));
  } else {
    T x = static_cast<T>(t);
    if (static_cast<long double>(x) < t) x = std::nextafter(x, std::numeric_limits<T>::infinity());
    return x;
  }
}

}  // namespace vd_detail

// The seed's coefficients and P1 breakpoints quantised into format Fmt: the one place where a
// datapath's constants are derived from VdSeedCoefficients.
template <class Fmt>
struct VdCoefficientsIn {
  using C = typename Fmt::Coef;
  using In = typename Fmt::In;
  std::array<C, 3> p2{};
  std::array<C, 4> p3{};
  std::array<In, 2> p1_break{};
  std::array<std::array<C, 2>, 3> p1{};

  static const VdCoefficientsIn& get() {
    static const VdCoefficientsIn c = make();
    return c;
  }

 private:
  static VdCoefficientsIn make() {
    using S = VdSeedCoefficients;
    VdCoefficientsIn c;
    for (size_t i = 0; i < c.p2.size(); ++i) c.p2[i] = vd_detail::quantize<C>(S::kP2[i]);
    for (size_t i = 0; i < c.p3.size(); ++i) c.p3[i] = vd_detail::quantize<C>(S::kP3[i]);
    for (size_t i = 0; i < c.p1_break.size(); ++i) {
      c.p1_break[i] = vd_detail::ceil_to<In>(S::kP1Break[i]);
    }
    for (size_t k = 0; k < c.p1.size(); ++k) {
      for (size_t j = 0; j < 2; ++j) c.p1[k][j] = vd_detail::quantize<C>(S::kP1[k][j]);
    }
    return c;
  }
};

}  // namespace texsim
