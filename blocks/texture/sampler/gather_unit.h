#pragma once
// Gather unit (OpImageGather, Vulkan "Texel Gathering"): the four texels a bilinear filter at
// (u, v) on the base level reads, one component of each, unweighted, in the spec's order
// (i0,j1), (i1,j1), (i1,j0), (i0,j0). The texel coordinates come from the same fixed-point
// datapath and address modes as the address generator's linear quad, with the sampler's and the
// fragment's constant offsets added to the integer coordinates before wrapping.
#include <cstdint>
#include <string>

#include "blocks/base/fragment.h"
#include "blocks/base/op_counts.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/texel_address_gen.h"

namespace texsim {

class GatherUnit {
 public:
  // The base level's quad at (u, v) (non-finite: 0) with offsets (du, dv) beyond the
  // sampler's; the weights are 1 (every texel is returned).
  static TexelQuad quad(const TexelAddressGen::Config& c, const Texture& tex, double u, double v,
                        int du, int dv);
  // Component `component` (0..3 = r, g, b, a; larger is refused) of the quad's texels in the
  // spec's order; a border tap gives the component of `border` (the border colour in the
  // texture's format, border_texel()). Counts the border taps into *border_taps.
  static Rgba gather(const TexelQuad& q, const Texture& tex, int component, const Rgba& border,
                     int* border_taps);
  // Per fragment: the linear quad's address arithmetic without the weights, 4 texel reads and
  // the component select.
  static OpCounts ops_per_item(const TexelAddressGen::Config& c);
  std::string name() const { return "gather"; }
};

}  // namespace texsim
