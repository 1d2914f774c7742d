#include "blocks/geometry/sample_projection.h"

#include <cmath>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/base/derive_timing.h"

namespace texsim {

static_assert(Block<SampleProjection>);

SampleProjection::Config SampleProjection::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"lanes"});
  Config c;
  c.lanes = static_cast<int>(r.get_int("lanes", c.lanes, 1, 64));
  return c;
}

glm::dvec3 SampleProjection::thesis_closed_form(const Rotation& rot, const glm::dvec3& p, double r,
                                                ClosedForm form, OpCounts& ops) {
  const double ny = rot.normal.y, nz = rot.normal.z;
  const double sa_sb = rot.sin_a * rot.sin_b, ca_sb = rot.cos_a * rot.sin_b;  // per polygon
  const double xn = rot.cos_b * p.x + rot.sin_b * p.z;
  const double yn = rot.cos_a * p.y + ny * p.z - sa_sb * p.x;
  const double zn = nz * p.z - rot.sin_a * p.y - ca_sb * p.x;
  ops.mul += 2 + 3 + 3;
  ops.add += 1 + 2 + 2;
  double d = 0;
  if (form == ClosedForm::Corrected) {
    d = 1 + r * zn;
    ops.mul += 1;
    ops.add += 1;
  } else {
    d = 1 - r * rot.sin_a * p.y + r * nz * p.z - r * ny * p.x;  // r·sin α etc. per polygon
    ops.mul += 3;
    ops.add += 3;
  }
  const double k = 1 / d;
  ops.rcp += 1;
  ops.mul += 3;
  return {xn * k, yn * k, zn * k};
}

SampleProjection::Setup SampleProjection::setup(const Rotation& rot, double z_rot, double focal_px,
                                                double cx, double cy, OpCounts& ops) {
  Setup s;
  s.cx = cx;
  s.cy = cy;
  s.z_c = focal_px;
  const glm::dvec3 c0 = PolygonRotation::inverse(rot, {1, 0, 0}, ops);
  const glm::dvec3 c1 = PolygonRotation::inverse(rot, {0, 1, 0}, ops);
  const glm::dvec3 c2 = PolygonRotation::inverse(rot, {0, 0, z_rot}, ops);
  // P (r = −1/z_c) after moving the eye from the origin to z = z_c on the thesis's axis:
  // w = 1 + r (z_c − Z) = −r Z, X and Y unchanged.
  const double r = -1.0 / focal_px;
  ops.rcp += 1;
  ops.mul += 3;
  s.m[0][0] = c0.x;
  s.m[0][1] = c1.x;
  s.m[0][2] = c2.x;
  s.m[1][0] = c0.y;
  s.m[1][1] = c1.y;
  s.m[1][2] = c2.y;
  s.m[2][0] = -r * c0.z;
  s.m[2][1] = -r * c1.z;
  s.m[2][2] = -r * c2.z;
  return s;
}

SampleProjection::Setup SampleProjection::setup_orthographic(const Rotation& rot, double z_rot,
                                                             double px_per_unit, double cx,
                                                             double cy, OpCounts& ops) {
  Setup s;
  s.cx = cx;
  s.cy = cy;
  s.z_c = px_per_unit;
  s.orthographic = true;
  const glm::dvec3 c0 = PolygonRotation::inverse(rot, {1, 0, 0}, ops);
  const glm::dvec3 c1 = PolygonRotation::inverse(rot, {0, 1, 0}, ops);
  const glm::dvec3 c2 = PolygonRotation::inverse(rot, {0, 0, z_rot}, ops);
  ops.mul += 6;
  s.m[0][0] = px_per_unit * c0.x;
  s.m[0][1] = px_per_unit * c1.x;
  s.m[0][2] = px_per_unit * c2.x;
  s.m[1][0] = px_per_unit * c0.y;
  s.m[1][1] = px_per_unit * c1.y;
  s.m[1][2] = px_per_unit * c2.y;
  s.m[2][0] = c0.z;
  s.m[2][1] = c1.z;
  s.m[2][2] = c2.z;
  return s;
}

ProjectedSample SampleProjection::project(const Setup& s, double xr, double yr, OpCounts& ops) {
  if (s.orthographic) {
    ops.mul += 6;
    ops.add += 6 + 2;
    ops.cmp += 1;
    ProjectedSample p;
    p.x = s.cx + s.m[0][0] * xr + s.m[0][1] * yr + s.m[0][2];
    p.y = s.cy + s.m[1][0] * xr + s.m[1][1] * yr + s.m[1][2];
    p.depth = s.m[2][0] * xr + s.m[2][1] * yr + s.m[2][2];
    p.valid = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.depth);
    return p;
  }
  ops.mul += 6 + 3;
  ops.add += 6 + 2;
  ops.rcp += 1;
  ops.cmp += 1;
  ProjectedSample p;
  const double X = s.m[0][0] * xr + s.m[0][1] * yr + s.m[0][2];
  const double Y = s.m[1][0] * xr + s.m[1][1] * yr + s.m[1][2];
  const double w = s.m[2][0] * xr + s.m[2][1] * yr + s.m[2][2];
  if (!(w > 0)) return p;  // behind the eye (or on its plane): no screen position
  const double inv_w = 1.0 / w;
  p.x = s.cx + X * inv_w;
  p.y = s.cy + Y * inv_w;
  p.depth = w * s.z_c;
  p.valid = std::isfinite(p.x) && std::isfinite(p.y);
  return p;
}

OpCounts SampleProjection::ops_per_item() const {
  OpCounts o;
  o.mul = 9;
  o.add = 8;
  o.rcp = 1;
  o.cmp = 1;
  return o;
}

OpCounts SampleProjection::polygon_ops() const {
  OpCounts o;
  o.mul = 27;  // three inverse rotations (8 each) and the three P multiplies
  o.add = 12;  // three inverse rotations (4 each)
  o.rcp = 1;
  return o;
}

TimingSpec SampleProjection::timing(const TechTable& t) const {
  // Critical path: the w dot product (mul, 2 add), the reciprocal, the multiply, the centre add.
  OpCounts path;
  path.mul = 2;
  path.add = 3;
  path.rcp = 1;
  return derive_timing(t, ops_per_item(), path, Datapath::Spatial,
                       static_cast<uint32_t>(cfg_.lanes), polygon_ops());
}

}  // namespace texsim
