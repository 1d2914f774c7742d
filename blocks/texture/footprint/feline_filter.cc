#include "blocks/texture/footprint/feline_filter.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <type_traits>

#include "blocks/base/block.h"
#include "blocks/texture/footprint/multi_probe_filter.h"
#include "blocks/texture/subtexel/vd_evaluator_params.h"

namespace texsim {

static_assert(Block<FelineFilter>);

FelineFilter::Config FelineFilter::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"axis", "weights", "max_probes", "weight_alpha", "radius_px", "max_aniso",
                    "arith", "address_u", "address_v"});
  Config c;
  c.axis = static_cast<Axis>(
      r.get_choice("axis", static_cast<int>(c.axis), {"parallelogram", "ellipse"}));
  c.weights = static_cast<Weights>(
      r.get_choice("weights", static_cast<int>(c.weights), {"equal", "gaussian"}));
  c.max_probes = static_cast<int>(r.get_int("max_probes", c.max_probes, 1, ProbeSet::kMax));
  c.weight_alpha = r.get_double("weight_alpha", c.weight_alpha);
  if (!(c.weight_alpha >= 0) || !(c.weight_alpha <= 64))
    r.fail("weight_alpha", "must be in [0, 64]");
  c.radius_px = r.get_double("radius_px", c.radius_px);
  if (!(c.radius_px > 0) || !(c.radius_px <= 16)) r.fail("radius_px", "must be in (0, 16]");
  c.max_aniso = r.get_double("max_aniso", c.max_aniso);
  if (!(c.max_aniso >= 1) || !(c.max_aniso <= 1024)) r.fail("max_aniso", "must be in [1, 1024]");
  c.arith =
      kProbeArith.at(r.get_choice("arith", kProbeArith.index_of(c.arith), kProbeArith.key_list()));
  c.address_u = footprint_address_mode(r, "address_u");
  c.address_v = footprint_address_mode(r, "address_v");
  return c;
}

FelineFilter::FelineFilter(const Config& c) : cfg_(c) {
  cfg_.max_probes = std::clamp(cfg_.max_probes, 1, ProbeSet::kMax);
  TexelAddressGen::Config a;
  a.filter = FilterMode::Trilinear;
  a.address_u = c.address_u;
  a.address_v = c.address_v;
  addr_ = TexelAddressGen(a);
}

ProbeSet FelineFilter::probes(const Texture& tex, const Fragment& f, OpCounts& ops,
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
ProbeSet FelineFilter::probes_t(const Texture& tex, const Fragment& f, FilterStats* st) const {
  static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>);
  {
    // Ellipse footprint set-up in T; everything else in double (T = float: the original model).
    ProbeSet p;
    const double w0 = tex.width(0), h0 = tex.height(0);
    const double u = std::isfinite(f.u) ? f.u : 0.0, v = std::isfinite(f.v) ? f.v : 0.0;
    p.n = 1;
    p.u[0] = u;
    p.v[0] = v;
    p.w[0] = 1;
    const bool finite = std::isfinite(f.dudx) && std::isfinite(f.dvdx) && std::isfinite(f.dudy) &&
                        std::isfinite(f.dvdy);
    if (!finite) {
      if (st) st->bad_input = true;
      p.lambda = -1e30f;  // point footprint: level 0
      return p;
    }
    const double R = cfg_.radius_px;
    double lu = 0, lv = 0, minor = 0;  // the half line (texels) and the minor size
    if (cfg_.axis == Axis::Parallelogram) {
      const double ax = f.dudx * w0 * R, ay = f.dvdx * h0 * R;
      const double bx = f.dudy * w0 * R, by = f.dvdy * h0 * R;
      const double la = std::hypot(ax, ay), lb = std::hypot(bx, by);
      if (la >= lb) {
        lu = ax;
        lv = ay;
        minor = lb;
      } else {
        lu = bx;
        lv = by;
        minor = la;
      }
    } else {
      OpCounts scratch;
      const Footprint fp = footprint_setup<T>(f, static_cast<int>(w0), static_cast<int>(h0), R,
                                              cfg_.max_aniso, scratch);
      if (fp.overflow) {
        p.lambda = 1e30f;
        return p;
      }
      const double rmaj = std::sqrt(fp.major2);
      minor = std::sqrt(fp.minor2);
      const double th = MultiProbeFilter::major_angle(fp.suu, fp.suv, fp.svv, false);
      lu = std::cos(th) * rmaj;
      lv = std::sin(th) * rmaj;
    }
    const double len = std::hypot(lu, lv);
    if (!std::isfinite(len)) {
      p.lambda = 1e30f;
      return p;
    }
    if (!(len > 0)) {
      p.lambda = -1e30f;
      return p;
    }
    int n = 1;
    if (minor > 0)
      n = static_cast<int>(
          std::min(std::ceil(len / minor - 1e-9), static_cast<double>(cfg_.max_probes)));
    else
      n = cfg_.max_probes;
    n = std::clamp(n, 1, cfg_.max_probes);
    p.lambda = static_cast<float>(std::log2(std::max(minor, len / n)) + f.lod_bias);
    p.n = n;
    for (int k = 0; k < n; ++k) {
      const double t = static_cast<double>(2 * k + 1 - n) / n;
      const auto i = static_cast<size_t>(k);
      p.u[i] = u + t * lu / w0;
      p.v[i] = v + t * lv / h0;
      p.w[i] = cfg_.weights == Weights::Equal
                   ? 1.0f
                   : static_cast<float>(std::exp(-cfg_.weight_alpha * t * t));
    }
    return p;
  }
}

