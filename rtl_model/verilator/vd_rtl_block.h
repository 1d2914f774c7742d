#pragma once
// The V(d) evaluators' Verilated RTL (rtl_model/rtl/vd_p2.v, vd_p1.v) as BoardBlocks, so the
// virtual board (rtl_model/link/virtual_board.h) runs the RTL behind the link protocol: each
// STREAM drives the inputs one per clock through RtlHarness and returns the RTL's results and
// its own cycle count. The RTL is built for the parameters of rtl_model/params/rtl_params.h
// (u0.16 inputs); a configuration byte other than 16 is refused.
// This header needs no Verilator: a build without it links vd_rtl_block_absent.cc instead,
// where rtl_board_available() is false and make_rtl_block says why it cannot.
#include <memory>
#include <string>
#include <vector>

#include "rtl_model/link/board_block.h"

namespace texsim::link {

// Whether this build has the Verilated RTL blocks.
bool rtl_board_available();
// The input fraction bits the RTL is built for (16; 0 without Verilator).
int rtl_frac_bits();
// The names make_rtl_block knows ("vd_p2", "vd_p1"; none without Verilator).
std::vector<std::string> rtl_block_names();
// The block of that name, reset and ready; throws LinkError for any other name or when the
// build has no Verilator.
std::unique_ptr<BoardBlock> make_rtl_block(const std::string& name);

}  // namespace texsim::link
