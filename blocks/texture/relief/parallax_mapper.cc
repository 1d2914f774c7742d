#include "blocks/texture/relief/parallax_mapper.h"

#include <algorithm>
#include <cmath>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<ParallaxMapper>);

namespace {

// One bilinear height read: 4 texels, 3 lerps.
void count_sample(OpCounts& ops) {
  ops.mem += 4;
  ops.mul += 3;
  ops.add += 6;
}

}  // namespace

ParallaxMapper::Config ParallaxMapper::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"method", "depth_texels", "offset_limiting", "min_view_z", "min_layers",
                    "max_layers", "binary_steps", "datapath"});
  Config c;
  c.method = static_cast<Method>(r.get_choice("method", 1, {"offset", "iterative"}));
  c.depth_texels = r.get_double("depth_texels", c.depth_texels);
  c.offset_limiting = r.get_bool("offset_limiting", c.offset_limiting);
  c.min_view_z = r.get_double("min_view_z", c.min_view_z);
  c.min_layers = static_cast<int32_t>(r.get_int("min_layers", c.min_layers, 1, 1024));
  c.max_layers = static_cast<int32_t>(r.get_int("max_layers", c.max_layers, 1, 1024));
  c.binary_steps = static_cast<int32_t>(r.get_int("binary_steps", c.binary_steps, 0, 32));
  c.datapath = parse_datapath(r, c.datapath);
  if (!(c.depth_texels >= 0 && c.depth_texels <= 1024))
    r.fail("depth_texels", "must be in [0, 1024]");
  if (!(c.min_view_z > 0 && c.min_view_z <= 1)) r.fail("min_view_z", "must be in (0, 1]");
  if (c.max_layers < c.min_layers) r.fail("max_layers", "must be >= min_layers");
  return c;
}

ParallaxMapper::Result ParallaxMapper::map(const ReliefHeightMap& hm, double u, double v, double vx,
                                           double vy, double vz, OpCounts& ops,
                                           std::vector<ReliefRead>* reads) const {
  Result res;
  res.u = u;
  res.v = v;
  ops += fragment_setup_ops();
  const double len = std::sqrt(vx * vx + vy * vy + vz * vz);
  if (!std::isfinite(u) || !std::isfinite(v) || !std::isfinite(len) || !(len > 0) ||
      hm.width <= 0 || hm.height <= 0) {
    res.bad_input = true;
    return res;
  }
  const double nx = vx / len, ny = vy / len, nz = std::max(vz / len, cfg_.min_view_z);
  // Texel shift per unit depth (0..1) along the ray into the relief.
  const double sx = -nx / nz * cfg_.depth_texels, sy = -ny / nz * cfg_.depth_texels;
  if (cfg_.method == Method::Offset) {
    return offset(hm, u, v, sx, sy, -nx * cfg_.depth_texels, -ny * cfg_.depth_texels, ops, reads);
  }
  return iterative(hm, u, v, sx, sy, nz, ops, reads);
}

ParallaxMapper::Result ParallaxMapper::offset(const ReliefHeightMap& hm, double u, double v,
                                              double sx, double sy, double lx, double ly,
                                              OpCounts& ops, std::vector<ReliefRead>* reads) const {
  Result res;
  const double depth = 1.0 - hm.bilinear(u, v);
  if (reads) hm.bilinear_texels(u, v, *reads);
  count_sample(ops);
  res.samples = 1;
  res.linear_steps = 1;
  res.depth = depth;
  res.u = u + (cfg_.offset_limiting ? lx : sx) * depth;
  res.v = v + (cfg_.offset_limiting ? ly : sy) * depth;
  ops.add += 3;
  ops.mul += 2;
  return res;
}

ParallaxMapper::Result ParallaxMapper::iterative(const ReliefHeightMap& hm, double u, double v,
                                                 double sx, double sy, double vz, OpCounts& ops,
                                                 std::vector<ReliefRead>* reads) const {
  Result res;
  // Layers from min (normal incidence) to max (grazing): the iteration cap.
  const auto n =
      static_cast<int32_t>(std::lround(cfg_.max_layers + (cfg_.min_layers - cfg_.max_layers) * vz));
  const double step = 1.0 / std::max(n, 1);
  // Linear search: the first layer at or below the surface. Depth 1 is always at or below it.
  double d_prev = 0, d = 0;
  for (int32_t i = 0; i <= n; ++i) {
    d = std::min(i * step, 1.0);
    const double surf = 1.0 - hm.bilinear(u + sx * d, v + sy * d);
    if (reads) hm.bilinear_texels(u + sx * d, v + sy * d, *reads);
    count_sample(ops);
    ops.add += 4;  // u, v, depth, 1 - h
    ops.cmp += 1;
    ++res.samples;
    ++res.linear_steps;
    if (d >= surf) break;
    d_prev = d;
  }
  // Binary refinement of the bracket [d_prev, d].
  double lo = d_prev, hi = d;
  if (res.linear_steps > 1) {
    for (int32_t k = 0; k < cfg_.binary_steps; ++k) {
      const double mid = 0.5 * (lo + hi);
      const double surf = 1.0 - hm.bilinear(u + sx * mid, v + sy * mid);
      if (reads) hm.bilinear_texels(u + sx * mid, v + sy * mid, *reads);
      count_sample(ops);
      ops.add += 4;
      ops.mul += 2;
      ops.cmp += 1;
      ++res.samples;
      ++res.binary_steps;
      (mid >= surf ? hi : lo) = mid;
    }
  }
  res.depth = hi;
  res.u = u + sx * hi;
  res.v = v + sy * hi;
  return res;
}

OpCounts ParallaxMapper::ops_per_item() const {
  OpCounts o;
  count_sample(o);
  o.add += 4;
  o.mul += 2;
  o.cmp += 1;
  return o;
}

OpCounts ParallaxMapper::critical_path() const {
  // Address, read, lerps, compare: the loop-carried chain of one step.
  OpCounts p;
  p.mul = 3;
  p.add = 3;
  p.mem = 1;
  p.cmp = 1;
  return p;
}

OpCounts ParallaxMapper::fragment_setup_ops() const {
  // |V| (3 mul, 2 add, sqrt), V/|V| (rcp, 3 mul), clamp of V.z, 1/V.z and the two shifts
  // (rcp, 4 mul), the layer count (1 mul, 1 add, 1 round as cmp), input checks (1 cmp).
  OpCounts o;
  o.mul = 3 + 3 + 4 + 1;
  o.add = 2 + 1;
  o.sqrt = 1;
  o.rcp = 2;
  o.cmp = 3;
  return o;
}

TimingSpec ParallaxMapper::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), critical_path(), cfg_.datapath, 1, fragment_setup_ops());
}

}  // namespace texsim
