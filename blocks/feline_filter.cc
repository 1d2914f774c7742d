#include "blocks/feline_filter.h"

#include <algorithm>
#include <cmath>

namespace texsim {

FelineFilter::Config FelineFilter::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"axis", "weights", "max_probes", "weight_alpha", "radius_px", "max_aniso", "address_u",
                    "address_v"});
  Config c;
  c.axis = static_cast<Axis>(r.get_choice("axis", static_cast<int>(c.axis), {"parallelogram", "ellipse"}));
  c.weights = static_cast<Weights>(r.get_choice("weights", static_cast<int>(c.weights), {"equal", "gaussian"}));
  c.max_probes = static_cast<int>(r.get_int("max_probes", c.max_probes, 1, ProbeSet::kMax));
  c.weight_alpha = r.get_double("weight_alpha", c.weight_alpha);
  if (!(c.weight_alpha >= 0) || !(c.weight_alpha <= 64)) r.fail("weight_alpha", "must be in [0, 64]");
  c.radius_px = r.get_double("radius_px", c.radius_px);
  if (!(c.radius_px > 0) || !(c.radius_px <= 16)) r.fail("radius_px", "must be in (0, 16]");
  c.max_aniso = r.get_double("max_aniso", c.max_aniso);
  if (!(c.max_aniso >= 1) || !(c.max_aniso <= 1024)) r.fail("max_aniso", "must be in [1, 1024]");
  const std::vector<std::string_view> modes = {"wrap", "clamp", "mirror"};
  c.address_u = static_cast<AddressMode>(r.get_choice("address_u", 0, modes));
  c.address_v = static_cast<AddressMode>(r.get_choice("address_v", 0, modes));
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

ProbeSet FelineFilter::probes(const Texture& tex, const Fragment& f, OpCounts& ops, FilterStats* st) const {
  ProbeSet p;
  ops += setup_ops();
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
    const Footprint fp = footprint_setup<float>(f, static_cast<int>(w0), static_cast<int>(h0), R,
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
  if (minor > 0) n = static_cast<int>(std::min(std::ceil(len / minor - 1e-9), static_cast<double>(cfg_.max_probes)));
  else n = cfg_.max_probes;
  n = std::clamp(n, 1, cfg_.max_probes);
  p.lambda = static_cast<float>(std::log2(std::max(minor, len / n)) + f.lod_bias);
  p.n = n;
  for (int k = 0; k < n; ++k) {
    const double t = static_cast<double>(2 * k + 1 - n) / n;
    const auto i = static_cast<size_t>(k);
    p.u[i] = u + t * lu / w0;
    p.v[i] = v + t * lv / h0;
    p.w[i] = cfg_.weights == Weights::Equal ? 1.0f : static_cast<float>(std::exp(-cfg_.weight_alpha * t * t));
  }
  return p;
}

FilterOutput FelineFilter::filter(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                                  OpCounts& ops) const {
  FilterStats st;
  const ProbeSet p = probes(tex, f, ops, &st);
  OpCounts per;
  per.mul = 2;  // t·(lu, lv)
  per.add = 2;
  if (cfg_.weights == Weights::Gaussian) {
    per.mul += 1;
    per.lut += 1;
  }
  ops += per * static_cast<uint64_t>(p.n);
  FilterOutput o = run_probes(addr_, tex, p, fetched, ops);
  o.stats.bad_input = st.bad_input;
  return o;
}

OpCounts FelineFilter::setup_ops() const {
  OpCounts o;
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

OpCounts FelineFilter::per_probe_ops() const {
  OpCounts o;
  o.mul = 2;
  o.add = 2;
  if (cfg_.weights == Weights::Gaussian) {
    o.mul += 1;
    o.lut += 1;
  }
  o += addr_.ops_per_probe(false) + trilinear_probe_blend_ops();
  return o;
}

TimingSpec FelineFilter::timing(const TechTable& tech) const {
  OpCounts path;
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
  OpCounts tail;
  tail.mem = 1;
  tail.mul = 2;
  tail.add = 4;
  tail.rcp = 1;
  TimingSpec t;
  t.latency = static_cast<uint32_t>(std::ceil(tech.path_latency(path) + tech.path_latency(tail))) +
              addr_.timing(tech).latency;
  t.ii = 1;
  t.lanes = 1;
  OpCounts lane = per_probe_ops();
  lane.mem = 0;
  t.area = tech.area_of(setup_ops()) + tech.area_of(lane) + tech.area_of(probe_normalise_ops());
  return t;
}

}  // namespace texsim
