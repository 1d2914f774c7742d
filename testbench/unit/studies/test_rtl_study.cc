// `texsim study rtl`: its option parsing, a clean message with no Verilog or no tools, and (when
// yosys and nextpnr-ice40 are installed) one example block through the whole flow.
#include <gtest/gtest.h>

#include "blocks/base/input_error.h"
#include "pipeline/studies/study_rtl.h"
#include "rtl_model/synth/synth_flow.h"
#include "testbench/lib/cli_harness.h"

namespace {

using cli_harness::Cli;
using cli_harness::sh;
using cli_harness::shell;
using cli_harness::slurp;

TEST(RtlStudy, ParamsAndMedian) {
  const auto p = texsim::parse_rtl_param("W=8,12,16");
  EXPECT_EQ(p.first, "W");
  EXPECT_EQ(p.second, (std::vector<int>{8, 12, 16}));
  EXPECT_THROW(texsim::parse_rtl_param("W="), texsim::InputError);
  EXPECT_THROW(texsim::parse_rtl_param("8=W"), texsim::InputError);
  EXPECT_DOUBLE_EQ(texsim::median_of({3, 1, 2}), 2);
  EXPECT_DOUBLE_EQ(texsim::median_of({4, 1, 3, 2}), 2.5);
}

class RtlStudyCli : public Cli {};

TEST_F(RtlStudyCli, NoVerilogIsACleanMessage) {
  const auto r = sh("study rtl --rtl " + path("none") + " --out " + path("out"));
  EXPECT_EQ(r.code, 0) << r.out;
  if (texsim::synth::find_tools().yosys.empty()) GTEST_SKIP() << "yosys not installed";
  EXPECT_NE(r.out.find("no RTL blocks in"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(path("out/rtl.csv")));
}

TEST_F(RtlStudyCli, MissingToolsSkip) {
  const auto r = shell("PATH=/nonexistent " + std::string(TEXSIM_BINARY) + " study rtl --rtl " +
                       TEXSIM_SOURCE_DIR "/rtl_model/synth/examples --out " + path("out"));
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("skipped: yosys and nextpnr-ice40 not found on PATH"), std::string::npos)
      << r.out;
}

TEST_F(RtlStudyCli, ExampleBlockThroughTheFlow) {
  const texsim::synth::Tools t = texsim::synth::find_tools();
  if (!t.missing().empty()) GTEST_SKIP() << t.missing();
  const auto r = sh("study rtl --rtl " TEXSIM_SOURCE_DIR
                    "/rtl_model/synth/examples --param W=8 "
                    "--seeds 2 --out " +
                    path("out"));
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string csv = slurp(path("out/rtl.csv"));
  // block, parameters, error, generic cells, multipliers, LUT4, DFF, carry, SB_MAC16, fallback,
  // Fmax median/min/max, seeds routed: both multipliers of the example fit the UP5K's DSPs.
  EXPECT_NE(csv.find("\nhorner2,W=8,-,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",2,no,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",2,\n"), std::string::npos) << csv;  // two seeds routed
  EXPECT_TRUE(fs::exists(path("out/rtl.md")));
  EXPECT_TRUE(fs::exists(path("out/rtl.png")));
}

}  // namespace
