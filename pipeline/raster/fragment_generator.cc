#include "pipeline/raster/fragment_generator.h"

#include <algorithm>
#include <limits>

#include "pipeline/geometry/plane_projection.h"
#include "pipeline/geometry/screen_extent.h"

namespace texsim {

namespace {

// Rows resolved together: the depth buffer holds one band, not the whole image.
constexpr int kBandRows = 32;

}  // namespace

void generate_fragments(const Scene& scene, uint32_t frame,
                        const std::function<void(const Fragment&)>& emit) {
  std::vector<PlaneProjection> maps;
  std::vector<PixelRect> rects;
  maps.reserve(scene.primitives.size());
  for (const auto& p : scene.primitives) {
    maps.emplace_back(scene, p);
    rects.push_back(primitive_extent(maps.back(), scene.width, scene.height));
  }
  // Pixels outside every primitive's extent cannot be covered: not visited.
  const PixelRect r = scene_extent(scene, maps);
  const int w = r.x1 - r.x0;
  std::vector<int32_t> owner;
  std::vector<double> depth;
  for (int band = r.y0; band < r.y1; band += kBandRows) {
    const int band_end = std::min(band + kBandRows, r.y1);
    const size_t n = static_cast<size_t>(band_end - band) * static_cast<size_t>(w);
    owner.assign(n, -1);
    depth.assign(n, std::numeric_limits<double>::infinity());
    // The nearest primitive at each pixel centre; the first one on a tie.
    for (size_t p = 0; p < maps.size(); ++p) {
      const PixelRect& pr = rects[p];
      for (int y = std::max(band, pr.y0); y < std::min(band_end, pr.y1); ++y) {
        for (int x = pr.x0; x < pr.x1; ++x) {
          const UvSample s = maps[p].at(x + 0.5, y + 0.5);
          const size_t k = static_cast<size_t>(y - band) * static_cast<size_t>(w) +
                           static_cast<size_t>(x - r.x0);
          if (s.inside && (owner[k] < 0 || s.depth < depth[k])) {
            owner[k] = static_cast<int32_t>(p);
            depth[k] = s.depth;
          }
        }
      }
    }
    for (int y = band; y < band_end; ++y) {
      for (int x = r.x0; x < r.x1; ++x) {
        const int32_t best = owner[static_cast<size_t>(y - band) * static_cast<size_t>(w) +
                                   static_cast<size_t>(x - r.x0)];
        if (best < 0) continue;
        const UvSample hit = maps[static_cast<size_t>(best)].at(x + 0.5, y + 0.5);
        Fragment f = hit.fragment(static_cast<uint32_t>(x), static_cast<uint32_t>(y));
        f.frame = frame;
        f.prim = static_cast<uint32_t>(best);
        f.tex = static_cast<uint32_t>(scene
                                          .materials[static_cast<size_t>(
                                              scene.primitives[static_cast<size_t>(best)].material)]
                                          .texture);
        emit(f);
      }
    }
  }
}

std::vector<Fragment> generate_fragments(const Scene& scene, uint32_t frame) {
  std::vector<Fragment> out;
  generate_fragments(scene, frame, [&](const Fragment& f) { out.push_back(f); });
  return out;
}

}  // namespace texsim
