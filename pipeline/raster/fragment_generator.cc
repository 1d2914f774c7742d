#include "pipeline/raster/fragment_generator.h"

#include <limits>

#include "pipeline/geometry/plane_projection.h"
#include "pipeline/geometry/screen_extent.h"
#include "pipeline/texture/effect_registry.h"

namespace texsim {

void generate_fragments(const Scene& scene, uint32_t frame,
                        const std::function<void(const Fragment&)>& emit,
                        std::vector<RasterCounters>* raster,
                        const std::vector<MaterialSetup>* built) {
  const std::vector<MaterialSetup> own =
      built ? std::vector<MaterialSetup>{} : build_materials(scene);
  const std::vector<MaterialSetup>& mats = built ? *built : own;
  std::vector<PlaneProjection> maps;
  maps.reserve(scene.primitives.size());
  for (const auto& p : scene.primitives) maps.emplace_back(scene, p);
  const PixelRect r = scene_extent(scene, maps);
  const int w = r.x1 - r.x0;
  const auto index = [&](int32_t x, int32_t y) {
    return static_cast<size_t>(y - r.y0) * static_cast<size_t>(w) + static_cast<size_t>(x - r.x0);
  };
  std::vector<int32_t> owner(static_cast<size_t>(r.pixels()), -1);
  std::vector<double> depth(owner.size(), std::numeric_limits<double>::infinity());
  std::vector<RasterCounters> counters(mats.size());
  for (size_t p = 0; p < maps.size(); ++p) {
    const auto m = static_cast<size_t>(scene.primitives[p].material);
    rasterize_primitive(maps[p], mats[m].raster, scene.tech, scene.width, scene.height, counters[m],
                        [&](int32_t x, int32_t y) {
                          if (x < r.x0 || y < r.y0 || x >= r.x1 || y >= r.y1) return;
                          const double d = maps[p].at(x + 0.5, y + 0.5).depth;
                          if (!(d > 0)) return;  // on the horizon line: nothing of it seen there
                          const size_t k = index(x, y);
                          if (owner[k] < 0 || d < depth[k]) {
                            owner[k] = static_cast<int32_t>(p);
                            depth[k] = d;
                          }
                        });
  }
  if (raster) *raster = counters;
  for (int y = r.y0; y < r.y1; ++y) {
    for (int x = r.x0; x < r.x1; ++x) {
      const int32_t best = owner[index(x, y)];
      if (best < 0) continue;
      const auto b = static_cast<size_t>(best);
      Fragment f =
          maps[b].at(x + 0.5, y + 0.5).fragment(static_cast<uint32_t>(x), static_cast<uint32_t>(y));
      f.frame = frame;
      f.prim = static_cast<uint32_t>(best);
      f.tex = static_cast<uint32_t>(
          scene.materials[static_cast<size_t>(scene.primitives[b].material)].texture);
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
