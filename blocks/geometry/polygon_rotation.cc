#include "blocks/geometry/polygon_rotation.h"

#include <cmath>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/base/derive_timing.h"

namespace texsim {

static_assert(Block<PolygonRotation>);

const char* rotation_case_name(RotationCase c) {
  switch (c) {
    case RotationCase::General:
      return "general";
    case RotationCase::Identity:
      return "identity";
    case RotationCase::DZero:
      return "d = 0";
    case RotationCase::Degenerate:
      return "degenerate";
  }
  return "?";
}

PolygonRotation::Config PolygonRotation::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"lanes"});
  Config c;
  c.lanes = static_cast<int>(r.get_int("lanes", c.lanes, 1, 64));
  return c;
}

glm::dvec3 PolygonRotation::unit_normal(const glm::dvec3& a, const glm::dvec3& b,
                                        const glm::dvec3& c, OpCounts& ops) {
  const glm::dvec3 e1 = b - a, e2 = c - a;
  const glm::dvec3 n{e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z,
                     e1.x * e2.y - e1.y * e2.x};
  const double len2 = n.x * n.x + n.y * n.y + n.z * n.z;
  ops.add += 6 + 3 + 2;
  ops.mul += 6 + 3 + 3;
  ops.sqrt += 1;
  ops.rcp += 1;
  ops.cmp += 1;
  if (!(len2 > 0) || !std::isfinite(len2)) return glm::dvec3(0);
  const double inv = 1.0 / std::sqrt(len2);
  return n * inv;
}

Rotation PolygonRotation::setup(glm::dvec3 n, OpCounts& ops) {
  Rotation r;
  ops.cmp += 3;
  if (!(n.x * n.x + n.y * n.y + n.z * n.z > 0) || !std::isfinite(n.x + n.y + n.z)) {
    r.kind = RotationCase::Degenerate;
    r.normal = glm::dvec3(0);
    return r;
  }
  if (n.z < 0) {  // the same plane, seen with the other normal: rotate the short way
    n = -n;
    r.flipped = true;
  }
  r.normal = n;
  if (n.x == 0 && n.y == 0) {  // parallel to the screen: the exact identity
    r.kind = RotationCase::Identity;
    return r;
  }
  const double d = std::sqrt(n.y * n.y + n.z * n.z);
  ops.mul += 2;
  ops.add += 1;
  ops.sqrt += 1;
  if (d == 0) {  // Ny = Nz = 0: no rotation about x is needed; β = ±90° about y
    r.kind = RotationCase::DZero;
    r.cos_a = 1;
    r.sin_a = 0;
    r.cos_b = 0;
    r.sin_b = n.x;
    return r;
  }
  const double inv_d = 1.0 / d;
  ops.rcp += 1;
  ops.mul += 2;
  r.kind = RotationCase::General;
  r.cos_a = n.z * inv_d;
  r.sin_a = n.y * inv_d;
  r.cos_b = d;
  r.sin_b = n.x;
  return r;
}

glm::dvec2 PolygonRotation::rotate_xy(const Rotation& r, const glm::dvec3& p, OpCounts& ops) {
  ops.mul += 6;
  ops.add += 3;
  // z1 = y sin α + z cos α is the depth after the rotation about x.
  const double z1 = p.y * r.sin_a + p.z * r.cos_a;
  return {p.x * r.cos_b - z1 * r.sin_b, p.y * r.cos_a - p.z * r.sin_a};
}

double PolygonRotation::rotate_z(const Rotation& r, const glm::dvec3& p, OpCounts& ops) {
  ops.mul += 3;
  ops.add += 2;
  const double z1 = p.y * r.sin_a + p.z * r.cos_a;
  return p.x * r.sin_b + z1 * r.cos_b;
}

RotatedPolygon PolygonRotation::rotate_polygon(const Rotation& r, const std::vector<glm::dvec3>& v,
                                               OpCounts& ops) {
  RotatedPolygon out;
  out.xy.reserve(v.size());
  for (const glm::dvec3& p : v) out.xy.push_back(rotate_xy(r, p, ops));
  if (!v.empty()) out.z = rotate_z(r, v[0], ops);
  return out;
}

glm::dvec3 PolygonRotation::inverse(const Rotation& r, const glm::dvec3& p, OpCounts& ops) {
  // Undo the rotation about y, then the one about x: 8 mul 4 add.
  ops.mul += 8;
  ops.add += 4;
  const double x = p.x * r.cos_b + p.z * r.sin_b;
  const double z1 = -p.x * r.sin_b + p.z * r.cos_b;
  return {x, p.y * r.cos_a + z1 * r.sin_a, -p.y * r.sin_a + z1 * r.cos_a};
}

OpCounts PolygonRotation::ops_per_item() const {
  OpCounts o;
  o.mul = 6;
  o.add = 3;
  return o;
}

OpCounts PolygonRotation::polygon_ops() const {
  OpCounts o;
  o.add = 6 + 3 + 2 + 1 + 2;
  o.mul = 6 + 3 + 3 + 2 + 2 + 3;
  o.sqrt = 2;
  o.rcp = 2;
  o.cmp = 4;
  return o;
}

TimingSpec PolygonRotation::timing(const TechTable& t) const {
  // Critical path of a vertex: the multiply of z1, its add, the multiply by sin β and the add.
  OpCounts path;
  path.mul = 2;
  path.add = 2;
  return derive_timing(t, ops_per_item(), path, Datapath::Spatial,
                       static_cast<uint32_t>(cfg_.lanes), polygon_ops());
}

}  // namespace texsim