template ProbeSet FelineFilter::probes_t<float>(const Texture&, const Fragment&,
                                                FilterStats*) const;
template ProbeSet FelineFilter::probes_t<double>(const Texture&, const Fragment&,
                                                 FilterStats*) const;

ProbeSet FelineFilter::probes_fixed(const Texture& tex, const Fragment& f, FilterStats* st) const {
  using Deriv = ProbeFx::Deriv;
  using Sigma = ProbeFx::Sigma;
  using Len = ProbeFx::Len;
  using Vec = ProbeFx::Vec;
  using Coord = ProbeFx::Coord;
  using Lod = ProbeFx::Lod;
  using Ratio = ProbeFx::Ratio;
  using Const = ProbeFx::Const;
  using Arg = ProbeFx::Arg;
  using vd_detail::cast;
  using vd_detail::mul;
  ProbeSet p;
  const int w0 = tex.width(0), h0 = tex.height(0);
  const Coord cu(std::isfinite(f.u) ? f.u : 0.0), cv(std::isfinite(f.v) ? f.v : 0.0);
  p.n = 1;
  p.u[0] = cu.to_double();
  p.v[0] = cv.to_double();
  p.w[0] = 1;
  const double R = cfg_.radius_px;
  Vec lu, lv;      // the half line (texels)
  Len len, minor;  // its length and the minor size
  if (cfg_.axis == Axis::Parallelogram) {
    if (!std::isfinite(f.dudx) || !std::isfinite(f.dvdx) || !std::isfinite(f.dudy) ||
        !std::isfinite(f.dvdy)) {
      if (st) st->bad_input = true;
      p.lambda = -1e30f;  // point footprint: level 0
      return p;
    }
    const double sw = w0 * R, sh = h0 * R;
    const Deriv ax(f.dudx * sw), ay(f.dvdx * sh), bx(f.dudy * sw), by(f.dvdy * sh);
    for (const Deriv d : {ax, ay, bx, by}) {
      if (d.raw() == Deriv::kRawMax || d.raw() == Deriv::kRawMin) {
        p.lambda = 1e30f;  // saturated: most minified level
        return p;
      }
    }
    const Sigma la2 = mul<Sigma>(ax, ax) + mul<Sigma>(ay, ay),
                lb2 = mul<Sigma>(bx, bx) + mul<Sigma>(by, by);
    const bool a_longer = la2 >= lb2;
    len = probe_fx::sqrt_len(a_longer ? la2 : lb2);
    minor = probe_fx::sqrt_len(a_longer ? lb2 : la2);
    lu = cast<Vec>(a_longer ? ax : bx);
    lv = cast<Vec>(a_longer ? ay : by);
  } else {
    const ProbeFootprintFx fp = probe_footprint_fx(f, w0, h0, R, cfg_.max_aniso, false);
    if (fp.bad_input) {
      if (st) st->bad_input = true;
      p.lambda = -1e30f;
      return p;
    }
    if (fp.overflow) {
      p.lambda = 1e30f;
      return p;
    }
    len = probe_fx::sqrt_len(fp.major2);
    minor = probe_fx::sqrt_len(fp.minor2);
    const ProbeFx::Angle theta = ProbeFx::Angle::from_raw(fp.two_theta.raw() >> 1);
    probe_fx::rotate(mul<Vec>(len, probe_fx::inv_gain()), theta, lu, lv);
  }
  if (len.raw() <= 0) {
    p.lambda = -1e30f;
    return p;
  }
  // N = min(⌈|line|/minor⌉, max_probes); the divider saturates at 64 probes.
  int n = cfg_.max_probes;
  if (minor.raw() > 0) {
    bool exact = false;
    const int64_t q = probe_fx::count_quotient(len.raw(), minor.raw(), exact);
    n = static_cast<int>(std::min<int64_t>(q + (exact ? 0 : 1), cfg_.max_probes));
  }
  n = std::clamp(n, 1, cfg_.max_probes);
  const Ratio inv_n(1.0 / n);  // table of 1/N
  const Len seg = mul<Len>(len, inv_n);
  const Len lod_len = std::max(minor, seg);
  if (lod_len.raw() <= 0) {
    p.lambda = -1e30f;
    return p;
  }
  p.lambda = static_cast<float>(
      (probe_fx::log2_of(lod_len.raw(), Len::kFracBits) + Lod(f.lod_bias)).to_double());
  // Probe k at t_k = m/N, m = 2k + 1 − N: the centre + m·(line/N).
  const Coord du = mul<Coord>(mul<Vec>(lu, inv_n), Const(1.0 / w0));
  const Coord dv = mul<Coord>(mul<Vec>(lv, inv_n), Const(1.0 / h0));
  const bool gauss = cfg_.weights == Weights::Gaussian;
  // Gaussian: w = exp(−w_α·m²/N²) = 2^-(m²·c), c = w_α·log2(e)/N².
  const Arg c =
      gauss ? mul<Arg>(mul<Ratio>(inv_n, inv_n), Const(cfg_.weight_alpha * std::numbers::log2e))
            : Arg(0);
  p.n = n;
  for (int k = 0; k < n; ++k) {
    const int64_t m = 2 * k + 1 - n;
    const auto i = static_cast<size_t>(k);
    p.u[i] = (cu + Coord::from_raw(m * du.raw())).to_double();
    p.v[i] = (cv + Coord::from_raw(m * dv.raw())).to_double();
    p.w[i] = gauss ? static_cast<float>(probe_fx::exp2_neg(Arg::from_raw(std::min<int64_t>(
                                                               m * m * c.raw(), Arg::kRawMax)))
                                            .to_double())
                   : 1.0f;
  }
  return p;
}

