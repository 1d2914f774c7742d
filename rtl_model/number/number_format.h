#pragma once
// Number-format registry: every number format a block datapath can be configured in, with its
// registry name, its C++ type (float, double or a Fixed<I, F, ...>) and one dispatch from the
// runtime value to the type (docs/number-formats.md). Blocks accept a subset of the registry
// under their own config spellings (NumberFormatChoices), e.g. EWA's arith = "fixed" is
// S18_30; reports print the type's own name (format_name<T>()).
#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "rtl_model/number/fixed.h"

namespace texsim {

enum class NumberFormat : int {
  Float,         // float32
  Double,        // float64
  S16_16,        // coordinate datapaths: s16.16, s20.28, s24.36 (HalfEven, saturating)
  S20_28,        //
  S24_36,        //
  S18_30,        // EWA's per-texel Q (HalfEven, saturating)
  S20_28HalfUp,  // SPAF's edge functions and Q (HalfUp, saturating)
  S16_24HalfUp,  // the probe filters' fixed set-up, by its input (the derivatives J)
  Fx16,          // V(d) evaluators, by their input u0.16, u0.12, u0.8 (HalfUp, saturating);
  Fx12,          // coefficients and outputs follow from it (VdFixedFormat)
  Fx8,           //
  kCount
};
inline constexpr int kNumberFormats = static_cast<int>(NumberFormat::kCount);

namespace number_format_detail {
template <int I, int F>
using SignedHalfEven = Fixed<I, F, Signedness::Signed, Rounding::HalfEven, Overflow::Saturate>;
template <int I, int F>
using SignedHalfUp = Fixed<I, F, Signedness::Signed, Rounding::HalfUp, Overflow::Saturate>;
template <int F>
using UnsignedFraction = Fixed<0, F, Signedness::Unsigned, Rounding::HalfUp, Overflow::Saturate>;

// The type of each format, in the order of NumberFormat.
template <NumberFormat N>
struct TypeOf;
template <>
struct TypeOf<NumberFormat::Float> {
  using type = float;
};
template <>
struct TypeOf<NumberFormat::Double> {
  using type = double;
};
template <>
struct TypeOf<NumberFormat::S16_16> {
  using type = SignedHalfEven<16, 16>;
};
template <>
struct TypeOf<NumberFormat::S20_28> {
  using type = SignedHalfEven<20, 28>;
};
template <>
struct TypeOf<NumberFormat::S24_36> {
  using type = SignedHalfEven<24, 36>;
};
template <>
struct TypeOf<NumberFormat::S18_30> {
  using type = SignedHalfEven<18, 30>;
};
template <>
struct TypeOf<NumberFormat::S20_28HalfUp> {
  using type = SignedHalfUp<20, 28>;
};
template <>
struct TypeOf<NumberFormat::S16_24HalfUp> {
  using type = SignedHalfUp<16, 24>;
};
template <>
struct TypeOf<NumberFormat::Fx16> {
  using type = UnsignedFraction<16>;
};
template <>
struct TypeOf<NumberFormat::Fx12> {
  using type = UnsignedFraction<12>;
};
template <>
struct TypeOf<NumberFormat::Fx8> {
  using type = UnsignedFraction<8>;
};
}  // namespace number_format_detail

// The C++ type of a format.
template <NumberFormat N>
using number_format_t = typename number_format_detail::TypeOf<N>::type;

// Registry names (unique; fixed formats with a rounding other than HalfEven say so).
inline constexpr std::array<std::string_view, kNumberFormats> kNumberFormatNames = {
    "float",          "double",         "s16.16", "s20.28", "s24.36", "s18.30",
    "s20.28-half-up", "s16.24-half-up", "fx16",   "fx12",   "fx8"};

constexpr std::string_view number_format_name(NumberFormat f) {
  return kNumberFormatNames[static_cast<size_t>(f)];
}

// Calls fn(T{}) with T the type of `f` if `f` is one of Fs (else the last of Fs) and returns
// its result; only the listed formats are instantiated.
template <NumberFormat First, NumberFormat... Rest, class Fn>
decltype(auto) visit_number_format_in(NumberFormat f, Fn&& fn) {
  if constexpr (sizeof...(Rest) == 0) {
    return fn(number_format_t<First>{});
  } else {
    if (f == First) return fn(number_format_t<First>{});
    return visit_number_format_in<Rest...>(f, std::forward<Fn>(fn));
  }
}

// The same over every format of the registry.
template <class Fn>
decltype(auto) visit_number_format(NumberFormat f, Fn&& fn) {
  using enum NumberFormat;
  return visit_number_format_in<Float, Double, S16_16, S20_28, S24_36, S18_30, S20_28HalfUp,
                                S16_24HalfUp, Fx16, Fx12, Fx8>(f, std::forward<Fn>(fn));
}

// The formats one block accepts, under the block's config spellings: keys[i] selects the i-th
// of Fs. index_of/at translate to and from ConfigReader::get_choice's index; visit dispatches
// over these formats only.
template <NumberFormat... Fs>
struct NumberFormatChoices {
  static constexpr std::array<NumberFormat, sizeof...(Fs)> kFormats{Fs...};
  std::array<std::string_view, sizeof...(Fs)> keys;

  std::vector<std::string_view> key_list() const { return {keys.begin(), keys.end()}; }
  static constexpr int index_of(NumberFormat f) {
    for (size_t i = 0; i < kFormats.size(); ++i) {
      if (kFormats[i] == f) return static_cast<int>(i);
    }
    return 0;
  }
  static constexpr NumberFormat at(int i) { return kFormats[static_cast<size_t>(i)]; }
  constexpr std::string_view key_of(NumberFormat f) const {
    return keys[static_cast<size_t>(index_of(f))];
  }
  template <class Fn>
  static decltype(auto) visit(NumberFormat f, Fn&& fn) {
    return visit_number_format_in<Fs...>(f, std::forward<Fn>(fn));
  }
};

// The coordinate blocks' formats (pipeline/texture/coord_method.cc), keyed by registry name.
inline constexpr NumberFormatChoices<NumberFormat::Float, NumberFormat::Double,
                                     NumberFormat::S16_16, NumberFormat::S20_28,
                                     NumberFormat::S24_36>
    kCoordFormats{{"float", "double", "s16.16", "s20.28", "s24.36"}};

}  // namespace texsim
