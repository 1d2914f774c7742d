#pragma once
// Taps of an unnormalised sampler (Vulkan unnormalizedCoordinates): (u, v) are texel
// coordinates on level 0 — no scaling by the level's size, no mip selection, one probe; the
// same float→fixed converter, nearest or bilinear weights and clamp / border addressing as the
// address generator (SamplerSetup refuses the other modes, offsets and comparison).
#include "blocks/base/op_counts.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/texel_address_gen.h"

namespace texsim {

class UnnormalizedTaps {
 public:
  // Writes the taps at texel coordinates (u, v) (non-finite: 0) into out, with the border
  // colour in the texture's format when some tap reads it.
  static void taps(const TexelAddressGen::Config& c, const Texture& tex, double u, double v,
                   FilterTaps& out);
  // Per fragment: two float→fixed conversions, the address modes, the bilinear weights; no
  // scaling by the level's size and no level selection.
  static OpCounts ops_per_item(const TexelAddressGen::Config& c);
};

}  // namespace texsim
