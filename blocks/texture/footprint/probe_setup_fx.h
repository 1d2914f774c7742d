#pragma once
// Fixed-point footprint set-up units of the probe filters (arith = "fixed"): the ProbeFx
// formats, Σ and its eigenvalues by one CORDIC vectoring, the CORDIC rotation, the
// digit-recurrence square root, log2/exp2 tables and the probe-count divider.
#include <cstdint>
#include <string>

#include "blocks/base/fragment.h"
#include "blocks/base/op_counts.h"
#include "rtl_model/number/fixed.h"
#include "rtl_model/number/number_format.h"

namespace texsim {

// Set-up arithmetic of the probe filters (`arith` key of both blocks): "float", "double" or
// "fixed" (the ProbeFx set below, named in the registry by its input format Deriv).
inline constexpr NumberFormatChoices<NumberFormat::Float, NumberFormat::Double,
                                     NumberFormat::S16_24HalfUp>
    kProbeArith{{"float", "double", "fixed"}};

// Fixed-point formats of the probe set-up (arith = "fixed"). Every format rounds half up (add
// half an LSB, truncate) and saturates. Widths:
//  Deriv  s16.24  derivatives × R in level-0 texels per pixel: |J| < 2^15 texels covers every
//                 texture up to 16384² (beyond, the footprint is flagged as overflow and the
//                 most minified level is read, as the float set-up does for Σ overflowing);
//                 24 fraction bits keep an 8× magnified J (1/8 texel) to 2^-21 relative.
//  Sigma  s34.28  Σ and eigenvalues: Σ < 2^31 texel² from Deriv, one more bit for the CORDIC
//                 gain (1.65); 28 fraction bits keep magnified footprints (Σ ≈ 10⁻⁴ texel²)
//                 to 4·10⁻⁵ relative. The CORDIC vectoring normalises its inputs (leading-zero
//                 shift) and runs on 62-bit registers, so its angle does not depend on |Σ|.
//  Angle  s3.28   radians, |2θ| ≤ π.
//  Len    s17.24  radii, lengths, probe step (texels, < 2^16 from Sigma).
//  Vec    s18.40  CORDIC rotation registers: the major-axis vector in texels; 40 fraction bits
//                 so 20 truncating shifts cost < 2^-35 texel.
//  Coord  s16.32  probe positions in normalised coordinates (2^-32: 2^-18 texel at 16384).
//  Lod    s8.16   λ.
//  Ratio  u1.32   step/R_major, 1/N and 1/(N − 1) (tables of 32 entries): 31 probes' offsets
//                 m·(line/N) stay within 31·2^-33 of the line's length.
//  Const  u7.40   per-configuration constants: 1/K (CORDIC gain), 1/maxAniso², 1/w0, 1/h0, α,
//                 w_α·log2(e).
//  Arg    u7.24   exp2 argument y (≥ 16 gives weight 0 in u1.15 anyway).
//  Weight u1.15   probe weights.
struct ProbeFx {
  template <int I, int F>
  using S = Fixed<I, F, Signedness::Signed, Rounding::HalfUp, Overflow::Saturate>;
  template <int I, int F>
  using U = Fixed<I, F, Signedness::Unsigned, Rounding::HalfUp, Overflow::Saturate>;
  using Deriv = number_format_t<NumberFormat::S16_24HalfUp>;  // = S<16, 24>
  using Sigma = S<34, 28>;
  using Angle = S<3, 28>;
  using Len = S<17, 24>;
  using Vec = S<18, 40>;
  using Coord = S<16, 32>;
  using Lod = S<8, 16>;
  using Ratio = U<1, 32>;
  using Const = U<7, 40>;
  using Arg = U<7, 24>;
  using Weight = U<1, 15>;
  // CORDIC iterations (vectoring and rotation each). The residual angle after n steps is
  // below atan(2^-(n-1)) ≈ 2^-19 rad: a probe k·step from the centre moves by at most
  // R_major·2^-19, i.e. 64/α·2^-19 < 2^-11 texel of the probe's level at the 64:1 clamp.
  static constexpr int kCordicSteps = 20;
  // log2(1 + f) and 2^-f tables: f rounded to 10 bits, entries at j/1024 (exact at 0).
  static constexpr int kTableBits = 10;
  // Quotient steps of the probe-count divider: quotients ≥ 32 only say "more than 31 probes".
  static constexpr int kCountSteps = 6;
  static std::string name();  // e.g. "s16.16 J, s34.28 Σ, ..."
};

// The fixed-point footprint set-up of the probe filters: Σ = R²·J·Jᵀ from Deriv, its
// eigenvalues as t ± s with s = |((Σuu − Σvv)/2, Σuv)| and 2θ = atan2(Σuv, (Σuu − Σvv)/2) from
// one CORDIC vectoring, and the max-anisotropy clamp λ₋ ≥ λ₊/maxAniso² (the clamp keeps the
// eigenvectors, so θ needs no update: Σ' is never formed).
struct ProbeFootprintFx {
  ProbeFx::Sigma major2{}, minor2{};  // eigenvalues after the clamp (texels²)
  ProbeFx::Angle two_theta{};         // 2θ of the major axis (seed_theta: the printed form)
  bool clamped = false;
  bool bad_input = false;  // non-finite derivatives: point footprint
  bool overflow = false;   // a derivative saturated Deriv: most minified level
};
ProbeFootprintFx probe_footprint_fx(const Fragment& f, int w0, int h0, double radius_px,
                                    double max_aniso, bool seed_theta);
OpCounts probe_footprint_fx_ops();

// Datapath units of the fixed set-up, public for the tests.
namespace probe_fx {
// √x rounded to nearest (digit recurrence on the raw bits, then one rounding step).
ProbeFx::Len sqrt_len(ProbeFx::Sigma x);
// log2(raw·2^-frac_bits) for raw > 0: leading-one position plus a table of log2(1 + j/1024).
ProbeFx::Lod log2_of(int64_t raw, int frac_bits);
// 2^-y: table of 2^(-j/1024) (u0.24 entries) shifted right by ⌊y⌋, rounded into u1.15.
ProbeFx::Weight exp2_neg(ProbeFx::Arg y);
// CORDIC vectoring of (x, y), inputs normalised by a leading-zero shift and the magnitude
// shifted back: returns K·|(x, y)| in `mag` (gain K not removed) and
// atan2(y, x) (seed_literal: atan(y/x), folded into (−π/2, π/2]).
ProbeFx::Angle vector_angle(ProbeFx::Sigma x, ProbeFx::Sigma y, bool seed_literal,
                            ProbeFx::Sigma& mag);
// CORDIC rotation of (r, 0) by theta (|theta| ≤ π/2): returns r·K·(cos θ, sin θ); callers
// pre-scale r by 1/K.
void rotate(ProbeFx::Vec r, ProbeFx::Angle theta, ProbeFx::Vec& x, ProbeFx::Vec& y);
// The CORDIC gain K = ∏ √(1 + 2^-2i) over kCordicSteps steps, and its reciprocal as Const.
double cordic_gain();
ProbeFx::Const inv_gain();
// Integer part of a/b for a, b > 0, saturated at 2^kCountSteps (a restoring divider); rem_zero
// tells whether the remainder is zero (for ⌈a/b⌉).
int64_t count_quotient(int64_t a, int64_t b, bool& rem_zero);
// Operations of one CORDIC pass (vectoring or rotation: 3 add, 1 cmp per step) and of the
// probe-count divider with its remainder test.
OpCounts cordic_ops();
OpCounts count_divider_ops();
}  // namespace probe_fx

}  // namespace texsim
