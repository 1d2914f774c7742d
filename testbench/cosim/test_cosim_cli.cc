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

// The virtual board runs the Verilated RTL by default when texsim has it; the host still
// compares every result with the C++ core. Without Verilator the command says so.
TEST(CosimCli, RtlBoardMatchesTheCoreOrSaysItIsMissing) {
  const auto r = sh("cosim --block vd_p2 --link virtual --board rtl --vectors 10000 --seed 5");
  if (r.out.find("built without Verilator") != std::string::npos) {
    EXPECT_EQ(r.code, 4) << r.out;
    const auto d = sh("cosim --vectors 100");
    EXPECT_EQ(d.code, 0) << d.out;
    EXPECT_NE(d.out.find("built without Verilator"), std::string::npos) << d.out;
    GTEST_SKIP() << "texsim was built without Verilator";
  }
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("runs the Verilated RTL"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("10000 sent, 10000 match, 0 mismatch"), std::string::npos) << r.out;
  // 40 STREAMs of 250 vectors through the 8-cycle pipeline: 40 * 257 RTL cycles.
  EXPECT_NE(r.out.find("board: 10000 vectors, 10280 cycles"), std::string::npos) << r.out;
  const auto d = sh("cosim --block vd_p1 --vectors 2000");
  EXPECT_EQ(d.code, 0) << d.out;
  EXPECT_NE(d.out.find("runs the Verilated RTL"), std::string::npos) << d.out;
  const auto m = sh("cosim --board model --vectors 2000");
  EXPECT_EQ(m.code, 0) << m.out;
  EXPECT_NE(m.out.find("runs the C++ models"), std::string::npos) << m.out;
  // The RTL is built for u0.16: by default other formats fall back to the models, an explicit
  // request for the RTL is a usage error.
  const auto f = sh("cosim --frac-bits 12 --vectors 2000");
  EXPECT_EQ(f.code, 0) << f.out;
  EXPECT_NE(f.out.find("the RTL is built for u0.16 inputs only"), std::string::npos) << f.out;
  const auto fr = sh("cosim --board rtl --frac-bits 12 --vectors 10");
  EXPECT_EQ(fr.code, 2) << fr.out;
  EXPECT_NE(fr.out.find("u0.16 inputs only"), std::string::npos) << fr.out;
  // A waveform asked for in a directory that does not exist: an error, not a silent run.
  const auto w = cli_harness::shell("TEXSIM_RTL_TRACE=/nonexistent/texsim-waves " +
                                    std::string(TEXSIM_BINARY) + " cosim --vectors 10");
  EXPECT_EQ(w.code, 2) << w.out;
  EXPECT_NE(w.out.find("TEXSIM_RTL_TRACE=/nonexistent/texsim-waves: no such directory"),
            std::string::npos)
      << w.out;
}

TEST(CosimCli, NoUsbBoardIsAClearErrorNotAHang) {
  const auto r = sh("cosim --link hid --vid 1209 --pid 7e57 --vectors 10");
  EXPECT_EQ(r.code, 4) << r.out;
  EXPECT_NE(r.out.find("no USB HID device 1209:7e57 found"), std::string::npos) << r.out;
}

// Usage errors exit 2 (docs/cli.md, "Exit status"); text echoed from the command line is
// escaped.
TEST(CosimCli, BadArgumentsAreClearErrors) {
  const auto block = sh("cosim --block vd_p7 --vectors 10");
  EXPECT_EQ(block.code, 2) << block.out;
  EXPECT_NE(block.out.find("no block 'vd_p7' (blocks: vd_p2, vd_p1)"), std::string::npos)
      << block.out;
  const auto vid = sh("cosim --link hid --vid zz");
  EXPECT_EQ(vid.code, 2) << vid.out;
  EXPECT_NE(vid.out.find("not a 16-bit hex id"), std::string::npos) << vid.out;
  EXPECT_EQ(sh("cosim --link usb").code, 2);
  EXPECT_EQ(sh("cosim --board fpga").code, 2);
  const auto hid = sh("cosim --link hid --board rtl --vectors 10");
  EXPECT_EQ(hid.code, 2) << hid.out;
  EXPECT_NE(hid.out.find("--board: applies to --link virtual only"), std::string::npos) << hid.out;
  const auto bell = sh("cosim --block \"$(printf 'vd\\007\\033[2J')\" --vectors 10");
  EXPECT_EQ(bell.code, 2) << bell.out;
  EXPECT_NE(bell.out.find("no block 'vd\\x07\\x1B[2J'"), std::string::npos) << bell.out;
  EXPECT_EQ(bell.out.find('\a'), std::string::npos) << bell.out;
}

}  // namespace
