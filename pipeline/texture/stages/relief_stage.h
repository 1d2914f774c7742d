#pragma once
// A material's relief (its `relief` table, surface_effects.h), in the relief slot in front of
// LOD: shifts the fragment's (u, v) over the height map, one loop step per step ii; in a timed
// unit its height (or distance-map) reads go through the cache before the filter's.
#include <cstdint>
#include <memory>
#include <vector>

#include "pipeline/texture/stages/unit_stage.h"
#include "pipeline/texture/surface_effects.h"

namespace texsim {

class ReliefStage final : public SurfaceStage {
 public:
  // height: the height texture; colour: the material's texture (read by the visibility-aware
  // filter); volume_base: where the distance map's volume lies in memory (one byte a voxel).
  ReliefStage(const ReliefSetup& s, const Texture& height, const Texture& colour,
              uint64_t volume_base, const TechTable& tech);
  void declare(SlotPlan& plan, const TechTable& tech) const override {
    // The footprint's derivatives follow the shift in the same slot.
    const ReliefFootprint& fp = effect_.footprint();
    plan.occupy(Slot::Relief,
                effect_.timing(tech).latency + (fp.active() ? fp.timing(tech).latency : 0));
  }
  void bind(const SlotPlan& plan, const TechTable& /*tech*/) override {
    slot_ = plan.index(Slot::Relief);
  }
  void rows(StageReport& r, std::vector<BlockUse>& out) const override {
    r.add(out, effect_.name(), effect_.arithmetic(), effect_.timing(r.tech), ops_, fetches_);
    const ReliefFootprint& fp = effect_.footprint();
    if (fp.active()) r.add(out, fp.name(), fp.arithmetic(), fp.timing(r.tech), footprint_ops_);
  }
  void enter(SurfaceItem& it, FetchStage& fetch) override;
  Rgba leave(const SurfaceItem& /*it*/, const Rgba& c) override { return c; }

  const ReliefEffect& effect() const { return effect_; }
  // The distinct cache lines of reads of this relief's height map, distance map or colour
  // texture, sorted.
  void lines(const std::vector<ReliefRead>& reads, const FetchStage& fetch,
             std::vector<uint64_t>& out) const;
  uint64_t steps() const { return steps_; }
  uint64_t fetches() const { return fetches_; }

  // Quad footprint: g's derivatives replaced by the differences of the shifted coordinates
  // between the lanes of its 2×2 quad (fine: its own row and column; coarse: the top row and
  // the left column). f: the fragment before the shift, sh its own shift; each other lane is
  // f's coordinates moved by f's derivatives to that pixel, shifted along that pixel's view.
  void quad_derivatives(Fragment& g, const Fragment& f, const ReliefEffect::Shift& sh,
                        const SurfaceItem& it);

 private:
  ReliefEffect effect_;
  const Texture& height_;
  const Texture& colour_;
  uint64_t volume_base_;
  uint32_t step_ii_;
  int slot_ = -1;
  OpCounts ops_;
  OpCounts footprint_ops_;  // the footprint's derivatives (not the quad lanes' own shifts)
  uint64_t steps_ = 0, fetches_ = 0;  // loop steps and height reads (data-dependent)
  std::vector<ReliefRead> reads_;     // the current fragment's reads (timed)
  std::vector<uint64_t> lines_;       // their distinct cache lines
};

}  // namespace texsim
