#include "blocks/texture/footprint/multi_probe_filter.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <type_traits>

#include "blocks/base/block.h"
#include "blocks/texture/sampler/texel_blend.h"
#include "blocks/texture/subtexel/vd_evaluator_params.h"

namespace texsim {

static_assert(Block<MultiProbeFilter>);

MultiProbeFilter::Config MultiProbeFilter::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"alpha", "max_probes", "weight_alpha", "radius_px", "max_aniso", "seed_theta",
                    "temporal", "arith", "address_u", "address_v"});
  Config c;
  c.alpha = r.get_double("alpha", c.alpha);
  if (!(c.alpha >= 0.25) || !(c.alpha <= 16)) r.fail("alpha", "must be in [0.25, 16]");
  c.max_probes = static_cast<int>(r.get_int("max_probes", c.max_probes, 1, ProbeSet::kMax));
  if (c.max_probes % 2 == 0)
    r.fail("max_probes", "must be odd (probes sit symmetrically about the centre)");
  c.weight_alpha = r.get_double("weight_alpha", c.weight_alpha);
  if (!(c.weight_alpha >= 0) || !(c.weight_alpha <= 64))
    r.fail("weight_alpha", "must be in [0, 64]");
  c.radius_px = r.get_double("radius_px", c.radius_px);
  if (!(c.radius_px > 0) || !(c.radius_px <= 16)) r.fail("radius_px", "must be in (0, 16]");
  c.max_aniso = r.get_double("max_aniso", c.max_aniso);
  if (!(c.max_aniso >= 1) || !(c.max_aniso <= 1024)) r.fail("max_aniso", "must be in [1, 1024]");
  c.seed_theta = r.get_bool("seed_theta", c.seed_theta);
  c.temporal = r.get_bool("temporal", c.temporal);
  c.arith =
      kProbeArith.at(r.get_choice("arith", kProbeArith.index_of(c.arith), kProbeArith.key_list()));
  c.address_u = footprint_address_mode(r, "address_u");
  c.address_v = footprint_address_mode(r, "address_v");
  return c;
}

namespace {
TexelAddressGen::Config trilinear(AddressMode au, AddressMode av) {
  TexelAddressGen::Config c;
  c.filter = FilterMode::Trilinear;
  c.address_u = au;
  c.address_v = av;
  return c;
}
}  // namespace

MultiProbeFilter::MultiProbeFilter(const Config& c)
    : cfg_(c), addr_(trilinear(c.address_u, c.address_v)) {
  cfg_.max_probes = std::clamp(cfg_.max_probes | 1, 1, ProbeSet::kMax);
}

double MultiProbeFilter::major_angle(double suu, double suv, double svv, bool seed_literal) {
  if (seed_literal) {
    // A − C = Σvv − Σuu and B = −2Σuv: B/(A − C) = 2Σuv/(Σuu − Σvv), but atan folds the angle
    // into (−π/4, π/4): when Σvv > Σuu this is the minor axis.
    const double den = svv - suu;
    if (den == 0) return suv == 0 ? 0.0 : (suv > 0 ? 0.25 : -0.25) * 3.14159265358979323846;
    return 0.5 * std::atan((-2.0 * suv) / den);
  }
  return 0.5 * std::atan2(2.0 * suv, suu - svv);
}

ProbeSet MultiProbeFilter::probes(const Texture& tex, const Fragment& f, OpCounts& ops,
                                  FilterStats* st) const {
  ops += setup_ops();
  return kProbeArith.visit(cfg_.arith, [&](auto t) {
    using T = decltype(t);
    if constexpr (is_fixed_v<T>) {
      return probes_fixed(tex, f, st);
    } else {
      return probes_t<T>(tex, f, st);
    }
  });
}

