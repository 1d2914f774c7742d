#pragma once
// A material's footprint filter (EWA, multi-ellipse probes, Feline, SPAF; footprint_filter.h)
// in place of LOD → address → blend: one block that scans, weights and accumulates in the
// address slot for its issue cycles; its texels go through the cache, the blend normalises.
#include <cstdint>
#include <vector>

#include "pipeline/texture/footprint_filter.h"
#include "pipeline/texture/stages/unit_stage.h"

namespace texsim {

class FootprintStage final : public FilterStage {
 public:
  explicit FootprintStage(const FootprintFilter& f) : filter_(f) {}
  void declare(SlotPlan& plan, const TechTable& tech) const override {
    plan.occupy(Slot::Address, filter_.timing(tech).latency);
  }
  void rows(StageReport& r, std::vector<BlockUse>& out) const override {
    r.add(out, filter_.name(), filter_.arithmetic(), filter_.timing(r.tech), ops_, texels_);
  }
  Result filter(const Fragment& f, const Texture& tex, const SurfaceItem* surface, bool timed,
                const FetchStage& fetch) override;

 private:
  const FootprintFilter& filter_;
  OpCounts ops_;  // counted per call (data-dependent)
  uint64_t texels_ = 0;
  std::vector<TexelRef> fetched_;  // the current fragment's texels
  std::vector<uint64_t> lines_;    // their distinct cache lines
};

}  // namespace texsim
