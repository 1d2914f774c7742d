#include "blocks/texture/relief/terrain_ray_marcher.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<TerrainRayMarcher>);

TerrainRayMarcher::Config TerrainRayMarcher::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"function", "deformation", "blend_shift", "step", "altitude_step", "max_steps",
                    "refine_steps", "normal", "normal_epsilon", "datapath"});
  Config c;
  c.evaluator.basis.kind =
      static_cast<FiniteKind>(r.get_choice("function", 0, {"cosine", "quadratic", "exp2", "tent"}));
  c.evaluator.basis.deformation =
      static_cast<Deformation>(r.get_choice("deformation", 0, {"none", "widened", "blended"}));
  c.evaluator.basis.blend_shift = static_cast<int32_t>(r.get_int("blend_shift", 1, 0, 30));
  c.step = r.get_double("step", c.step);
  c.altitude_step = r.get_double("altitude_step", c.altitude_step);
  c.max_steps = static_cast<int32_t>(r.get_int("max_steps", c.max_steps, 1, 1 << 20));
  c.refine_steps = static_cast<int32_t>(r.get_int("refine_steps", c.refine_steps, 0, 52));
  c.normal = static_cast<NormalMode>(r.get_choice("normal", 0, {"gradient", "central"}));
  c.normal_epsilon = r.get_double("normal_epsilon", c.normal_epsilon);
  c.datapath = parse_datapath(r, c.datapath);
  if (!(c.step > 0 && c.step <= 1e6)) r.fail("step", "must be in (0, 1e6]");
  if (!(c.altitude_step >= 0 && c.altitude_step <= 100))
    r.fail("altitude_step", "must be in [0, 100] (0: off)");
  if (!(c.normal_epsilon > 0 && c.normal_epsilon <= 1))
    r.fail("normal_epsilon", "must be in (0, 1]");
  return c;
}

TerrainRayMarcher::Result TerrainRayMarcher::march(const AviationCamera& cam, const TerrainGrid& g,
                                                   double top, double xs, double ys,
                                                   OpCounts& ops) const {
  Result r = march_ray(g, top, cam.eye(), cam.view_vector(xs, ys), ops);
  if (r.hit) {
    r.normal = normal_at(g, r.point.x, r.point.z, r, ops);
    r.fetches = r.evaluations * static_cast<uint32_t>(eval_.fetches_per_item());
  }
  return r;
}

TerrainRayMarcher::Result TerrainRayMarcher::march_ray(const TerrainGrid& g, double top,
                                                       const glm::dvec3& eye, const glm::dvec3& v,
                                                       OpCounts& ops,
                                                       std::vector<ReliefRead>* reads) const {
  Result r;
  ops += ray_setup_ops();
  const double len = glm::length(v);
  const bool eye_ok = std::isfinite(eye.x) && std::isfinite(eye.y) && std::isfinite(eye.z);
  if (!eye_ok || !std::isfinite(len) || !(len > 0) || !std::isfinite(top) || g.nx <= 0 ||
      g.nz <= 0) {
    return r;
  }
  const glm::dvec3 d = v / len;
  std::vector<TerrainNode> nodes;  // the evaluator's reads (only when `reads` is given)
  std::vector<TerrainNode>* const log = reads ? &nodes : nullptr;
  auto height = [&](double t) {
    ++r.evaluations;
    const glm::dvec3 p = eye + t * d;
    const double y = p.y - eval_.height(g, p.x, p.z, ops, log);  // < 0: below the surface
    if (reads) {
      for (const TerrainNode& n : nodes) reads->push_back({n.i, n.j, ReliefRead::kHeightRead});
      nodes.clear();
    }
    return y;
  };
  double t = 0;
  if (eye.y > top) {
    if (!(d.y < 0)) return r;  // above every height, going up or level: sky
    t = (eye.y - top) / -d.y;  // skip to the top of the height field
  }
  double t_prev = t;
  for (;;) {
    if (r.steps >= static_cast<uint32_t>(cfg_.max_steps)) {
      r.capped = true;
      break;
    }
    const glm::dvec3 p = eye + t * d;
    if (p.y > top && !(d.y < 0)) break;  // climbed out above the field
    ++r.steps;
    ops.mul += 3;
    ops.add += 3;
    ops.cmp += 2;
    const double above = height(t);
    if (above < 0) {
      r.hit = true;
      break;
    }
    t_prev = t;
    if (cfg_.altitude_step > 0) {  // step ∝ the height above the ground here
      t += std::max(cfg_.step, cfg_.altitude_step * above);
      ops.mul += 1;
      ops.cmp += 1;
    } else {
      t += cfg_.step;
    }
  }
  if (r.hit) {
    double lo = t_prev, hi = t;  // lo above (or the start), hi below
    for (int32_t k = 0; k < cfg_.refine_steps && hi > lo; ++k) {
      const double mid = 0.5 * (lo + hi);
      (height(mid) < 0 ? hi : lo) = mid;
      ++r.refinements;
      ops.mul += 3;
      ops.add += 4;
      ops.cmp += 1;
    }
    r.t = hi;
    r.point = eye + hi * d;
  }
  r.fetches = r.evaluations * static_cast<uint32_t>(eval_.fetches_per_item());
  return r;
}

