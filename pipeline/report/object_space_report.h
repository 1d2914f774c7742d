#pragma once
// The object-space sections of a run's report (docs/reports.md): for every material drawn by the
// object-space pipeline (effect `object_space`) what its blocks did and cost — samples, cycles by
// stage, operations by block, texels, cache and DRAM, accumulation-buffer traffic and holes —
// and the frame's cycles of both pipelines. Absent when no material has the effect.
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "pipeline/raster/object_space_pipeline.h"

namespace texsim {

struct ObjectSpaceMaterialInfo {
  std::string material;
  ObjectSpaceConfig config;
  ObjectSpaceResult result;   // its per-pixel vectors are left empty
  uint64_t pixels_shown = 0;  // pixels the frame's depth test gave this material
  uint64_t holes_shown = 0;   // of those, pixels without splat weight (drawn as background)
  // The blocks the material went through, in pipeline order.
  std::vector<std::string> blocks() const;
};

struct ObjectSpaceInfo {
  std::vector<ObjectSpaceMaterialInfo> materials;  // empty: no material has the effect
  uint64_t screen_cycles = 0;  // the screen-space pass: max(texture unit, its rasterisers)
  bool active() const { return !materials.empty(); }
  uint64_t cycles() const;  // every object-space pass
  // The frame: the object-space passes, then the screen-space pass.
  uint64_t frame_cycles() const { return cycles() + screen_cycles; }
  const ObjectSpaceMaterialInfo* find(const std::string& material) const;
};

// Adds materials.NAME.object_space for each object-space material and the top-level
// object_space section (nothing when inactive).
void add_object_space_json(nlohmann::ordered_json& j, const ObjectSpaceInfo& info);
void object_space_markdown(std::ostream& md, const ObjectSpaceInfo& info);

}  // namespace texsim
