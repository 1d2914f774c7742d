#pragma once
// The operation a fragment asks of the texture unit (Fragment::op, trace version 4's op code).
// Depth comparison and min/max reduction are sampler state, not operations: they apply to any
// of these through the sampler the fragment picks (Fragment::sampler).
#include <cstdint>
#include <string_view>

namespace texsim {

enum class SampleOp : uint8_t {
  kSample = 0,      // implicit LOD from the derivatives (texture())
  kSampleLod = 1,   // explicit LOD in Fragment::lod (textureLod())
  kSampleGrad = 2,  // explicit gradients in the derivative fields (textureGrad())
  kGather = 3,      // four texels of one component, no filtering (textureGather())
  kCount
};
inline constexpr int kSampleOps = static_cast<int>(SampleOp::kCount);

// Names used in scenes, CSV traces and report keys.
inline constexpr std::string_view kSampleOpNames[kSampleOps] = {"sample", "lod", "grad", "gather"};

inline constexpr bool valid_sample_op(uint8_t op) { return op < kSampleOps; }

}  // namespace texsim
