#include "blocks/raster/object_space_raster.h"

#include <algorithm>
#include <cmath>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/base/derive_timing.h"

namespace texsim {

static_assert(Block<ObjectSpaceRaster>);

ObjectSpaceRaster::Config ObjectSpaceRaster::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"max_step_px", "lanes"});
  Config c;
  c.max_step_px = r.get_double("max_step_px", c.max_step_px);
  if (!(c.max_step_px > 0 && c.max_step_px <= 4)) r.fail("max_step_px", "must be in (0, 4]");
  c.lanes = static_cast<int>(r.get_int("lanes", c.lanes, 1, 64));
  return c;
}

double ObjectSpaceRaster::max_screen_scale(const std::vector<glm::dvec3>& view, double focal_px,
                                           OpCounts& ops) {
  double inv_z = 0, q2 = 0;
  for (const glm::dvec3& p : view) {
    ops.rcp += 1;
    ops.mul += 5;
    ops.add += 2;
    ops.cmp += 2;
    if (!(p.z > 0)) return 0;
    const double iz = 1.0 / p.z;
    const double qx = p.x * iz, qy = p.y * iz;
    inv_z = std::max(inv_z, iz);
    q2 = std::max(q2, qx * qx + qy * qy);
  }
  ops.sqrt += 1;
  ops.mul += 1;
  ops.add += 1;
  return focal_px * inv_z * std::sqrt(1 + q2);
}

double ObjectSpaceRaster::step(double jmax, OpCounts& ops) const {
  ops.rcp += 1;
  ops.mul += 1;
  if (!(jmax > 0) || !std::isfinite(jmax)) return 0;
  return cfg_.max_step_px / jmax;
}

double ObjectSpaceRaster::lod(const PlaneUvMap& m, double h, int tw, int th, OpCounts& ops) {
  ops.mul += 4 + 2;
  ops.add += 2;
  ops.cmp += 1;
  ops.sqrt += 1;
  ops.lut += 1;
  const double ax = m.ux * tw, ay = m.vx * th, bx = m.uy * tw, by = m.vy * th;
  const double len2 = std::max(ax * ax + ay * ay, bx * bx + by * by);
  if (!(len2 > 0)) return 0;
  return std::log2(h * std::sqrt(len2));
}

PlaneUvMap ObjectSpaceRaster::uv_map(const glm::dvec2 p[3], const glm::dvec2 uv[3], OpCounts& ops) {
  // Solve the 2 × 2 system of the two edges from vertex 0 (Cramer).
  const double e1x = p[1].x - p[0].x, e1y = p[1].y - p[0].y;
  const double e2x = p[2].x - p[0].x, e2y = p[2].y - p[0].y;
  const double det = e1x * e2y - e2x * e1y;
  ops.add += 4 + 1 + 4 + 4;
  ops.mul += 2 + 8 + 4;
  ops.rcp += 1;
  PlaneUvMap m;
  if (det == 0) {
    m.u0 = uv[0].x;
    m.v0 = uv[0].y;
    return m;
  }
  const double inv = 1.0 / det;
  const double du1 = uv[1].x - uv[0].x, du2 = uv[2].x - uv[0].x;
  const double dv1 = uv[1].y - uv[0].y, dv2 = uv[2].y - uv[0].y;
  m.ux = (du1 * e2y - du2 * e1y) * inv;
  m.uy = (du2 * e1x - du1 * e2x) * inv;
  m.vx = (dv1 * e2y - dv2 * e1y) * inv;
  m.vy = (dv2 * e1x - dv1 * e2x) * inv;
  m.u0 = uv[0].x - m.ux * p[0].x - m.uy * p[0].y;
  m.v0 = uv[0].y - m.vx * p[0].x - m.vy * p[0].y;
  return m;
}

double ObjectSpaceRaster::sample_bound(const RotatedPolygon& poly, double h) {
  if (!(h > 0)) return 0;
  double area2 = 0, perim = 0, w = 0, hgt = 0;
  const size_t n = poly.xy.size();
  glm::dvec2 lo = n ? poly.xy[0] : glm::dvec2(0), hi = lo;
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec2 a = poly.xy[i], b = poly.xy[(i + 1) % n];
    area2 += a.x * b.y - b.x * a.y;
    perim += std::hypot(b.x - a.x, b.y - a.y);
    lo = {std::min(lo.x, a.x), std::min(lo.y, a.y)};
    hi = {std::max(hi.x, a.x), std::max(hi.y, a.y)};
  }
  w = hi.x - lo.x;
  hgt = hi.y - lo.y;
  return std::fabs(area2) / 2 / (h * h) + (perim + w + hgt) / h + static_cast<double>(n) + 2;
}

bool ObjectSpaceRaster::span(const RotatedPolygon& poly, double y, double& xl, double& xr) {
  bool any = false;
  const size_t n = poly.xy.size();
  for (size_t e = 0; e < n; ++e) {
    const glm::dvec2 a = poly.xy[e], b = poly.xy[(e + 1) % n];
    if (y < std::min(a.y, b.y) || y > std::max(a.y, b.y)) continue;
    double xa = a.x, xb = b.x;  // a horizontal edge on the line: both ends
    if (a.y != b.y) xa = xb = a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y);
    if (!any) {
      xl = std::min(xa, xb);
      xr = std::max(xa, xb);
      any = true;
    } else {
      xl = std::min({xl, xa, xb});
      xr = std::max({xr, xa, xb});
    }
  }
  return any;
}

OpCounts ObjectSpaceRaster::ops_per_item() const {
  OpCounts o;
  o.add = 3;  // x, u, v stepped by their increments
  o.cmp = 1;  // end of span
  return o;
}

OpCounts ObjectSpaceRaster::row_ops() const {
  // Span ends: two edge intersections (1 div 2 mul 3 add each), the two rounded grid ends
  // (2 mul 2 cmp), the row's first u and v (4 mul 4 add).
  OpCounts o;
  o.div = 2;
  o.mul = 4 + 2 + 4;
  o.add = 6 + 4;
  o.cmp = 2 + 2;
  return o;
}

TimingSpec ObjectSpaceRaster::timing(const TechTable& t) const {
  // One sample per cycle per lane: the critical path is the coordinate add.
  OpCounts path;
  path.add = 1;
  return derive_timing(t, ops_per_item(), path, Datapath::Spatial,
                       static_cast<uint32_t>(cfg_.lanes), row_ops());
}

}  // namespace texsim
