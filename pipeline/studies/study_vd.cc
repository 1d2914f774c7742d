#include "pipeline/studies/study_vd.h"

#include <mpfr.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <sstream>
#include <vector>

#include "blocks/base/tech_table.h"
#include "blocks/texture/subtexel/subtexel_cutoff.h"
#include "pipeline/kernel/parallel_range.h"
#include "pipeline/report/plot.h"
#include "pipeline/studies/study_table.h"

namespace texsim {

long double vd_reference(long double d) {
  return 0.5L * std::erfc(-d * VdSeedCoefficients::kInvSigmaSqrt2);
}

long double vd_reference_mpfr(long double d) {
  mpfr_t x, k, r;
  mpfr_inits2(160, x, k, r, static_cast<mpfr_ptr>(nullptr));
  mpfr_sqrt_ui(k, 2, MPFR_RNDN);
  mpfr_ui_div(k, 5, k, MPFR_RNDN);  // 1/(σ√2) with σ = 1/5 exactly
  mpfr_set_ld(x, d, MPFR_RNDN);     // exact: d is a long double
  mpfr_mul(x, x, k, MPFR_RNDN);
  mpfr_neg(x, x, MPFR_RNDN);
  mpfr_erfc(r, x, MPFR_RNDN);
  mpfr_div_2ui(r, r, 1, MPFR_RNDN);
  const long double v = mpfr_get_ld(r, MPFR_RNDN);
  mpfr_clears(x, k, r, static_cast<mpfr_ptr>(nullptr));
  return v;
}

namespace {

// Running maximum of |err| with its first arg max, and the mean over counted points.
struct ErrAcc {
  long double max_abs = -1;
  long double argmax = 0;
  long double sum = 0;
  uint64_t counted = 0;  // points in the mean
  uint64_t evaluated = 0;
  void add(long double d, long double err, bool in_mean) {
    const long double a = std::fabs(err);
    if (a > max_abs) {
      max_abs = a;
      argmax = d;
    }
    if (in_mean) {
      sum += a;
      ++counted;
    }
    ++evaluated;
  }
};

template <class Ev, class Fmt>
long double value_at(long double d) {
  using In = typename Fmt::In;
  return static_cast<long double>(to_double(Ev{}.template eval<Fmt>(vd_detail::quantize<In>(d))));
}

// Final figures: the maximum re-evaluated against MPFR at the arg max.
template <class Ev, class Fmt>
VdErrorStats finish(const ErrAcc& acc, NumberFormat f, std::string sweep) {
  VdErrorStats s;
  s.evaluator = Ev::kKind;
  s.format = f;
  s.argmax_d = static_cast<double>(acc.argmax);
  const long double v = value_at<Ev, Fmt>(acc.argmax);
  s.signed_at_max = static_cast<double>(v - vd_reference_mpfr(acc.argmax));
  s.max_abs = std::fabs(s.signed_at_max);
  s.mean_abs =
      acc.counted ? static_cast<double>(acc.sum / static_cast<long double>(acc.counted)) : 0;
  s.points = acc.evaluated;
  s.sweep = std::move(sweep);
  return s;
}

template <class Ev, class Fmt>
VdErrorStats measure_typed(NumberFormat f, uint64_t grid) {
  using In = typename Fmt::In;
  const Ev ev;
  ErrAcc acc;
  if constexpr (is_fixed_v<In>) {
    const int64_t last = int64_t{1} << (In::kFracBits - 1);  // the code of 0.5
    for (int64_t code = 0; code <= last; ++code) {
      const In d = In::from_raw(code);
      const long double x = static_cast<long double>(d.to_double());
      const long double v = static_cast<long double>(to_double(ev.template eval<Fmt>(d)));
      acc.add(x, v - vd_reference(x), true);
    }
    return finish<Ev, Fmt>(acc, f, "every code in [0, 0.5] (" + std::to_string(last + 1) + ")");
  } else {
    for (uint64_t i = 0; i <= grid; ++i) {
      const In d =
          static_cast<In>(0.5L * static_cast<long double>(i) / static_cast<long double>(grid));
      const long double x = static_cast<long double>(d);
      acc.add(x, static_cast<long double>(ev.template eval<Fmt>(d)) - vd_reference(x), true);
    }
    // Every representable input within 2^20 steps of the grid's arg max.
    const In centre = static_cast<In>(acc.argmax);
    const In lo = 0, hi = static_cast<In>(0.5);
    constexpr int kSteps = 1 << 20;
    for (int dir : {-1, 1}) {
      In d = centre;
      const In target = dir < 0 ? lo : hi;
      for (int s = 0; s < kSteps && d != target; ++s) {
        d = std::nextafter(d, target);
        const long double x = static_cast<long double>(d);
        acc.add(x, static_cast<long double>(ev.template eval<Fmt>(d)) - vd_reference(x), false);
      }
    }
    return finish<Ev, Fmt>(acc, f,
                           "grid of " + std::to_string(grid + 1) + " + every " + format_name<In>() +
                               " within 2^20 steps of its arg max");
  }
}

std::string fmt_g(double v, int prec = 4) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}

std::string fmt_e(double v, int prec = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*e", prec, v);
  return buf;
}

std::string format_label(NumberFormat f) {
  return visit_vd_format(f, [](auto fmt) { return decltype(fmt)::name(); });
}

}  // namespace

