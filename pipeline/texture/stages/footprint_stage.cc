#include "pipeline/texture/stages/footprint_stage.h"

#include <algorithm>

#include "pipeline/texture/stages/fetch_stage.h"

namespace texsim {

FilterStage::Result FootprintStage::filter(const Fragment& f, const Texture& tex,
                                           const SurfaceItem* /*surface*/, bool timed,
                                           const FetchStage& fetch) {
  fetched_.clear();
  const FilterOutput out = filter_.filter(tex, f, &fetched_, ops_);
  texels_ += fetched_.size();
  Result r;
  r.colour = out.colour;
  r.texels = fetched_.size();
  if (timed) {
    r.address_cycles = std::max<uint32_t>(1, filter_.issue_cycles(out.stats));
    lines_.clear();
    for (const TexelRef& t : fetched_)
      lines_.push_back(fetch.line_of(tex.address(t.level, t.x, t.y)));
    std::sort(lines_.begin(), lines_.end());
    lines_.erase(std::unique(lines_.begin(), lines_.end()), lines_.end());
    r.lines = &lines_;
  }
  return r;
}

}  // namespace texsim
