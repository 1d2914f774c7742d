#pragma once
// The exact cell-by-cell walk of a ray through the voxels of a relief volume (a 3-D DDA):
// the distance-map builder and the tests use it to find where a ray enters solid voxels.
// Arithmetic: double.
#include <array>
#include <cmath>
#include <cstdint>
#include <glm/vec3.hpp>
#include <limits>

namespace texsim {

// Walks the cells (centres at integers, faces at k + 1/2) that the ray p + t·d, t >= 0, passes
// through, in order, while they lie in x ∈ [0, w), y ∈ [0, h), z ∈ [-1, depth) (z = -1 is the
// base layer). visit(x, y, z, t_in, t_out) returns false to stop.
template <class Visit>
void walk_voxels(const glm::dvec3& p, const glm::dvec3& d, int32_t w, int32_t h, int32_t depth,
                 Visit&& visit) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::array<int32_t, 3> c{};
  std::array<double, 3> next{}, delta{};
  std::array<int32_t, 3> step{};
  for (int a = 0; a < 3; ++a) {
    const double pa = p[a], da = d[a];
    if (!std::isfinite(pa) || std::fabs(pa) > 1e9) return;
    c[a] = static_cast<int32_t>(std::floor(pa + 0.5));
    if (da > 0) {
      step[a] = 1;
      next[a] = (c[a] + 0.5 - pa) / da;
      delta[a] = 1 / da;
    } else if (da < 0) {
      step[a] = -1;
      next[a] = (c[a] - 0.5 - pa) / da;
      delta[a] = -1 / da;
    } else {
      next[a] = kInf;
      delta[a] = kInf;
    }
  }
  double t = 0;
  while (c[0] >= 0 && c[0] < w && c[1] >= 0 && c[1] < h && c[2] >= -1 && c[2] < depth) {
    int axis = next[0] <= next[1] ? 0 : 1;
    if (next[2] < next[axis]) axis = 2;
    const double t_out = next[axis];
    if (!visit(c[0], c[1], c[2], t, t_out) || !(t_out < kInf)) return;
    c[axis] += step[axis];
    t = t_out;
    next[axis] += delta[axis];
  }
}

}  // namespace texsim
