#include "pipeline/raster/fragment_generator.h"

#include "pipeline/geometry/plane_projection.h"
#include "pipeline/geometry/screen_extent.h"

namespace texsim {

void generate_fragments(const Scene& scene, uint32_t frame,
                        const std::function<void(const Fragment&)>& emit) {
  std::vector<PlaneProjection> maps;
  maps.reserve(scene.planes.size());
  for (const auto& p : scene.planes) maps.emplace_back(scene, p);
  // Pixels outside the planes' extent cannot be covered: not visited.
  const PixelRect r = scene_extent(scene, maps);
  for (int y = r.y0; y < r.y1; ++y) {
    for (int x = r.x0; x < r.x1; ++x) {
      int best = -1;
      UvSample hit;
      for (size_t p = 0; p < maps.size(); ++p) {
        const UvSample s = maps[p].at(x + 0.5, y + 0.5);
        if (s.inside && (best < 0 || s.depth < hit.depth)) {
          best = static_cast<int>(p);
          hit = s;
        }
      }
      if (best < 0) continue;
      Fragment f = hit.fragment(static_cast<uint32_t>(x), static_cast<uint32_t>(y));
      f.frame = frame;
      f.prim = static_cast<uint32_t>(best);
      f.tex = static_cast<uint32_t>(scene.materials[scene.planes[best].material].texture);
      emit(f);
    }
  }
}

std::vector<Fragment> generate_fragments(const Scene& scene, uint32_t frame) {
  std::vector<Fragment> out;
  generate_fragments(scene, frame, [&](const Fragment& f) { out.push_back(f); });
  return out;
}

}  // namespace texsim
