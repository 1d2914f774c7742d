#include "blocks/geometry/projective_map.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace texsim {

namespace {

constexpr long double kNaN = std::numeric_limits<long double>::quiet_NaN();

Vec3L cross(const Vec3L& a, const Vec3L& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
long double dot(const Vec3L& a, const Vec3L& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
long double norm(const Vec3L& a) { return std::sqrt(dot(a, a)); }
Vec3L scale(const Vec3L& a, long double s) { return {a.x * s, a.y * s, a.z * s}; }
Vec3L add(const Vec3L& a, const Vec3L& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }

// Rodrigues rotation of v about the unit axis k by angle t.
Vec3L rotate(const Vec3L& v, const Vec3L& k, long double t) {
  const long double c = std::cos(t), s = std::sin(t);
  const Vec3L kxv = cross(k, v);
  const long double kv = dot(k, v);
  return add(add(scale(v, c), scale(kxv, s)), scale(k, kv * (1 - c)));
}

}  // namespace

bool ProjectiveMap::finite() const {
  for (long double c : {A, B, C, D, E, F, G, H, I}) {
    if (!std::isfinite(c)) return false;
  }
  return !degenerate;
}

ProjectiveMap ProjectiveMap::scaled(long double s) const {
  ProjectiveMap m = *this;
  for (long double* c : {&m.A, &m.B, &m.C, &m.D, &m.E, &m.F, &m.G, &m.H, &m.I}) *c *= s;
  return m;
}

ProjectiveMap ProjectiveMap::normalised(const long double* xs, const long double* ys, int n) const {
  long double qmax = 0;
  for (int k = 0; k < n; ++k) qmax = std::max(qmax, std::fabs(den(xs[k], ys[k])));
  if (!(qmax > 0) || !std::isfinite(qmax)) return *this;
  int e = 0;
  (void)std::frexp(qmax, &e);  // qmax = m·2^e, m in [0.5, 1)
  return scaled(std::ldexp(1.0L, -e));
}

ProjectiveMap ProjectiveMap::translated(long double du, long double dv) const {
  // (num_u - du·q)/q = u - du: subtract du times the denominator row from the u row.
  ProjectiveMap m = *this;
  m.A -= du * G;
  m.B -= du * H;
  m.C -= du * I;
  m.D -= dv * G;
  m.E -= dv * H;
  m.F -= dv * I;
  return m;
}

ProjectiveMap ProjectiveMap::from_plane(const Vec3L& origin, const Vec3L& axis_u,
                                        const Vec3L& axis_v, const Camera& cam) {
  // K' maps a view-space point P to Z·(i, j, 1) with (i, j) the pixel-index coordinates
  // (centre of pixel i at xs = i + 0.5, hence the -0.5).
  const long double focal = cam.focal_px(), cx = cam.cx(), cy = cam.cy();
  auto kp = [&](const Vec3L& p) {
    return Vec3L{focal * p.x + (cx - 0.5L) * p.z, focal * p.y + (cy - 0.5L) * p.z, p.z};
  };
  // Texture->screen: M·(u, v, 1) = K'(origin + u·axis_u + v·axis_v) = Z·(i, j, 1).
  const Vec3L c0 = kp(axis_u), c1 = kp(axis_v), c2 = kp(origin);
  // Screen->texture: N = M^-1 = adj(M)/det(M); rows of adj are cross products of columns.
  const Vec3L r0 = cross(c1, c2), r1 = cross(c2, c0), r2 = cross(c0, c1);
  const long double det = dot(c0, r0);
  ProjectiveMap m;
  const long double size = norm(c0) * norm(c1) * norm(c2);
  if (!(std::fabs(det) > 1e-15L * size) || !std::isfinite(det)) {
    m.A = m.B = m.C = m.D = m.E = m.F = m.G = m.H = m.I = kNaN;
    m.degenerate = true;
    return m;
  }
  const long double inv = 1.0L / det;
  m.A = r0.x * inv;
  m.B = r0.y * inv;
  m.C = r0.z * inv;
  m.D = r1.x * inv;
  m.E = r1.y * inv;
  m.F = r1.z * inv;
  m.G = r2.x * inv;
  m.H = r2.y * inv;
  m.I = r2.z * inv;
  return m;
}

PlaneFrame plane_frame(const PlaneView& pv) {
  constexpr long double kDeg = 3.14159265358979323846264338327950288L / 180.0L;
  const long double d = pv.distance;
  const long double s = d / (pv.camera.focal_px() * pv.texels_per_pixel);  // texel size
  const long double phi = pv.azimuth_deg * kDeg;
  const Vec3L axis{std::cos(phi), std::sin(phi), 0};
  const long double t = pv.tilt_deg * kDeg;
  const Vec3L au = scale(rotate({1, 0, 0}, axis, t), s);
  const Vec3L av = scale(rotate({0, 1, 0}, axis, t), s);
  const Vec3L hit{0, 0, d};
  const Vec3L origin = add(hit, add(scale(au, -static_cast<long double>(pv.u_offset)),
                                    scale(av, -static_cast<long double>(pv.v_offset))));
  return {origin, au, av};
}

void project_to_pixel(const Vec3L& p, const Camera& cam, long double& x, long double& y) {
  const long double focal = cam.focal_px();
  x = focal * p.x / p.z + cam.cx() - 0.5L;
  y = focal * p.y / p.z + cam.cy() - 0.5L;
}

ProjectiveMap ProjectiveMap::from_plane_view(const PlaneView& pv) {
  const PlaneFrame f = plane_frame(pv);
  return from_plane(f.origin, f.axis_u, f.axis_v, pv.camera);
}

DerivsL analytic_derivs(const ProjectiveMap& m, long double x, long double y) {
  const long double q = m.den(x, y);
  const long double u = m.num_u(x, y) / q, v = m.num_v(x, y) / q;
  // d/dx (w/q) = (A q - G w)/q^2 = (A - G u)/q, and likewise.
  return {(m.A - m.G * u) / q, (m.D - m.G * v) / q, (m.B - m.H * u) / q, (m.E - m.H * v) / q};
}

DerivsL forward_diff_derivs(const ProjectiveMap& m, long double x, long double y) {
  const long double u0 = m.u(x, y), v0 = m.v(x, y);
  return {m.u(x + 1, y) - u0, m.v(x + 1, y) - v0, m.u(x, y + 1) - u0, m.v(x, y + 1) - v0};
}

}  // namespace texsim
