#pragma once
// Vulkan texel-filtering conformance checker: from the spec's precision rules, the set of
// results an implementation may return for one isotropic sample, and a pass/fail verdict
// (docs/derivations/filters.md §6). Independent of the filter blocks: it shares only Texture and
// AddressMode. Arithmetic: double, with the spec's tolerances made explicit as intervals.
#include <string>

#include "blocks/base/fragment.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/lod_unit.h"
#include "blocks/texture/sampler/texel_address_gen.h"

namespace texsim {

// The sampler state the checker models (one filter for magnification and minification,
// anisotropy disabled, level_base = 0 and the whole pyramid in the view).
struct VkSamplerState {
  enum class Filter { Nearest, Linear };
  enum class MipmapMode { Nearest, Linear };
  Filter filter = Filter::Linear;
  MipmapMode mipmap_mode = MipmapMode::Nearest;
  AddressMode address_u = AddressMode::Wrap;
  AddressMode address_v = AddressMode::Wrap;
  double mip_lod_bias = 0;
  double min_lod = 0;
  double max_lod = 1000;
  // CLAMP_TO_BORDER's colour (VK_BORDER_COLOR_FLOAT_* or a custom float colour), before the
  // image format's substitution of the channels it lacks.
  double border[4] = {0, 0, 0, 0};
  // ConstOffset of the sample instruction (minTexelOffset..maxTexelOffset = -8..7).
  int offset_u = 0, offset_v = 0;
  // unnormalizedCoordinates: u, v are texel coordinates of level_base (not scaled by the size);
  // the spec's valid usage then leaves LOD 0 only.
  bool unnormalized = false;
};

// Precision limits and the checker's own tolerances.
struct VkFilterPrecision {
  int sub_texel_bits = 8;  // VkPhysicalDeviceLimits::subTexelPrecisionBits
  int mipmap_bits = 8;     // VkPhysicalDeviceLimits::mipmapPrecisionBits
  // Error of the implementation's texel coordinate u·width (float32 input and multiply),
  // relative to |u·width|, plus an absolute 1e-9.
  double coord_rel_eps = 1.0 / (1 << 21);
  // Error of the weighted sum (float32 products and sums), per channel, times max(1, |value|).
  double color_eps = 1.0 / (1 << 14);
};

struct VkSampleQuery {
  double u = 0, v = 0;                            // normalised coordinates
  double dudx = 0, dvdx = 0, dudy = 0, dvdy = 0;  // normalised derivatives
  double shader_bias = 0;                         // the instruction's Bias operand
  // textureLod: λ_base = lod (the derivatives and shader_bias unused), then the sampler's bias
  // and the clamp ("LOD Operation").
  bool explicit_lod = false;
  double lod = 0;
};

struct ConformanceVerdict {
  bool pass = false;
  bool judged = true;  // false: the spec leaves the result undefined (pass is then true)
  std::string reason;  // "ok", or which range the result misses and by how much
  double lambda_lo = 0, lambda_hi = 0;  // λ interval after bias and [min_lod, max_lod]
  int level_lo = 0, level_hi = 0;       // levels that may contribute
  double miss = 0;  // distance outside the closest acceptable range (0 when passing)
};

// Conformance checker for Vulkan isotropic texel filtering (docs/derivations/filters.md §7),
// with the five address modes, border colours, texel offsets and the LOD clamp:
// acceptable result set from LOD, sub-texel and mipmap precision rules; not a model of any
// hardware.
class VulkanConformance {
 public:
  VulkanConformance(const VkSamplerState& sampler, const VkFilterPrecision& precision)
      : s_(sampler), p_(precision) {}

  // λ interval the spec allows for this query: ρ from the scale-factor bounds
  // max(|m_u|, |m_v|) ≤ f ≤ √2 (|m_u| + |m_v|) per screen axis, ±2^-mipmap_bits LOD accuracy,
  // then bias and the [min_lod, max_lod] clamp. Non-finite derivatives allow any λ.
  void lod_interval(const Texture& tex, const VkSampleQuery& q, double& lo, double& hi) const;

  // Whether `result` is one of the values the spec allows (within color_eps), and why not.
  ConformanceVerdict check(const Texture& tex, const VkSampleQuery& q, const Rgba& result) const;

  const VkSamplerState& sampler() const { return s_; }
  const VkFilterPrecision& precision() const { return p_; }

 private:
  VkSamplerState s_;
  VkFilterPrecision p_;
};

// The Vulkan sampler state of texsim's address-generator and LOD configurations (filter,
// mipmap mode, address modes, bias and LOD range, border colour, offsets, unnormalised).
VkSamplerState vk_sampler_of(const TexelAddressGen::Config& a, const LodUnit::Config& l);
// A fragment as a query: its coordinates, derivatives and bias, and its explicit LOD when its
// operation is SampleOp::kSampleLod.
VkSampleQuery vk_query_of(const Fragment& f);

}  // namespace texsim
