#pragma once
// The bilinear lerp on the link (docs/rtl/link.md): CONFIGURE carries the texel and sub-texel
// bits (u8 each); a STREAM carries kLerpWords inputs per lerp (the four RGBA texels t00, t10,
// t01, t11, then fx in the low and fy in the high 16 bits) and returns kLerpWords words per
// lerp: the blended RGBA, then zeros.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "blocks/texture/sampler/bilinear_lerp.h"

namespace texsim::link {

inline constexpr size_t kLerpWords = 5;

// One lerp's operands, as BilinearLerp::lerp takes them.
struct LerpOperands {
  std::array<uint32_t, 4> quad{};  // t00, t10, t01, t11
  uint32_t fx = 0, fy = 0;         // u0.sub_bits weights of the +1 texels
};

std::vector<uint8_t> lerp_configuration(const BilinearLerp::Config& c);
// The board's side; throws LinkError when the payload is not two bytes in 1..16.
BilinearLerp::Config read_lerp_configuration(std::span<const uint8_t> payload);

void encode_lerp(const LerpOperands& op, std::span<uint32_t, kLerpWords> out);
// Any words decode (weights are the low and high 16 bits; the block masks them to its width).
LerpOperands decode_lerp(std::span<const uint32_t, kLerpWords> in);

}  // namespace texsim::link
