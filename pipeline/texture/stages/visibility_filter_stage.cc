#include "pipeline/texture/stages/visibility_filter_stage.h"

#include <algorithm>

namespace texsim {

VisibilityFilterStage::VisibilityFilterStage(const ReliefStage& relief, const TechTable& tech)
    : relief_(relief), ii_(std::max<uint32_t>(1, vaf().timing(tech).ii)) {}

FilterStage::Result VisibilityFilterStage::filter(const Fragment& g, const Texture& /*tex*/,
                                                  const SurfaceItem* surface, bool timed,
                                                  const FetchStage& fetch) {
  reads_.clear();
  const VisibilityAwareFilter::Result r =
      relief_.effect().filter_visible(g, surface->view_ts, surface->sf.u_length(),
                                      surface->sf.v_length(), ops_, timed ? &reads_ : nullptr);
  const uint32_t n = r.stats.colour_reads + r.stats.trace_reads;
  texels_ += n;
  Result out;
  out.colour = {r.colour.x, r.colour.y, r.colour.z, r.colour.w};
  out.texels = n;
  if (timed) {
    relief_.lines(reads_, fetch, lines_);
    out.address_cycles = std::max<uint32_t>(1, n * ii_);
    out.lines = &lines_;
  }
  return out;
}

}  // namespace texsim
