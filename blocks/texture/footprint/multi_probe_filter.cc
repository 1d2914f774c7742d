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

OpCounts probe_blend_ops() {
  OpCounts o;
  o.mul = 4;      // w_k · probe colour
  o.add = 4 + 1;  // accumulate RGBA, Σw
  return o;
}

OpCounts trilinear_probe_blend_ops() { return TexelBlend::ops_per_item() * 8 + probe_blend_ops(); }

OpCounts probe_normalise_ops() {
  OpCounts o;
  o.cmp = 1;
  o.rcp = 1;
  o.mul = 4;
  return o;
}

FilterOutput run_probes(const TexelAddressGen& addr, const Texture& tex, const ProbeSet& probes,
                        const OpCounts& probe_setup, bool bad_input, std::vector<TexelRef>* fetched,
                        OpCounts& ops) {
  FilterOutput out;
  out.stats.bad_input = bad_input;
  ops += probe_setup * static_cast<uint64_t>(probes.n);
  FilterTaps taps;
  LodResult lod;
  lod.lambda = probes.lambda;
  lod.probes = 1;
  glm::vec4 sum(0), plain(0);
  float wsum = 0;
  int32_t finest = 1 << 30;
  for (int k = 0; k < probes.n; ++k) {
    const auto ku = static_cast<size_t>(k);
    addr.taps(tex, probes.u[ku], probes.v[ku], lod, taps, ops);
    glm::vec4 c(0);
    for (int t = 0; t < taps.count; ++t) {
      const TexelTap& tp = taps.tap[static_cast<size_t>(t)];
      c += tp.w * tex.texel(tp.level, tp.x, tp.y);
      if (fetched) fetched->push_back({tp.level, tp.x, tp.y});
      finest = std::min(finest, tp.level);
    }
    ops += TexelBlend::ops_per_item() * static_cast<uint64_t>(taps.count);
    ops += probe_blend_ops();
    out.stats.texels += static_cast<uint32_t>(taps.count);
    sum += probes.w[ku] * c;
    plain += c;
    wsum += probes.w[ku];
  }
  ops += probe_normalise_ops();
  out.stats.probes = static_cast<uint32_t>(probes.n);
  out.stats.visited = out.stats.probes;
  out.stats.level = probes.n > 0 ? finest : 0;
  if (wsum > 0) {
    out.colour = sum * (1.0f / wsum);
  } else if (probes.n > 0) {
    out.stats.fallback = true;  // every Gaussian weight underflowed: the probes' mean
    out.colour = plain * (1.0f / static_cast<float>(probes.n));
  }
  return out;
}

OpCounts probe_lane_ops(const TexelAddressGen& addr, const OpCounts& probe_setup) {
  return probe_setup + addr.ops_per_item(false) + trilinear_probe_blend_ops();
}

TimingSpec probe_filter_timing(const TechTable& tech, const OpCounts& setup_path,
                               const TexelAddressGen& addr, const OpCounts& setup_ops,
                               const OpCounts& probe_setup) {
  OpCounts tail;  // blend of one probe's taps, weighting, normalisation
  tail.mem = 1;
  tail.mul = 2;
  tail.add = 4;
  tail.rcp = 1;
  // One probe per cycle; the set-up and one probe's lane and normaliser exist once.
  OpCounts lane = probe_lane_ops(addr, probe_setup);
  lane.mem = 0;
  TimingSpec t =
      derive_timing(tech, setup_ops, tech.path_latency(setup_path) + tech.path_latency(tail),
                    Datapath::Spatial, 1, lane + probe_normalise_ops());
  t.latency += addr.timing(tech).latency;  // the address generator's pipeline in series
  return t;
}

std::string ProbeFx::name() {
  return Deriv::name() + " J, " + Sigma::name() + " Sigma, " + Angle::name() + " angle, " +
         Len::name() + " lengths, " + Coord::name() + " positions, " + Lod::name() + " LOD, " +
         Weight::name() + " weights";
}

// ---- fixed-point set-up units -------------------------------------------------------------

