#include "blocks/geometry/vertex_transform.h"

#include <cmath>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<VertexTransform>);

VertexTransform::Config VertexTransform::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"lanes"});
  Config c;
  c.lanes = static_cast<int>(r.get_int("lanes", c.lanes, 1, 64));
  return c;
}

VertexTransform::VertexTransform(const Camera& cam, const Config& c)
    : cfg_(c),
      orthographic_(cam.orthographic),
      near_(cam.near),
      width_(cam.width),
      height_(cam.height) {
  const glm::dmat4 view = glm::lookAt(cam.position, cam.look_at, cam.up);
  const double aspect = static_cast<double>(cam.width) / cam.height;
  // The far plane only bounds the depth range; nothing is clipped against it.
  const double far = 1e12;
  glm::dmat4 proj;
  if (cam.orthographic) {
    const auto h = static_cast<double>(cam.ortho_half_height);
    proj = glm::ortho(-h * aspect, h * aspect, -h, h, cam.near, far);
    // Clip z = the view depth (w stays 1), so the near test reads it without a far-plane scale.
    proj[2][2] = -1;
    proj[3][2] = 0;
  } else {
    proj = glm::perspective(2.0 * std::atan(static_cast<double>(cam.tan_half_fov_y)), aspect,
                            cam.near, far);
  }
  mvp_ = proj * view;
}

bool VertexTransform::to_screen(const glm::dvec4& c, ScreenVertex& out) const {
  // Perspective: w = view depth; orthographic: w = 1 and z = the view depth.
  if (!((orthographic_ ? c.z : c.w) >= near_)) return false;
  const double inv_w = 1.0 / c.w;
  out.x = (c.x * inv_w + 1.0) * 0.5 * width_ - 0.5;
  out.y = (1.0 - c.y * inv_w) * 0.5 * height_ - 0.5;
  out.w = c.w;
  return std::isfinite(out.x) && std::isfinite(out.y);
}

double VertexTransform::front_area(const ScreenVertex v[3]) {
  // With y down the screen, a triangle counter-clockwise in the world (front) is clockwise on
  // the screen: its area in (x, y) with y down is negative, so the sign is flipped.
  return -((v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (v[1].y - v[0].y));
}

OpCounts VertexTransform::ops_per_item() const {
  OpCounts o;
  o.mul = 16 + 2 + 2;
  o.add = 12 + 2;
  o.rcp = 1;
  o.cmp = 1;
  return o;
}

OpCounts VertexTransform::triangle_ops() const {
  OpCounts o;
  o.mul = 2;
  o.add = 5;
  o.cmp = 1;
  return o;
}

TimingSpec VertexTransform::timing(const TechTable& t) const {
  // Critical path: a multiply-add chain of the matrix row (mul + 3 add), the reciprocal, the
  // scaling multiply and the viewport add.
  OpCounts path;
  path.mul = 2;
  path.add = 4;
  path.rcp = 1;
  return derive_timing(t, ops_per_item(), path, Datapath::Spatial, cfg_.lanes, triangle_ops());
}

}  // namespace texsim
