#pragma once
// Vulkan conformance checker for cube maps, cube arrays and array layers (docs/texture-types.md
// §5): from the spec's rules, the results an implementation may return for one sample, and a
// verdict. Independent of the layered blocks: faces come from the spec's table in double with
// every face whose major magnitude ties allowed, neighbour texels across an edge by projecting
// the texel centre's direction onto the cube (not by CubeSeam's fold), corners as the average of
// the three texels that meet there, the layer by clamp(RNE(a), 0, d − 1); filtering is bilinear
// with mipmap mode nearest at an explicit λ (textureLod), within the sub-texel precision.
#include <string>

#include "blocks/texture/memory/texture_memory.h"

namespace texsim {

struct VkCubeQuery {
  double dir[3] = {0, 0, 1};  // (u, v, w): the direction (cube), or (u, v, −) (array)
  double lambda = 0;          // explicit LOD
  double layer = 0;           // array layer, or cube index of a cube array
};

struct VkCubeVerdict {
  bool pass = false;
  bool judged = true;  // false: the spec leaves the result undefined (a zero direction)
  std::string reason;
  int faces = 0;  // faces the spec allows for the direction (more than one at a tie)
};

class VulkanCubeConformance {
 public:
  // `seamless` false: each face is filtered alone with clamp-to-edge
  // (VK_EXT_non_seamless_cube_map with CLAMP_TO_EDGE).
  VulkanCubeConformance(bool seamless, int sub_texel_bits = 8)
      : seamless_(seamless), sub_texel_bits_(sub_texel_bits) {}
  VkCubeVerdict check_cube(const Texture& tex, const VkCubeQuery& q, const Rgba& result) const;
  // A 2-D array texture, CLAMP_TO_EDGE, bilinear at q.dir[0..1] on layer clamp(RNE(q.layer)).
  VkCubeVerdict check_array(const Texture& tex, const VkCubeQuery& q, const Rgba& result) const;

  double color_eps = 1.0 / (1 << 14);

 private:
  bool seamless_;
  int sub_texel_bits_;
};

}  // namespace texsim
