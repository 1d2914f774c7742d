#pragma once
// Texel blend: the weighted-sum datapath Σ w·texel over a fragment's taps, with texel reads
// (docs/filters.md §5). Arithmetic: float32 products and a float32 adder tree per group of
// `taps_per_cycle` taps, the group sums accumulated in tap order.
#include <cstdint>

#include "blocks/config_reader.h"
#include "blocks/op_counts.h"
#include "blocks/tech_table.h"
#include "blocks/texel_address_gen.h"
#include "blocks/texture_memory.h"
#include "blocks/timing_spec.h"

namespace texsim {

// Texel blend (docs/filters.md §5): reads the taps' texels and forms the weighted RGBA sum.
class TexelBlend {
 public:
  struct Config {
    // Multiply-accumulate lanes: taps blended per cycle (8 = one trilinear probe per cycle,
    // 4 = one bilinear probe). Key: taps_per_cycle (1..32, a power of two).
    int taps_per_cycle = 8;
    static Config from_toml(const ConfigReader& r);
  };

  TexelBlend() = default;
  explicit TexelBlend(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // Σ w_k · texel_k over taps.tap[0 .. count). Counts one memory read, 4 mul and 4 add per tap.
  Rgba blend(const FilterTaps& taps, const Texture& tex, OpCounts& ops) const {
    ops += ops_per_tap() * static_cast<uint64_t>(taps.count > 0 ? taps.count : 0);
    return blend(taps, tex);
  }
  // The same without counting (the count is ops_per_tap() times the number of taps).
  Rgba blend(const FilterTaps& taps, const Texture& tex) const;

  // Cycles one fragment occupies the datapath: ⌈count / taps_per_cycle⌉ (at least 1).
  uint32_t issue_cycles(const FilterTaps& taps) const {
    const int g = cfg_.taps_per_cycle > 1 ? cfg_.taps_per_cycle : 1;
    const int c = (taps.count + g - 1) / g;
    return static_cast<uint32_t>(c > 1 ? c : 1);
  }
  static OpCounts ops_per_tap() {
    OpCounts o;
    o.mem = 1;  // one texel read
    o.mul = 4;  // w · RGBA
    o.add = 4;  // RGBA accumulate (tree levels + group accumulation: one add per product)
    return o;
  }
  // Latency: texel read, multiply, log2(taps_per_cycle) adder levels, accumulate. ii = 1 group.
  TimingSpec timing(const TechTable& tech) const;

 private:
  Config cfg_;
};

}  // namespace texsim