namespace probe_fx {

namespace {

// Rounds a non-negative wide value right by s bits, half up.
wide_int shr_half_up(wide_int v, int s) {
  return s <= 0 ? v << -s : (v + (wide_int{1} << (s - 1))) >> s;
}

// atan(2^-i) in Angle, i < kCordicSteps.
const std::array<int64_t, ProbeFx::kCordicSteps>& atan_table() {
  static const std::array<int64_t, ProbeFx::kCordicSteps> t = [] {
    std::array<int64_t, ProbeFx::kCordicSteps> a{};
    for (int i = 0; i < ProbeFx::kCordicSteps; ++i) {
      a[static_cast<size_t>(i)] = ProbeFx::Angle(std::atan(std::ldexp(1.0, -i))).raw();
    }
    return a;
  }();
  return t;
}

// log2(1 + j/1024) in Lod and 2^(-j/1024) in u0.24, j = 0 … 1023.
constexpr int kTable = 1 << ProbeFx::kTableBits;
const std::array<int64_t, kTable>& log2_table() {
  static const std::array<int64_t, kTable> t = [] {
    std::array<int64_t, kTable> a{};
    for (int j = 0; j < kTable; ++j)
      a[static_cast<size_t>(j)] =
          ProbeFx::Lod(std::log2(1.0 + j / static_cast<double>(kTable))).raw();
    return a;
  }();
  return t;
}
constexpr int kExpEntryBits = 24;
const std::array<int64_t, kTable>& exp2_table() {
  static const std::array<int64_t, kTable> t = [] {
    std::array<int64_t, kTable> a{};
    for (int j = 0; j < kTable; ++j) {
      a[static_cast<size_t>(j)] =
          std::llround(std::ldexp(std::exp2(-j / static_cast<double>(kTable)), kExpEntryBits));
    }
    return a;
  }();
  return t;
}

__extension__ typedef unsigned __int128 wide_uint;

// Integer square root (floor) of a 128-bit value: the digit recurrence, one result bit per step.
uint64_t isqrt(wide_uint n) {
  wide_uint rem = 0, root = 0;
  for (int i = 126; i >= 0; i -= 2) {
    rem = (rem << 2) | ((n >> i) & 3);
    root <<= 1;
    const wide_uint trial = (root << 1) | 1;
    if (rem >= trial) {
      rem -= trial;
      root |= 1;
    }
  }
  return static_cast<uint64_t>(root);
}

}  // namespace

ProbeFx::Len sqrt_len(ProbeFx::Sigma x) {
  using Len = ProbeFx::Len;
  if (x.raw() <= 0) return Len(0);
  // √(raw·2^-Fs) with Fl fraction bits = √(raw·2^(2Fl − Fs))·2^-Fl.
  constexpr int sh = 2 * Len::kFracBits - ProbeFx::Sigma::kFracBits;
  static_assert(sh >= 0, "Len needs at least half of Sigma's fraction bits");
  const wide_uint n = static_cast<wide_uint>(x.raw()) << sh;
  uint64_t r = isqrt(n);
  if (n - static_cast<wide_uint>(r) * r > r) ++r;  // n ≥ (r + ½)²: round up
  return Len::from_raw(static_cast<int64_t>(r));
}

ProbeFx::Lod log2_of(int64_t raw, int frac_bits) {
  using Lod = ProbeFx::Lod;
  if (raw <= 0) return Lod::min();
  int e = 63 - std::countl_zero(static_cast<uint64_t>(raw));  // leading-one position
  // f = raw/2^e − 1 to kTableBits bits, rounded; a carry out of the fraction bumps e.
  const wide_int mant = static_cast<wide_int>(raw) - (wide_int{1} << e);
  int64_t j = static_cast<int64_t>(shr_half_up(mant, e - ProbeFx::kTableBits));
  if (j >= kTable) {
    j = 0;
    ++e;
  }
  const wide_int v = (static_cast<wide_int>(e - frac_bits) << Lod::kFracBits) +
                     log2_table()[static_cast<size_t>(j)];
  return Lod::from_raw(static_cast<int64_t>(std::clamp<wide_int>(v, Lod::kRawMin, Lod::kRawMax)));
}

ProbeFx::Weight exp2_neg(ProbeFx::Arg y) {
  using Weight = ProbeFx::Weight;
  constexpr int fa = ProbeFx::Arg::kFracBits;
  int64_t e = y.raw() >> fa;
  int64_t j = static_cast<int64_t>(
      shr_half_up(y.raw() & ((int64_t{1} << fa) - 1), fa - ProbeFx::kTableBits));
  if (j >= kTable) {
    j = 0;
    ++e;
  }
  // entry·2^-24·2^-e into u1.15: a right shift by 24 − 15 + e with rounding.
  const int s = kExpEntryBits - Weight::kFracBits + static_cast<int>(std::min<int64_t>(e, 40));
  const int64_t w = static_cast<int64_t>(shr_half_up(exp2_table()[static_cast<size_t>(j)], s));
  return Weight::from_raw(w);
}

ProbeFx::Angle vector_angle(ProbeFx::Sigma x0, ProbeFx::Sigma y0, bool seed_literal,
                            ProbeFx::Sigma& mag) {
  using Angle = ProbeFx::Angle;
  // Pre-rotation into the right half-plane: (x, y) → (−x, −y), z0 = ±π (atan2) or 0 (the seed's
  // atan folds the quadrant away).
  int64_t x = x0.raw(), y = y0.raw(), z = 0;
  if (x < 0) {
    x = -x;
    y = -y;
    if (!seed_literal)
      z = y0.raw() >= 0 ? Angle(std::numbers::pi).raw() : -Angle(std::numbers::pi).raw();
  }
  // Normalisation (leading-zero count, barrel shift): the larger of |x|, |y| gets its leading one
  // at bit kTop, so the truncating shifts cost 2^-kTop relative whatever the footprint's size;
  // the gain (≤ 1.65·√2) still fits below bit 62.
  constexpr int kTop = 59;
  const uint64_t big = static_cast<uint64_t>(std::max(x, y < 0 ? -y : y));
  const int norm = big == 0 ? 0 : kTop - (63 - std::countl_zero(big));
  x = norm >= 0 ? x << norm : x >> -norm;
  y = norm >= 0 ? y << norm : y >> -norm;
  const auto& at = atan_table();
  for (int i = 0; i < ProbeFx::kCordicSteps; ++i) {
    const int64_t xs = x >> i, ys = y >> i;  // arithmetic shifts truncate (toward −∞)
    if (y >= 0) {
      x += ys;
      y -= xs;
      z += at[static_cast<size_t>(i)];
    } else {
      x -= ys;
      y += xs;
      z -= at[static_cast<size_t>(i)];
    }
  }
  mag = vd_detail::from_wide<ProbeFx::Sigma>(
      x, ProbeFx::Sigma::kFracBits + norm);  // shift back, rounded
  return Angle::from_raw(z);
}

void rotate(ProbeFx::Vec r, ProbeFx::Angle theta, ProbeFx::Vec& xo, ProbeFx::Vec& yo) {
  int64_t x = r.raw(), y = 0, z = theta.raw();
  const auto& at = atan_table();
  for (int i = 0; i < ProbeFx::kCordicSteps; ++i) {
    const int64_t xs = x >> i, ys = y >> i;
    if (z >= 0) {
      x -= ys;
      y += xs;
      z -= at[static_cast<size_t>(i)];
    } else {
      x += ys;
      y -= xs;
      z += at[static_cast<size_t>(i)];
    }
  }
  xo = ProbeFx::Vec::from_raw(x);
  yo = ProbeFx::Vec::from_raw(y);
}

double cordic_gain() {
  double k = 1;
  for (int i = 0; i < ProbeFx::kCordicSteps; ++i) k *= std::sqrt(1.0 + std::ldexp(1.0, -2 * i));
  return k;
}

ProbeFx::Const inv_gain() {
  static const ProbeFx::Const c(1.0 / cordic_gain());
  return c;
}

int64_t count_quotient(int64_t a, int64_t b, bool& rem_zero) {
  constexpr int64_t kSat = int64_t{1} << ProbeFx::kCountSteps;
  if (a >= kSat * b) {  // the first step's compare: the quotient has more bits than the divider
    rem_zero = false;
    return kSat;
  }
  rem_zero = a % b == 0;
  return a / b;
}

OpCounts cordic_ops() {
  OpCounts o;
  o.add = 3 * ProbeFx::kCordicSteps;  // x, y shift-adds and the angle accumulator
  o.cmp = ProbeFx::kCordicSteps;      // direction: sign of y (vectoring) or z (rotation)
  return o;
}

OpCounts count_divider_ops() {
  OpCounts o;
  o.add = ProbeFx::kCountSteps;      // trial subtractions
  o.cmp = ProbeFx::kCountSteps + 1;  // restore/keep per step, remainder = 0
  return o;
}

}  // namespace probe_fx