VdErrorStats measure_vd_error(VdEvaluatorKind k, NumberFormat f, uint64_t grid) {
  return visit_vd_evaluator(k, [&](auto ev) {
    using Ev = decltype(ev);
    return visit_vd_format(f, [&](auto fmt) { return measure_typed<Ev, decltype(fmt)>(f, grid); });
  });
}

std::array<VdErrorStats, 4> measure_vd_error_all_floats(std::ostream* progress) {
  using Fmt = VdFloatFormat<float>;
  std::array<ErrAcc, 4> acc;
  const VdEvaluatorExact e0;
  const VdEvaluatorP3 e3;
  const VdEvaluatorP2 e2;
  const VdEvaluatorP1 e1;
  const uint32_t last = std::bit_cast<uint32_t>(0.5f);
  const double k = static_cast<double>(VdSeedCoefficients::kInvSigmaSqrt2);
  for (uint32_t b = 0;; ++b) {
    const float d = std::bit_cast<float>(b);
    const double ref = 0.5 * std::erfc(-static_cast<double>(d) * k);
    const long double x = d;
    acc[0].add(x, static_cast<double>(e0.eval<Fmt>(d)) - ref, true);
    acc[1].add(x, static_cast<double>(e3.eval<Fmt>(d)) - ref, true);
    acc[2].add(x, static_cast<double>(e2.eval<Fmt>(d)) - ref, true);
    acc[3].add(x, static_cast<double>(e1.eval<Fmt>(d)) - ref, true);
    if (progress && (b & ((1u << 27) - 1)) == 0)
      *progress << "  float bits " << b << " / " << last << "\n";
    if (b == last) break;
  }
  const std::string sweep = "every float in [0, 0.5] (" + std::to_string(uint64_t{last} + 1) + ")";
  return {finish<VdEvaluatorExact, Fmt>(acc[0], NumberFormat::Float, sweep),
          finish<VdEvaluatorP3, Fmt>(acc[1], NumberFormat::Float, sweep),
          finish<VdEvaluatorP2, Fmt>(acc[2], NumberFormat::Float, sweep),
          finish<VdEvaluatorP1, Fmt>(acc[3], NumberFormat::Float, sweep)};
}

VdSigmaFit vd_best_sigma(VdEvaluatorKind k, double lo, double hi) {
  constexpr int kGrid = 2000;
  constexpr int kSigmas = 400;
  VdSigmaFit best{lo, std::numeric_limits<double>::infinity()};
  std::vector<long double> v(kGrid + 1);
  visit_vd_evaluator(k, [&](auto ev) {
    using Fmt = VdFloatFormat<double>;
    for (int i = 0; i <= kGrid; ++i)
      v[static_cast<size_t>(i)] = ev.template eval<Fmt>(0.5 * i / kGrid);
  });
  for (int s = 0; s <= kSigmas; ++s) {
    const long double sigma = lo + (hi - lo) * s / kSigmas;
    long double m = 0;
    for (int i = 0; i <= kGrid; ++i) {
      const long double d = 0.5L * i / kGrid;
      const long double ref = 0.5L * std::erfc(-d / (sigma * std::sqrt(2.0L)));
      m = std::max(m, std::fabs(v[static_cast<size_t>(i)] - ref));
    }
    if (m < best.max_abs) best = {static_cast<double>(sigma), static_cast<double>(m)};
  }
  return best;
}

