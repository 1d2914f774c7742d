#include "pipeline/texture/stages/relief_stage.h"

#include <algorithm>
#include <glm/geometric.hpp>

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
  const Fragment f = it.g;
  const ReliefEffect::Shift sh =
      effect_.shift(it.g.u, it.g.v, it.view_ts, it.sf.u_length(), it.sf.v_length(), ops_,
                    it.timed ? &reads_ : nullptr);
  it.g.u = sh.u;
  it.g.v = sh.v;
  const ReliefFootprint& fp = effect_.footprint();
  if (fp.quad()) {
    quad_derivatives(it.g, f, sh, it);
  } else if (fp.active()) {
    effect_.analytic_derivatives(it.g, sh, footprint_ops_);
  }
  steps_ += sh.steps;
  fetches_ += sh.fetches;
  if (!it.timed) return;
  it.extra_ii[slot_] += sh.steps > 0 ? sh.steps * step_ii_ - 1 : 0;
  if (!reads_.empty()) {
    lines(reads_, fetch, lines_);
    fetch.stage_reads(lines_, reads_.size());
  }
}

void ReliefStage::quad_derivatives(Fragment& g, const Fragment& f, const ReliefEffect::Shift& sh,
                                   const SurfaceItem& it) {
  // The view at a pixel: the fragment's own, moved by the camera's change between the pixels
  // (a trace's fragment carries its own view only).
  const glm::dvec3 own = it.sf.to_tangent(it.sf.view(f.x + 0.5, f.y + 0.5));
  const int lane = static_cast<int>((f.x & 1U) | (f.y & 1U) << 1);
  OpCounts lane_ops;  // the other lanes' shifts are their own work, not this fragment's
  const auto shifted = [&](int l) {
    if (l == lane) return glm::dvec2(sh.u, sh.v);
    const double dx = (l & 1) - (lane & 1), dy = (l >> 1) - (lane >> 1);
    const glm::dvec3 view = glm::normalize(
        it.view_ts + it.sf.to_tangent(it.sf.view(f.x + dx + 0.5, f.y + dy + 0.5)) - own);
    const ReliefEffect::Shift s =
        effect_.shift(f.u + f.dudx * dx + f.dudy * dy, f.v + f.dvdx * dx + f.dvdy * dy, view,
                      it.sf.u_length(), it.sf.v_length(), lane_ops);
    return glm::dvec2(s.u, s.v);
  };
  const bool fine = effect_.footprint().config().mode == ReliefFootprint::Mode::QuadFine;
  const int row = fine ? (lane & 2) : 0, col = fine ? (lane & 1) : 0;
  const glm::dvec2 ddx = shifted(row | 1) - shifted(row);
  const glm::dvec2 ddy = shifted(col | 2) - shifted(col);
  g.dudx = ddx.x;
  g.dvdx = ddx.y;
  g.dudy = ddy.x;
  g.dvdy = ddy.y;
  ReliefFootprint::count_quad(footprint_ops_);
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
