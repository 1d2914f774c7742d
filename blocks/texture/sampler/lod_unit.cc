#include "blocks/texture/sampler/lod_unit.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "blocks/base/block.h"

namespace texsim {

static_assert(Block<LodUnit>);

namespace {

// Latency of the slower of two parallel branches.
double slower(const TechTable& t, const OpCounts& a, const OpCounts& b) {
  return std::max(t.path_latency(a), t.path_latency(b));
}

}  // namespace

LodUnit::Config LodUnit::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"aniso", "max_aniso", "lod_bias", "min_lod", "max_lod"});
  Config c;
  c.aniso = static_cast<AnisoMode>(r.get_choice("aniso", 0, {"isotropic", "vulkan"}));
  c.max_aniso = static_cast<int>(r.get_int("max_aniso", c.max_aniso, 1, 16));
  c.lod_bias = static_cast<float>(r.get_double("lod_bias", c.lod_bias));
  c.min_lod = static_cast<float>(r.get_double("min_lod", c.min_lod));
  c.max_lod = static_cast<float>(r.get_double("max_lod", c.max_lod));
  // Vulkan leaves λ undefined when lodmin > lodmax; a scene asking for it is an error.
  if (c.min_lod > c.max_lod) r.fail("min_lod", "must be <= max_lod");
  return c;
}

OpCounts LodUnit::count_ops(const Config& c) {
  OpCounts o;
  // Derivatives to texels (4 mul), squared lengths |(mux,mvx)|², |(muy,mvy)|² (4 mul, 2 add).
  // λ = ½·log2(ρ²) needs no square root: the ½ is an exponent decrement (1 add).
  o.mul = 8;
  o.add = 2 + 1;
  o.cmp = 1;   // ρmax² = max(ρx², ρy²)
  o.lut = 1;   // log2
  o.add += 2;  // sampler bias + fragment bias, then λ_base + bias
  o.cmp += 2;  // clamp to [min_lod, max_lod]
  if (c.aniso == AnisoMode::Vulkan) {
    o.cmp += 1;      // ρmin² = min(ρx², ρy²)
    o.div += 1;      // ρmax²/ρmin²
    o.sqrt += 1;     // ρmax/ρmin
    o.cmp += 1 + 2;  // η = min(ratio, maxAniso); the ρ = 0 special cases
    o.add += 1;      // N = ⌈η⌉ (round up)
    o.lut += 1;      // log2 N (N ≤ 16: a 16-entry table)
    o.add += 1;      // λ_base = ½log2 ρmax² − log2 N
    o.lut += 1;      // 1/N (16-entry table)
    o.cmp += 1;      // major axis select (x or y derivatives)
    o.mul += 2;      // probe step = major vector / N
  }
  return o;
}

OpCounts LodUnit::ops_for(SampleOp op) const {
  if (op != SampleOp::kSampleLod) return ops_;
  OpCounts o;
  o.add = 1;  // λ_base + sampler bias
  o.cmp = 3;  // the select of λ_base, the clamp to [min_lod, max_lod]
  return o;
}

TimingSpec LodUnit::timing(const TechTable& tech) const {
  // Common front: scale (mul), square (mul), sum (add), max (cmp).
  OpCounts front;
  front.mul = 2;
  front.add = 1;
  front.cmp = 1;
  // Back: bias add, clamp (2 cmp).
  OpCounts back;
  back.add = 1;
  back.cmp = 2;
  double lat = 0;
  if (cfg_.aniso == AnisoMode::Isotropic) {
    OpCounts log_path;
    log_path.lut = 1;
    log_path.add = 1;  // ½
    lat = tech.path_latency(front) + tech.path_latency(log_path) + tech.path_latency(back);
  } else {
    // N path: div, sqrt, min with maxAniso, special cases, round up.
    OpCounts n_path;
    n_path.div = 1;
    n_path.sqrt = 1;
    n_path.cmp = 2;
    n_path.add = 1;
    // After N: log2 N and subtract, then bias and clamp; in parallel 1/N and the axis multiply.
    OpCounts lam_path;
    lam_path.lut = 1;
    lam_path.add = 1;
    lam_path += back;
    OpCounts axis_path;
    axis_path.lut = 1;
    axis_path.mul = 1;
    lat = tech.path_latency(front) + tech.path_latency(n_path) + slower(tech, lam_path, axis_path);
  }
  return derive_timing(tech, ops_per_item(), lat, Datapath::Spatial);
}

}  // namespace texsim
