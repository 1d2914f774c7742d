#include "blocks/texture/relief/sphere_tracer.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<SphereTracer>);

SphereTracer::Config SphereTracer::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"max_iterations", "min_step", "safety", "datapath"});
  Config c;
  c.max_iterations =
      static_cast<int32_t>(r.get_int("max_iterations", c.max_iterations, 1, 1 << 16));
  c.min_step = r.get_double("min_step", c.min_step);
  c.safety = r.get_double("safety", c.safety);
  c.datapath = parse_datapath(r, c.datapath);
  if (!(c.min_step >= 0 && c.min_step <= 16)) r.fail("min_step", "must be in [0, 16]");
  if (!(c.safety >= 0 && c.safety <= 4)) r.fail("safety", "must be in [0, 4]");
  if (c.safety > 0 && !(c.min_step > 0)) r.fail("min_step", "must be > 0 when safety > 0");
  return c;
}

SphereTracer::Result SphereTracer::trace(const DistanceMap& m, const glm::dvec3& start,
                                         const glm::dvec3& dir, OpCounts& ops,
                                         std::vector<ReliefRead>* reads) const {
  Result res;
  res.pos = start;
  ops += ray_setup_ops();
  const double len = glm::length(dir);
  const bool finite = std::isfinite(start.x) && std::isfinite(start.y) && std::isfinite(start.z) &&
                      std::isfinite(len);
  if (!finite || !(len > 0) || m.width <= 0 || m.height <= 0 || m.depth <= 0) return res;
  const glm::dvec3 d = dir / len;
  glm::dvec3 p = start;
  const double top = m.depth - 0.5;
  if (p.z >= top) {
    if (!(d.z < 0)) {
      res.status = Status::Miss;
      return res;
    }
    p += d * ((p.z - top) / -d.z + 1e-9);  // onto the top face, just inside
  }
  for (;;) {
    res.pos = p;
    if (p.z < -0.5) {  // below the top of the base layer: the base is solid
      res.status = Status::Hit;
      return res;
    }
    const auto ix = static_cast<int64_t>(std::floor(p.x + 0.5));
    const auto iy = static_cast<int64_t>(std::floor(p.y + 0.5));
    const auto iz = static_cast<int64_t>(std::floor(p.z + 0.5));
    if (ix < 0 || ix >= m.width || iy < 0 || iy >= m.height || iz >= m.depth) {
      res.status = Status::Miss;
      return res;
    }
    const double dist = m.at(static_cast<int32_t>(ix), static_cast<int32_t>(iy),
                             static_cast<int32_t>(std::max<int64_t>(iz, 0)));
    ++res.fetches;
    if (reads) {
      reads->push_back({static_cast<int32_t>(ix), static_cast<int32_t>(iy),
                        static_cast<int32_t>(std::max<int64_t>(iz, 0))});
    }
    ops.mem += 1;
    ops.cmp += 4;  // the three bounds and the hit test
    if (!(dist > 0)) {
      res.status = Status::Hit;
      return res;
    }
    if (res.iterations >= static_cast<uint32_t>(cfg_.max_iterations)) {
      res.status = Status::Capped;
      return res;
    }
    p += d * std::max(dist - cfg_.safety, cfg_.min_step);
    ++res.iterations;
    ops.mul += 3;
    ops.add += 3 + (cfg_.safety > 0 ? 1 : 0);
    ops.cmp += 1;  // max with min_step
  }
}

OpCounts SphereTracer::ops_per_item() const {
  OpCounts o;
  o.mem = 1;
  o.cmp = 5;  // bounds (3), hit test, max with min_step
  o.mul = 3;  // d·s
  o.add = 3;  // p += d·s
  return o;
}

OpCounts SphereTracer::critical_path() const {
  // The loop-carried chain: read at p, compare, step, add to p.
  OpCounts p;
  p.mem = 1;
  p.cmp = 2;
  p.mul = 1;
  p.add = 1;
  return p;
}

OpCounts SphereTracer::ray_setup_ops() const {
  // |d| (3 mul, 2 add, sqrt), 1/|d| and 3 products, the entry onto the top face (1 div,
  // 3 mul-adds, 1 compare).
  OpCounts o;
  o.mul = 3 + 3 + 3;
  o.add = 2 + 3 + 1;
  o.sqrt = 1;
  o.rcp = 1;
  o.div = 1;
  o.cmp = 1;
  return o;
}

TimingSpec SphereTracer::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), critical_path(), cfg_.datapath, 1, ray_setup_ops());
}

}  // namespace texsim
