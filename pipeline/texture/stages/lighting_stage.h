#pragma once
// A material's lighting (ПРО; its `lighting` table, surface_effects.h), in the lighting slot
// after the blend: the normal unit then the Blinn-Phong shader.
#include <cstdint>
#include <vector>

#include "pipeline/texture/stages/unit_stage.h"
#include "pipeline/texture/surface_effects.h"

namespace texsim {

class LightingStage final : public SurfaceStage {
 public:
  // normal_tex: the normal or height texture (null for flat normals).
  LightingStage(const LightingSetup& s, const Texture* normal_tex, const TechTable& tech)
      : effect_(s, normal_tex), extra_ii_(effect_.timing(tech).ii - 1) {}
  void declare(SlotPlan& plan, const TechTable& tech) const override {
    plan.occupy(Slot::Lighting, effect_.timing(tech).latency);
  }
  void bind(const SlotPlan& plan, const TechTable& /*tech*/) override {
    slot_ = plan.index(Slot::Lighting);
  }
  void rows(StageReport& r, std::vector<BlockUse>& out) const override;
  void enter(SurfaceItem& it, FetchStage& /*fetch*/) override {
    if (it.timed) it.extra_ii[slot_] += extra_ii_;
  }
  Rgba leave(const SurfaceItem& it, const Rgba& c) override {
    const glm::dvec3 light_ts = it.sf.to_tangent(effect_.setup().light_dir);
    return effect_.shade(c, it.g.u, it.g.v, it.view_ts, light_ts, normal_ops_, shader_ops_);
  }

 private:
  LightingEffect effect_;
  uint32_t extra_ii_;
  int slot_ = -1;
  OpCounts normal_ops_, shader_ops_;
};

}  // namespace texsim