double vd_error_vs_texel_normalised(VdEvaluatorKind k) {
  constexpr int kGrid = 2000;
  const long double lo = 1.0L - vd_reference(0.5L);  // Φ(−0.5/σ)
  const long double span = vd_reference(0.5L) - lo;
  long double m = 0;
  visit_vd_evaluator(k, [&](auto ev) {
    for (int i = 0; i <= kGrid; ++i) {
      const double d = 0.5 * i / kGrid;
      const long double ref = (vd_reference(d) - lo) / span;
      m = std::max(
          m, std::fabs(static_cast<long double>(ev.template eval<VdFloatFormat<double>>(d)) - ref));
    }
  });
  return static_cast<double>(m);
}

namespace {

// Solves the n×n system M·x = r (Gaussian elimination, partial pivoting).
std::vector<long double> solve(std::vector<std::vector<long double>> m,
                               std::vector<long double> r) {
  const size_t n = r.size();
  for (size_t i = 0; i < n; ++i) {
    size_t p = i;
    for (size_t j = i + 1; j < n; ++j) {
      if (std::fabs(m[j][i]) > std::fabs(m[p][i])) p = j;
    }
    std::swap(m[i], m[p]);
    std::swap(r[i], r[p]);
    for (size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const long double f = m[j][i] / m[i][i];
      for (size_t c = i; c < n; ++c) m[j][c] -= f * m[i][c];
      r[j] -= f * r[i];
    }
  }
  for (size_t i = 0; i < n; ++i) r[i] /= m[i][i];
  return r;
}

}  // namespace

VdPolyFit vd_minimax_fit(int degree, bool pin_half) {
  const int k0 = pin_half ? 1 : 0;                         // lowest free power
  const size_t nb = static_cast<size_t>(degree + 1 - k0);  // free coefficients
  const size_t n = nb + 1;                                 // reference points (with the level E)
  const long double c0 = pin_half ? 0.5L : 0.0L;
  constexpr int kGrid = 20000;
  std::vector<long double> g, target;
  for (int i = pin_half ? 1 : 0; i <= kGrid; ++i) {  // pinned: the error at 0 is 0 by design
    g.push_back(0.5L * i / kGrid);
    target.push_back(vd_reference(g.back()) - c0);
  }
  std::vector<size_t> ref(n);
  for (size_t i = 0; i < n; ++i) {  // Chebyshev-like start
    const long double t =
        0.5L - 0.5L * std::cos(3.14159265358979323846L * static_cast<long double>(i) /
                               static_cast<long double>(n - 1));
    ref[i] = static_cast<size_t>(std::lround(t * static_cast<long double>(g.size() - 1)));
  }
  std::vector<long double> coef(nb, 0.0L), err(g.size());
  auto poly = [&](long double d) {
    long double s = 0, p = k0 ? d : 1.0L;
    for (size_t j = 0; j < nb; ++j, p *= d) s += coef[j] * p;
    return s;
  };
  for (int iter = 0; iter < 60; ++iter) {
    std::vector<std::vector<long double>> m(n, std::vector<long double>(n));
    std::vector<long double> r(n);
    for (size_t i = 0; i < n; ++i) {
      long double p = k0 ? g[ref[i]] : 1.0L;
      for (size_t j = 0; j < nb; ++j, p *= g[ref[i]]) m[i][j] = p;
      m[i][nb] = (i % 2) ? -1.0L : 1.0L;
      r[i] = target[ref[i]];
    }
    const auto x = solve(m, r);
    for (size_t j = 0; j < nb; ++j) coef[j] = x[j];
    for (size_t i = 0; i < g.size(); ++i) err[i] = poly(g[i]) - target[i];
    // Exchange: local extrema of the error (and the end points), alternating in sign.
    std::vector<size_t> ext;
    for (size_t i = 0; i < g.size(); ++i) {
      const bool left = i == 0 || std::fabs(err[i]) >= std::fabs(err[i - 1]);
      const bool right = i + 1 == g.size() || std::fabs(err[i]) >= std::fabs(err[i + 1]);
      if (!(left && right)) continue;
      if (!ext.empty() && (err[i] > 0) == (err[ext.back()] > 0)) {
        if (std::fabs(err[i]) > std::fabs(err[ext.back()])) ext.back() = i;
      } else {
        ext.push_back(i);
      }
    }
    while (ext.size() > n) {
      if (std::fabs(err[ext.front()]) < std::fabs(err[ext.back()]))
        ext.erase(ext.begin());
      else
        ext.pop_back();
    }
    if (ext.size() < n || ext == ref) break;
    ref = ext;
  }
  VdPolyFit fit;
  fit.coef.assign(static_cast<size_t>(degree) + 1, 0.0);
  fit.coef[0] = static_cast<double>(c0);
  for (size_t j = 0; j < nb; ++j)
    fit.coef[j + static_cast<size_t>(k0)] = static_cast<double>(coef[j]);
  for (int i = 0; i <= 200000; ++i) {
    const long double d = 0.5L * i / 200000;
    long double v = 0, p = 1;
    for (double c : fit.coef) {
      v += c * p;
      p *= d;
    }
    const double e = static_cast<double>(std::fabs(v - vd_reference(d)));
    if (e > fit.max_abs) {
      fit.max_abs = e;
      fit.argmax_d = static_cast<double>(d);
    }
  }
  return fit;
}

