// Sub-texel cut-off volume block: W = V(0.5) − V(d) with V(−d) = 1 − V(d), on each V(d)
// evaluator and number format — end points, clamps, symmetry jump at d = 0, monotonicity,
// and its error against the exact volume bounded by the evaluator's measured error.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "blocks/base/input_error.h"
#include "blocks/texture/subtexel/subtexel_cutoff.h"
#include "pipeline/studies/study_vd.h"

namespace texsim {
namespace {

using S = VdSeedCoefficients;

SubtexelCutoff make(VdEvaluatorKind k, NumberFormat f = NumberFormat::Double) {
  SubtexelCutoff::Config c;
  c.evaluator = k;
  c.format = f;
  return SubtexelCutoff(c);
}

template <class Fmt>
void check_endpoints_and_sign(VdEvaluatorKind k) {
  using SIn = typename Fmt::SIn;
  using In = typename Fmt::In;
  const SubtexelCutoff cut = make(k);
  const double v_half = visit_vd_evaluator(
      k, [](auto ev) { return to_double(ev.template eval<Fmt>(vd_detail::quantize<In>(0.5L))); });
  const std::string what = std::string(vd_evaluator_name(k)) + " " + Fmt::name();
  EXPECT_EQ(to_double(cut.weight<Fmt>(vd_detail::quantize<SIn>(0.5L))), 0.0) << what;
  // Wholly inside: 2·V̂(0.5) − 1 (exact in every format: one subtraction of representable values).
  EXPECT_NEAR(to_double(cut.full_weight<Fmt>()), 2 * v_half - 1, 1e-6) << what;
  // Beyond ±0.5 the weight clamps to the end values.
  EXPECT_EQ(to_double(cut.weight<Fmt>(vd_detail::quantize<SIn>(0.75L))), 0.0) << what;
  EXPECT_EQ(cut.weight<Fmt>(vd_detail::quantize<SIn>(-0.75L)), cut.full_weight<Fmt>()) << what;
  // Never negative, never above the full weight, over a dense sweep of [−0.5, 0.5].
  const double full = to_double(cut.full_weight<Fmt>());
  for (int i = -20000; i <= 20000; ++i) {
    const double w = to_double(cut.weight<Fmt>(vd_detail::quantize<SIn>(0.5L * i / 20000)));
    ASSERT_GE(w, 0.0) << what << " i " << i;
    ASSERT_LE(w, full + 1e-12) << what << " i " << i;
  }
}

TEST(SubtexelCutoff, EndpointsClampsAndSign) {
  for (VdEvaluatorKind k : kVdEvaluatorKinds) {
    check_endpoints_and_sign<VdFloatFormat<float>>(k);
    check_endpoints_and_sign<VdFloatFormat<double>>(k);
    check_endpoints_and_sign<VdFx16>(k);
    check_endpoints_and_sign<VdFx12>(k);
    check_endpoints_and_sign<VdFx8>(k);
  }
}

TEST(SubtexelCutoff, NonFiniteInputs) {
  using D = VdFloatFormat<double>;
  using F = VdFloatFormat<float>;
  for (VdEvaluatorKind k : kVdEvaluatorKinds) {
    const SubtexelCutoff cut = make(k);
    EXPECT_EQ(cut.weight<D>(std::numeric_limits<double>::quiet_NaN()), 0.0);
    EXPECT_EQ(cut.weight<D>(std::numeric_limits<double>::infinity()), 0.0);
    EXPECT_EQ(cut.weight<D>(-std::numeric_limits<double>::infinity()), cut.full_weight<D>());
    EXPECT_EQ(cut.weight<F>(std::numeric_limits<float>::quiet_NaN()), 0.0f);
    // Fixed inputs cannot be NaN; the conversion saturates huge values to the clamp.
    EXPECT_EQ(cut.weight<VdFx16>(VdFx16::SIn(1e30)).to_double(), 0.0);
    EXPECT_EQ(cut.weight<VdFx16>(VdFx16::SIn(-1e30)), cut.full_weight<VdFx16>());
  }
}

// The symmetric extension has a step at d = 0 of 2·V̂(0) − 1 wherever V̂(0) ≠ 0.5 (P3: 0.496,
// P1: 0.506): a texel whose centre lies on the edge gets two different weights.
TEST(SubtexelCutoff, JumpAtZeroIsTwiceTheOffsetOfVAtZero) {
  const double expect[] = {0.0, 2 * S::kP3[0] - 1, 2 * S::kP2[0] - 1, 2 * S::kP1[0][0] - 1};
  for (size_t i = 0; i < kVdEvaluatorKinds.size(); ++i) {
    const auto k = kVdEvaluatorKinds[i];
    const auto dbl = measure_cutoff_error(k, NumberFormat::Double);
    EXPECT_NEAR(dbl.jump_at_zero, expect[i], 1e-12) << vd_evaluator_name(k);
    const auto fx = measure_cutoff_error(k, NumberFormat::Fx16);
    // One input LSB away from 0 the slope (≤ 2.3) adds at most 2.3 · 2^-16 to the step.
    EXPECT_NEAR(fx.jump_at_zero, expect[i], 2.3 / 65536 + 2 * VdFx16::Out::lsb())
        << vd_evaluator_name(k);
  }
  EXPECT_NE(expect[1], 0.0);
  EXPECT_NE(expect[3], 0.0);
}

// W's error is the difference of two V errors, so at most twice the evaluator's max error.
TEST(SubtexelCutoff, ErrorBoundedByTwiceTheEvaluatorError) {
  for (VdEvaluatorKind k : kVdEvaluatorKinds) {
    for (NumberFormat f : {NumberFormat::Double, NumberFormat::Fx16}) {
      const auto v = measure_vd_error(k, f, 1'000'000);
      const auto w = measure_cutoff_error(k, f);
      EXPECT_LE(w.max_abs, 2 * v.max_abs + 1e-12)
          << vd_evaluator_name(k) << " " << static_cast<int>(f);
      EXPECT_GT(w.points, 60000u);
    }
  }
}

// P2 and P3 turn down before d = 0.5 (P2' = 0 at d = −c1/(2·c2) ≈ 0.456, P3' = 0 near 0.479), so
// V̂(0.5) − V̂(d) would go negative there; the block clamps V̂ to V̂(0.5). P2's dip is
// c2·(0.5 − d*)².
TEST(SubtexelCutoff, NegativeVolumeBeforeClampMatchesPolynomialShape) {
  const double dstar = -S::kP2[1] / (2 * S::kP2[2]);
  const double p2_dip = S::kP2[2] * (0.5 - dstar) * (0.5 - dstar);
  EXPECT_NEAR(measure_cutoff_error(VdEvaluatorKind::P2, NumberFormat::Double).min_unclamped, p2_dip,
              1e-8);
  // P3: the dip from the cubic's stationary point in [0, 0.5].
  const double a = 3 * S::kP3[3], b = 2 * S::kP3[2], c = S::kP3[1];
  const double r = (-b - std::sqrt(b * b - 4 * a * c)) / (2 * a);
  ASSERT_GT(r, 0.45);
  ASSERT_LT(r, 0.5);
  auto p3 = [](double d) { return S::kP3[0] + d * (S::kP3[1] + d * (S::kP3[2] + d * S::kP3[3])); };
  EXPECT_NEAR(measure_cutoff_error(VdEvaluatorKind::P3, NumberFormat::Double).min_unclamped,
              p3(0.5) - p3(r), 1e-8);
  EXPECT_LT(p3(0.5) - p3(r), 0.0);
  EXPECT_GE(measure_cutoff_error(VdEvaluatorKind::Exact, NumberFormat::Double).min_unclamped, 0.0);
  EXPECT_GE(measure_cutoff_error(VdEvaluatorKind::P1, NumberFormat::Double).min_unclamped, 0.0);
}

// W never increases with d, except for P1 at its second breakpoint (on both sides of the
// centre), where V̂ drops by (0.636 + 1.008·0.305) − (0.853 + 0.295·0.305). In fixed point a
// polynomial's rounded value may also step back by one output LSB where its slope is below
// one LSB per input code (near the peaks of P2 and P3).
template <class Fmt>
void check_monotone(int64_t n, double wiggle) {
  using SIn = typename Fmt::SIn;
  const double p1_rise =
      (S::kP1[1][0] + S::kP1[1][1] * 0.305) - (S::kP1[2][0] + S::kP1[2][1] * 0.305);
  ASSERT_GT(p1_rise, 0.0);
  for (VdEvaluatorKind k : kVdEvaluatorKinds) {
    const SubtexelCutoff cut = make(k);
    double max_rise = 0, at = 0, p1_max = 0;
    // Within each side of 0 (the step at 0 is the other test's subject).
    for (int side : {-1, 1}) {
      auto input = [&](int64_t i) {
        return vd_detail::quantize<SIn>(0.5L * static_cast<long double>(i) / n);
      };
      const int64_t first = side < 0 ? -n : 1, stop = side < 0 ? -1 : n;
      double prev = to_double(cut.weight<Fmt>(input(first)));
      for (int64_t i = first + 1; i <= stop; ++i) {
        const double x = 0.5 * static_cast<double>(i) / static_cast<double>(n);
        const double w = to_double(cut.weight<Fmt>(input(i)));
        const bool at_break = std::fabs(std::fabs(x) - 0.305) <= 1.0 / static_cast<double>(n);
        if (k == VdEvaluatorKind::P1 && at_break) {
          p1_max = std::max(p1_max, w - prev);
        } else if (w - prev > max_rise) {
          max_rise = w - prev;
          at = x;
        }
        prev = w;
      }
    }
    EXPECT_LE(max_rise, wiggle) << vd_evaluator_name(k) << " " << Fmt::name() << " at " << at;
    if (k == VdEvaluatorKind::P1) {
      EXPECT_NEAR(p1_max, p1_rise, 2 * wiggle + 2 * 0.295 / static_cast<double>(n)) << Fmt::name();
    }
  }
}

TEST(SubtexelCutoff, MonotoneExceptP1Breakpoint) {
  check_monotone<VdFx16>(32768, VdFx16::Out::lsb());
  check_monotone<VdFx12>(2048, VdFx12::Out::lsb());
  check_monotone<VdFloatFormat<double>>(200000, 4e-16);
}

TEST(SubtexelCutoff, RuntimeFormatMatchesTemplate) {
  for (VdEvaluatorKind k : kVdEvaluatorKinds) {
    for (double d : {-0.6, -0.31, -0.1, 0.0, 0.04, 0.2, 0.4999, 0.7}) {
      EXPECT_EQ(make(k, NumberFormat::Fx16).weight(d),
                make(k).weight<VdFx16>(VdFx16::SIn(d)).to_double());
      EXPECT_EQ(make(k, NumberFormat::Fx8).weight(d),
                make(k).weight<VdFx8>(VdFx8::SIn(d)).to_double());
      EXPECT_EQ(make(k, NumberFormat::Float).weight(d),
                static_cast<double>(make(k).weight<VdFloatFormat<float>>(static_cast<float>(d))));
      EXPECT_EQ(make(k, NumberFormat::Double).weight(d), make(k).weight<VdFloatFormat<double>>(d));
    }
  }
}

TEST(SubtexelCutoff, OpsAndTiming) {
  TechTable t = TechTable::defaults();
  for (VdEvaluatorKind k : kVdEvaluatorKinds) {
    const SubtexelCutoff cut = make(k);
    const OpCounts ev = visit_vd_evaluator(k, [](auto e) { return e.ops_per_item(); });
    const OpCounts evp = visit_vd_evaluator(k, [](auto e) { return e.critical_path(); });
    EXPECT_EQ(cut.ops_per_item().mul, ev.mul);
    EXPECT_EQ(cut.ops_per_item().lut, ev.lut);
    EXPECT_EQ(cut.ops_per_item().add, ev.add + 2);
    EXPECT_EQ(cut.ops_per_item().cmp, ev.cmp + 4);
    const double path = t.path_latency(evp) + 2 * t.lat(OpKind::Add) + 3 * t.lat(OpKind::Cmp);
    EXPECT_EQ(cut.timing(t).latency, static_cast<uint32_t>(std::ceil(path)));
    EXPECT_DOUBLE_EQ(cut.timing(t).area, t.area_of(cut.ops_per_item()));
  }
}

TEST(SubtexelCutoff, ConfigFromToml) {
  toml::table ok =
      toml::parse(std::string_view("evaluator = \"p1\"\nformat = \"fx12\"\nlanes = 2\n"),
                  std::string_view("s.toml"));
  const auto c = SubtexelCutoff::Config::from_toml(ConfigReader(ok, "s.toml", "subtexel"));
  EXPECT_EQ(c.evaluator, VdEvaluatorKind::P1);
  EXPECT_EQ(c.format, NumberFormat::Fx12);
  EXPECT_EQ(c.lanes, 2u);
  toml::table bad =
      toml::parse(std::string_view("evaluator = \"p4\"\n"), std::string_view("s.toml"));
  try {
    SubtexelCutoff::Config::from_toml(ConfigReader(bad, "s.toml", "subtexel"));
    FAIL() << "unknown evaluator accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("evaluator"), std::string::npos);
  }
  toml::table typo = toml::parse(std::string_view("sigma = 0.3\n"), std::string_view("s.toml"));
  EXPECT_THROW(SubtexelCutoff::Config::from_toml(ConfigReader(typo, "s.toml", "subtexel")),
               InputError);
}

}  // namespace
}  // namespace texsim