OpCounts probe_footprint_fx_ops() {
  OpCounts o;
  // Non-finite test, Deriv converters (×w0·R, ×h0·R) and their saturation test: 1 cmp, 4 mul,
  // 1 cmp. Σ: 6 mul, 3 add. t, d = (Σuu ± Σvv)/2: 2 add. CORDIC vectoring: pre-rotation
  // (negate x, y; pick z0): 2 add, 2 cmp; normalisation (max |x|, |y|; leading-zero count):
  // 2 cmp; the steps; gain 1/K: 1 mul. λ± = t ± s: 2 add; λ₋ ≥ 0: 1 cmp. Clamp: λ₊·(1/maxA²)
  // 1 mul, compare with λ₋ 1 cmp, select 1 cmp.
  o.mul = 4 + 6 + 1 + 1;
  o.add = 3 + 2 + 2 + 2;
  o.cmp = 1 + 1 + 2 + 2 + 1 + 2;
  return o + probe_fx::cordic_ops();
}

ProbeFootprintFx probe_footprint_fx(const Fragment& f, int w0, int h0, double radius_px,
                                    double max_aniso, bool seed_theta) {
  using Deriv = ProbeFx::Deriv;
  using Sigma = ProbeFx::Sigma;
  using vd_detail::mul;
  ProbeFootprintFx fp;
  if (!std::isfinite(f.dudx) || !std::isfinite(f.dvdx) || !std::isfinite(f.dudy) ||
      !std::isfinite(f.dvdy)) {
    fp.bad_input = true;
    return fp;
  }
  // Converters: the derivative times w0·R rounded once into Deriv.
  const double sw = static_cast<double>(w0) * radius_px, sh = static_cast<double>(h0) * radius_px;
  const Deriv ux(f.dudx * sw), uy(f.dudy * sw), vx(f.dvdx * sh), vy(f.dvdy * sh);
  for (const Deriv d : {ux, uy, vx, vy}) {
    if (d.raw() == Deriv::kRawMax || d.raw() == Deriv::kRawMin) fp.overflow = true;
  }
  if (fp.overflow) return fp;
  const Sigma suu = mul<Sigma>(ux, ux) + mul<Sigma>(uy, uy);
  const Sigma suv = mul<Sigma>(ux, vx) + mul<Sigma>(uy, vy);
  const Sigma svv = mul<Sigma>(vx, vx) + mul<Sigma>(vy, vy);
  // (a ± b)/2 with the halving as one more fraction bit, rounded back.
  const auto half_sum = [](Sigma a, Sigma b, int sign) {
    const wide_int v = static_cast<wide_int>(a.raw()) + sign * static_cast<wide_int>(b.raw());
    return vd_detail::from_wide<Sigma>(v, Sigma::kFracBits + 1);
  };
  const Sigma t = half_sum(suu, svv, 1), d = half_sum(suu, svv, -1);
  Sigma mag;
  fp.two_theta = probe_fx::vector_angle(d, suv, seed_theta, mag);
  const Sigma s = mul<Sigma>(mag, probe_fx::inv_gain());
  const Sigma lp = t + s;
  Sigma lm = t - s;
  if (lm < Sigma(0)) lm = Sigma(0);
  const ProbeFx::Const inv_a2(1.0 / (max_aniso * max_aniso));
  const Sigma target = mul<Sigma>(lp, inv_a2);
  if (target > lm) {
    lm = target;
    fp.clamped = true;
  }
  fp.major2 = lp;
  fp.minor2 = lm;
  return fp;
}

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
  const std::vector<std::string_view> modes = {"wrap", "clamp", "mirror"};
  c.address_u = static_cast<AddressMode>(r.get_choice("address_u", 0, modes));
  c.address_v = static_cast<AddressMode>(r.get_choice("address_v", 0, modes));
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
        probe_fx::exp2_neg(Arg::from_raw(std::min<int64_t>(k * k * c.raw(), Arg::kRawMax)))
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
