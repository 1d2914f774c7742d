#pragma once
// Finite functions for terrain interpolation (seed 003 §2.3–2.4; docs/derivations/terrain.md):
// the three base functions, the tent, and the two deformations. A FiniteBasis is the 1-D kernel
// f^k that a height evaluator weights the grid heights with.
// Arithmetic: double (std::cos, std::exp2 for the transcendental parts).
#include <cstdint>

namespace texsim {

// Base functions f(t), even, f(0) = 1, zero for |t| >= 1, f(t) + f(t - 1) = 1 on [0, 1]:
//  Cosine:    (cos πt + 1)/2
//  Quadratic: 1 - 2t² (|t| < 1/2), 2(1 - |t|)² (1/2 <= |t| < 1)
//  Exp2:      2^-(2t)² (|t| < 1/2), 1 - 2^-(2 - 2|t|)² (1/2 <= |t| < 1)
//  Tent:      1 - |t| (variant 2's f2; not C¹)
enum class FiniteKind { Cosine, Quadratic, Exp2, Tent };
double finite_value(FiniteKind k, double t);
double finite_derivative(FiniteKind k,
                         double t);  // one-sided at the tent's kinks: the t > 0 side at 0

// Deformations (seed 003 §2.4):
//  None:    f
//  Widened: variant 1, f¹(t) = (2/3)·f((2/3)·t), support (-3/2, 3/2), 3 × 3 heights per point
//  Blended: variant 2, f² = f2 + a·(f1 - f2), f1 = the base function, f2 = the tent, a = 2^-d
enum class Deformation { None, Widened, Blended };

struct FiniteBasis {
  FiniteKind kind = FiniteKind::Cosine;
  Deformation deformation = Deformation::None;
  int32_t blend_shift = 1;  // d of a = 2^-d (Blended)

  double blend_weight() const;  // a
  double radius() const { return deformation == Deformation::Widened ? 1.5 : 1.0; }
  double value(double t) const;
  double derivative(double t) const;
};

}  // namespace texsim
