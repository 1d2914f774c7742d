#pragma once
// Gaussian pixel-model weight unit (thesis formula 4; docs/derivations/gaussian-weights.md): per
// footprint a set-up turns the derivatives into q(U, V) = a·U² + b·U·V + c·V², per texel it
// evaluates q and the weight exp(−q/2) or its power-8 form (1 − q/16)^8 (three squarings, 0 from q
// = 16). The set-up is either the exact quadratic form (Heckbert's A, B, C over F) or the seed's
// θ/L/d axis formulas, kept as approximations whose error the testbench measures.
// Arithmetic: set-up and q in float/double; the weight in float, double or fixed
// (q u5.11 → weight u1.15, HalfUp, saturating).
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "blocks/base/config_reader.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/subtexel/vd_evaluator_params.h"

namespace texsim {

enum class GaussianWeightFunction : int { Exp, Pow8 };
enum class GaussianAxes : int {
  QuadraticForm,  // q = (A U² + B U V + C V²)/F: the exact 1-σ ellipse (METHODS §4, §5.3)
  SeedAxes,       // θ, L, d from the x-derivative vector: L² = Ux²+Vx², d² = Uy²+Vy²,
                  // cos θ = Ux/L, sin θ = Vx/L — exact only when the derivative vectors are
                  // orthogonal
  SeedLiteral,    // as printed: L² = C, d² = A, cos θ = Ux/L, sin θ = Vy/d
};

template <class T>
struct GaussianWeightFormat {
  using Q = T;
  using W = T;
  static std::string name() { return format_name<T>(); }
};
// q < 32 in u5.11 (the power-8 form needs q < 16 only; one more integer bit keeps "q ≥ 16"
// a plain MSB test); weights in [0, 1] in u1.15.
struct GaussianWeightFx16 {
  using Q = Fixed<5, 11, Signedness::Unsigned, Rounding::HalfUp, Overflow::Saturate>;
  using W = Fixed<1, 15, Signedness::Unsigned, Rounding::HalfUp, Overflow::Saturate>;
  static std::string name() { return Q::name() + "/" + W::name(); }
};

// Per-footprint constants: q(U, V) = a·U² + b·U·V + c·V². `degenerate` (zero-area footprint,
// non-finite derivatives) makes q = +∞ for every texel, so every weight is 0 and the filter's
// all-weights-zero fallback applies.
template <class T>
struct EllipseQuadratic {
  T a = 0, b = 0, c = 0;
  bool degenerate = true;
};

class GaussianWeight {
 public:
  struct Config {
    GaussianWeightFunction function = GaussianWeightFunction::Pow8;
    GaussianAxes axes = GaussianAxes::QuadraticForm;
    uint32_t lanes = 1;  // texels weighted per cycle
    // Keys: function ("exp"|"pow8"), axes ("quadratic_form"|"seed_axes"|"seed_literal"), lanes.
    static Config from_toml(const ConfigReader& r);
  };

