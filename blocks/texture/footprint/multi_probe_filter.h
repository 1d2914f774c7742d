#pragma once
// Multi-ellipse probe filter (Mavridis & Papaioannou; seed 004 eq. 12–17): the footprint
// ellipse approximated by N trilinear probes along its major axis, N = 2·R_major/(α·R_minor) − 1
// (odd), spread over L = 2·(R_major − α·R_minor), weighted by a Gaussian of their distance to
// the centre; optionally half the probes per frame, alternating (docs/anisotropic-filters.md §4).
// Arithmetic (Config::arith): set-up = footprint, axes, N, LOD, probe positions and weights.
//  - float:  footprint set-up in float32; axes, N, positions and weights evaluated in double
//            from it (the block's original model, kept bit-identical).
//  - double: the same in double throughout.
//  - fixed:  every set-up quantity in the ProbeFx formats below (round half up, saturating):
//            square roots by a digit-recurrence unit, the axis angle and the major-axis vector
//            by CORDIC (vectoring, then rotation: no atan/cos/sin tables), log2 and exp2 by
//            tables of 1024 entries, the probe-count quotient by a 6-step restoring divider.
// In every mode the probes run through the trilinear texel address generator (float32
// coordinates, u0.8 weights) and are blended in float32. This header also holds the probe
// executor and the fixed-point set-up that FelineFilter shares.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/config_reader.h"
#include "blocks/base/fragment.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/footprint/ewa_filter.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/texel_address_gen.h"
#include "rtl_model/number/fixed.h"
#include "rtl_model/number/number_format.h"

namespace texsim {

// A set of weighted isotropic probes at one LOD (normalised coordinates).
struct ProbeSet {
  static constexpr int kMax = 31;
  int n = 0;
  std::array<double, kMax> u{}, v{};
  std::array<float, kMax> w{};
  float lambda = 0;
};

// Runs each probe as a trilinear lookup (TexelAddressGen, one probe per cycle), blends its 8
// taps and sums the probes with their weights, normalised by Σw (all weights zero: the
// probes' plain mean). Appends the taps' texels to `fetched`; counts each probe's set-up
// (`probe_setup`: position and weight), address, blend and weighting operations. `bad_input`
// is the set-up's verdict on the fragment, passed to the output's stats.
FilterOutput run_probes(const TexelAddressGen& addr, const Texture& tex, const ProbeSet& probes,
                        const OpCounts& probe_setup, bool bad_input, std::vector<TexelRef>* fetched,
                        OpCounts& ops);
// One probe lane of a probe filter: its set-up, trilinear address and blend with weighting.
OpCounts probe_lane_ops(const TexelAddressGen& addr, const OpCounts& probe_setup);
// Timing of a probe filter: the set-up's critical path `setup_path`, then one probe's address
// path, blend and normalisation; II 1 (one probe per cycle); area of the set-up (`setup_ops`),
// one probe lane and the normalisation.
TimingSpec probe_filter_timing(const TechTable& tech, const OpCounts& setup_path,
                               const TexelAddressGen& addr, const OpCounts& setup_ops,
                               const OpCounts& probe_setup);
// Operations of run_probes per probe besides TexelAddressGen's (blend 8 taps, weighting) and
// per fragment (normalisation).
OpCounts probe_blend_ops();
// A trilinear probe's blend (8 taps through TexelBlend) plus its weighting.
OpCounts trilinear_probe_blend_ops();
OpCounts probe_normalise_ops();

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

class MultiProbeFilter {
 public:
  struct Config {
    double alpha = 1.0;   // the seed's α: a probe's radius in minor radii (spacing α·R_minor)
    int max_probes = 15;  // odd, ≤ 31
    double weight_alpha = 2.0;  // probe weight exp(−w_α·(d/R_major)²): EWA's pixel model
    double radius_px = 1.0;     // R: footprint radius in pixels
    double max_aniso = 64;      // minor axis stretched to ≥ major/max_aniso before N is taken
    bool seed_theta = false;    // θ = atan(B/(A−C))/2 as printed (loses the quadrant)
    bool temporal = false;  // alternate probe subsets between frames (0, ±2, ±4 … / 0, ±1, ±3 …)
    NumberFormat arith = NumberFormat::Float;  // set-up arithmetic (see the header comment)
    AddressMode address_u = AddressMode::Wrap;
    AddressMode address_v = AddressMode::Wrap;
    // Keys: alpha, max_probes, weight_alpha, radius_px, max_aniso, seed_theta, temporal,
    // arith (float|double|fixed), address_u, address_v.
    static Config from_toml(const ConfigReader& r);
  };

  MultiProbeFilter() : MultiProbeFilter(Config{}) {}
  explicit MultiProbeFilter(const Config& c);
  const Config& config() const { return cfg_; }

  // The probes of one fragment (positions, weights, LOD) in the configured arithmetic; adds
  // the set-up operations.
  ProbeSet probes(const Texture& tex, const Fragment& f, OpCounts& ops,
                  FilterStats* st = nullptr) const;
  FilterOutput filter(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                      OpCounts& ops) const;

  // Major-axis angle from the footprint covariance: ½·atan2(2Σuv, Σuu − Σvv), or the seed's
  // printed ½·atan(B/(A − C)) with A = Σvv, B = −2Σuv, C = Σuu of the quadratic form.
  static double major_angle(double suu, double suv, double svv, bool seed_literal);

  // Cycles one fragment occupies the probe datapath: one probe per cycle.
  uint32_t issue_cycles(const FilterStats& s) const { return s.probes > 0 ? s.probes : 1; }
  OpCounts setup_ops() const;
  // Item: one probe: position, weight, address (trilinear), blend.
  OpCounts ops_per_item() const;
  OpCounts probe_setup_ops() const;  // per probe: position and weight only
  TimingSpec timing(const TechTable& tech) const;
  // Name of the arithmetic for reports.
  std::string arithmetic() const;
  std::string name() const { return "filter.multi_probe"; }

 private:
  // The set-up in one number format (T = float or double; fixed point: probes_fixed).
  template <class T>
  ProbeSet probes_t(const Texture& tex, const Fragment& f, FilterStats* st) const;
  ProbeSet probes_fixed(const Texture& tex, const Fragment& f, FilterStats* st) const;
  Config cfg_;
  TexelAddressGen addr_;
};

}  // namespace texsim
