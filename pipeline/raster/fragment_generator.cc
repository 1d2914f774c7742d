#include "pipeline/raster/fragment_generator.h"

#include <algorithm>
#include <limits>

#include "pipeline/geometry/direction_map.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/geometry/screen_extent.h"
#include "pipeline/raster/raster_order.h"
#include "pipeline/texture/effect_registry.h"

namespace texsim {

namespace {

// Adds each material's quads and helper lanes: in every 2×2 square anchored at even x, y, one
// quad per primitive that kept a pixel there; the quad's lanes it did not keep are helper lanes
// (lanes outside r or the screen too: a GPU runs all four).
void count_quads(const Scene& scene, const PixelRect& r, const std::vector<int32_t>& owner,
                 std::vector<RasterCounters>& counters) {
  const auto w = static_cast<size_t>(r.x1 - r.x0);
  for (int y = r.y0 & ~1; y < r.y1; y += 2) {
    for (int x = r.x0 & ~1; x < r.x1; x += 2) {
      int32_t kept[4];
      int n = 0;
      for (int lane = 0; lane < 4; ++lane) {
        const int px = x + (lane & 1), py = y + (lane >> 1);
        if (px < r.x0 || py < r.y0 || px >= r.x1 || py >= r.y1) continue;
        const int32_t o =
            owner[static_cast<size_t>(py - r.y0) * w + static_cast<size_t>(px - r.x0)];
        if (o >= 0) kept[n++] = o;
      }
      for (int i = 0; i < n; ++i) {
        bool first = true;
        int lanes = 0;
        for (int j = 0; j < n; ++j) {
          if (kept[j] != kept[i]) continue;
          first = first && j >= i;
          ++lanes;
        }
        if (!first) continue;
        RasterCounters& c =
            counters[static_cast<size_t>(scene.primitives[static_cast<size_t>(kept[i])].material)];
        ++c.quads;
        c.helper_lanes += static_cast<uint64_t>(4 - lanes);
      }
    }
  }
}

}  // namespace

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
  // Cube materials look up a direction per pixel (effect `lookup`), one map per primitive.
  std::vector<DirectionMap> dirs(maps.size());
  for (size_t p = 0; p < maps.size(); ++p) {
    const MaterialSetup& ms = mats[static_cast<size_t>(scene.primitives[p].material)];
    if (ms.lookup && ms.lookup->direction != LayeredLookup::Direction::None)
      dirs[p] = DirectionMap::make(scene.camera, scene.primitives[p],
                                   ms.lookup->direction == LayeredLookup::Direction::Reflect);
  }
  const PixelRect r = scene_extent(scene, maps);
  const int w = r.x1 - r.x0;
  const auto index = [&](int32_t x, int32_t y) {
    return static_cast<size_t>(y - r.y0) * static_cast<size_t>(w) + static_cast<size_t>(x - r.x0);
  };
  std::vector<int32_t> owner(static_cast<size_t>(r.pixels()), -1);
  std::vector<double> depth(owner.size(), std::numeric_limits<double>::infinity());
  std::vector<RasterCounters> counters(mats.size());
  // The rasteriser's own coordinates of the kept pixel (rect_scan's constant-depth rows); held
  // only when some material has them.
  const bool any_uv = std::any_of(
      mats.begin(), mats.end(), [](const MaterialSetup& ms) { return ms.raster.constant_depth(); });
  std::vector<CoordSample> uvs(any_uv ? owner.size() : 0);
  for (size_t p = 0; p < maps.size(); ++p) {
    const auto m = static_cast<size_t>(scene.primitives[p].material);
    rasterize_primitive(maps[p], mats[m].raster, scene.tech, scene.width, scene.height, counters[m],
                        [&](int32_t x, int32_t y, const CoordSample* uv) {
                          if (x < r.x0 || y < r.y0 || x >= r.x1 || y >= r.y1) return;
                          const double d = maps[p].at(x + 0.5, y + 0.5).depth;
                          if (!(d > 0)) return;  // on the horizon line: nothing of it seen there
                          const size_t k = index(x, y);
                          if (owner[k] < 0 || d < depth[k]) {
                            owner[k] = static_cast<int32_t>(p);
                            depth[k] = d;
                            if (any_uv) uvs[k] = uv ? *uv : CoordSample{};
                          }
                        });
  }
  count_quads(scene, r, owner, counters);
  if (raster) *raster = counters;
  const auto emit_pixel = [&](int x, int y, int32_t best) {
    const auto b = static_cast<size_t>(best);
    Fragment f =
        maps[b].at(x + 0.5, y + 0.5).fragment(static_cast<uint32_t>(x), static_cast<uint32_t>(y));
    // Constant-depth rows give u, v; the derivatives stay the exact ones at the pixel centre
    // (the seed's datapath has none).
    if (any_uv && uvs[index(x, y)].valid) {
      f.u = uvs[index(x, y)].u;
      f.v = uvs[index(x, y)].v;
    }
    if (const auto& lk = mats[static_cast<size_t>(scene.primitives[b].material)].lookup) {
      if (lk->direction != LayeredLookup::Direction::None) dirs[b].apply(f);
      f.layer = static_cast<float>(lk->layer);
      lk->apply_r(f);
    }
    f.frame = frame;
    f.prim = static_cast<uint32_t>(best);
    const auto m = static_cast<size_t>(scene.primitives[b].material);
    f.tex = static_cast<uint32_t>(scene.materials[m].texture);
    // The material's operation (docs/scenes.md `operation`); none: an implicit-LOD sample.
    if (mats[m].operation) mats[m].operation->apply(f);
    emit(f);
  };
  const RasterWalk walk(scene.raster, scene.width, scene.height, r);
  if (scene.raster.kind == RasterOrder::Kind::Rows) {
    walk.for_each([&](int x, int y) {
      if (const int32_t best = owner[index(x, y)]; best >= 0) emit_pixel(x, y, best);
    });
    return;
  }
  // Tiled: a quad's kept pixels are held until the walk leaves it, then handed on primitive by
  // primitive (each in lane order), so every primitive's quad arrives as one run of fragments,
  // as a GPU's rasteriser issues it (the rule QuadAssembler recovers quads by).
  struct Held {
    int x, y;
    int32_t owner;
  };
  Held held[4];
  int n = 0;
  const auto release = [&] {
    for (int i = 0; i < n; ++i) {
      const int32_t o = held[i].owner;
      if (o < 0) continue;
      for (int j = i; j < n; ++j) {
        if (held[j].owner != o) continue;
        emit_pixel(held[j].x, held[j].y, o);
        held[j].owner = -1;
      }
    }
    n = 0;
  };
  walk.for_each([&](int x, int y) {
    const int32_t best = owner[index(x, y)];
    if (best < 0) return;
    if (n > 0 && ((held[0].x ^ x) >> 1 != 0 || (held[0].y ^ y) >> 1 != 0)) release();
    held[n++] = {x, y, best};
  });
  release();
}

std::vector<Fragment> generate_fragments(const Scene& scene, uint32_t frame) {
  std::vector<Fragment> out;
  generate_fragments(scene, frame, [&](const Fragment& f) { out.push_back(f); });
  return out;
}

}  // namespace texsim
