#pragma once
// The stages one material needs, in pipeline order: [coordinate front end] [relief] then its
// filter — LOD → address → blend, or a footprint or visibility-aware filter between the LOD
// slot and the blend, which its fragments pass through — then [lighting]. Adding an effect:
// its stage class (a UnitStage; a SurfaceStage around the filter, or a FilterStage in its
// place), its slot in unit_stage.h if it needs a new one, and a line in assemble_stages().
#include <memory>
#include <vector>

#include "blocks/base/tech_table.h"
#include "pipeline/texture/effect_registry.h"
#include "pipeline/texture/pipeline_setup.h"
#include "pipeline/texture/stages/address_stage.h"
#include "pipeline/texture/stages/blend_stage.h"
#include "pipeline/texture/stages/front_end_stage.h"
#include "pipeline/texture/stages/lod_stage.h"
#include "pipeline/texture/stages/unit_stage.h"

namespace texsim {

struct MaterialStages {
  std::vector<std::unique_ptr<UnitStage>> all;  // owned, in pipeline order
  // The same stages by role. The unit's templated kernels call the LOD, address and blend
  // stages' and the front end's methods directly (non-virtual, inlined: the per-fragment cost
  // of the classic path stays that of the blocks alone); a filter stage and the surface
  // stages, whose work per fragment is far larger, are called through their base classes.
  FrontEndStage* front = nullptr;      // null: fragments arrive with their coordinates
  LodStage* lod = nullptr;             // always set (a bypassed one beside a filter stage)
  AddressStage* address = nullptr;     // null when a filter stage takes the address slot
  BlendStage* blend = nullptr;         // always set
  FilterStage* filter = nullptr;       // footprint or visibility-aware filter, or null
  std::vector<SurfaceStage*> surface;  // relief, lighting: in order
};

// Material m's stages. `relief_index` counts the relief stages built so far for the unit
// (each distance map gets a region of memory of its own). Throws std::invalid_argument when a
// texture an effect names is not bound.
MaterialStages assemble_stages(const MaterialSetup& m, TextureSet& textures,
                               const PipelineSetup& setup, const TechTable& tech,
                               int& relief_index);

}  // namespace texsim
