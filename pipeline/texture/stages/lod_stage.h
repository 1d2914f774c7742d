#pragma once
// A material's LOD unit (its `lod` table), in the LOD slot. A material with a footprint or
// visibility-aware filter passes through the slot without using it (`bypassed`): the slot is
// still sized by its configuration, and it reports nothing.
#include "blocks/texture/sampler/lod_unit.h"
#include "pipeline/texture/stages/unit_stage.h"

namespace texsim {

class LodStage final : public UnitStage {
 public:
  LodStage(const LodUnit::Config& c, bool bypassed) : lod_(c), bypassed_(bypassed) {}
  void declare(SlotPlan& plan, const TechTable& tech) const override {
    plan.occupy(Slot::Lod, lod_.timing(tech).latency);
  }
  // Counted per fragment of the material (the report's fragments).
  void rows(StageReport& r, std::vector<BlockUse>& out) const override {
    if (bypassed_) return;
    r.add(out, lod_.name(), lod_.arithmetic(), lod_.timing(r.tech),
          lod_.ops_per_item() * r.fragments);
  }
  [[gnu::always_inline]] LodResult eval(const Fragment& f, const Texture& tex) const {
    return lod_.eval(f, tex.width(0), tex.height(0));
  }
  LodResult eval_volume(const Fragment& f, const Texture& tex) const {
    return lod_.eval_volume(f, tex.width(0), tex.height(0), tex.shape().slices);
  }
  const LodUnit::Config& config() const { return lod_.config(); }
  OpCounts ops_for(SampleOp op) const { return lod_.ops_for(op); }

 private:
  LodUnit lod_;
  bool bypassed_;
};

}  // namespace texsim
