// Sequential equivalence of the retimed RTL blocks (rtl_model/rtl/) with the earlier forms they
// replace (rtl_model/rtl/ref/), proved by yosys (rtl_model/synth/equiv_check.h): vd_p2 and
// vd_p1 at u0.8 with the multiplier whole and with the operand cut the u0.16 build uses (at
// DSP_W = 8 instead of 16), bilinear_lerp at a small width, and both V(d) blocks at the
// generated u0.16 parameters. Each has a negative control: the retimed source with one LSB
// added to its result must be refuted. Skipped, with the reason, when yosys is not on PATH.
// The proofs take seconds to a minute each: CI runs vd_p1's at u0.8 (about 2 s with its
// mutant); TEXSIM_RTL_EQUIV_ALL=1 adds the others (about 1 min 50 s of CPU).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "rtl_model/params/rtl_params.h"
#include "rtl_model/synth/equiv_check.h"
#include "rtl_model/synth/synth_flow.h"

namespace {

namespace fs = std::filesystem;
using texsim::synth::EquivJob;
using texsim::synth::EquivResult;

const std::string kRtl = std::string(TEXSIM_SOURCE_DIR) + "/rtl_model/rtl/";

// yosys' path, or "" with the reason to skip (no yosys; or a long proof not asked for).
std::string yosys_or_skip_reason(std::string& reason, bool long_proof = false) {
  const texsim::synth::Tools t = texsim::synth::find_tools();
  if (t.yosys.empty()) {
    reason = "yosys not found on PATH: equivalence not checked";
    return "";
  }
  if (long_proof &&
      std::getenv("TEXSIM_RTL_EQUIV_ALL") == nullptr) {  // NOLINT(concurrency-mt-unsafe)
    reason = "a proof of several seconds: set TEXSIM_RTL_EQUIV_ALL=1";
    return "";
  }
  return t.yosys;
}

// The work folder is removed when the test passed (it has the yosys log otherwise).
void clean(const fs::path& dir) {
  std::error_code ec;
  if (!testing::Test::HasFailure()) fs::remove_all(dir, ec);
}

fs::path work_dir(const std::string& name) {
  fs::path d =
      fs::temp_directory_path() / ("texsim_equiv_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// A copy of rtl file `name` in dir with the one occurrence of `from` replaced by `to`.
std::string mutant(const fs::path& dir, const std::string& name, const std::string& from,
                   const std::string& to) {
  std::ifstream in(kRtl + name);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "mutation site '" << from << "' not in " << name;
  EXPECT_EQ(text.find(from, at + 1), std::string::npos) << "'" << from << "' twice in " << name;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  const fs::path out = dir / name;
  std::ofstream(out) << text;
  return out.string();
}

std::vector<std::string> helpers() {
  return {kRtl + "texsim_pipe.v",   kRtl + "texsim_round_sat.v", kRtl + "texsim_op_counters.v",
          kRtl + "texsim_mul_rs.v", kRtl + "texsim_add_sat.v",   kRtl + "texsim_mul_tree.v"};
}

// The V(d) job at u0.8 (VdFx8's coefficients); dsp_w cuts texsim_mul_rs's operand there.
// The V(d) job at u0.8 (VdFx8's coefficients; dsp_w cuts texsim_mul_rs's operand there) or,
// with generated = true, at the build's own parameters (rtl_params.h, DSP_W as built).
EquivJob vd_job(bool p2, int dsp_w, const fs::path& dir, const std::string& gate_file,
                bool generated = false) {
  EquivJob j;
  j.files = helpers();
  j.files.push_back(kRtl + (p2 ? "ref/vd_p2_comb.v" : "ref/vd_p1_comb.v"));
  j.files.push_back(gate_file);
  j.gold = p2 ? "vd_p2_comb" : "vd_p1_comb";
  j.gate = p2 ? "vd_p2" : "vd_p1";
  namespace rp = texsim::rtl_params;
  int fin = 8;
  if (generated) {
    j.params = p2 ? rp::vd_p2_params<>() : rp::vd_p1_params<>();
    fin = rp::kVdFin;
  } else {
    j.params = p2 ? rp::vd_p2_params<texsim::VdFx8>() : rp::vd_p1_params<texsim::VdFx8>();
    j.setup = {"chparam -set DSP_W " + std::to_string(dsp_w) + " texsim_mul_rs"};
  }
  j.inputs = {{"d", fin}};
  j.output = {"v", fin};  // u1.FC with FC = FIN − 1
  j.max_steps = 12;
  j.work_dir = dir.string();
  return j;
}

EquivJob lerp_job(const fs::path& dir, const std::string& gate_file) {
  EquivJob j;
  j.files = helpers();
  j.files.push_back(kRtl + "ref/bilinear_lerp_comb.v");
  j.files.push_back(gate_file);
  j.gold = "bilinear_lerp_comb";
  j.gate = "bilinear_lerp";
  constexpr int kT = 2, kS = 2;
  j.params = {{"T", kT}, {"S", kS}, {"MUL_LAT", 3}, {"ADD_LAT", 1}};
  j.inputs = {{"t00", 4 * kT}, {"t10", 4 * kT}, {"t01", 4 * kT},
              {"t11", 4 * kT}, {"fx", kS},      {"fy", kS}};
  j.output = {"out", 4 * kT};
  j.max_steps = 14;
  j.work_dir = dir.string();
  return j;
}

void expect_proved(const EquivResult& r) {
  EXPECT_TRUE(r.error.empty()) << r.error;
  EXPECT_TRUE(r.proved) << "not proved equal; see " << r.log;
  EXPECT_FALSE(r.refuted) << "counterexample in " << r.log;
}

void expect_refuted(const EquivResult& r) {
  EXPECT_TRUE(r.error.empty()) << r.error;
  EXPECT_TRUE(r.refuted) << "the one-LSB mutant was not refuted; see " << r.log;
  EXPECT_FALSE(r.proved);
}

TEST(RtlEquiv, VdP1RetimedEqualsCombinational) {
  std::string why;
  const std::string yosys = yosys_or_skip_reason(why);
  if (yosys.empty()) GTEST_SKIP() << why;
  const fs::path d = work_dir("vd_p1");
  expect_proved(texsim::synth::check_equivalence(vd_job(false, 8, d, kRtl + "vd_p1.v"), yosys));
  clean(d);
}

TEST(RtlEquiv, VdP1OneLsbMutantIsRefuted) {
  std::string why;
  const std::string yosys = yosys_or_skip_reason(why);
  if (yosys.empty()) GTEST_SKIP() << why;
  const fs::path d = work_dir("vd_p1_mutant");
  const std::string m = mutant(d, "vd_p1.v", ".b(off3_q)", ".b(off3_q + 1'b1)");
  expect_refuted(texsim::synth::check_equivalence(vd_job(false, 8, d, m), yosys));
  clean(d);
}

TEST(RtlEquiv, VdP2RetimedEqualsCombinational) {
  std::string why;
  const std::string yosys = yosys_or_skip_reason(why, true);
  if (yosys.empty()) GTEST_SKIP() << why;
  for (const int dsp_w : {16, 8}) {
    SCOPED_TRACE("DSP_W = " + std::to_string(dsp_w));
    const fs::path d = work_dir("vd_p2_" + std::to_string(dsp_w));
    expect_proved(
        texsim::synth::check_equivalence(vd_job(true, dsp_w, d, kRtl + "vd_p2.v"), yosys));
    clean(d);
  }
}

// The build's own u0.16 blocks (18×16 products cut for the DSP against the earlier 18×17
// $mul): about 30 s (vd_p1) and 70 s (vd_p2) of SAT.
TEST(RtlEquiv, GeneratedVdBlocksEqualCombinational) {
  std::string why;
  const std::string yosys = yosys_or_skip_reason(why, true);
  if (yosys.empty()) GTEST_SKIP() << why;
  static_assert(texsim::rtl_params::kVdFc == texsim::rtl_params::kVdFin - 1);
  for (const bool p2 : {false, true}) {
    SCOPED_TRACE(p2 ? "vd_p2" : "vd_p1");
    const fs::path d = work_dir(p2 ? "vd_p2_generated" : "vd_p1_generated");
    expect_proved(texsim::synth::check_equivalence(
        vd_job(p2, 16, d, kRtl + (p2 ? "vd_p2.v" : "vd_p1.v"), true), yosys));
    clean(d);
  }
}

TEST(RtlEquiv, LerpRetimedEqualsCombinational) {
  std::string why;
  const std::string yosys = yosys_or_skip_reason(why, true);
  if (yosys.empty()) GTEST_SKIP() << why;
  const fs::path d = work_dir("lerp");
  expect_proved(texsim::synth::check_equivalence(lerp_job(d, kRtl + "bilinear_lerp.v"), yosys));
  clean(d);
}

TEST(RtlEquiv, VdP2AndLerpOneLsbMutantsAreRefuted) {
  std::string why;
  const std::string yosys = yosys_or_skip_reason(why, true);
  if (yosys.empty()) GTEST_SKIP() << why;
  {
    const fs::path d = work_dir("vd_p2_mutant");
    const std::string m = mutant(d, "vd_p2.v", ".b(K0)", ".b(K0 + 1'b1)");
    expect_refuted(texsim::synth::check_equivalence(vd_job(true, 8, d, m), yosys));
    clean(d);
  }
  {
    const fs::path d = work_dir("lerp_mutant");
    const std::string m = mutant(d, "bilinear_lerp.v", "assign res = acc[2*S+:T];",
                                 "assign res = acc[2*S+:T] + 1'b1;");
    expect_refuted(texsim::synth::check_equivalence(lerp_job(d, m), yosys));
    clean(d);
  }
}

}  // namespace
