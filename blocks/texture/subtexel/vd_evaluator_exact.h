#pragma once
// V(d) evaluator computing Φ(d/σ) itself, the reference block against which the seed's
// approximations are weighed (docs/derivations/vd-evaluators.md). In float/double it evaluates erfc
// in that type; in a fixed format it is a ROM holding Φ(d/σ) correctly rounded to the output format
// for every input code (2^(F−1)+1 entries cover [0, 0.5]). Either way one table look-up (lut) per
// evaluation.
#include <cmath>
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

class VdEvaluatorExact {
 public:
  static constexpr VdEvaluatorKind kKind = VdEvaluatorKind::Exact;

  using Config = VdEvaluatorConfig;

  VdEvaluatorExact() = default;
  explicit VdEvaluatorExact(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  template <class Fmt>
  typename Fmt::Out eval(typename Fmt::In d) const {
    using Out = typename Fmt::Out;
    if constexpr (is_fixed_v<Out>) {
      // ROM content: Φ at the code's exact value, rounded once into Out.
      const long double x = static_cast<long double>(d.to_double());
      return vd_detail::quantize<Out>(0.5L * std::erfc(-x * VdSeedCoefficients::kInvSigmaSqrt2));
    } else {
      const Out k = static_cast<Out>(VdSeedCoefficients::kInvSigmaSqrt2);
      return static_cast<Out>(0.5) * std::erfc(-static_cast<Out>(d) * k);
    }
  }

  // Entries of the fixed-format ROM covering d ∈ [0, 0.5] (0 for float/double).
  template <class Fmt>
  static uint64_t rom_entries() {
    if constexpr (is_fixed_v<typename Fmt::In>) {
      return (uint64_t{1} << (Fmt::In::kFracBits - 1)) + 1;
    } else {
      return 0;
    }
  }

  // Item: one evaluation of V(d).
  static constexpr OpCounts ops_per_item() {
    OpCounts o;
    o.lut = 1;
    return o;
  }
  static constexpr OpCounts critical_path() { return ops_per_item(); }
  TimingSpec timing(const TechTable& tech) const {
    return vd_pipelined_timing(tech, ops_per_item(), critical_path(), cfg_.lanes);
  }
  static std::string name() { return vd_evaluator_report_name(kKind); }
  // The format is the caller\'s Fmt (float, double or a fixed u0.F/s3.F/u1.F set).
  static std::string arithmetic() { return "per-call format"; }

 private:
  Config cfg_;
};

static_assert(Block<VdEvaluatorExact>);

}  // namespace texsim
