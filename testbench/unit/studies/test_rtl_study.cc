// `texsim study rtl`: its option parsing, the parameters and error figures it builds blocks
// with, the measured-area table the C++ side reads back, a clean message with no Verilog or no
// tools, and (when yosys and nextpnr-ice40 are installed) the example block and one real block
// of rtl_model/rtl at a small width through the whole flow.
#include <gtest/gtest.h>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/base/tech_table.h"
#include "blocks/texture/sampler/fixed_sampler.h"
#include "pipeline/app/study_rtl_sampler.h"
#include "pipeline/studies/study_rtl.h"
#include "pipeline/studies/study_rtl_params.h"
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

TEST(RtlStudy, FitsTheUp5kSaysWhatIsOver) {
  texsim::synth::SynthResult r;
  r.lut4 = 5280;
  r.mac16 = 8;
  r.ram = 30;
  EXPECT_EQ(texsim::synth::up5k_fit(r), "yes");
  r.lut4 = 59001;
  r.ram = 31;
  EXPECT_EQ(texsim::synth::up5k_fit(r), "no: SB_LUT4 59001/5280, BRAM 31/30");
  r = {};
  r.mac16 = 16;
  r.pnr_without_dsp = true;
  r.fmax_mhz = {40.0};
  EXPECT_EQ(texsim::synth::up5k_fit(r), "no: SB_MAC16 16/8; fits with LUT multipliers");
  r = {};
  r.dff = 9000;  // one flip-flop per logic cell
  EXPECT_EQ(texsim::synth::up5k_fit(r), "no: DFF 9000/5280");
  r = {};
  r.pnr_error = "does not fit the UP5K: ICESTORM_LC 7564/5280 143%";
  EXPECT_EQ(texsim::synth::up5k_fit(r), "no: ICESTORM_LC 7564/5280 143%");
}

int64_t param(const texsim::RtlStudyPoint& p, const std::string& name) {
  for (const auto& [n, v] : p.params) {
    if (n == name) return v;
  }
  ADD_FAILURE() << "no parameter " << name;
  return -1;
}

TEST(RtlStudy, PointsFollowTheCppFormats) {
  // Default: the generated parameters, with the C++ error and latency.
  const auto p16 = texsim::rtl_study_point("vd_p2", {});
  EXPECT_TRUE(texsim::rtl_study_is_generated("vd_p2", p16.params));
  EXPECT_EQ(param(p16, "FIN"), 16);
  EXPECT_EQ(p16.latency, "8");
  EXPECT_FALSE(p16.max_error.empty());
  // A narrower V(d) width brings its own format's coefficients.
  const auto p12 = texsim::rtl_study_point("vd_p2", {{"FIN", 12}});
  EXPECT_EQ(param(p12, "FC"), 11);
  EXPECT_NE(param(p12, "C1"), param(p16, "C1"));
  EXPECT_FALSE(texsim::rtl_study_is_generated("vd_p2", p12.params));
  EXPECT_NE(texsim::rtl_study_point("vd_p1", {{"FIN", 10}}).problem, "");
  // u/v: W alone gives Fixed<W/2, W/2> and its minimum denominator (1/4096).
  const auto uv = texsim::rtl_study_point("uv_incremental", {{"W", 24}});
  EXPECT_EQ(param(uv, "F"), 12);
  EXPECT_EQ(param(uv, "MIN_DEN"), 1);
  EXPECT_EQ(texsim::rtl_report_block("uv_incremental"), "coords.incremental[s16.16]");
  // A module the C++ side does not know gets exactly the sweep.
  const auto other = texsim::rtl_study_point("horner2", {{"W", 8}});
  ASSERT_EQ(other.params.size(), 1U);
  EXPECT_EQ(other.latency, "");
}

TEST(RtlStudy, SamplerIsABlockAtItsWidths) {
  // Named like the shared helpers (texsim_*), but a block of rtl_params.h.
  EXPECT_TRUE(texsim::rtl_study_known_block("texsim_sampler"));
  EXPECT_FALSE(texsim::rtl_study_known_block("texsim_pipe"));
  const auto g = texsim::rtl_study_point("texsim_sampler", {});
  EXPECT_TRUE(texsim::rtl_study_is_generated("texsim_sampler", g.params));
  const auto p = texsim::rtl_study_point("texsim_sampler", {{"S", 4}, {"M", 4}});
  EXPECT_EQ(param(p, "S"), 4);
  EXPECT_EQ(param(p, "M"), 4);
  EXPECT_EQ(param(p, "LOD_LAT"), param(g, "LOD_LAT"));  // latencies stay the C++ model's
  EXPECT_EQ(p.latency,
            std::to_string(texsim::FixedSampler::latency(texsim::TechTable::defaults())));
  EXPECT_FALSE(texsim::rtl_study_is_generated("texsim_sampler", p.params));
}

