#include "pipeline/geometry/plane_projection.h"

#include <cmath>

#include "blocks/geometry/near_clipper.h"
#include "pipeline/scene/scene_meshes.h"

namespace texsim {

// The scene's memory estimate counts kPlaneProjectionBytes for each projection of a face.
static_assert(sizeof(PlaneProjection) <= kPlaneProjectionBytes);

namespace {
using V = long double;
struct V3 {
  V x, y, z;
};
V3 lv(const glm::dvec3& v) { return {v.x, v.y, v.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator*(V3 a, V s) { return {a.x * s, a.y * s, a.z * s}; }
V dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
V3 normalize(V3 a) { return a * (1.0L / std::sqrt(dot(a, a))); }
}  // namespace

PlaneProjection::PlaneProjection(const Scene& scene, const ScenePrimitive& plane) {
  const Camera& cam = scene.camera;
  const V3 f = normalize(lv(cam.look_at) - lv(cam.position));
  const V3 r = normalize(cross(f, lv(cam.up)));
  const V3 up = cross(r, f);
  const V th = cam.orthographic ? cam.ortho_half_height : cam.tan_half_fov_y;
  const V aspect = static_cast<V>(cam.width) / cam.height;
  // Perspective: the view ray through pixel (x, y) leaves the eye along D0 + x Dx + y Dy (unit
  // component along f). Orthographic: it leaves the point eye + D0 − f + x Dx + y Dy along f.
  const V3 dx = r * (2.0L * th * aspect / cam.width);
  const V3 dy = up * (-2.0L * th / cam.height);
  const V3 d0 = f - r * (th * aspect) + up * th;
  // Solve origin + a eu + b ev = o + t d (Cramer): with n = eu × ev, w = o − origin,
  // a = d·(w × ev) / d·n, b = d·(eu × w) / d·n, t = −(w·n) / d·n.
  const V3 eu = lv(plane.edge_u), ev = lv(plane.edge_v);
  const V3 w = lv(cam.position) - lv(plane.origin);
  const V3 n = cross(eu, ev);
  if (cam.orthographic) {
    // d = f fixed, w linear in (x, y): a, b and t are affine in the pixel (G = H = 0).
    const V3 w0 = w + d0 - f, ea = cross(ev, f), eb = cross(f, eu);
    G = H = 0;
    I = dot(n, f);
    a_[0] = dot(dx, ea);
    a_[1] = dot(dy, ea);
    a_[2] = dot(w0, ea);
    b_[0] = dot(dx, eb);
    b_[1] = dot(dy, eb);
    b_[2] = dot(w0, eb);
    depth_num_[0] = -dot(dx, n);
    depth_num_[1] = -dot(dy, n);
    depth_num_[2] = -dot(w0, n);
  } else {
    const V3 pa = cross(w, ev), pb = cross(eu, w);
    G = dot(n, dx);
    H = dot(n, dy);
    I = dot(n, d0);
    a_[0] = dot(pa, dx);
    a_[1] = dot(pa, dy);
    a_[2] = dot(pa, d0);
    b_[0] = dot(pb, dx);
    b_[1] = dot(pb, dy);
    b_[2] = dot(pb, d0);
    depth_num_[0] = depth_num_[1] = 0;
    depth_num_[2] = -dot(w, n);
  }
  const V ua = plane.uv_edge_u.x, ub = plane.uv_edge_v.x, ou = plane.uv_origin.x;
  const V va = plane.uv_edge_u.y, vb = plane.uv_edge_v.y, ov = plane.uv_origin.y;
  A = ua * a_[0] + ub * b_[0] + ou * G;
  B = ua * a_[1] + ub * b_[1] + ou * H;
  C = ua * a_[2] + ub * b_[2] + ou * I;
  D = va * a_[0] + vb * b_[0] + ov * G;
  E = va * a_[1] + vb * b_[1] + ov * H;
  F = va * a_[2] + vb * b_[2] + ov * I;
  near_ = cam.near;
  triangle_ = plane.shape == ScenePrimitive::Shape::Triangle;
  degenerate_ = dot(n, n) == 0;
  cull_back_ = plane.cull_back;
  // The back is seen when the eye (perspective) or the view direction (orthographic) lies on
  // the side n points away from.
  back_facing_ = !degenerate_ && (cam.orthographic ? dot(n, f) > 0 : dot(n, w) < 0);
  const V3 c = lv(cam.position);
  const V3 o = lv(plane.origin);
  const V3 corners[4] = {o, o + eu, triangle_ ? o + ev : o + eu + ev, o + ev};
  for (int k = 0; k < 3; ++k) {
    const V cv[3] = {c.x, c.y, c.z}, rv[3] = {r.x, r.y, r.z}, uv[3] = {up.x, up.y, up.z},
            fv[3] = {f.x, f.y, f.z};
    cam_[k] = cv[k];
    right_[k] = rv[k];
    up_[k] = uv[k];
    fwd_[k] = fv[k];
  }
  for (int i = 0; i < 4; ++i) {
    corner_[i][0] = corners[i].x;
    corner_[i][1] = corners[i].y;
    corner_[i][2] = corners[i].z;
  }
  tan_half_ = th;
  aspect_ = aspect;
  width_ = cam.width;
  height_ = cam.height;
  orthographic_ = cam.orthographic;
}

std::vector<glm::dvec2> PlaneProjection::screen_polygon() const {
  std::vector<Vec3L> poly;
  if (degenerate_) return {};
  for (int i = 0; i < (triangle_ ? 3 : 4); ++i) {
    const long double* p = corner_[i];
    const V d[3] = {p[0] - cam_[0], p[1] - cam_[1], p[2] - cam_[2]};
    auto along = [&](const long double* a) { return d[0] * a[0] + d[1] * a[1] + d[2] * a[2]; };
    poly.push_back({along(right_), along(up_), along(fwd_)});  // view space, Z forward
  }
  poly = clip_polygon_z(poly, static_cast<V>(near_), true);
  std::vector<glm::dvec2> out;
  if (poly.size() < 3) return out;
  // Inverse of the view ray D0 + x Dx + y Dy at continuous pixel coordinates, then the
  // half-pixel shift to pixel-index coordinates.
  for (const Vec3L& p : poly) {
    const V z = orthographic_ ? 1 : p.z;
    const V xs = (p.x / z + tan_half_ * aspect_) * width_ / (2 * tan_half_ * aspect_);
    const V ys = (tan_half_ - p.y / z) * height_ / (2 * tan_half_);
    out.emplace_back(static_cast<double>(xs - 0.5L), static_cast<double>(ys - 0.5L));
  }
  return out;
}

ProjectiveMap PlaneProjection::texel_map(int tw, int th) const {
  // Continuous x = index + 1/2: fold the half pixel into C, F and I; scale u, v to texels.
  ProjectiveMap m;
  const V w = tw, h = th;
  m.A = A * w;
  m.B = B * w;
  m.C = (C + (A + B) / 2) * w;
  m.D = D * h;
  m.E = E * h;
  m.F = (F + (D + E) / 2) * h;
  m.G = G;
  m.H = H;
  m.I = I + (G + H) / 2;
  // In front of the camera depth = depth_num / q > 0: make q positive there (perspective: the
  // numerator is constant; orthographic: q is, and its sign is the plane side seen).
  return (orthographic_ ? I < 0 : depth_num_[2] < 0) ? m.scaled(-1) : m;
}

UvSample PlaneProjection::at(double xd, double yd) const {
  const V x = xd, y = yd;
  UvSample s;
  const V q = den(x, y);
  if (q == 0) return s;
  const V nu = num_u(x, y), nv = num_v(x, y);
  const V a = (a_[0] * x + a_[1] * y + a_[2]) / q, b = (b_[0] * x + b_[1] * y + b_[2]) / q;
  const V depth = (depth_num_[0] * x + depth_num_[1] * y + depth_num_[2]) / q;
  s.depth = static_cast<double>(depth);
  s.inside = depth >= near_ && a >= 0 && b >= 0 && (triangle_ ? a + b <= 1 : a <= 1 && b <= 1);
  s.u = static_cast<double>(nu / q);
  s.v = static_cast<double>(nv / q);
  const V q2 = q * q;
  s.dudx = static_cast<double>((A * q - G * nu) / q2);
  s.dudy = static_cast<double>((B * q - H * nu) / q2);
  s.dvdx = static_cast<double>((D * q - G * nv) / q2);
  s.dvdy = static_cast<double>((E * q - H * nv) / q2);
  return s;
}

std::vector<Fragment> pixel_fragments(const PlaneProjection& proj, int width, int height) {
  std::vector<Fragment> frags;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const UvSample s = proj.at(x + 0.5, y + 0.5);
      if (!s.inside) continue;
      Fragment f;
      f.x = static_cast<uint32_t>(x);
      f.y = static_cast<uint32_t>(y);
      f.u = s.u;
      f.v = s.v;
      f.dudx = s.dudx;
      f.dvdx = s.dvdx;
      f.dudy = s.dudy;
      f.dvdy = s.dvdy;
      frags.push_back(f);
    }
  }
  return frags;
}

}  // namespace texsim
