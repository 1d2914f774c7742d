#include "pipeline/plane_projection.h"

#include <cmath>

namespace texsim {

namespace {
using V = long double;
struct V3 { V x, y, z; };
V3 lv(const glm::dvec3& v) { return {v.x, v.y, v.z}; }
V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 operator*(V3 a, V s) { return {a.x * s, a.y * s, a.z * s}; }
V dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V3 normalize(V3 a) { return a * (1.0L / std::sqrt(dot(a, a))); }
}  // namespace

PlaneProjection::PlaneProjection(const Scene& scene, const ScenePlane& plane) {
  const Camera& cam = scene.camera;
  const V3 f = normalize(lv(cam.look_at) - lv(cam.position));
  const V3 r = normalize(cross(f, lv(cam.up)));
  const V3 up = cross(r, f);
  const V th = std::tan(static_cast<V>(cam.fov_y_deg) * 3.14159265358979323846264338327950288L / 360.0L);
  const V aspect = static_cast<V>(scene.width) / scene.height;
  // View ray (not normalised, unit component along f) through pixel (x, y): D0 + x Dx + y Dy.
  const V3 dx = r * (2.0L * th * aspect / scene.width);
  const V3 dy = up * (-2.0L * th / scene.height);
  const V3 d0 = f - r * (th * aspect) + up * th;
  // Solve origin + a eu + b ev = cam + t d (Cramer): with n = eu × ev, w = cam − origin,
  // a = d·(w × ev) / d·n, b = d·(eu × w) / d·n, t = −(w·n) / d·n.
  const V3 eu = lv(plane.edge_u), ev = lv(plane.edge_v);
  const V3 w = lv(cam.position) - lv(plane.origin);
  const V3 n = cross(eu, ev), pa = cross(w, ev), pb = cross(eu, w);
  G = dot(n, dx);
  H = dot(n, dy);
  I = dot(n, d0);
  a_[0] = dot(pa, dx); a_[1] = dot(pa, dy); a_[2] = dot(pa, d0);
  b_[0] = dot(pb, dx); b_[1] = dot(pb, dy); b_[2] = dot(pb, d0);
  depth_num_ = -dot(w, n);
  const V su = plane.uv_scale.x, sv = plane.uv_scale.y;
  const V ou = plane.uv_offset.x, ov = plane.uv_offset.y;
  A = su * a_[0] + ou * G; B = su * a_[1] + ou * H; C = su * a_[2] + ou * I;
  D = sv * b_[0] + ov * G; E = sv * b_[1] + ov * H; F = sv * b_[2] + ov * I;
  near_ = cam.near;
}

UvSample PlaneProjection::at(double xd, double yd) const {
  const V x = xd, y = yd;
  UvSample s;
  const V den = G * x + H * y + I;
  if (den == 0) return s;
  const V nu = A * x + B * y + C, nv = D * x + E * y + F;
  const V a = (a_[0] * x + a_[1] * y + a_[2]) / den, b = (b_[0] * x + b_[1] * y + b_[2]) / den;
  const V depth = depth_num_ / den;
  s.depth = static_cast<double>(depth);
  s.inside = depth >= near_ && a >= 0 && a <= 1 && b >= 0 && b <= 1;
  s.u = static_cast<double>(nu / den);
  s.v = static_cast<double>(nv / den);
  const V den2 = den * den;
  s.dudx = static_cast<double>((A * den - G * nu) / den2);
  s.dudy = static_cast<double>((B * den - H * nu) / den2);
  s.dvdx = static_cast<double>((D * den - G * nv) / den2);
  s.dvdy = static_cast<double>((E * den - H * nv) / den2);
  return s;
}

}  // namespace texsim
