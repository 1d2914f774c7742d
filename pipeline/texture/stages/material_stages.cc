#include "pipeline/texture/stages/material_stages.h"

#include <stdexcept>
#include <utility>

#include "pipeline/texture/stages/footprint_stage.h"
#include "pipeline/texture/stages/lighting_stage.h"
#include "pipeline/texture/stages/relief_stage.h"
#include "pipeline/texture/stages/visibility_filter_stage.h"

namespace texsim {

namespace {

template <class S, class... Args>
S* add(MaterialStages& ms, Args&&... args) {
  ms.all.push_back(std::make_unique<S>(std::forward<Args>(args)...));
  return static_cast<S*>(ms.all.back().get());
}

const Texture& bound(TextureSet& textures, int id, const MaterialSetup& m, const char* what) {
  if (id < 0 || id >= textures.size())
    throw std::invalid_argument("texture unit: material '" + m.name + "': " + what +
                                " texture is not bound");
  return textures[id];
}

ReliefStage* add_relief(MaterialStages& ms, const MaterialSetup& m, TextureSet& textures,
                        const TechTable& tech, int& relief_index) {
  const Texture& height = bound(textures, m.relief->height_tex, m, "relief height");
  // Each distance map in a region of its own, far above the textures.
  const uint64_t volume = (uint64_t{1} << 40) + (static_cast<uint64_t>(relief_index++) << 32);
  ReliefStage* r = add<ReliefStage>(ms, *m.relief, height, textures[m.texture], volume, tech);
  ms.surface.push_back(r);
  return r;
}

}  // namespace

MaterialStages assemble_stages(const MaterialSetup& m, TextureSet& textures,
                               const PipelineSetup& setup, const TechTable& tech,
                               int& relief_index) {
  MaterialStages ms;
  if (m.coords) ms.front = add<FrontEndStage>(ms, *m.coords);
  const ReliefStage* relief = m.relief ? add_relief(ms, m, textures, tech, relief_index) : nullptr;
  const bool visible = relief && relief->effect().has_visibility_filter();
  const bool filter_stage = visible || m.footprint;
  ms.lod = add<LodStage>(ms, m.lod, filter_stage);
  if (visible) {
    ms.filter = add<VisibilityFilterStage>(ms, *relief, tech);
  } else if (m.footprint) {
    ms.filter = add<FootprintStage>(ms, *m.footprint);
  } else {
    ms.address = add<AddressStage>(ms, m.filter);
  }
  const uint32_t taps = ms.address ? ms.address->taps_per_probe() : 0;
  ms.blend = add<BlendStage>(ms, setup.blend, taps, filter_stage);
  if (m.lighting) {
    const int nt = m.lighting->normal_tex;
    const bool flat = m.lighting->normal == LightingSetup::Normal::Flat;
    const Texture* normals = flat && nt < 0 ? nullptr : &bound(textures, nt, m, "lighting normal");
    ms.surface.push_back(add<LightingStage>(ms, *m.lighting, normals, tech));
  }
  return ms;
}

}  // namespace texsim
