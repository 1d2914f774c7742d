// `texsim cosim` end to end: the virtual board matches the C++ core, and a missing USB board or
// an unknown block is a clear message with a non-zero exit, never a hang.
#include <gtest/gtest.h>

#include "testbench/lib/cli_harness.h"

namespace {

using cli_harness::sh;

TEST(CosimCli, VirtualBoardMatchesTheCore) {
  const auto r = sh("cosim --block vd_p2 --link virtual --vectors 5000 --seed 7");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("5000 sent, 5000 match, 0 mismatch"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("board: 5000 vectors"), std::string::npos) << r.out;
  const auto p1 = sh("cosim --block vd_p1 --frac-bits 12 --vectors 3000");
  EXPECT_EQ(p1.code, 0) << p1.out;
  EXPECT_NE(p1.out.find("12-bit inputs (u0.12)"), std::string::npos) << p1.out;
}

TEST(CosimCli, NoUsbBoardIsAClearErrorNotAHang) {
  const auto r = sh("cosim --link hid --vid 1209 --pid 7e57 --vectors 10");
  EXPECT_EQ(r.code, 4) << r.out;
  EXPECT_NE(r.out.find("no USB HID device 1209:7e57 found"), std::string::npos) << r.out;
}

TEST(CosimCli, BadArgumentsAreClearErrors) {
  const auto block = sh("cosim --block vd_p7 --vectors 10");
  EXPECT_EQ(block.code, 4) << block.out;
  EXPECT_NE(block.out.find("no block 'vd_p7' (blocks: vd_p2, vd_p1)"), std::string::npos)
      << block.out;
  const auto vid = sh("cosim --link hid --vid zz");
  EXPECT_EQ(vid.code, 2) << vid.out;
  EXPECT_NE(vid.out.find("not a 16-bit hex id"), std::string::npos) << vid.out;
  EXPECT_EQ(sh("cosim --link usb").code, 2);
}

}  // namespace
