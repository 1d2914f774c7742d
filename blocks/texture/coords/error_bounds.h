#pragma once
// A-priori error bounds of the coordinate blocks' steps (docs/derivations/coords-derivations.md
// §3.3).
namespace texsim {

// Bound on |ŵ/ẑ − w/z| (texels) after the division step of a block, given |ŵ − w| <= dw and
// |ẑ − z| <= dz at the exact values w, z (z > dz > = 0), for a number format with `unit` = the
// LSB (fixed, round to nearest: each rounding <= unit/2) or the unit roundoff (float: each
// rounding <= unit·|result|). `reciprocal` = r = 1/ẑ then ŵ·r (two roundings, the first
// scaled by |ŵ|). +inf if z <= dz.
double quotient_error_bound(double w, double z, double dw, double dz, bool reciprocal, bool fixed,
                            double unit);
// Error of a linear form a·x + b·y + c evaluated in the format (coefficients rounded into it,
// then two products and two sums): fixed-point products of integers are exact, so only the
// coefficients' rounding counts; in float every operation rounds.
double linear_form_error_bound(long double a, long double b, long double c, long double x,
                               long double y, bool fixed, double unit);

}  // namespace texsim