template <class T>
ProbeSet MultiProbeFilter::probes_t(const Texture& tex, const Fragment& f, FilterStats* st) const {
  static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>);
  {
    // Footprint set-up in T; the rest in double from it (T = float: the original model).
    ProbeSet p;
    const int w0 = tex.width(0), h0 = tex.height(0);
    OpCounts scratch;  // setup_ops() already holds the footprint set-up
    const Footprint fp = footprint_setup<T>(f, w0, h0, cfg_.radius_px, cfg_.max_aniso, scratch);
    if (st) st->bad_input = fp.bad_input;
    const double u = std::isfinite(f.u) ? f.u : 0.0, v = std::isfinite(f.v) ? f.v : 0.0;
    const double rmaj = std::sqrt(fp.major2), rmin = std::sqrt(fp.minor2);
    p.n = 1;
    p.u[0] = u;
    p.v[0] = v;
    p.w[0] = 1;
    if (fp.overflow) {
      p.lambda = 1e30f;  // most minified level
      return p;
    }
    if (!(rmin > 0)) {
      p.lambda = -1e30f;  // a point: magnification
      return p;
    }
    const double ar = cfg_.alpha * rmin;
    p.lambda = static_cast<float>(std::log2(ar) + f.lod_bias);
    // N = 2·R_major/(α·R_minor) − 1, rounded up to odd, at most max_probes.
    const double nreal = 2.0 * rmaj / ar - 1.0;
    int n = static_cast<int>(std::ceil(std::min(nreal, 1e6) - 1e-9));
    n = std::max(n, 1);
    if (n % 2 == 0) ++n;
    n = std::min(n, cfg_.max_probes);
    if (n == 1) return p;
    const double len = 2.0 * std::max(rmaj - ar, 0.0);  // L
    const double step = len / (n - 1);
    const double th = major_angle(fp.suu, fp.suv, fp.svv, cfg_.seed_theta);
    const double du = std::cos(th) * step / w0, dv = std::sin(th) * step / h0;
    const int half = (n - 1) / 2;
    const int parity = static_cast<int>((f.frame + f.x + f.y) & 1u);
    p.n = 0;
    for (int k = -half; k <= half; ++k) {
      if (cfg_.temporal && k != 0 && (std::abs(k) & 1) != parity) continue;
      const auto i = static_cast<size_t>(p.n++);
      p.u[i] = u + k * du;
      p.v[i] = v + k * dv;
      const double d = k * step / rmaj;
      p.w[i] = static_cast<float>(std::exp(-cfg_.weight_alpha * d * d));
    }
    return p;
  }
}

template ProbeSet MultiProbeFilter::probes_t<float>(const Texture&, const Fragment&,
                                                    FilterStats*) const;
template ProbeSet MultiProbeFilter::probes_t<double>(const Texture&, const Fragment&,
                                                     FilterStats*) const;

