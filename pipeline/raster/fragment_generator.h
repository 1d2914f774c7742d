#pragma once
// Reference fragment generator: rasterises a scene's textured planes at pixel centres (nearest
// plane wins) and emits fragments with exact texture coordinates and derivatives.
#include <functional>
#include <vector>

#include "blocks/base/fragment.h"
#include "pipeline/scene/scene.h"

namespace texsim {

// Calls `emit` for every covered pixel in raster order (rows top to bottom), frame `frame`.
// Fragment::prim is the plane index, Fragment::tex the material's texture index.
void generate_fragments(const Scene& scene, uint32_t frame,
                        const std::function<void(const Fragment&)>& emit);
std::vector<Fragment> generate_fragments(const Scene& scene, uint32_t frame = 0);

}  // namespace texsim
