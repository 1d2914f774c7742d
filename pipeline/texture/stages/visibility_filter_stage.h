#pragma once
// The visibility-aware filter of a relief material (its relief's `visibility_filter` table),
// in place of its filter: one read per issue cycle in the address slot, its colour and trace
// reads through the cache.
#include <cstdint>
#include <vector>

#include "pipeline/texture/stages/relief_stage.h"

namespace texsim {

class VisibilityFilterStage final : public FilterStage {
 public:
  VisibilityFilterStage(const ReliefStage& relief, const TechTable& tech);
  void declare(SlotPlan& plan, const TechTable& tech) const override {
    plan.occupy(Slot::Address, vaf().timing(tech).latency);
  }
  void rows(StageReport& r, std::vector<BlockUse>& out) const override {
    r.add(out, vaf().name(), vaf().arithmetic(), vaf().timing(r.tech), ops_, texels_);
  }
  Result filter(const Fragment& g, const Texture& tex, const SurfaceItem* surface, bool timed,
                const FetchStage& fetch) override;

 private:
  const VisibilityAwareFilter& vaf() const { return relief_.effect().visibility_filter(); }
  const ReliefStage& relief_;
  uint32_t ii_;  // issue cycles per read
  OpCounts ops_;
  uint64_t texels_ = 0;  // colours and trace heights read
  std::vector<ReliefRead> reads_;
  std::vector<uint64_t> lines_;
};

}  // namespace texsim
