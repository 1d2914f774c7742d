#pragma once
// A material's coordinate front end (its `coords` table): the coordinate unit, and its
// derivative unit when it has one, in the coordinate and derivative slots in front of LOD.
// The unit generates a triangle's fragments and their costs per slot (generate()); those
// costs come back with each fragment the unit textures (cost()) or drops (drop()).
#include <cstdint>
#include <vector>

#include "pipeline/texture/coord_method.h"
#include "pipeline/texture/stages/unit_stage.h"

namespace texsim {

// Fragments a coordinate front end produced and what became of them.
struct FrontEndStats {
  uint64_t generated = 0;  // pixels the coordinate units computed
  uint64_t occluded = 0;   // left after the front end: hidden by a nearer plane, or covered twice
  uint64_t rejected = 0;   // coordinates rejected by the block (not textured)
};

class FrontEndStage final : public UnitStage {
 public:
  explicit FrontEndStage(const CoordUnit& unit) : unit_(unit), count_(unit.has_derivs() ? 2 : 1) {}
  void declare(SlotPlan& plan, const TechTable& tech) const override;
  void bind(const SlotPlan& plan, const TechTable& tech) override;
  void rows(StageReport& r, std::vector<BlockUse>& out) const override;

  // Slots it occupies (costs per fragment).
  int count() const { return count_; }
  void generate(const CoordTriangle& tri, const TechTable& tech,
                std::vector<CoordUnitFragment>& out, std::vector<ItemCost>& costs);
  // A fragment's cost in front-end slot s (`front`: its costs, or null).
  ItemCost cost(const ItemCost* front, int s) const {
    ItemCost c;
    if (front && s < count_) c = front[s];
    c.extra_ii += extra_[s];
    return c;
  }
  // A fragment that leaves after the front end; its issue cycles in each slot are added to
  // owed[slot], charged to the next fragment there (`front` null: untimed).
  void drop(const ItemCost* front, bool rejected, uint32_t* owed);
  const FrontEndStats& stats() const { return stats_; }

 private:
  const CoordUnit& unit_;
  int count_;
  // Added issue cycles per slot so the shared slot (sized for the widest unit) gives this
  // unit its own throughput: ceil(ii × lanes_slot / lanes_unit) − 1.
  uint32_t extra_[2] = {};
  OpCounts coord_ops_, deriv_ops_;
  FrontEndStats stats_;
};

}  // namespace texsim
