#pragma once
// Fragment generator of a scene: every primitive the geometry subsystem keeps is drawn through
// its material's rasteriser (primitive_raster.h); a depth test keeps the nearest primitive per
// pixel (the first one on a tie); each kept pixel becomes a fragment with the exact texture
// coordinates and derivatives of its primitive's projective map at the pixel centre.
#include <functional>
#include <vector>

#include "blocks/base/fragment.h"
#include "pipeline/raster/primitive_raster.h"
#include "pipeline/scene/scene.h"
#include "pipeline/texture/effect_registry.h"

namespace texsim {

// Calls `emit` for every kept pixel in the scene's raster order (Scene::raster: rows top to
// bottom by default, or tiles and 2×2 quads, pipeline/raster/raster_order.h), frame `frame`.
// Fragment::prim is the primitive index, Fragment::tex the material's texture index.
// `raster`, if given, receives each material's rasteriser counters (indexed by material) and
// its quads and helper lanes after the depth test (the same in every order).
// `mats`: the scene's materials if the caller has built them (otherwise built here).
void generate_fragments(const Scene& scene, uint32_t frame,
                        const std::function<void(const Fragment&)>& emit,
                        std::vector<RasterCounters>* raster = nullptr,
                        const std::vector<MaterialSetup>* mats = nullptr);
std::vector<Fragment> generate_fragments(const Scene& scene, uint32_t frame = 0);

// Bytes the depth test holds per pixel of the scene's extent (owner and depth).
constexpr uint64_t kDepthTestBytesPerPixel = sizeof(int32_t) + sizeof(double);

}  // namespace texsim
