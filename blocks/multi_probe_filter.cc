#include "blocks/multi_probe_filter.h"

#include "blocks/texel_blend.h"

#include <algorithm>
#include <cmath>

namespace texsim {

OpCounts probe_blend_ops() {
  OpCounts o;
  o.mul = 4;      // w_k · probe colour
  o.add = 4 + 1;  // accumulate RGBA, Σw
  return o;
}

OpCounts trilinear_probe_blend_ops() { return TexelBlend::ops_per_tap() * 8 + probe_blend_ops(); }

OpCounts probe_normalise_ops() {
  OpCounts o;
  o.cmp = 1;
  o.rcp = 1;
  o.mul = 4;
  return o;
}

FilterOutput run_probes(const TexelAddressGen& addr, const Texture& tex, const ProbeSet& probes,
                        std::vector<TexelRef>* fetched, OpCounts& ops) {
  FilterOutput out;
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
    ops += TexelBlend::ops_per_tap() * static_cast<uint64_t>(taps.count);
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

MultiProbeFilter::Config MultiProbeFilter::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"alpha", "max_probes", "weight_alpha", "radius_px", "max_aniso", "seed_theta",
                    "temporal", "address_u", "address_v"});
  Config c;
  c.alpha = r.get_double("alpha", c.alpha);
  if (!(c.alpha >= 0.25) || !(c.alpha <= 16)) r.fail("alpha", "must be in [0.25, 16]");
  c.max_probes = static_cast<int>(r.get_int("max_probes", c.max_probes, 1, ProbeSet::kMax));
  if (c.max_probes % 2 == 0) r.fail("max_probes", "must be odd (probes sit symmetrically about the centre)");
  c.weight_alpha = r.get_double("weight_alpha", c.weight_alpha);
  if (!(c.weight_alpha >= 0) || !(c.weight_alpha <= 64)) r.fail("weight_alpha", "must be in [0, 64]");
  c.radius_px = r.get_double("radius_px", c.radius_px);
  if (!(c.radius_px > 0) || !(c.radius_px <= 16)) r.fail("radius_px", "must be in (0, 16]");
  c.max_aniso = r.get_double("max_aniso", c.max_aniso);
  if (!(c.max_aniso >= 1) || !(c.max_aniso <= 1024)) r.fail("max_aniso", "must be in [1, 1024]");
  c.seed_theta = r.get_bool("seed_theta", c.seed_theta);
  c.temporal = r.get_bool("temporal", c.temporal);
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
  ProbeSet p;
  ops += setup_ops();
  const int w0 = tex.width(0), h0 = tex.height(0);
  OpCounts scratch;  // setup_ops() already holds the footprint set-up
  const Footprint fp = footprint_setup<float>(f, w0, h0, cfg_.radius_px, cfg_.max_aniso, scratch);
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

FilterOutput MultiProbeFilter::filter(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                                      OpCounts& ops) const {
  FilterStats st;
  const ProbeSet p = probes(tex, f, ops, &st);
  OpCounts per;
  per.mul = 2 + 1;  // position k·(du, dv), d²·w_α
  per.add = 2;
  per.lut = 1;      // exp
  ops += per * static_cast<uint64_t>(p.n);
  FilterOutput o = run_probes(addr_, tex, p, fetched, ops);
  o.stats.bad_input = st.bad_input;
  return o;
}

OpCounts MultiProbeFilter::setup_ops() const {
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

OpCounts MultiProbeFilter::per_probe_ops() const {
  OpCounts o;
  o.mul = 3;
  o.add = 2;
  o.lut = 1;
  o += addr_.ops_per_probe(false) + trilinear_probe_blend_ops();
  return o;
}

TimingSpec MultiProbeFilter::timing(const TechTable& tech) const {
  // Set-up: derivatives → Σ → eigenvalues → √ → rcp → N → step → position; then one probe's
  // address path and the blend, then normalisation.
  OpCounts path;
  path.mul = 1 + 1 + 1 + 1 + 1;
  path.add = 1 + 1 + 1 + 1;
  path.sqrt = 2;
  path.rcp = 2;
  path.lut = 1;
  path.cmp = 2;
  const TimingSpec a = addr_.timing(tech);
  OpCounts tail;
  tail.mem = 1;
  tail.mul = 2;
  tail.add = 4;
  tail.rcp = 1;
  TimingSpec t;
  t.latency = static_cast<uint32_t>(std::ceil(tech.path_latency(path) + tech.path_latency(tail))) + a.latency;
  t.ii = 1;
  t.lanes = 1;
  OpCounts lane = per_probe_ops();
  lane.mem = 0;
  t.area = tech.area_of(setup_ops()) + tech.area_of(lane) + tech.area_of(probe_normalise_ops());
  return t;
}

}  // namespace texsim