  GaussianWeight() = default;
  explicit GaussianWeight(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // exp(−q/2). Fixed: an ideal table, exp correctly rounded into W. q < 0 (rounding in a
  // nearly degenerate q) counts as 0; NaN gives 0.
  template <class Fmt>
  static typename Fmt::W weight_exp(typename Fmt::Q q) {
    using W = typename Fmt::W;
    using Q = typename Fmt::Q;
    if constexpr (is_fixed_v<W>) {
      return vd_detail::quantize<W>(std::exp(-0.5L * static_cast<long double>(q.to_double())));
    } else {
      if (q != q) return W(0);
      if (q < Q(0)) q = Q(0);
      return std::exp(static_cast<W>(-0.5) * static_cast<W>(q));
    }
  }

  // (1 − q/16)^8 for 0 ≤ q < 16, else 0 (q < 0 counts as 0; NaN gives 0). The /16 is a shift:
  // in fixed point t = 1 − q/16 is exact in W; each squaring rounds once.
  template <class Fmt>
  static typename Fmt::W weight_pow8(typename Fmt::Q q) {
    using W = typename Fmt::W;
    using Q = typename Fmt::Q;
    const Q sixteen = vd_detail::quantize<Q>(16.0L);
    if (!(q < sixteen)) return vd_detail::quantize<W>(0.0L);  // also NaN
    if (q < vd_detail::quantize<Q>(0.0L)) q = vd_detail::quantize<Q>(0.0L);
    const W t = vd_detail::sub<W>(vd_detail::quantize<W>(1.0L),
                                  vd_detail::mul<W>(q, vd_detail::quantize<W>(0.0625L)));
    const W t2 = vd_detail::mul<W>(t, t);
    const W t4 = vd_detail::mul<W>(t2, t2);
    return vd_detail::mul<W>(t4, t4);
  }

  // The configured weight function.
  template <class Fmt>
  typename Fmt::W weight(typename Fmt::Q q) const {
    return cfg_.function == GaussianWeightFunction::Exp ? weight_exp<Fmt>(q) : weight_pow8<Fmt>(q);
  }

  // Per-footprint set-up from the derivatives (texels per pixel) with the given axes rule.
  template <class T>
  static EllipseQuadratic<T> setup(GaussianAxes axes, T ux, T vx, T uy, T vy) {
    EllipseQuadratic<T> e;
    const T one = T(1);
    T ia = 0, ic = 0, cs = 0, sn = 0;  // 1/L², 1/d², cos θ, sin θ of the axis rules
    switch (axes) {
      case GaussianAxes::QuadraticForm: {
        const T A = vx * vx + vy * vy;
        const T B = T(-2) * (ux * vx + uy * vy);
        const T C = ux * ux + uy * uy;
        const T det = ux * vy - uy * vx;
        const T F = det * det;
        if (!(F > T(0)) || !std::isfinite(F) || !std::isfinite(A + B + C)) return e;
        const T r = one / F;
        e.a = A * r;
        e.b = B * r;
        e.c = C * r;
        e.degenerate = !(std::isfinite(e.a) && std::isfinite(e.b) && std::isfinite(e.c));
        return e;
      }
      case GaussianAxes::SeedAxes: {
        const T l2 = ux * ux + vx * vx;
        const T d2 = uy * uy + vy * vy;
        if (!(l2 > T(0)) || !(d2 > T(0)) || !std::isfinite(l2) || !std::isfinite(d2)) return e;
        const T il = one / std::sqrt(l2);
        cs = ux * il;
        sn = vx * il;
        ia = il * il;
        ic = one / d2;
        break;
      }
      case GaussianAxes::SeedLiteral: {
        const T A = vx * vx + vy * vy;
        const T C = ux * ux + uy * uy;
        if (!(A > T(0)) || !(C > T(0)) || !std::isfinite(A) || !std::isfinite(C)) return e;
        cs = ux / std::sqrt(C);
        sn = vy / std::sqrt(A);
        ia = one / C;
        ic = one / A;
        break;
      }
    }
    // x' = U cos θ + V sin θ, y' = V cos θ − U sin θ, q = x'²/L² + y'²/d², expanded once per
    // footprint so the per-texel work is the same quadratic form for every rule.
    const T c2 = cs * cs, s2 = sn * sn, csn = cs * sn;
    e.a = c2 * ia + s2 * ic;
    e.b = T(2) * csn * (ia - ic);
    e.c = s2 * ia + c2 * ic;
    e.degenerate = !(std::isfinite(e.a) && std::isfinite(e.b) && std::isfinite(e.c));
    return e;
  }

  // q at texel offset (U, V) from the footprint centre: (a·U + b·V)·U + c·V·V.
  template <class T>
  static T q_of(const EllipseQuadratic<T>& e, T U, T V) {
    if (e.degenerate) return std::numeric_limits<T>::infinity();
    return (e.a * U + e.b * V) * U + e.c * V * V;
  }

  // Weight of the texel at offset (U, V) with the configured function (float/double).
  template <class T>
  T weight_at(const EllipseQuadratic<T>& e, T U, T V) const {
    return weight<GaussianWeightFormat<T>>(q_of(e, U, V));
  }

  // Operations of the per-footprint set-up for the configured axes rule.
  OpCounts setup_ops() const;
  // Item: one texel. Operations: q (5 mul, 2 add) and the weight function.
  OpCounts ops_per_item() const;
  OpCounts texel_critical_path() const;
  // Per-texel datapath (fully pipelined, `lanes` texels per cycle).
  TimingSpec timing(const TechTable& tech) const;
  // Per-footprint set-up unit (fully pipelined, one footprint per cycle).
  TimingSpec setup_timing(const TechTable& tech) const;
  std::string name() const { return "gaussian_weight"; }
  // The format is the caller's (GaussianWeightFormat<float|double> or GaussianWeightFx16).
  std::string arithmetic() const { return "per-call format"; }

 private:
  Config cfg_;
};

}  // namespace texsim
