#include "blocks/texture/subtexel/subtexel_cutoff.h"

#include <cmath>
#include <vector>

#include "blocks/base/block.h"

namespace texsim {

static_assert(Block<SubtexelCutoff>);

namespace {

// The parts around the evaluator: |d| (sign test + negate), clamp to 0.5, V̂ = min(V̂, V̂(0.5)),
// combine with the constant V(0.5) or V(0.5) − 1 (select + add).
OpCounts wrapper_ops() {
  OpCounts o;
  o.cmp = 1 + 1 + 1 + 1;
  o.add = 1 + 1;
  return o;
}

}  // namespace

SubtexelCutoff::Config SubtexelCutoff::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"evaluator", "format", "lanes"});
  Config c;
  const std::vector<std::string_view> evs(kVdEvaluatorNames.begin(), kVdEvaluatorNames.end());
  c.evaluator =
      static_cast<VdEvaluatorKind>(r.get_choice("evaluator", static_cast<int>(c.evaluator), evs));
  c.format =
      kVdFormats.at(r.get_choice("format", kVdFormats.index_of(c.format), kVdFormats.key_list()));
  c.lanes = static_cast<uint32_t>(r.get_int("lanes", c.lanes, 1, 64));
  return c;
}

double SubtexelCutoff::weight(double d) const {
  return visit_vd_format(cfg_.format, [&](auto fmt) {
    using Fmt = decltype(fmt);
    using SIn = typename Fmt::SIn;
    return to_double(weight<Fmt>(vd_detail::quantize<SIn>(static_cast<long double>(d))));
  });
}

double SubtexelCutoff::fraction(double d) const {
  return visit_vd_format(cfg_.format, [&](auto fmt) {
    using Fmt = decltype(fmt);
    const Fraction<Fmt> frac(*this);
    return to_double(frac(vd_detail::quantize<typename Fmt::SIn>(static_cast<long double>(d))));
  });
}

std::string SubtexelCutoff::name() const {
  return vd_evaluator_report_name(cfg_.evaluator) + " " + arithmetic();
}

std::string SubtexelCutoff::arithmetic() const {
  std::string s(kVdFormats.key_of(cfg_.format));
  if (cfg_.format != NumberFormat::Float && cfg_.format != NumberFormat::Double) {
    s += " (" + visit_vd_format(cfg_.format, [](auto fmt) { return decltype(fmt)::name(); }) + ")";
  }
  return s;
}

OpCounts SubtexelCutoff::ops_per_item() const {
  return visit_vd_evaluator(cfg_.evaluator,
                            [](auto ev) { return ev.ops_per_item() + wrapper_ops(); });
}

OpCounts SubtexelCutoff::critical_path() const {
  // Sign test → negate → clamp → evaluator → min → add; the constant select runs beside.
  OpCounts w = wrapper_ops();
  w.cmp -= 1;
  return visit_vd_evaluator(cfg_.evaluator, [&](auto ev) { return ev.critical_path() + w; });
}

TimingSpec SubtexelCutoff::timing(const TechTable& tech) const {
  // V(0.5) is a constant register per evaluator kind, not a second evaluator.
  return derive_timing(tech, ops_per_item(), critical_path(), Datapath::Spatial, cfg_.lanes);
}

}  // namespace texsim