FilterOutput FelineFilter::filter(const Texture& tex, const Fragment& f,
                                  std::vector<TexelRef>* fetched, OpCounts& ops) const {
  FilterStats st;
  const ProbeSet p = probes(tex, f, ops, &st);
  return run_probes(addr_, tex, p, probe_setup_ops(), st.bad_input, fetched, ops);
}

OpCounts FelineFilter::setup_ops() const {
  OpCounts o;
  if (cfg_.arith == NumberFormat::S16_24HalfUp) {
    if (cfg_.axis == Axis::Parallelogram) {
      // Non-finite and saturation tests: 2 cmp; Deriv converters: 4 mul; lengths²: 4 mul, 2 add;
      // compare and select: 3 cmp; √ of both (digit recurrence): 2 sqrt.
      o.mul = 4 + 4;
      o.add = 2;
      o.cmp = 2 + 3;
      o.sqrt = 2;
    } else {
      // Fixed footprint set-up (CORDIC vectoring), √ of both eigenvalues, the half line by
      // R_major·(1/K) (mul) and a CORDIC rotation.
      o = probe_footprint_fx_ops() + probe_fx::cordic_ops();
      o.sqrt += 2;
      o.mul += 1;
    }
    // N: the divider, +1 unless exact (add), clamp (cmp); 1/N table (lut); |line|/N (mul);
    // max with minor (cmp); log2: leading one (cmp), table (lut), exponent + table (add);
    // bias (add); line/N (2 mul) to normalised (2 mul); Gaussian: (1/N)² and ×w_α·log2 e (2 mul).
    o += probe_fx::count_divider_ops();
    o.add += 1 + 1 + 1;
    o.cmp += 1 + 1 + 1;
    o.lut += 1 + 1;
    o.mul += 1 + 2 + 2;
    if (cfg_.weights == Weights::Gaussian) o.mul += 2;
    return o;
  }
  if (cfg_.axis == Axis::Parallelogram) {
    // Two vectors to texels: 4 mul; lengths²: 4 mul, 2 add; compare and select: 3 cmp;
    // √ of the shorter (LOD) and the longer (N): 2 sqrt.
    o.mul = 4 + 4;
    o.add = 2;
    o.cmp = 3;
    o.sqrt = 2;
  } else {
    // Footprint set-up, √ of both eigenvalues, θ by table and cos/sin, the half line: 2 mul.
    o = footprint_setup_ops();
    o.sqrt += 2;
    o.lut += 3;
    o.mul += 2;
  }
  // N = ⌈len/minor⌉: rcp, mul, ceil and clamp 2 cmp; λ: len·(1/N) (rcp, mul), max (cmp),
  // log2 (table), bias (add); the line to normalised coordinates: 2 mul.
  o.rcp += 2;
  o.mul += 2 + 2;
  o.cmp += 3;
  o.lut += 1;
  o.add += 1;
  return o;
}

