#pragma once
// The V(d) evaluators P2 and P1 (blocks/texture/subtexel) as BoardBlocks, run by their C++
// functional cores: "vd_p2" and "vd_p1". Configuration: one byte, the input's fraction bits
// (16, 12 or 8: the fx16, fx12, fx8 formats u0.F in, u1.(F-1) out); the default is 16.
// An input is the raw code of d (u0.F), a result the raw code of V(d).
#include <memory>
#include <string>
#include <vector>

#include "rtl_model/link/board_block.h"

namespace texsim::link {

// The names make_core_block knows.
std::vector<std::string> core_block_names();
// The block of that name; throws LinkError naming the known ones for any other.
std::unique_ptr<BoardBlock> make_core_block(const std::string& name);

}  // namespace texsim::link
