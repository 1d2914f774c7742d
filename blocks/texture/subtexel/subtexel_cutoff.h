#pragma once
// Sub-texel cut-off volume W = V(0.5) − V(d) of a Gaussian texel (σ = 0.2) cut by a footprint
// edge at signed distance d, with V(−d) = 1 − V(d), on a selectable V(d) evaluator block;
// models the thesis's sub-texel weighting (docs/derivations/vd-evaluators.md §"Cut-off volume").
// Arithmetic: the evaluator's format (float, double, or fixed u0.F/s3.F/u1.F, signed input
// s1.F); V̂ is clamped to V̂(0.5) because P2 and P3 are not monotonic near d = 0.5.
#include <cstdint>
#include <string>

#include "blocks/base/config_reader.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/subtexel/vd_evaluator_exact.h"
#include "blocks/texture/subtexel/vd_evaluator_p1.h"
#include "blocks/texture/subtexel/vd_evaluator_p2.h"
#include "blocks/texture/subtexel/vd_evaluator_p3.h"
#include "blocks/texture/subtexel/vd_evaluator_params.h"

namespace texsim {

// Calls f(Evaluator{}) with the V(d) evaluator block selected by `k`.
template <class F>
decltype(auto) visit_vd_evaluator(VdEvaluatorKind k, F&& f) {
  switch (k) {
    case VdEvaluatorKind::Exact:
      return f(VdEvaluatorExact{});
    case VdEvaluatorKind::P3:
      return f(VdEvaluatorP3{});
    case VdEvaluatorKind::P2:
      return f(VdEvaluatorP2{});
    case VdEvaluatorKind::P1:
      break;
  }
  return f(VdEvaluatorP1{});
}

class SubtexelCutoff {
 public:
  struct Config {
    VdEvaluatorKind evaluator = VdEvaluatorKind::P2;
    NumberFormat format = NumberFormat::Float;  // used by the double-in/double-out entry
    uint32_t lanes = 1;
    // Keys: evaluator ("exact"|"p3"|"p2"|"p1"), format ("float"|"double"|"fx16"|"fx12"|
    // "fx8"), lanes.
    static Config from_toml(const ConfigReader& r);
  };

  SubtexelCutoff() = default;
  explicit SubtexelCutoff(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // W for a cut line at signed distance d (texel units; d > 0: the centre is cut off).
  // |d| is clamped to 0.5: d ≥ 0.5 gives 0, d ≤ −0.5 gives full_weight(). NaN gives 0 (the
  // texel is dropped). The evaluator is the configured one; the format is Fmt.
  template <class Fmt>
  typename Fmt::Out weight(typename Fmt::SIn d) const {
    using SIn = typename Fmt::SIn;
    using In = typename Fmt::In;
    using A = typename Fmt::Acc;
    using Out = typename Fmt::Out;
    const SIn half = vd_detail::quantize<SIn>(0.5L);
    const SIn zero = vd_detail::quantize<SIn>(0.0L);
    const bool neg = d < zero;
    SIn a = neg ? -d : d;
    if (!(a <= half)) a = half;  // also catches NaN
    return visit_vd_evaluator(cfg_.evaluator, [&](auto ev) {
      const Out v_half = ev.template eval<Fmt>(vd_detail::cast<In>(half));
      Out v = ev.template eval<Fmt>(vd_detail::cast<In>(a));
      // P2 and P3 peak before d = 0.5; clamping V̂ to V̂(0.5) keeps W within [0, full] on both
      // sides of the centre and W monotone, at the cost of one comparator.
      if (v_half < v) v = v_half;
      // W = V(0.5) − V(|d|) for d ≥ 0; V(0.5) − (1 − V(|d|)) = (V(0.5) − 1) + V(|d|) for d < 0.
      const A w =
          neg ? vd_detail::add<A>(vd_detail::sub<A>(v_half, vd_detail::quantize<A>(1.0L)), v)
              : vd_detail::sub<A>(v_half, v);
      return vd_detail::cast<Out>(w);
    });
  }

  // Weight of a texel wholly on the inner side: W(−0.5) = 2·V(0.5) − 1 (not 1: the Gaussian
  // texel's tails outside [−0.5, 0.5] are not counted).
  template <class Fmt>
  typename Fmt::Out full_weight() const {
    return weight<Fmt>(vd_detail::quantize<typename Fmt::SIn>(-0.5L));
  }

  // W in the configured format: d rounded into it, W returned as a double.
  double weight(double d) const;

  // W(d)/W(−½): the part of a wholly inside texel's volume that remains, in Fmt's output
  // type, as a filter's coverage factor. W(−½) and 1/W(−½) (rounded into Out) are constant
  // registers; per call one multiply and one select (exactly 1 once W reaches W(−½)).
  template <class Fmt>
  class Fraction {
   public:
    using SIn = typename Fmt::SIn;
    using Out = typename Fmt::Out;
    explicit Fraction(const SubtexelCutoff& c)
        : cut_(&c),
          full_(c.full_weight<Fmt>()),
          inv_full_(vd_detail::quantize<Out>(1.0L / static_cast<long double>(to_double(full_)))),
          one_(vd_detail::quantize<Out>(1.0L)) {}
    Out operator()(SIn d) const {
      const Out w = cut_->weight<Fmt>(d);
      return w < full_ ? vd_detail::mul<Out>(w, inv_full_) : one_;
    }
    Out one() const { return one_; }

   private:
    const SubtexelCutoff* cut_;
    Out full_, inv_full_, one_;
  };
  // Fraction in the configured format: d rounded into it, the fraction returned as a double.
  double fraction(double d) const;
  // Operations of one Fraction call beyond ops_per_item(): the multiply by 1/W(−½) and the select.
  static OpCounts fraction_extra_ops() {
    OpCounts o;
    o.mul = 1;
    o.cmp = 1;
    return o;
  }

  // Evaluator and format for reports, e.g. "V(d) P2 fx16 (u0.16/s3.15/u1.15)".
  std::string name() const;
  // The format alone, e.g. "fx16 (u0.16/s3.15/u1.15)" or "float".
  std::string arithmetic() const;

  // Item: one cut-off W(d) (one texel cut by one edge).
  OpCounts ops_per_item() const;
  OpCounts critical_path() const;
  TimingSpec timing(const TechTable& tech) const;

 private:
  Config cfg_;
};

}  // namespace texsim
