#pragma once
// The sampling operations in the Vulkan checker: depth comparison ("Depth Compare Operation":
// each texel compared with the reference before filtering, then filtered as a colour — so the
// allowed results are VulkanConformance's on the texture of comparison results) and gather
// ("Texel Gathering": the four texels of the linear footprint on the base level, one component
// each, in the order (i0,j1), (i1,j1), (i1,j0), (i0,j0)). Independent of the blocks: it shares
// Texture, AddressMode and the CompareOp names only.
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/sampler_modes.h"
#include "testbench/conformance/vulkan_conformance.h"

namespace texsim {

class VulkanOpsConformance {
 public:
  VulkanOpsConformance(const VkSamplerState& sampler, const VkFilterPrecision& precision)
      : filter_(sampler, precision) {}

  // The spec's comparison, in double: `reference OP depth`; a NaN fails all but NOT_EQUAL and
  // ALWAYS.
  static bool passes(CompareOp op, double reference, double depth);
  // Texture of comparison results: per texel of every level (p, p, p, 1), p = [ref OP red].
  // The reference is clamped to [0, 1] on a UNORM depth texture (D16).
  static Texture compared(const Texture& depth, CompareOp op, double reference);
  // A comparing sampler's result: allowed when the filter of `compared` may give it.
  ConformanceVerdict check_compare(const Texture& depth, const VkSampleQuery& q, CompareOp op,
                                   double reference, const Rgba& result) const;
  // Gather of `component`: allowed when some (i0, j0) within the coordinate's precision gives
  // exactly these four values in the spec's order (the border colour's component for a border
  // texel). `du`, `dv`: the instruction's offsets beyond the sampler's.
  ConformanceVerdict check_gather(const Texture& tex, const VkSampleQuery& q, int component, int du,
                                  int dv, const Rgba& result) const;

  const VulkanConformance& filter() const { return filter_; }

 private:
  VulkanConformance filter_;
};

}  // namespace texsim