CutoffErrorStats measure_cutoff_error(VdEvaluatorKind k, NumberFormat f) {
  SubtexelCutoff::Config cfg;
  cfg.evaluator = k;
  const SubtexelCutoff cut(cfg);
  const long double w_ref_half = vd_reference(0.5L);
  CutoffErrorStats st;
  st.min_unclamped = std::numeric_limits<double>::infinity();
  visit_vd_format(f, [&](auto fmt) {
    using Fmt = decltype(fmt);
    using SIn = typename Fmt::SIn;
    using In = typename Fmt::In;
    auto visit = [&](SIn d) {
      const long double x = static_cast<long double>(to_double(d));
      const long double w = static_cast<long double>(to_double(cut.weight<Fmt>(d)));
      const long double err = std::fabs(w - (w_ref_half - vd_reference(x)));
      if (err > st.max_abs) {
        st.max_abs = static_cast<double>(err);
        st.argmax_d = static_cast<double>(x);
      }
      ++st.points;
    };
    SIn minus_tiny;
    if constexpr (is_fixed_v<SIn>) {
      const int64_t half = int64_t{1} << (SIn::kFracBits - 1);
      for (int64_t c = -half; c <= half; ++c) visit(SIn::from_raw(c));
      minus_tiny = SIn::from_raw(-1);
    } else {
      constexpr int64_t kN = 1'000'000;
      for (int64_t i = -kN; i <= kN; ++i)
        visit(static_cast<SIn>(0.5L * static_cast<long double>(i) / kN));
      minus_tiny = -std::numeric_limits<SIn>::denorm_min();
    }
    st.jump_at_zero = to_double(cut.weight<Fmt>(minus_tiny)) -
                      to_double(cut.weight<Fmt>(vd_detail::quantize<SIn>(0.0L)));
    // Before the clamp: V̂(0.5) − V̂(d) on every input code / a fine grid of [0, 0.5].
    visit_vd_evaluator(k, [&](auto ev) {
      const long double vh = to_double(ev.template eval<Fmt>(vd_detail::quantize<In>(0.5L)));
      constexpr int64_t kM = 200'000;
      for (int64_t i = 0; i <= kM; ++i) {
        const In d = vd_detail::quantize<In>(0.5L * static_cast<long double>(i) / kM);
        const double w = static_cast<double>(vh - to_double(ev.template eval<Fmt>(d)));
        st.min_unclamped = std::min(st.min_unclamped, w);
      }
    });
  });
  return st;
}