ProbeSet MultiProbeFilter::probes_fixed(const Texture& tex, const Fragment& f,
                                        FilterStats* st) const {
  using Len = ProbeFx::Len;
  using Vec = ProbeFx::Vec;
  using Coord = ProbeFx::Coord;
  using Lod = ProbeFx::Lod;
  using Ratio = ProbeFx::Ratio;
  using Const = ProbeFx::Const;
  using Arg = ProbeFx::Arg;
  using vd_detail::mul;
  ProbeSet p;
  const int w0 = tex.width(0), h0 = tex.height(0);
  const ProbeFootprintFx fp =
      probe_footprint_fx(f, w0, h0, cfg_.radius_px, cfg_.max_aniso, cfg_.seed_theta);
  if (st) st->bad_input = fp.bad_input;
  // The centre through the coordinate converter (non-finite: 0, as the float path).
  const Coord cu(std::isfinite(f.u) ? f.u : 0.0), cv(std::isfinite(f.v) ? f.v : 0.0);
  p.n = 1;
  p.u[0] = cu.to_double();
  p.v[0] = cv.to_double();
  p.w[0] = 1;
  if (fp.overflow) {
    p.lambda = 1e30f;  // most minified level
    return p;
  }
  const Len rmaj = probe_fx::sqrt_len(fp.major2), rmin = probe_fx::sqrt_len(fp.minor2);
  const Len ar = mul<Len>(Const(cfg_.alpha), rmin);
  if (fp.minor2.raw() <= 0 || ar.raw() <= 0) {
    p.lambda = -1e30f;  // a point (or below the formats' resolution): magnification
    return p;
  }
  // λ = ½·log2(λ₋) + log2(α) + bias: no square root on the LOD path.
  const Lod half_log =
      Lod::from_raw((probe_fx::log2_of(fp.minor2.raw(), ProbeFx::Sigma::kFracBits).raw() + 1) >> 1);
  p.lambda =
      static_cast<float>((half_log + Lod(std::log2(cfg_.alpha)) + Lod(f.lod_bias)).to_double());
  // N: the smallest odd n ≥ 2·R_major/(α·R_minor) − 1, i.e. ⌈q⌉ − 1 with q from the divider.
  bool exact = false;
  const int64_t q = probe_fx::count_quotient(2 * rmaj.raw(), ar.raw(), exact);
  int n = static_cast<int>(q) - (exact ? 1 : 0);
  n = std::max(n, 1);
  if (n % 2 == 0) ++n;
  n = std::min(n, cfg_.max_probes);
  if (n == 1) return p;
  const Len len = Len::from_raw(2 * std::max<int64_t>(rmaj.raw() - ar.raw(), 0));  // L
  const Len step = mul<Len>(len, Ratio(1.0 / (n - 1)));  // table of 1/(N − 1)
  const ProbeFx::Angle theta = ProbeFx::Angle::from_raw(fp.two_theta.raw() >> 1);
  Vec ax, ay;  // step·(cos θ, sin θ) in texels
  probe_fx::rotate(mul<Vec>(step, probe_fx::inv_gain()), theta, ax, ay);
  const Coord du = mul<Coord>(ax, Const(1.0 / w0)), dv = mul<Coord>(ay, Const(1.0 / h0));
  // Weight argument per unit k²: w_α·log2(e)·(step/R_major)², so w_k = 2^-(k²·c).
  const Ratio g = rmaj.raw() > 0
                      ? Ratio::from_raw(static_cast<int64_t>(std::min<wide_int>(
                            (static_cast<wide_int>(step.raw()) << Ratio::kFracBits) / rmaj.raw(),
                            Ratio::kRawMax)))
                      : Ratio(0);
  const Arg c = mul<Arg>(mul<Ratio>(g, g), Const(cfg_.weight_alpha * std::numbers::log2e));
  const int half = (n - 1) / 2;
  const int parity = static_cast<int>((f.frame + f.x + f.y) & 1u);
  p.n = 0;
  for (int k = -half; k <= half; ++k) {
    if (cfg_.temporal && k != 0 && (std::abs(k) & 1) != parity) continue;
    const auto i = static_cast<size_t>(p.n++);
    p.u[i] = (cu + Coord::from_raw(k * du.raw())).to_double();
    p.v[i] = (cv + Coord::from_raw(k * dv.raw())).to_double();
    p.w[i] = static_cast<float>(
        probe_fx::exp2_neg(Arg::from_raw(std::min<int64_t>(int64_t{k} * k * c.raw(), Arg::kRawMax)))
            .to_double());
  }
  return p;
}

FilterOutput MultiProbeFilter::filter(const Texture& tex, const Fragment& f,
                                      std::vector<TexelRef>* fetched, OpCounts& ops) const {
  FilterStats st;
  const ProbeSet p = probes(tex, f, ops, &st);
  return run_probes(addr_, tex, p, probe_setup_ops(), st.bad_input, fetched, ops);
}

