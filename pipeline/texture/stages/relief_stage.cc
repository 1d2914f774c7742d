#include "pipeline/texture/stages/relief_stage.h"

#include <algorithm>

#include "pipeline/texture/stages/fetch_stage.h"

namespace texsim {

ReliefStage::ReliefStage(const ReliefSetup& s, const Texture& height, const Texture& colour,
                         uint64_t volume_base, const TechTable& tech)
    : effect_(s, height, &colour),
      height_(height),
      colour_(colour),
      volume_base_(volume_base),
      step_ii_(effect_.timing(tech).ii) {}

void ReliefStage::enter(SurfaceItem& it, FetchStage& fetch) {
  reads_.clear();
  const ReliefEffect::Shift sh =
      effect_.shift(it.g.u, it.g.v, it.view_ts, it.sf.u_length(), it.sf.v_length(), ops_,
                    it.timed ? &reads_ : nullptr);
  it.g.u = sh.u;
  it.g.v = sh.v;
  steps_ += sh.steps;
  fetches_ += sh.fetches;
  if (!it.timed) return;
  it.extra_ii[slot_] += sh.steps > 0 ? sh.steps * step_ii_ - 1 : 0;
  if (!reads_.empty()) {
    lines(reads_, fetch, lines_);
    fetch.stage_reads(lines_, reads_.size());
  }
}

void ReliefStage::lines(const std::vector<ReliefRead>& reads, const FetchStage& fetch,
                        std::vector<uint64_t>& out) const {
  out.clear();
  const ReliefHeightMap& hm = effect_.height_map();
  const DistanceMap& dm = effect_.distance_map();
  for (const ReliefRead& r : reads) {
    uint64_t addr = 0;
    if (r.z == ReliefRead::kHeightRead) {
      addr = height_.address(0, r.x, r.y);
    } else if (r.z == ReliefRead::kColourRead) {
      // The filter's colour grid is the height map's: texel (x, y) is the colour texel it
      // was resampled from.
      addr = colour_.address(0, static_cast<int>(int64_t{r.x} * colour_.width(0) / hm.width),
                             static_cast<int>(int64_t{r.y} * colour_.height(0) / hm.height));
    } else {
      addr = volume_base_ + dm.index(r.x, r.y, r.z);
    }
    out.push_back(fetch.line_of(addr));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

}  // namespace texsim
