#pragma once
// What a number format can hold, for float, double and Fixed<I,F> alike: finiteness, the
// results it could not hold, its largest magnitude and its rounding unit.
#include <cmath>
#include <limits>

#include "rtl_model/number/fixed.h"

namespace texsim {

template <class T>
bool is_finite_value(T x) {
  if constexpr (is_fixed_v<T>)
    return true;
  else
    return std::isfinite(x);
}

// A result the format could not hold: non-finite (float) or saturated at a rail (Fixed).
template <class T>
bool out_of_range(T x) {
  if constexpr (is_fixed_v<T>)
    return x == T::max() || x == T::min();
  else
    return !std::isfinite(x);
}

// Largest magnitude a number format can hold (used to reject maps that would saturate).
template <class T>
double format_max() {
  if constexpr (is_fixed_v<T>)
    return to_double(T::max());
  else
    return static_cast<double>(std::numeric_limits<T>::max());
}

template <class T>
constexpr bool format_is_fixed() {
  return is_fixed_v<T>;
}

// The LSB (fixed, round to nearest) or the unit roundoff (float).
template <class T>
constexpr double format_unit() {
  if constexpr (is_fixed_v<T>)
    return T::lsb();
  else
    return static_cast<double>(std::numeric_limits<T>::epsilon()) / 2;
}

}  // namespace texsim
