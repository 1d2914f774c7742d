#include "blocks/texture/layered/cube_face_select.h"

#include <algorithm>
#include <cmath>

#include "blocks/base/derive_timing.h"

namespace texsim {

namespace {

// Vulkan's table: face, major axis, sc axis, tc axis.
constexpr std::array<CubeFaceAxes, kCubeFaces> kAxes = {{
    {{1, 0, 0}, {0, 0, -1}, {0, -1, 0}},   // +X: sc = −rz, tc = −ry
    {{-1, 0, 0}, {0, 0, 1}, {0, -1, 0}},   // −X: sc = +rz, tc = −ry
    {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}},     // +Y: sc = +rx, tc = +rz
    {{0, -1, 0}, {1, 0, 0}, {0, 0, -1}},   // −Y: sc = +rx, tc = −rz
    {{0, 0, 1}, {1, 0, 0}, {0, -1, 0}},    // +Z: sc = +rx, tc = −ry
    {{0, 0, -1}, {-1, 0, 0}, {0, -1, 0}},  // −Z: sc = −rx, tc = −ry
}};

float finite_or_zero(float x) { return std::isfinite(x) ? x : 0.0f; }

float dot(const std::array<int, 3>& a, const float r[3]) {
  return static_cast<float>(a[0]) * r[0] + static_cast<float>(a[1]) * r[1] +
         static_cast<float>(a[2]) * r[2];
}

}  // namespace

const CubeFaceAxes& cube_face_axes(int face) { return kAxes[static_cast<size_t>(face)]; }

CubeFaceCoord CubeFaceSelect::select(float rx, float ry, float rz) {
  const float r[3] = {finite_or_zero(rx), finite_or_zero(ry), finite_or_zero(rz)};
  const float ax = std::fabs(r[0]), ay = std::fabs(r[1]), az = std::fabs(r[2]);
  int axis = 0;
  if (az >= ax && az >= ay) {
    axis = 2;
  } else if (ay >= ax) {
    axis = 1;
  }
  CubeFaceCoord c;
  c.face = 2 * axis + (std::signbit(r[axis]) ? 1 : 0);
  const CubeFaceAxes& a = kAxes[static_cast<size_t>(c.face)];
  c.rc = std::fabs(r[axis]);
  // The axes are unit vectors: sc and tc are one signed component each (a mux, no multiply).
  c.sc = dot(a.s, r);
  c.tc = dot(a.t, r);
  if (c.rc > 0) {
    // |sc|, |tc| ≤ |rc|, so the quotients are in [−1, 1]; the clamp only guards rounding.
    c.s = std::clamp(0.5f * (c.sc / c.rc) + 0.5f, 0.0f, 1.0f);
    c.t = std::clamp(0.5f * (c.tc / c.rc) + 0.5f, 0.0f, 1.0f);
  }
  return c;
}

CubeFaceDerivs CubeFaceSelect::derivatives(const CubeFaceCoord& c, const float ddx[3],
                                           const float ddy[3]) {
  CubeFaceDerivs d;
  if (!(c.rc > 0)) return d;
  const CubeFaceAxes& a = kAxes[static_cast<size_t>(c.face)];
  const float dx[3] = {finite_or_zero(ddx[0]), finite_or_zero(ddx[1]), finite_or_zero(ddx[2])};
  const float dy[3] = {finite_or_zero(ddy[0]), finite_or_zero(ddy[1]), finite_or_zero(ddy[2])};
  const float inv = 1.0f / c.rc;
  const float qs = c.sc * inv, qt = c.tc * inv;
  // ∂|rc| = ∂(m·r) (m is the outward axis, so m·r = |rc|).
  const float drx = dot(a.m, dx), dry = dot(a.m, dy);
  d.dsdx = 0.5f * (dot(a.s, dx) - qs * drx) * inv;
  d.dtdx = 0.5f * (dot(a.t, dx) - qt * drx) * inv;
  d.dsdy = 0.5f * (dot(a.s, dy) - qs * dry) * inv;
  d.dtdy = 0.5f * (dot(a.t, dy) - qt * dry) * inv;
  return d;
}

OpCounts CubeFaceSelect::ops_per_item() {
  OpCounts o;
  o.cmp = 3;  // |z| ≥ |x|, |z| ≥ |y|, |y| ≥ |x| (absolute values and muxes are wiring)
  o.rcp = 1;  // 1/|rc|
  o.mul = 2;  // sc/|rc|, tc/|rc| (× ½ is an exponent decrement)
  o.add = 2;  // + ½
  // Derivatives, four of them: (∂sc − q·∂|rc|)·(1/|rc|).
  o.mul += 8;
  o.add += 4;
  o.cmp += 2;  // clamps of s and t
  return o;
}

TimingSpec CubeFaceSelect::timing(const TechTable& tech) {
  OpCounts path;
  path.cmp = 2;  // the compares, then the select of rc
  path.rcp = 1;
  path.mul = 2;  // q = sc·(1/|rc|), then q·∂|rc| (derivatives, the longer branch)
  path.add = 1;
  path.mul += 1;  // × 1/|rc|
  return derive_timing(tech, ops_per_item(), path, Datapath::Spatial);
}

}  // namespace texsim
