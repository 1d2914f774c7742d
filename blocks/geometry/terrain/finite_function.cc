#include "blocks/geometry/terrain/finite_function.h"

#include <cmath>
#include <numbers>

namespace texsim {

double finite_value(FiniteKind k, double t) {
  const double a = std::fabs(t);
  if (!(a < 1)) return 0.0;  // also NaN -> 0
  switch (k) {
    case FiniteKind::Cosine:
      return 0.5 * (std::cos(std::numbers::pi * a) + 1);
    case FiniteKind::Quadratic:
      return a < 0.5 ? 1 - 2 * a * a : 2 * (1 - a) * (1 - a);
    case FiniteKind::Exp2:
      return a < 0.5 ? std::exp2(-4 * a * a) : 1 - std::exp2(-(2 - 2 * a) * (2 - 2 * a));
    case FiniteKind::Tent:
      return 1 - a;
  }
  return 0.0;
}

double finite_derivative(FiniteKind k, double t) {
  const double a = std::fabs(t);
  if (!(a < 1)) return 0.0;
  const double s = t < 0 ? -1.0 : 1.0;  // f is even: f'(t) = sign(t)·f'(|t|)
  double d = 0;
  switch (k) {
    case FiniteKind::Cosine:
      d = -0.5 * std::numbers::pi * std::sin(std::numbers::pi * a);
      break;
    case FiniteKind::Quadratic:
      d = a < 0.5 ? -4 * a : -4 * (1 - a);
      break;
    case FiniteKind::Exp2: {
      const double ln2 = std::numbers::ln2;
      if (a < 0.5) {
        d = std::exp2(-4 * a * a) * ln2 * (-8 * a);
      } else {
        const double b = 2 - 2 * a;
        d = -std::exp2(-b * b) * ln2 * (4 * b);  // d/da of 1 - 2^-b², b' = -2
      }
      break;
    }
    case FiniteKind::Tent:
      d = -1;
      break;
  }
  return s * d;
}

double FiniteBasis::blend_weight() const { return std::ldexp(1.0, -blend_shift); }

double FiniteBasis::value(double t) const {
  switch (deformation) {
    case Deformation::None:
      return finite_value(kind, t);
    case Deformation::Widened:
      return 2.0 / 3.0 * finite_value(kind, 2.0 / 3.0 * t);
    case Deformation::Blended: {
      const double f2 = finite_value(FiniteKind::Tent, t);
      return f2 + blend_weight() * (finite_value(kind, t) - f2);
    }
  }
  return 0.0;
}

double FiniteBasis::derivative(double t) const {
  switch (deformation) {
    case Deformation::None:
      return finite_derivative(kind, t);
    case Deformation::Widened:
      return 4.0 / 9.0 * finite_derivative(kind, 2.0 / 3.0 * t);
    case Deformation::Blended: {
      const double f2 = finite_derivative(FiniteKind::Tent, t);
      return f2 + blend_weight() * (finite_derivative(kind, t) - f2);
    }
  }
  return 0.0;
}

}  // namespace texsim
