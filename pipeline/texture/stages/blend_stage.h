#pragma once
// The blend (the unit's `[pipeline.blend]`), in the blend slot: the weighted sum of a
// material's taps, taps_per_cycle a cycle. After a footprint or visibility-aware filter it
// only normalises (`bypassed`: counted in the filter's block, no row of its own).
#include <cstdint>

#include "blocks/texture/sampler/texel_blend.h"
#include "pipeline/texture/stages/unit_stage.h"

namespace texsim {

class BlendStage final : public UnitStage {
 public:
  // taps_per_probe: the taps of one probe of the material's address stage.
  BlendStage(const TexelBlend::Config& c, uint32_t taps_per_probe, bool bypassed);
  void declare(SlotPlan& plan, const TechTable& tech) const override {
    plan.set(Slot::Blend, blend_.timing(tech));
  }
  // Blends the taps the address stage's row counted (r.taps).
  void rows(StageReport& r, std::vector<BlockUse>& out) const override {
    if (bypassed_) return;
    // A border tap is multiplied and summed like any other, without its texel read.
    OpCounts ops = TexelBlend::ops_per_item() * r.taps;
    ops.mem -= r.border_taps;
    r.add(out, blend_.name(), blend_.arithmetic(), blend_.timing(r.tech), ops);
  }
  const TexelBlend& blend() const { return blend_; }
  // Extra issue cycles of a fragment of N = 1..16 probes.
  uint32_t extra_ii(uint32_t probes) const { return extra_ii_[probes]; }

 private:
  TexelBlend blend_;
  bool bypassed_;
  // N × taps per probe taps at taps_per_cycle: a table instead of a division per fragment.
  uint32_t extra_ii_[17] = {};
};

}  // namespace texsim
