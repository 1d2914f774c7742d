#pragma once
// `texsim study vd`: maximum absolute error of each V(d) evaluator block in each number format
// against Φ(d/σ), next to the seed's claims, with ops, latency and area from the technology
// table (docs/derivations/vd-evaluators.md explains the method and the results).
#include <array>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "blocks/texture/subtexel/vd_evaluator_params.h"

namespace texsim {

// Φ(d/σ), σ = 0.2, in long double (erfcl); the sweeps' reference, checked against MPFR in
// testbench/unit/texture/test_vd_evaluators.cc.
long double vd_reference(long double d);
// Φ(d/σ) computed with MPFR at 160 bits (σ = 1/5 exactly), rounded to long double.
long double vd_reference_mpfr(long double d);

struct VdErrorStats {
  VdEvaluatorKind evaluator = VdEvaluatorKind::Exact;
  NumberFormat format = NumberFormat::Double;
  double max_abs = 0;        // max over the sweep of |V̂(d) − Φ(d/σ)| (MPFR at the arg max)
  double argmax_d = 0;       // the (first) input where it occurs
  double signed_at_max = 0;  // V̂ − Φ there
  double mean_abs = 0;       // mean |V̂ − Φ| over the sweep (neighbourhood scan excluded)
  uint64_t points = 0;       // inputs evaluated
  std::string sweep;         // which inputs: every code, or grid + neighbourhood, or all floats
};

// Fixed formats: every representable input in [0, 0.5]. float/double: the grid
// d_i = 0.5·i/grid (i = 0..grid, rounded into the format) plus every float/double within
// 2^20 steps of the grid's arg max.
VdErrorStats measure_vd_error(VdEvaluatorKind k, NumberFormat f, uint64_t grid = 10'000'000);

// Every float in [0, 0.5] (about 1.06·10^9 inputs) for all four evaluators at once, with a
// double-precision reference (erfc), the maximum then re-evaluated with MPFR. Takes tens of
// seconds; `progress` (optional) gets a line per eighth of the range.
std::array<VdErrorStats, 4> measure_vd_error_all_floats(std::ostream* progress = nullptr);

// σ in [lo, hi] for which the evaluator's maximum error on a 2001-point grid of [0, 0.5] is
// smallest, i.e. which normalisation the seed's coefficients fit best.
struct VdSigmaFit {
  double sigma = 0;
  double max_abs = 0;
};
VdSigmaFit vd_best_sigma(VdEvaluatorKind k, double lo = 0.15, double hi = 0.25);

// Max error (double, 2001-point grid) of the evaluator against the texel-normalised volume
// (Φ(d/σ) − Φ(−0.5/σ)) / (2·Φ(0.5/σ) − 1), the other plausible reading of "V".
double vd_error_vs_texel_normalised(VdEvaluatorKind k);

// Minimax polynomial of the given degree for Φ(d/σ) on [0, 0.5] (Remez exchange in long double
// on a 20001-point grid); with pin_half the constant term is fixed at 0.5 so that the symmetric
// extension V(−d) = 1 − V(d) stays continuous at 0. max_abs is measured on a 200001-point grid.
struct VdPolyFit {
  std::vector<double> coef;  // increasing powers of d
  double max_abs = 0;
  double argmax_d = 0;
};
VdPolyFit vd_minimax_fit(int degree, bool pin_half);

// W = V(0.5) − V(d) of SubtexelCutoff over d ∈ [−0.5, 0.5] against the exact volume.
struct CutoffErrorStats {
  double max_abs = 0;  // max |Ŵ(d) − W(d)|
  double argmax_d = 0;
  double jump_at_zero = 0;   // Ŵ(0⁻) − Ŵ(0⁺): nonzero when the evaluator's V(0) ≠ 0.5
  double min_unclamped = 0;  // smallest V̂(0.5) − V̂(|d|) for d ≥ 0 before the clamp to 0
  uint64_t points = 0;
};
// Double: grid of 2·10^6 + 1 points; fixed formats: every s1.F code in [−0.5, 0.5].
CutoffErrorStats measure_cutoff_error(VdEvaluatorKind k, NumberFormat f);

// Writes vd.csv, vd.md and vd.png into out_dir (created if missing); returns 0 on success.
// Progress and a summary go to `log`. Runs in a few seconds on one core.
int run_study_vd(const std::string& out_dir, std::ostream& log, int threads = 0);

}  // namespace texsim
