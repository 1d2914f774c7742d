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
  Rgba blend(const FilterTaps& taps, const Texture& tex, OpCounts& ops) const;

  // Cycles one fragment occupies the datapath: ⌈count / taps_per_cycle⌉ (at least 1).
  uint32_t issue_cycles(const FilterTaps& taps) const;
  OpCounts ops_per_tap() const;
  // Latency: texel read, multiply, log2(taps_per_cycle) adder levels, accumulate. ii = 1 group.
  TimingSpec timing(const TechTable& tech) const;

 private:
  Config cfg_;
};

}  // namespace texsim
