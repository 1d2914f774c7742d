#include "blocks/texel_blend.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace texsim {

TexelBlend::Config TexelBlend::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"taps_per_cycle"});
  Config c;
  c.taps_per_cycle = static_cast<int>(r.get_int("taps_per_cycle", c.taps_per_cycle, 1, 32));
  if (!std::has_single_bit(static_cast<unsigned>(c.taps_per_cycle))) {
    r.fail("taps_per_cycle", "must be a power of two (the adder tree is binary)");
  }
  return c;
}

OpCounts TexelBlend::ops_per_tap() const {
  OpCounts o;
  o.mem = 1;  // one texel read
  o.mul = 4;  // w · RGBA
  o.add = 4;  // RGBA accumulate (tree levels + group accumulation: one add per product)
  return o;
}

uint32_t TexelBlend::issue_cycles(const FilterTaps& taps) const {
  const int g = std::max(cfg_.taps_per_cycle, 1);
  return static_cast<uint32_t>(std::max(1, (taps.count + g - 1) / g));
}

Rgba TexelBlend::blend(const FilterTaps& taps, const Texture& tex, OpCounts& ops) const {
  ops += ops_per_tap() * static_cast<uint64_t>(std::max(taps.count, 0));
  const int g = std::clamp(cfg_.taps_per_cycle, 1, 32);
  Rgba acc(0.0f);
  Rgba prod[32];
  for (int base = 0; base < taps.count; base += g) {
    const int n = std::min(g, taps.count - base);
    for (int k = 0; k < n; ++k) {
      const TexelTap& t = taps.tap[static_cast<size_t>(base + k)];
      prod[k] = tex.texel(t.level, t.x, t.y) * t.w;
    }
    // Binary adder tree over the group, as the hardware sums its lanes.
    for (int width = n; width > 1; width = (width + 1) / 2) {
      for (int k = 0; k < width / 2; ++k) prod[k] = prod[2 * k] + prod[2 * k + 1];
      if (width & 1) prod[width / 2] = prod[width - 1];
    }
    acc += prod[0];
  }
  return acc;
}

TimingSpec TexelBlend::timing(const TechTable& tech) const {
  const int levels = std::bit_width(static_cast<unsigned>(std::max(cfg_.taps_per_cycle, 1))) - 1;
  OpCounts path;
  path.mem = 1;
  path.mul = 1;
  path.add = static_cast<uint64_t>(levels) + 1;  // tree + accumulator
  TimingSpec t;
  t.latency = std::max<uint32_t>(1, static_cast<uint32_t>(std::ceil(tech.path_latency(path))));
  t.ii = 1;
  t.lanes = 1;
  OpCounts units;  // taps_per_cycle read ports and RGBA multipliers, tree + accumulator adders
  units.mem = static_cast<uint64_t>(cfg_.taps_per_cycle);
  units.mul = 4 * static_cast<uint64_t>(cfg_.taps_per_cycle);
  units.add = 4 * static_cast<uint64_t>(cfg_.taps_per_cycle);
  t.area = tech.area_of(units);
  return t;
}

}  // namespace texsim
