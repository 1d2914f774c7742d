#include "pipeline/geometry/screen_extent.h"

#include <algorithm>
#include <cmath>

namespace texsim {

PixelRect primitive_extent(const PlaneProjection& map, int width, int height) {
  // Pixel-index coordinates: pixel i's centre is at i, so a polygon reaching x covers at most
  // pixels floor(x) .. ceil(x); one more on each side absorbs rounding.
  // A NaN corner (a projection overflowed) widens the box to the whole image: casting it to
  // int is undefined and gave extents of 2^31 pixels, i.e. memory estimates of 4e9 GiB.
  const auto clip = [](double v, int hi, int if_nan) {
    return std::isnan(v) ? if_nan : static_cast<int>(std::clamp(v, 0.0, static_cast<double>(hi)));
  };
  PixelRect r{width, height, 0, 0};
  if (map.culled()) return {};
  for (const glm::dvec2& p : map.screen_polygon()) {
    r.x0 = std::min(r.x0, clip(std::floor(p.x) - 1, width, 0));
    r.y0 = std::min(r.y0, clip(std::floor(p.y) - 1, height, 0));
    r.x1 = std::max(r.x1, clip(std::ceil(p.x) + 2, width, width));
    r.y1 = std::max(r.y1, clip(std::ceil(p.y) + 2, height, height));
  }
  return r.empty() ? PixelRect{} : r;
}

PixelRect scene_extent(const Scene& scene, const std::vector<PlaneProjection>& maps) {
  PixelRect r{scene.width, scene.height, 0, 0};
  for (const PlaneProjection& m : maps) {
    const PixelRect p = primitive_extent(m, scene.width, scene.height);
    if (p.empty()) continue;
    r.x0 = std::min(r.x0, p.x0);
    r.y0 = std::min(r.y0, p.y0);
    r.x1 = std::max(r.x1, p.x1);
    r.y1 = std::max(r.y1, p.y1);
  }
  return r.empty() ? PixelRect{} : r;
}

}  // namespace texsim
