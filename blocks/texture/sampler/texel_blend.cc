#include "blocks/texture/sampler/texel_blend.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "blocks/base/block.h"

namespace texsim {

static_assert(Block<TexelBlend>);

TexelBlend::Config TexelBlend::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"taps_per_cycle"});
  Config c;
  c.taps_per_cycle = static_cast<int>(r.get_int("taps_per_cycle", c.taps_per_cycle, 1, 32));
  if (!std::has_single_bit(static_cast<unsigned>(c.taps_per_cycle))) {
    r.fail("taps_per_cycle", "must be a power of two (the adder tree is binary)");
  }
  return c;
}

TimingSpec TexelBlend::timing(const TechTable& tech) const {
  const int levels =
      static_cast<int>(std::bit_width(static_cast<unsigned>(std::max(cfg_.taps_per_cycle, 1)))) - 1;
  OpCounts path;
  path.mem = 1;
  path.mul = 1;
  path.add = static_cast<uint64_t>(levels) + 1;  // tree + accumulator
  OpCounts units;  // taps_per_cycle read ports and RGBA multipliers, tree + accumulator adders
  units.mem = static_cast<uint64_t>(cfg_.taps_per_cycle);
  units.mul = 4 * static_cast<uint64_t>(cfg_.taps_per_cycle);
  units.add = 4 * static_cast<uint64_t>(cfg_.taps_per_cycle);
  return derive_timing(tech, units, path, Datapath::Spatial);
}

}  // namespace texsim
