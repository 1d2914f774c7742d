// make_rtl_block and make_rtl_sampler_block in a build without Verilator
// (cmake/TexsimVerilator.cmake links this file instead of vd_rtl_block.cc): there is no RTL to run,
// and the error says so.
#include "rtl_model/link/framing.h"
#include "rtl_model/verilator/lerp_rtl_block.h"
#include "rtl_model/verilator/sampler_rtl_block.h"
#include "rtl_model/verilator/vd_rtl_block.h"

namespace texsim::link {

bool rtl_board_available() { return false; }

int rtl_frac_bits() { return 0; }

std::vector<std::string> rtl_block_names() { return {}; }

std::unique_ptr<BoardBlock> make_rtl_block(const std::string& name) {
  throw LinkError("no RTL block '" + name +
                  "': texsim was built without Verilator, so the virtual board can run only "
                  "the C++ models (--board model)");
}

std::unique_ptr<BoardBlock> make_rtl_sampler_block() {
  throw LinkError(
      "no RTL sampler: texsim was built without Verilator, so the virtual board cannot run it");
}

std::unique_ptr<BoardBlock> make_rtl_lerp_block() {
  throw LinkError(
      "no RTL bilinear_lerp: texsim was built without Verilator, so the virtual board cannot run "
      "it");
}

}  // namespace texsim::link
