#pragma once
// V(d) evaluator with the seed's piecewise-linear P1: two comparators pick one of three
// (offset, slope) pairs, then 1 mul + 1 add; models the thesis's fig. 6b block
// (docs/derivations/vd-evaluators.md). Arithmetic: as P2 (the format's types, HalfUp, saturating).
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

class VdEvaluatorP1 {
 public:
  static constexpr VdEvaluatorKind kKind = VdEvaluatorKind::P1;

  using Config = VdEvaluatorConfig;

  VdEvaluatorP1() = default;
  explicit VdEvaluatorP1(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // Segment of d: 0 on [0, 0.165), 1 on [0.165, 0.305), 2 from 0.305 on. The thresholds are
  // rounded up into the input format so the decision equals the real-number one.
  template <class Fmt>
  static int segment(typename Fmt::In d) {
    const auto& c = VdCoefficientsIn<Fmt>::get();
    return d < c.p1_break[0] ? 0 : (d < c.p1_break[1] ? 1 : 2);
  }

  template <class Fmt>
  typename Fmt::Out eval(typename Fmt::In d) const {
    using A = typename Fmt::Acc;
    const auto& c = VdCoefficientsIn<Fmt>::get();
    const auto& seg = c.p1[static_cast<size_t>(segment<Fmt>(d))];
    const A t = vd_detail::mul<A>(seg[1], d);
    return vd_detail::cast<typename Fmt::Out>(vd_detail::add<A>(t, seg[0]));
  }

  // Item: one evaluation of V(d).
  static constexpr OpCounts ops_per_item() {
    OpCounts o;
    o.cmp = 3;  // two comparators (in parallel) + the coefficient-pair select
    o.mul = 1;
    o.add = 1;
    return o;
  }
  // Comparator, select, multiply, add in series (the two comparators work side by side).
  static constexpr OpCounts critical_path() {
    OpCounts o = ops_per_item();
    o.cmp = 2;
    return o;
  }
  TimingSpec timing(const TechTable& tech) const {
    return vd_pipelined_timing(tech, ops_per_item(), critical_path(), cfg_.lanes);
  }
  static std::string name() { return vd_evaluator_report_name(kKind); }
  // The format is the caller\'s Fmt (float, double or a fixed u0.F/s3.F/u1.F set).
  static std::string arithmetic() { return "per-call format"; }

 private:
  Config cfg_;
};

static_assert(Block<VdEvaluatorP1>);

}  // namespace texsim