OpCounts FelineFilter::probe_setup_ops() const {
  OpCounts o;
  o.mul = 2;  // t·(lu, lv) (fixed: m·(line/N))
  o.add = 2;
  if (cfg_.weights == Weights::Gaussian) {
    o.mul += 1;  // float: t²·w_α; fixed: m²·c
    o.lut += 1;  // exp (fixed: the 2^-f table and a shift)
    if (cfg_.arith == NumberFormat::S16_24HalfUp)
      o.add += 1;  // the m² counter: (m + 2)² = m² + 4m + 4
  }
  return o;
}

OpCounts FelineFilter::ops_per_item() const { return probe_lane_ops(addr_, probe_setup_ops()); }

TimingSpec FelineFilter::timing(const TechTable& tech) const {
  OpCounts path;
  if (cfg_.arith == NumberFormat::S16_24HalfUp) {
    constexpr uint64_t n = ProbeFx::kCordicSteps;
    if (cfg_.axis == Axis::Parallelogram) {
      // Converter, square, sum, compare, √, divider, clamp, 1/N table, line/N, to normalised,
      // m·Δ, + centre.
      path.mul = 1 + 1 + 1 + 1 + 1;
      path.add = 1 + ProbeFx::kCountSteps + 1;
      path.cmp = 1 + ProbeFx::kCountSteps + 1;
      path.sqrt = 1;
      path.lut = 1;
    } else {
      // Converter, Σ (mul, add), d (add), pre-rotation (cmp, add), normalisation (2 cmp),
      // vectoring, gain (mul), λ₊ (add), √, 1/K (mul), rotation, line/N (mul), to normalised
      // (mul), m·Δ (mul), + centre.
      path.mul = 1 + 1 + 1 + 1 + 1 + 1 + 1;
      path.add = 1 + 1 + 1 + n + 1 + n + 1;
      path.cmp = 1 + 2 + n + n;
      path.sqrt = 1;
    }
  } else {
    if (cfg_.axis == Axis::Parallelogram) {
      path.mul = 2;
      path.add = 1;
      path.cmp = 1;
      path.sqrt = 1;
    } else {
      path.mul = 4;
      path.add = 4;
      path.sqrt = 2;
      path.rcp = 1;
      path.lut = 2;
      path.cmp = 2;
    }
    path.rcp += 1;
    path.mul += 2;
    path.cmp += 1;
  }
  return probe_filter_timing(tech, path, addr_, setup_ops(), probe_setup_ops());
}

std::string FelineFilter::arithmetic() const {
  const std::string probes =
      "; trilinear probes (float32 coordinates, u0.8 weights), float32 blend";
  if (cfg_.arith == NumberFormat::Double) return "double set-up" + probes;
  if (cfg_.arith == NumberFormat::S16_24HalfUp) {
    return "fixed set-up (" + ProbeFx::name() +
           (cfg_.axis == Axis::Ellipse ? "; CORDIC axis" : "") +
           ", digit-recurrence sqrt, log2/exp2 tables)" + probes;
  }
  return std::string(cfg_.axis == Axis::Ellipse
                         ? "float32 footprint set-up, line/N/positions/weights in double"
                         : "line/N/positions/weights in double") +
         probes;
}

}  // namespace texsim
