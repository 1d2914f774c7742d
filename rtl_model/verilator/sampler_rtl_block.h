#pragma once
// The sampler's Verilated RTL (rtl_model/rtl/texsim_sampler.v) as a BoardBlock: the virtual
// board (rtl_model/link/virtual_board.h) loads its state and texture memory image from
// CONFIGURE messages (rtl_model/link/sampler_link.h) and streams fragments through it, one per
// clock, the texel reads answered from that image as the testbench's block RAM does.
// The RTL is built for sub_texel_bits and mipmap_bits of rtl_model/params/rtl_params.h; a
// state with others is refused.
#include <memory>

#include "rtl_model/link/board_block.h"

namespace texsim::link {

std::unique_ptr<BoardBlock> make_rtl_sampler_block();

}  // namespace texsim::link
