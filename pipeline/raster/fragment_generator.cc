#include "pipeline/raster/fragment_generator.h"

#include "pipeline/geometry/plane_projection.h"

namespace texsim {

void generate_fragments(const Scene& scene, uint32_t frame,
                        const std::function<void(const Fragment&)>& emit) {
  std::vector<PlaneProjection> maps;
  maps.reserve(scene.planes.size());
  for (const auto& p : scene.planes) maps.emplace_back(scene, p);
  for (int y = 0; y < scene.height; ++y) {
    for (int x = 0; x < scene.width; ++x) {
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
