#pragma once
// The bilinear lerp's Verilated RTL (rtl_model/rtl/bilinear_lerp.v) as a BoardBlock: the
// virtual board streams lerps (rtl_model/link/lerp_link.h) through it, one per clock. The RTL
// is built for rtl_params::kLerp (RGBA8 texels, u0.8 weights); another configuration is
// refused.
#include <memory>

#include "rtl_model/link/board_block.h"

namespace texsim::link {

std::unique_ptr<BoardBlock> make_rtl_lerp_block();

}  // namespace texsim::link
