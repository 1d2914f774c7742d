#pragma once
// The pixels a scene's planes can reach: what the run's image buffers and the reference
// generator need to cover, instead of the whole image.
#include <cstdint>
#include <vector>

#include "pipeline/geometry/plane_projection.h"

namespace texsim {

// Half-open pixel rectangle [x0, x1) × [y0, y1).
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  uint64_t pixels() const {
    return empty() ? 0 : static_cast<uint64_t>(x1 - x0) * static_cast<uint64_t>(y1 - y0);
  }
};

// Bounding box of one primitive's screen polygon with one pixel of margin, clipped to a
// width × height image; empty when it is not in view or culled.
PixelRect primitive_extent(const PlaneProjection& map, int width, int height);

// Bounding box of the planes' screen polygons with one pixel of margin, clipped to the
// scene's image; empty when no plane is in view.
PixelRect scene_extent(const Scene& scene, const std::vector<PlaneProjection>& maps);

}  // namespace texsim
