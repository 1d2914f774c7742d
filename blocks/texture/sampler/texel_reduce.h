#pragma once
// Texel reducer: what replaces the weighted blend when the sampler asks for a min/max
// reduction (VK_EXT_sampler_filter_minmax: the component-wise minimum or maximum of the texels
// the weighted average would use with non-zero weight) or a depth comparison (each texel's
// depth compared with the reference first, then the 0/1 results filtered with the taps'
// weights: percentage-closer filtering). The reference is clamped to [0, 1] for a UNORM depth
// format (D16), not for D32F.
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/sampler_modes.h"
#include "blocks/texture/sampler/texel_address_gen.h"

namespace texsim {

class TexelReduce {
 public:
  // Min or max over the taps with w != 0 (a border tap's texel is taps.border); (0,0,0,0)
  // when no tap has weight.
  static Rgba minmax(const FilterTaps& taps, const Texture& tex, Reduction r);
  // Σ w · [reference OP depth] over the taps, depth = the texel's red; as (v, v, v, 1).
  static Rgba compare(const FilterTaps& taps, const Texture& tex, CompareOp op, float reference);
  // The reference as the comparison sees it: clamped to [0, 1] for D16 (UNORM depth).
  static float reference(const Texture& tex, float reference);
  // Per tap, in place of TexelBlend::ops_per_item(): a min/max is a compare per channel; a
  // comparison is one compare, then one channel's multiply-accumulate.
  static OpCounts ops_per_tap(Reduction r, CompareOp op);
  std::string name() const { return "reduce"; }
};

}  // namespace texsim
