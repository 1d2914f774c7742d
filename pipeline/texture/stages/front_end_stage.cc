#include "pipeline/texture/stages/front_end_stage.h"

namespace texsim {

namespace {
constexpr Slot kFrontSlots[2] = {Slot::Coords, Slot::Derivs};
}

void FrontEndStage::declare(SlotPlan& plan, const TechTable& tech) const {
  const std::vector<StageConfig> st = unit_.stages(tech);
  for (int s = 0; s < count_; ++s) {
    const TimingSpec& u = st[static_cast<size_t>(s)].timing;
    plan.occupy(kFrontSlots[s], u.latency, u.lanes);
  }
}

void FrontEndStage::bind(const SlotPlan& plan, const TechTable& tech) {
  const std::vector<StageConfig> st = unit_.stages(tech);
  for (int s = 0; s < count_; ++s) {
    const TimingSpec& u = st[static_cast<size_t>(s)].timing;
    const uint32_t lanes = plan.timing(kFrontSlots[s]).lanes;
    extra_[s] = (u.ii * lanes + u.lanes - 1) / u.lanes - 1;
  }
}

void FrontEndStage::generate(const CoordTriangle& tri, const TechTable& tech,
                             std::vector<CoordUnitFragment>& out, std::vector<ItemCost>& costs) {
  const size_t before = out.size();
  unit_.generate(tri, tech, out, costs, coord_ops_, deriv_ops_);
  stats_.generated += out.size() - before;
}

void FrontEndStage::drop(const ItemCost* front, bool rejected, uint32_t* owed) {
  ++(rejected ? stats_.rejected : stats_.occluded);
  if (!front) return;
  for (int s = 0; s < count_; ++s) owed[s] += 1 + extra_[s] + front[s].extra_ii;
}

void FrontEndStage::rows(StageReport& r, std::vector<BlockUse>& out) const {
  const CoordUnitConfig& cc = unit_.config();
  const std::vector<StageConfig> st = unit_.stages(r.tech);
  const std::string arith = cc.format + ", " + datapath_name(cc.datapath) + " datapath";
  // The format is part of the name: two materials with one method in two formats are two units.
  r.add(out, "coords." + cc.coords + "[" + cc.format + "]", arith, st[0].timing, coord_ops_);
  if (count_ > 1)
    r.add(out, "derivs." + cc.derivs + "[" + cc.format + "]", arith, st[1].timing, deriv_ops_);
}

}  // namespace texsim
