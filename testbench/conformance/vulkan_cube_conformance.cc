#include "testbench/conformance/vulkan_cube_conformance.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <vector>

namespace texsim {

namespace {

using D3 = std::array<double, 3>;
using C4 = std::array<double, 4>;

// Vulkan's table: major axis index and sign, and the (sc, tc) of a direction on that face.
struct Face {
  int axis;
  double sign;
};
Face face_info(int f) { return {f / 2, f % 2 == 0 ? 1.0 : -1.0}; }
void face_sc_tc(int f, const D3& r, double& sc, double& tc) {
  switch (f) {
    case 0:
      sc = -r[2];
      tc = -r[1];
      return;
    case 1:
      sc = r[2];
      tc = -r[1];
      return;
    case 2:
      sc = r[0];
      tc = r[2];
      return;
    case 3:
      sc = r[0];
      tc = -r[2];
      return;
    case 4:
      sc = r[0];
      tc = -r[1];
      return;
    default:
      sc = -r[0];
      tc = -r[1];
      return;
  }
}
// The direction of face coordinate (sc, tc) ∈ [−1, 1]² on face f (the table inverted).
D3 face_dir(int f, double sc, double tc) {
  switch (f) {
    case 0:
      return {1, -tc, -sc};
    case 1:
      return {-1, -tc, sc};
    case 2:
      return {sc, 1, tc};
    case 3:
      return {sc, -1, -tc};
    case 4:
      return {sc, -tc, 1};
    default:
      return {-sc, -tc, -1};
  }
}
int major_face(const D3& r) {
  int a = 0;
  for (int k = 1; k < 3; ++k)
    if (std::fabs(r[static_cast<size_t>(k)]) > std::fabs(r[static_cast<size_t>(a)])) a = k;
  return 2 * a + (r[static_cast<size_t>(a)] < 0 ? 1 : 0);
}

C4 texel(const Texture& tex, int level, int x, int y) {
  const Rgba c = tex.texel(level, x, y);
  return {c.x, c.y, c.z, c.w};
}

// Texel (x, y) of face f at mip `mip` (n × n), x, y ∈ [−1, n]: across an edge, the texel of the
// face the centre's direction projects onto; at a corner, the average of the three.
C4 cube_texel(const Texture& tex, int cube, int f, int mip, int x, int y, int n, bool seamless) {
  auto level = [&](int face) { return tex.slice_level(cube * 6 + face, mip); };
  const bool ox = x < 0 || x >= n, oy = y < 0 || y >= n;
  if (!seamless || (!ox && !oy))
    return texel(tex, level(f), std::clamp(x, 0, n - 1), std::clamp(y, 0, n - 1));
  auto project = [&](int px, int py) {
    const double sc = (2.0 * px + 1 - n) / n, tc = (2.0 * py + 1 - n) / n;
    const D3 d = face_dir(f, sc, tc);
    const int g = major_face(d);
    double s2 = 0, t2 = 0;
    face_sc_tc(g, d, s2, t2);
    const double m = std::fabs(d[static_cast<size_t>(face_info(g).axis)]);
    const int i = std::clamp(static_cast<int>(std::floor((0.5 * s2 / m + 0.5) * n)), 0, n - 1);
    const int j = std::clamp(static_cast<int>(std::floor((0.5 * t2 / m + 0.5) * n)), 0, n - 1);
    return texel(tex, level(g), i, j);
  };
  if (ox != oy) return project(x, y);
  const int cx = std::clamp(x, 0, n - 1), cy = std::clamp(y, 0, n - 1);
  const C4 a = texel(tex, level(f), cx, cy), b = project(x, cy), c = project(cx, y);
  return {(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3,
          (a[3] + b[3] + c[3]) / 3};
}

// Range of a bilinear filter over the window [x0, x1] × [y0, y1] of texel-space positions
// (texel centres at integers): the filter is bilinear between integer grid lines, so its
// extremes lie at the window's corners or where grid lines cross it.
void bilinear_range(const std::function<C4(int, int)>& at, double x0, double x1, double y0,
                    double y1, C4& lo, C4& hi) {
  auto points = [](double a, double b) {
    std::vector<double> p = {a, b};
    for (double k = std::ceil(a); k < b; k += 1) p.push_back(k);
    return p;
  };
  lo.fill(1e300);
  hi.fill(-1e300);
  for (double x : points(x0, x1)) {
    for (double y : points(y0, y1)) {
      const double fx = std::floor(x), fy = std::floor(y);
      const double a = x - fx, b = y - fy;
      const int i = static_cast<int>(fx), j = static_cast<int>(fy);
      const C4 t00 = at(i, j), t10 = at(i + 1, j), t01 = at(i, j + 1), t11 = at(i + 1, j + 1);
      for (size_t k = 0; k < 4; ++k) {
        const double v = (1 - a) * (1 - b) * t00[k] + a * (1 - b) * t10[k] + (1 - a) * b * t01[k] +
                         a * b * t11[k];
        lo[k] = std::min(lo[k], v);
        hi[k] = std::max(hi[k], v);
      }
    }
  }
}

// Vulkan nearest-mip level(s) of λ on `mips` levels (a λ within the mipmap precision of a
// rounding point allows both levels).
std::vector<int> levels_of(double lambda, int mips) {
  const double d = std::clamp(lambda, 0.0, static_cast<double>(mips - 1));
  const double e = 1.0 / 256;
  std::vector<int> out;
  for (double v : {d - e, d + e}) {
    const int l = std::clamp(static_cast<int>(std::ceil(std::clamp(v, 0.0, mips - 1.0) + 0.5)) - 1,
                             0, mips - 1);
    if (std::find(out.begin(), out.end(), l) == out.end()) out.push_back(l);
  }
  return out;
}

bool inside(const C4& lo, const C4& hi, const Rgba& r, double eps) {
  for (int k = 0; k < 4; ++k) {
    const double v = r[k];
    if (!(v >= lo[static_cast<size_t>(k)] - eps && v <= hi[static_cast<size_t>(k)] + eps))
      return false;
  }
  return true;
}

// clamp(RNE(a), 0, d − 1) in double.
int layer_of(double a, int d) {
  if (!std::isfinite(a)) return 0;
  return static_cast<int>(std::clamp(std::nearbyint(std::clamp(a, -1.0, d + 1.0)), 0.0, d - 1.0));
}

}  // namespace

VkCubeVerdict VulkanCubeConformance::check_cube(const Texture& tex, const VkCubeQuery& q,
                                                const Rgba& result) const {
  VkCubeVerdict v;
  const D3 r = {q.dir[0], q.dir[1], q.dir[2]};
  const double m = std::max({std::fabs(r[0]), std::fabs(r[1]), std::fabs(r[2])});
  if (!(m > 0) || !std::isfinite(m)) {
    v.judged = false;
    v.pass = true;
    v.reason = "zero or non-finite direction: undefined";
    return v;
  }
  const int cube = layer_of(q.layer, tex.shape().slices / 6);
  const double window = std::ldexp(1.0, -sub_texel_bits_);
  for (int f = 0; f < 6; ++f) {
    const Face fi = face_info(f);
    const double c = r[static_cast<size_t>(fi.axis)] * fi.sign;
    // Faces whose major magnitude ties the largest (within float32 input rounding) are allowed.
    if (!(c > 0 && c >= m * (1 - std::ldexp(1.0, -22)))) continue;
    ++v.faces;
    double sc = 0, tc = 0;
    face_sc_tc(f, r, sc, tc);
    const double s = std::clamp(0.5 * sc / c + 0.5, 0.0, 1.0);
    const double t = std::clamp(0.5 * tc / c + 0.5, 0.0, 1.0);
    for (int mip : levels_of(q.lambda, tex.mips())) {
      const int n = tex.level(tex.slice_level(cube * 6 + f, mip)).width;
      const double x = s * n - 0.5, y = t * n - 0.5;
      const double e = window + n * std::ldexp(1.0, -21);
      C4 lo, hi;
      bilinear_range(
          [&](int i, int j) {
            return cube_texel(tex, cube, f, mip, std::clamp(i, -1, n), std::clamp(j, -1, n), n,
                              seamless_);
          },
          x - e, x + e, y - e, y + e, lo, hi);
      if (inside(lo, hi, result, color_eps)) {
        v.pass = true;
        v.reason = "ok";
        return v;
      }
    }
  }
  v.reason = "no allowed face and level gives the result";
  return v;
}

VkCubeVerdict VulkanCubeConformance::check_array(const Texture& tex, const VkCubeQuery& q,
                                                 const Rgba& result) const {
  VkCubeVerdict v;
  const int layer = layer_of(q.layer, tex.shape().slices);
  const double window = std::ldexp(1.0, -sub_texel_bits_);
  for (int mip : levels_of(q.lambda, tex.mips())) {
    const int level = tex.slice_level(layer, mip);
    const int w = tex.level(level).width, h = tex.level(level).height;
    const double x = q.dir[0] * w - 0.5, y = q.dir[1] * h - 0.5;
    const double ex = window + w * std::ldexp(1.0, -21), ey = window + h * std::ldexp(1.0, -21);
    C4 lo, hi;
    bilinear_range(
        [&](int i, int j) {
          return texel(tex, level, std::clamp(i, 0, w - 1), std::clamp(j, 0, h - 1));
        },
        x - ex, x + ex, y - ey, y + ey, lo, hi);
    if (inside(lo, hi, result, color_eps)) {
      v.pass = true;
      v.reason = "ok";
      return v;
    }
  }
  v.reason = "the result is not a bilinear sample of layer " + std::to_string(layer);
  return v;
}

}  // namespace texsim