TEST(RtlStudy, SamplerErrorFollowsTheWidths) {
  // The sampler's error column: FixedSampler on the bunny's fragments. Against the truth the
  // trilinear filter's own error dominates (a fraction of a dB between widths); against the
  // float32 sampler the width shows.
  texsim::SamplerSceneErrors e(TEXSIM_SOURCE_DIR "/scenes/bunny.toml", "fur");
  const texsim::SamplerSceneError w8 = e.measure(8, 8), w1 = e.measure(1, 1);
  EXPECT_EQ(w8.pixels, 23575U);
  EXPECT_GT(w8.psnr_db, w1.psnr_db + 0.5);
  EXPECT_GT(w8.psnr_vs_float_db, w1.psnr_vs_float_db + 6);
  EXPECT_THROW(
      texsim::SamplerSceneErrors(TEXSIM_SOURCE_DIR "/scenes/bunny.toml", "nothing").measure(8, 8),
      texsim::InputError);
}

TEST(RtlStudy, BilinearWeightError) {
  // Rounding the position to S bits moves each weight by up to 2^-(S+1): with full-scale
  // texels that is about 255·2^-S LSB, plus the datapath's half LSB.
  const double e8 = texsim::bilinear_weight_error_lsb(8, 8);
  const double e4 = texsim::bilinear_weight_error_lsb(8, 4);
  EXPECT_GT(e8, 0.5);
  EXPECT_LE(e8, 255.0 / 256 + 0.5);
  EXPECT_GT(e4, 8 * e8);
  EXPECT_LE(e4, 255.0 / 16 + 0.5);
}

TEST(RtlStudy, TechTableReadsMeasuredBlockAreas) {
  const auto t = texsim::TechTable::from_toml(
      texsim::parse_toml("[block_area]\n\"coords.incremental[s16.16]\" = 4417\n", "t.toml"),
      "t.toml");
  EXPECT_DOUBLE_EQ(t.block_area_or("coords.incremental[s16.16]", 105.5), 4417);
  EXPECT_DOUBLE_EQ(t.block_area_or("blend", 288), 288);
  EXPECT_TRUE(texsim::TechTable::defaults().block_area.empty());
  EXPECT_THROW(texsim::TechTable::from_toml(
                   texsim::parse_toml("[block_area]\nblend = -1\n", "t.toml"), "t.toml"),
               texsim::InputError);
  EXPECT_THROW(texsim::TechTable::from_toml(
                   texsim::parse_toml("[block_area]\nblend = \"x\"\n", "t.toml"), "t.toml"),
               texsim::InputError);
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
  // block, parameters, error, generic cells, multipliers, LUT4, DFF, carry, SB_MAC16, BRAM,
  // fallback, fits, Fmax median/min/max, seeds routed: both multipliers of the example fit the
  // UP5K's DSPs.
  EXPECT_NE(csv.find("\nhorner2,W=8,-,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",2,0,no,yes,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",2,\n"), std::string::npos) << csv;  // two seeds routed
  EXPECT_TRUE(fs::exists(path("out/rtl.md")));
  EXPECT_TRUE(fs::exists(path("out/rtl.png")));
}

TEST_F(RtlStudyCli, UnknownBlockIsAnError) {
  if (texsim::synth::find_tools().yosys.empty()) GTEST_SKIP() << "yosys not installed";
  const auto r =
      sh("study rtl --rtl " TEXSIM_SOURCE_DIR "/rtl_model/rtl --block texsim_pipe --out " +
         path("out"));
  EXPECT_NE(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("no block texsim_pipe"), std::string::npos) << r.out;
}

// A real block and its earlier form: read with the shared helpers, built with the C++ format's
// coefficients, placed and routed; about 15 s.
TEST_F(RtlStudyCli, RealBlockThroughTheFlow) {
  const texsim::synth::Tools t = texsim::synth::find_tools();
  if (!t.missing().empty()) GTEST_SKIP() << t.missing();
  const auto r = sh("study rtl --rtl " TEXSIM_SOURCE_DIR
                    "/rtl_model/rtl --block vd_p1 --param FIN=8 --seeds 2 --with-earlier --out " +
                    path("out"));
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string csv = slurp(path("out/rtl.csv"));
  // block, parameters, error (u0.8 exhaustive), latency, generic cells, then one 10x9 signed
  // multiplier (s3.7 slope by u0.8 d) in one SB_MAC16, nothing in LUTs, both seeds routed.
  EXPECT_NE(csv.find("\nvd_p1,FIN=8,1.22e-02,6,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",10x9s,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",1,0,no,yes,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",2,\n"), std::string::npos) << csv;
  // --with-earlier: the form the retimed block replaced, at the same parameters.
  EXPECT_NE(csv.find("\nvd_p1_comb,FIN=8,1.22e-02,6,"), std::string::npos) << csv;
  // FIN = 8 is not the generated build: nothing to feed back.
  const std::string toml = slurp(path("out/rtl_tech.toml"));
  EXPECT_NE(toml.find("[tech.block_area]\n"), std::string::npos) << toml;
  EXPECT_EQ(toml.find("vd_p1"), std::string::npos) << toml;
}

}  // namespace
