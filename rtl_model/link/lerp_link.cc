#include "rtl_model/link/lerp_link.h"

#include <string>

#include "rtl_model/link/framing.h"

namespace texsim::link {

std::vector<uint8_t> lerp_configuration(const BilinearLerp::Config& c) {
  return {static_cast<uint8_t>(c.texel_bits), static_cast<uint8_t>(c.sub_bits)};
}

BilinearLerp::Config read_lerp_configuration(std::span<const uint8_t> payload) {
  if (payload.size() != 2)
    throw LinkError("lerp configuration: " + std::to_string(payload.size()) +
                    " bytes, expected 2 (texel bits, sub-texel bits)");
  BilinearLerp::Config c;
  c.texel_bits = payload[0];
  c.sub_bits = payload[1];
  if (c.texel_bits < 1 || c.texel_bits > 16 || c.sub_bits < 1 || c.sub_bits > 16)
    throw LinkError("lerp configuration: texel bits " + std::to_string(c.texel_bits) +
                    " and sub-texel bits " + std::to_string(c.sub_bits) + " must be 1..16");
  return c;
}

void encode_lerp(const LerpOperands& op, std::span<uint32_t, kLerpWords> out) {
  for (size_t k = 0; k < 4; ++k) out[k] = op.quad[k];
  out[4] = (op.fx & 0xFFFFu) | (op.fy & 0xFFFFu) << 16;
}

LerpOperands decode_lerp(std::span<const uint32_t, kLerpWords> in) {
  LerpOperands op;
  for (size_t k = 0; k < 4; ++k) op.quad[k] = in[k];
  op.fx = in[4] & 0xFFFFu;
  op.fy = in[4] >> 16;
  return op;
}

}  // namespace texsim::link
