#pragma once
// V(d) evaluator with the seed's quadratic P2(d) = 0.5 + 2.151·d − 2.358·d² in Horner form
// (2 mul, 2 add): models the thesis's fig. 6a block; derived in docs/derivations/vd-evaluators.md.
// Arithmetic: the format's type throughout (float, double, or u0.F input / s3.F coefficients
// and intermediates / u1.F output, each product rounded once, HalfUp, saturating).
#include <cstdint>
#include <string>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/subtexel/vd_evaluator_common.h"
#include "blocks/texture/subtexel/vd_evaluator_params.h"

namespace texsim {

class VdEvaluatorP2 {
 public:
  static constexpr VdEvaluatorKind kKind = VdEvaluatorKind::P2;

  using Config = VdEvaluatorConfig;

  VdEvaluatorP2() = default;
  explicit VdEvaluatorP2(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // V(d) ≈ (c2·d + c1)·d + c0 for d ∈ [0, 0.5] (outside it, the same polynomial).
  template <class Fmt>
  typename Fmt::Out eval(typename Fmt::In d) const {
    using A = typename Fmt::Acc;
    const auto& c = VdCoefficientsIn<Fmt>::get();
    A t = vd_detail::mul<A>(c.p2[2], d);
    t = vd_detail::add<A>(t, c.p2[1]);
    t = vd_detail::mul<A>(t, d);
    t = vd_detail::add<A>(t, c.p2[0]);
    return vd_detail::cast<typename Fmt::Out>(t);
  }

  // Operations per evaluation; the datapath instantiates each once per lane, all in series.
  // Item: one evaluation of V(d).
  static constexpr OpCounts ops_per_item() {
    OpCounts o;
    o.mul = 2;
    o.add = 2;
    return o;
  }
  static constexpr OpCounts critical_path() { return ops_per_item(); }
  // Fully pipelined: one evaluation per cycle per lane.
  TimingSpec timing(const TechTable& tech) const {
    return vd_pipelined_timing(tech, ops_per_item(), critical_path(), cfg_.lanes);
  }
  static std::string name() { return vd_evaluator_report_name(kKind); }
  // The format is the caller\'s Fmt (float, double or a fixed u0.F/s3.F/u1.F set).
  static std::string arithmetic() { return "per-call format"; }

 private:
  Config cfg_;
};

static_assert(Block<VdEvaluatorP2>);

}  // namespace texsim
