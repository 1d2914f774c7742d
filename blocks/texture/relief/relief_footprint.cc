#include "blocks/texture/relief/relief_footprint.h"

#include <algorithm>
#include <cmath>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<ReliefFootprint>);

ReliefFootprint::Config ReliefFootprint::Config::from_toml(const ConfigReader& r) {
  Config c;
  c.mode = static_cast<Mode>(
      r.get_choice("footprint", 0, {"unshifted", "analytic", "quad", "quad_coarse"}));
  c.max_stretch = r.get_double("footprint_max_stretch", c.max_stretch);
  if (!(c.max_stretch >= 1 && c.max_stretch <= 1e6))
    r.fail("footprint_max_stretch", "must be in [1, 1e6]");
  return c;
}

void ReliefFootprint::gradient(const ReliefHeightMap& hm, double x, double y, double& hx,
                               double& hy) {
  hx = 0;
  hy = 0;
  if (!std::isfinite(x) || !std::isfinite(y) || hm.width <= 0 || hm.height <= 0) return;
  // The same cell and clamping as ReliefHeightMap::bilinear: the derivative of its two lerps.
  const double fx = std::floor(x), fy = std::floor(y);
  const double ax = x - fx, ay = y - fy;
  const auto ix = static_cast<int32_t>(std::clamp(fx, -1.0, static_cast<double>(hm.width)));
  const auto iy = static_cast<int32_t>(std::clamp(fy, -1.0, static_cast<double>(hm.height)));
  const double h00 = hm.texel(ix, iy), h10 = hm.texel(ix + 1, iy);
  const double h01 = hm.texel(ix, iy + 1), h11 = hm.texel(ix + 1, iy + 1);
  hx = (h10 - h00) + ((h11 - h01) - (h10 - h00)) * ay;
  hy = (h01 - h00) + ((h11 - h10) - (h01 - h00)) * ax;
}

ReliefFootprint::Derivs ReliefFootprint::analytic(const ReliefHeightMap& hm, Kind kind, double gx,
                                                  double gy, double sx, double sy, const Derivs& in,
                                                  OpCounts& ops) const {
  ops += ops_per_item();
  double hx = 0, hy = 0;
  gradient(hm, gx, gy, hx, hy);
  // Offset: J = I − l ∇hᵀ. Ray hit: d(depth) = −∇h·δ / (1 + ∇h·s), J = I − s ∇hᵀ / (1 + ∇h·s).
  double r = 1;
  if (kind == Kind::RayHit) r = 1 / std::max(1 + hx * sx + hy * sy, 1 / cfg_.max_stretch);
  if (!std::isfinite(r) || !std::isfinite(sx) || !std::isfinite(sy)) return in;
  const double kx = (hx * in.xx + hy * in.yx) * r, ky = (hx * in.xy + hy * in.yy) * r;
  return {in.xx - sx * kx, in.yx - sy * kx, in.xy - sx * ky, in.yy - sy * ky};
}

OpCounts ReliefFootprint::ops_per_item() const {
  OpCounts o;
  if (quad()) {
    count_quad(o);
    return o;
  }
  if (!active()) return o;
  // Derivatives to texels and back (8 mul); the gradient of the bilinear cell: 4 texels, the
  // fractions (2 add), two differences of differences and their lerps (8 add, 2 mul); 1 + ∇h·s
  // (2 mul, 2 add), its clamp and reciprocal; per screen axis ∇h·δ, ×r, and δ − s·k (5 mul,
  // 3 add).
  o.mem = 4;
  o.mul = 8 + 2 + 2 + 2 * 5;
  o.add = 2 + 8 + 2 + 2 * 3;
  o.cmp = 1;
  o.rcp = 1;
  return o;
}

OpCounts ReliefFootprint::critical_path() const {
  OpCounts p;
  if (quad()) {
    p.add = 1;  // one difference, once the neighbouring lane's shift is there
    return p;
  }
  if (!active()) return p;
  // Read, gradient (add, add, mul, add), 1 + ∇h·s (mul, add, add), clamp, rcp, ×r after
  // ∇h·δ, s·k, δ − s·k, and the scale back to normalised units.
  p.mem = 1;
  p.add = 3 + 2 + 1;
  p.mul = 1 + 1 + 1 + 1 + 1;
  p.cmp = 1;
  p.rcp = 1;
  return p;
}

TimingSpec ReliefFootprint::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), critical_path(), cfg_.datapath);
}

const char* ReliefFootprint::mode_name(Mode m) {
  switch (m) {
    case Mode::Unshifted:
      return "unshifted";
    case Mode::Analytic:
      return "analytic";
    case Mode::QuadFine:
      return "quad";
    case Mode::QuadCoarse:
      return "quad_coarse";
  }
  return "unshifted";
}

std::string ReliefFootprint::name() const {
  return std::string("relief.footprint[") + mode_name(cfg_.mode) + "]";
}

}  // namespace texsim
