#include "pipeline/geometry/screen_extent.h"

#include <algorithm>
#include <cmath>

namespace texsim {

PixelRect scene_extent(const Scene& scene, const std::vector<PlaneProjection>& maps) {
  // Pixel-index coordinates: pixel i's centre is at i, so a polygon reaching x covers at most
  // pixels floor(x) .. ceil(x); one more on each side absorbs rounding.
  const auto clip = [](double v, int hi) {
    return static_cast<int>(std::clamp(v, 0.0, static_cast<double>(hi)));
  };
  PixelRect r{scene.width, scene.height, 0, 0};
  for (const PlaneProjection& m : maps) {
    for (const glm::dvec2& p : m.screen_polygon()) {
      r.x0 = std::min(r.x0, clip(std::floor(p.x) - 1, scene.width));
      r.y0 = std::min(r.y0, clip(std::floor(p.y) - 1, scene.height));
      r.x1 = std::max(r.x1, clip(std::ceil(p.x) + 2, scene.width));
      r.y1 = std::max(r.y1, clip(std::ceil(p.y) + 2, scene.height));
    }
  }
  return r.empty() ? PixelRect{} : r;
}

}  // namespace texsim