OpCounts MultiProbeFilter::setup_ops() const {
  if (cfg_.arith == NumberFormat::S16_24HalfUp) {
    OpCounts o = probe_footprint_fx_ops();
    // R_major, R_minor: 2 sqrt (digit recurrence). λ: leading one (cmp), log2 table (lut),
    // exponent + table, + log2 α, + bias (3 add). α·R_minor: mul. N: the divider, then
    // −1 (add), odd and clamp (2 cmp). L: add. step: 1/(N − 1) table (lut), mul. Axis vector:
    // step·(1/K) (mul) and a CORDIC rotation; to normalised: 2 mul. Weights: step/R_major
    // (div), its square and ×w_α·log2 e (2 mul).
    o.sqrt += 2;
    o.cmp += 1 + 2;
    o.lut += 1 + 1;
    o.add += 3 + 1 + 1;
    o.mul += 1 + 1 + 1 + 2 + 2;
    o.div += 1;
    return o + probe_fx::count_divider_ops() + probe_fx::cordic_ops();
  }
  OpCounts o = footprint_setup_ops();
  // R_major, R_minor: 2 sqrt; θ: atan2 (table) and cos/sin (2 tables); N: α·R_minor (mul),
  // 1/(α·R_minor) (rcp), 2·R_major·(…) (mul), −1 (add), ceil/odd/clamp (3 cmp); L: add, mul;
  // step: rcp, mul; du, dv: 2 mul + 2 mul to normalised; λ: log2 (table), bias (add).
  o.sqrt += 2;
  o.lut += 3 + 1;
  o.mul += 1 + 1 + 1 + 1 + 4;
  o.rcp += 2;
  o.add += 1 + 1 + 1;
  o.cmp += 3;
  return o;
}

OpCounts MultiProbeFilter::probe_setup_ops() const {
  OpCounts o;
  o.mul = 2 + 1;  // position k·(du, dv); float: d²·w_α, fixed: k²·c
  o.add = 2;      // centre + offset
  o.lut = 1;      // exp (fixed: the 2^-f table and a shift)
  if (cfg_.arith == NumberFormat::S16_24HalfUp)
    o.add += 1;  // the k² counter: (k + 1)² = k² + 2k + 1
  return o;
}

OpCounts MultiProbeFilter::ops_per_item() const { return probe_lane_ops(addr_, probe_setup_ops()); }

TimingSpec MultiProbeFilter::timing(const TechTable& tech) const {
  // Set-up: derivatives → Σ → eigenvalues → √ → N → step → position; then one probe's address
  // path and the blend, then normalisation.
  OpCounts path;
  if (cfg_.arith == NumberFormat::S16_24HalfUp) {
    // Converter, Σ (mul, add), d (add), pre-rotation (cmp, add), normalisation (2 cmp),
    // vectoring, gain (mul),
    // λ₋ (add), clamp (mul, 2 cmp), √, α·R_minor (mul), divider, −1 (add), odd/clamp (cmp),
    // 1/(N − 1) (lut), step (mul), 1/K (mul), rotation, to normalised (mul), k·du (mul), + centre.
    constexpr uint64_t n = ProbeFx::kCordicSteps;
    path.mul = 1 + 1 + 1 + 1 + 1 + 1 + 1 + 1 + 1;
    path.add = 1 + 1 + 1 + n + 1 + ProbeFx::kCountSteps + 1 + n + 1;
    path.cmp = 1 + 2 + n + 2 + ProbeFx::kCountSteps + 1 + 1 + n;
    path.sqrt = 1;
    path.lut = 1;
  } else {
    path.mul = 1 + 1 + 1 + 1 + 1;
    path.add = 1 + 1 + 1 + 1;
    path.sqrt = 2;
    path.rcp = 2;
    path.lut = 1;
    path.cmp = 2;
  }
  return probe_filter_timing(tech, path, addr_, setup_ops(), probe_setup_ops());
}

std::string MultiProbeFilter::arithmetic() const {
  const std::string probes =
      "; trilinear probes (float32 coordinates, u0.8 weights), float32 blend";
  if (cfg_.arith == NumberFormat::Double) return "double set-up" + probes;
  if (cfg_.arith == NumberFormat::S16_24HalfUp) {
    return "fixed set-up (" + ProbeFx::name() +
           "; CORDIC axes, digit-recurrence sqrt, log2/exp2 tables)" + probes;
  }
  return "float32 footprint set-up, axes/N/positions/weights in double" + probes;
}

}  // namespace texsim