glm::dvec3 TerrainRayMarcher::normal_at(const TerrainGrid& g, double x, double z, Result& r,
                                        OpCounts& ops) const {
  double gx = 0, gz = 0;
  if (cfg_.normal == NormalMode::Gradient) {
    const auto s = eval_.sample(g, x, z, ops);
    gx = s.dydx;
    gz = s.dydz;
    r.evaluations += 1;
  } else {
    const double e = cfg_.normal_epsilon;
    gx = (eval_.height(g, x + e, z, ops) - eval_.height(g, x - e, z, ops)) / (2 * e);
    gz = (eval_.height(g, x, z + e, ops) - eval_.height(g, x, z - e, ops)) / (2 * e);
    r.evaluations += 4;
    ops.add += 6;
    ops.mul += 2;
  }
  // N = (-∂y/∂x, 1, -∂y/∂z) normalised.
  ops.mul += 3 + 3;
  ops.add += 2;
  ops.sqrt += 1;
  ops.rcp += 1;
  return glm::normalize(glm::dvec3(-gx, 1.0, -gz));
}

double TerrainRayMarcher::top_bound(const TerrainGrid& g) const {
  // Weights are >= 0 and sum to 1 (2 × 2 supports) or to at most 1.0408 (variant 1's measured
  // worst 2-D sum, docs/derivations/terrain.md §3): 10 % covers it.
  const double m = g.max_height();
  return eval_.config().basis.deformation == Deformation::Widened ? m + 0.1 * std::fabs(m) : m;
}

OpCounts TerrainRayMarcher::ops_per_item() const {
  OpCounts o = eval_.ops_per_item();
  o.mul += 3;
  o.add += 3 + 1;                // p = eye + t·d, y - h
  o.cmp += 2;                    // below? above the field?
  if (cfg_.altitude_step > 0) {  // k·(Y - y) and the max with dt
    o.mul += 1;
    o.cmp += 1;
  }
  return o;
}

OpCounts TerrainRayMarcher::critical_path() const {
  OpCounts p = eval_.critical_path();
  p.mul += 1;
  p.add += 2;
  p.cmp += 1;
  if (cfg_.altitude_step > 0) {  // the next t waits for k·(Y - y) and the max
    p.mul += 1;
    p.cmp += 1;
  }
  return p;
}

OpCounts TerrainRayMarcher::ray_setup_ops() const {
  static const OpCounts kView = AviationCamera().ops_per_item();  // the view vector
  OpCounts o = kView;
  o.mul += 3 + 3;
  o.add += 2;
  o.sqrt += 1;
  o.rcp += 1;
  o.div += 1;  // the skip to `top`
  o.cmp += 2;
  return o;
}

TimingSpec TerrainRayMarcher::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), critical_path(), cfg_.datapath, 1, ray_setup_ops());
}

}  // namespace texsim
