#include "pipeline/geometry/direction_map.h"

#include <glm/geometric.hpp>

namespace texsim {

DirectionMap DirectionMap::make(const Camera& c, const ScenePrimitive& p, bool reflect) {
  const glm::dvec3 fwd = glm::normalize(c.look_at - c.position);
  const glm::dvec3 right = glm::normalize(glm::cross(fwd, c.up));
  const glm::dvec3 down = glm::cross(fwd, right);  // the image's +y (camera.h: Y down)
  DirectionMap m;
  if (c.orthographic) {
    m.origin = fwd;
  } else {
    const auto f = static_cast<double>(c.focal_px());
    const auto cx = static_cast<double>(c.cx()), cy = static_cast<double>(c.cy());
    m.ddx = right / f;
    m.ddy = down / f;
    m.origin = fwd - cx * m.ddx - cy * m.ddy;
  }
  if (reflect) {
    // r = d − 2·(d·n)·n is linear in d: reflect each part of the map.
    const glm::dvec3 n = glm::normalize(glm::cross(p.edge_u, p.edge_v));
    const auto mirror = [&n](glm::dvec3 d) { return d - 2.0 * glm::dot(d, n) * n; };
    m.origin = mirror(m.origin);
    m.ddx = mirror(m.ddx);
    m.ddy = mirror(m.ddy);
  }
  return m;
}

DirectionMap DirectionMap::of(const Fragment& f) {
  DirectionMap m;
  m.ddx = {f.dudx, f.dvdx, f.dwdx};
  m.ddy = {f.dudy, f.dvdy, f.dwdy};
  m.origin = glm::dvec3(f.u, f.v, f.w) - (f.x + 0.5) * m.ddx - (f.y + 0.5) * m.ddy;
  return m;
}

void DirectionMap::apply(Fragment& f) const {
  const glm::dvec3 r = at(f.x + 0.5, f.y + 0.5);
  f.u = r.x;
  f.v = r.y;
  f.w = r.z;
  f.dudx = ddx.x;
  f.dvdx = ddx.y;
  f.dwdx = ddx.z;
  f.dudy = ddy.x;
  f.dvdy = ddy.y;
  f.dwdy = ddy.z;
}

}  // namespace texsim