namespace {

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

struct VdRow {
  VdErrorStats s;
  OpCounts ops;
  TimingSpec timing;
  std::optional<double> claim;
};

std::vector<VdRow> measure_vd_rows(const TechTable& tech, std::ostream& log, int threads) {
  // One task per evaluator × format, each filling its own row; logged in order afterwards.
  const size_t nf = kVdFormatKinds.size();
  std::vector<VdRow> rows(kVdEvaluatorKinds.size() * nf);
  parallel_tasks(rows.size(), threads, [&](size_t i) {
    const VdEvaluatorKind k = kVdEvaluatorKinds[i / nf];
    VdRow& r = rows[i];
    r.s = measure_vd_error(k, kVdFormatKinds[i % nf]);
    visit_vd_evaluator(k, [&](auto ev) {
      r.ops = ev.ops_per_item();
      r.timing = ev.timing(tech);
    });
    r.claim = vd_seed_claim(k);
  });
  for (const VdRow& r : rows) {
    log << "  vd " << vd_evaluator_name(r.s.evaluator) << " " << format_label(r.s.format)
        << ": max " << fmt_e(r.s.max_abs) << " at d = " << fmt_g(r.s.argmax_d, 8) << "\n";
  }
  return rows;
}

StudyTable vd_csv(const std::vector<VdRow>& rows) {
  StudyTable t({"evaluator", "format", "max_abs_err", "argmax_d", "signed_err_at_max",
                "mean_abs_err", "points", "sweep", "add", "mul", "cmp", "lut", "latency_cycles",
                "area", "seed_claim", "claim_holds"});
  for (const VdRow& r : rows) {
    t.add({std::string(vd_evaluator_name(r.s.evaluator)), format_label(r.s.format),
           fmt_e(r.s.max_abs, 6), fmt_g(r.s.argmax_d, 10), fmt_e(r.s.signed_at_max, 6),
           fmt_e(r.s.mean_abs, 6), std::to_string(r.s.points), "\"" + r.s.sweep + "\"",
           std::to_string(r.ops.add), std::to_string(r.ops.mul), std::to_string(r.ops.cmp),
           std::to_string(r.ops.lut), std::to_string(r.timing.latency), num(r.timing.area),
           r.claim ? num(*r.claim) : "", r.claim ? (r.s.max_abs <= *r.claim ? "yes" : "no") : ""});
  }
  return t;
}

std::string vd_error_section(const std::vector<VdRow>& rows) {
  StudyTable t({"evaluator", "format", "max abs error", "at d", "mean abs error", "inputs", "add",
                "mul", "cmp", "lut", "latency (cycles)", "area", "seed claim", "holds"});
  for (const VdRow& r : rows) {
    t.add({std::string(vd_evaluator_name(r.s.evaluator)), format_label(r.s.format),
           fmt_e(r.s.max_abs), fmt_g(r.s.argmax_d, 6), fmt_e(r.s.mean_abs),
           std::to_string(r.s.points), std::to_string(r.ops.add), std::to_string(r.ops.mul),
           std::to_string(r.ops.cmp), std::to_string(r.ops.lut), std::to_string(r.timing.latency),
           fmt_g(r.timing.area), r.claim ? fmt_g(*r.claim, 2) : "—",
           r.claim ? (r.s.max_abs <= *r.claim ? "yes" : "**no**") : "—"});
  }
  std::ostringstream o;
  o << "# V(d) evaluators: measured error against Φ(d/σ), σ = 0.2, d ∈ [0, 0.5]\n\n"
    << "Reference: Φ(d/σ) = erfc(−d/(σ√2))/2 in long double; each maximum re-evaluated with "
       "MPFR (160 bits) at its arg max. Fixed formats are named input/coefficients/output "
       "(HalfUp rounding, saturation). Ops per evaluation; latency and area from the default "
       "technology table (area does not scale with word width there).\n\n"
    << t.markdown();
  o << "\nSweeps: fixed formats — every input code in [0, 0.5]; float/double — ";
  for (const VdRow& r : rows) {
    if (r.s.format == NumberFormat::Float) {
      o << r.s.sweep << ".\n\n";
      break;
    }
  }
  return o.str();
}

// Which σ the seed's coefficients fit, and minimax refits on the same datapath.
std::string vd_fit_section(const std::vector<VdRow>& rows) {
  StudyTable fits(
      {"evaluator", "best σ", "max abs error at best σ", "max abs error vs texel-normalised"});
  for (VdEvaluatorKind k : {VdEvaluatorKind::P3, VdEvaluatorKind::P2, VdEvaluatorKind::P1}) {
    const VdSigmaFit sigma = vd_best_sigma(k);
    fits.add({std::string(vd_evaluator_name(k)), fmt_g(sigma.sigma, 5), fmt_e(sigma.max_abs),
              fmt_e(vd_error_vs_texel_normalised(k))});
  }
  struct Refit {
    std::string what;
    VdEvaluatorKind seed;
    VdPolyFit fit;
  };
  const std::vector<Refit> refits = {
      {"quadratic, V(0) = 0.5", VdEvaluatorKind::P2, vd_minimax_fit(2, true)},
      {"quadratic, free", VdEvaluatorKind::P2, vd_minimax_fit(2, false)},
      {"cubic, V(0) = 0.5", VdEvaluatorKind::P3, vd_minimax_fit(3, true)},
      {"cubic, free", VdEvaluatorKind::P3, vd_minimax_fit(3, false)},
  };
  StudyTable rt({"polynomial", "coefficients (d⁰, d¹, …)", "max abs error", "at d", "seed's",
                 "seed claim", "refit meets it"});
  for (const Refit& r : refits) {
    std::string cs;
    for (double c : r.fit.coef) cs += (cs.empty() ? "" : ", ") + fmt_g(c, 6);
    const auto seed = std::find_if(rows.begin(), rows.end(), [&](const VdRow& row) {
      return row.s.evaluator == r.seed && row.s.format == NumberFormat::Double;
    });
    const double claim = vd_seed_claim(r.seed).value_or(0);
    rt.add({r.what, cs, fmt_e(r.fit.max_abs), fmt_g(r.fit.argmax_d, 5), fmt_e(seed->s.max_abs),
            fmt_g(claim, 2), r.fit.max_abs <= claim ? "yes" : "no"});
  }
  return "## Which normalisation do the coefficients fit?\n\n"
         "σ minimising each polynomial's maximum error against Φ(d/σ) (σ scanned over "
         "[0.15, 0.25] in steps of 0.00025, 2001-point grid on [0, 0.5], double), and the error "
         "against the texel-normalised volume (Φ(d/σ) − Φ(−0.5/σ)) / (2·Φ(0.5/σ) − 1) at σ = 0.2:"
         "\n\n" +
         fits.markdown() +
         "\n## Refitted coefficients (same datapath, same op counts)\n\n"
         "Minimax polynomials for Φ(d/σ), σ = 0.2, on [0, 0.5] (Remez exchange, long double); "
         "max error on a 200001-point grid, double evaluation. V(0) = 0.5 keeps the symmetric "
         "extension continuous at d = 0.\n\n" +
         rt.markdown();
}

std::string vd_cutoff_section() {
  StudyTable t(
      {"evaluator", "format", "max abs error", "at d", "jump at d = 0", "min before clamp"});
  for (VdEvaluatorKind k : kVdEvaluatorKinds) {
    for (NumberFormat f : {NumberFormat::Double, NumberFormat::Fx16}) {
      const CutoffErrorStats c = measure_cutoff_error(k, f);
      t.add({std::string(vd_evaluator_name(k)), format_label(f), fmt_e(c.max_abs),
             fmt_g(c.argmax_d, 6), fmt_e(c.jump_at_zero), fmt_e(c.min_unclamped)});
    }
  }
  return "\n## Cut-off volume W = V(0.5) − V(d), d ∈ [−0.5, 0.5]\n\n"
         "SubtexelCutoff with each evaluator against the exact Φ(0.5/σ) − Φ(d/σ) (double: grid of "
         "2·10^6 + 1 points; u0.16 format: every s1.16 code). The jump is Ŵ(0⁻) − Ŵ(0⁺) "
         "(= 2·V̂(0) − 1 when V̂(0) ≠ 0.5); min before clamp is the most negative "
         "V̂(0.5) − V̂(d): where the polynomial peaks before d = 0.5 the block clamps V̂ to "
         "V̂(0.5), so W stays within [0, 2·V̂(0.5) − 1].\n\n" +
         t.markdown();
}

// Signed error over d in double, one line per evaluator.
PlotSpec vd_plot() {
  PlotSpec p;
  p.title = "V(d) evaluators: error against Phi(d/0.2), double";
  p.xlabel = "d (texels)";
  p.ylabel = "V(d) - Phi(d/sigma)";
  for (VdEvaluatorKind k : kVdEvaluatorKinds) {
    PlotSeries s;
    s.label = std::string(vd_evaluator_name(k));
    s.lines = true;
    visit_vd_evaluator(k, [&](auto ev) {
      constexpr int kN = 250;
      for (int i = 0; i <= kN; ++i) {
        const double d = 0.5 * i / kN;
        s.x.push_back(d);
        s.y.push_back(static_cast<double>(
            static_cast<long double>(ev.template eval<VdFloatFormat<double>>(d)) -
            vd_reference(d)));
      }
    });
    p.series.push_back(std::move(s));
  }
  return p;
}

}  // namespace

int run_study_vd(const std::string& out_dir, std::ostream& log, int threads) {
  const auto t0 = std::chrono::steady_clock::now();
  const StudyFiles files(out_dir);
  const std::vector<VdRow> rows = measure_vd_rows(TechTable::defaults(), log, threads);
  files.csv("vd.csv", vd_csv(rows));
  files.text("vd.md", vd_error_section(rows) + vd_fit_section(rows) + vd_cutoff_section());
  files.plot("vd.png", vd_plot());
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log << "study vd: wrote " << out_dir << "/vd.csv, vd.md, vd.png in " << fmt_g(secs, 3) << " s\n";
  return 0;
}

}  // namespace texsim
