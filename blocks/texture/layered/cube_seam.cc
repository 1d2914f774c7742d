#include "blocks/texture/layered/cube_seam.h"

#include <algorithm>

#include "blocks/texture/layered/cube_face_select.h"

namespace texsim {

namespace {

using Vec = std::array<int64_t, 3>;

Vec axis_times(const std::array<int, 3>& a, int64_t k) { return {a[0] * k, a[1] * k, a[2] * k}; }
Vec add(const Vec& a, const Vec& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
int64_t dot(const std::array<int, 3>& a, const Vec& v) {
  return a[0] * v[0] + a[1] * v[1] + a[2] * v[2];
}

// The face whose outward axis is `a` (a unit axis vector).
int face_of_axis(const std::array<int, 3>& a) {
  for (int k = 0; k < 3; ++k) {
    if (a[static_cast<size_t>(k)] != 0) return 2 * k + (a[static_cast<size_t>(k)] < 0 ? 1 : 0);
  }
  return 0;
}

// Texel (x, y) of `face` (n × n) folded across one edge: dx = ±1 when x is outside (then y is
// inside), else dy = ±1. In units of half a texel the face spans [−n, n] and a texel centre is
// at a = 2x + 1 − n; the centre one step outside lies one unit past the edge, and the fold puts
// it one unit inside the neighbour, whose major coordinate is then ±n.
CubeTexel fold(int face, int x, int y, int n, int dx, int dy) {
  const CubeFaceAxes& f = cube_face_axes(face);
  const int64_t nn = n;
  const int64_t a = dx != 0 ? dx * nn : 2 * int64_t{x} + 1 - nn;
  const int64_t b = dy != 0 ? dy * nn : 2 * int64_t{y} + 1 - nn;
  const Vec p = add(add(axis_times(f.m, nn - 1), axis_times(f.s, a)), axis_times(f.t, b));
  std::array<int, 3> out_axis = dx != 0 ? f.s : f.t;
  const int sign = dx != 0 ? dx : dy;
  for (int& c : out_axis) c *= sign;
  CubeTexel r;
  r.face = face_of_axis(out_axis);
  const CubeFaceAxes& g = cube_face_axes(r.face);
  r.x = static_cast<int>((dot(g.s, p) + nn - 1) / 2);
  r.y = static_cast<int>((dot(g.t, p) + nn - 1) / 2);
  return r;
}

}  // namespace

int CubeSeam::neighbour(int face, int dx, int dy) {
  const CubeFaceAxes& f = cube_face_axes(face);
  std::array<int, 3> a = dx != 0 ? f.s : f.t;
  const int sign = dx != 0 ? dx : dy;
  for (int& c : a) c *= sign;
  return face_of_axis(a);
}

int CubeSeam::resolve(int face, int x, int y, int n, std::array<CubeTexel, 3>& out) {
  x = std::clamp(x, -1, n);
  y = std::clamp(y, -1, n);
  const int dx = x < 0 ? -1 : (x >= n ? 1 : 0);
  const int dy = y < 0 ? -1 : (y >= n ? 1 : 0);
  if (dx == 0 && dy == 0) {
    out[0] = {face, x, y};
    return 1;
  }
  if (dx == 0 || dy == 0) {
    out[0] = fold(face, x, y, n, dx, dy);
    return 1;
  }
  // A corner: the face's own corner texel and its two neighbours' across each edge.
  const int cx = std::clamp(x, 0, n - 1), cy = std::clamp(y, 0, n - 1);
  out[0] = {face, cx, cy};
  out[1] = fold(face, x, cy, n, dx, 0);
  out[2] = fold(face, cx, y, n, 0, dy);
  return 3;
}

}  // namespace texsim
