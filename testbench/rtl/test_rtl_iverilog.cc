// A second simulator: Icarus Verilog (iverilog/vvp) runs the RTL blocks on the vectors of the
// Verilator lockstep tests (testbench/rtl/rtl_vectors.h), a CI-sized sample of them, with the
// outputs of the C++ cores as the expected values: vector files (docs/rtl/blocks.md, "Vector
// files") replayed by the testbenches of testbench/rtl/iverilog/, every output compared, and
// the latency with the C++ timing. A one-LSB change in one expected value must be reported at
// that vector. Skipped, with the reason, when iverilog or vvp is not on PATH.
// TEXSIM_IVERILOG_VECTORS sets the sample size (default 3000 per V(d) block, 600 for the lerp,
// whose four channels of pipelined LUT multipliers cost Icarus about 1.3 ms per vector).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "blocks/base/shell_quote.h"
#include "rtl_model/params/rtl_params.h"
#include "testbench/rtl/rtl_vectors.h"

namespace texsim::rtl {
namespace {

namespace fs = std::filesystem;

const std::string kRtl = std::string(TEXSIM_SOURCE_DIR) + "/rtl_model/rtl/";
const std::string kTb = std::string(TEXSIM_SOURCE_DIR) + "/testbench/rtl/iverilog/";

bool on_path(const std::string& tool) {
  return std::system(("command -v " + tool + " >/dev/null 2>&1").c_str()) == 0;
}

size_t sample_size(size_t def) {
  const char* s = std::getenv("TEXSIM_IVERILOG_VECTORS");  // NOLINT(concurrency-mt-unsafe)
  return s != nullptr && *s != '\0' ? std::strtoull(s, nullptr, 10) : def;
}

// The first `head` of `all` (the directed vectors), then every k-th of the rest so that about
// n are left.
template <class T>
std::vector<T> sample(const std::vector<T>& all, size_t head, size_t n) {
  head = std::min(head, all.size());
  const size_t rest = all.size() - head;
  const size_t step = rest > n ? (rest + n - 1) / n : 1;
  std::vector<T> s(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(head));
  s.reserve(head + rest / step + 1);
  for (size_t i = head; i < all.size(); i += step) s.push_back(all[i]);
  return s;
}

struct SimResult {
  int code = -1;
  std::string out;
  size_t vectors = 0, mismatches = 0;
  bool summary = false;
};

// Compiles the testbench with the block's parameters and runs it on the vector file.
SimResult simulate(const std::string& tb_top, const std::string& tb_file,
                   const std::vector<std::string>& rtl,
                   const std::vector<rtl_params::Param>& params, uint32_t latency,
                   const std::string& define, const fs::path& vec, size_t n) {
  const fs::path dir = vec.parent_path();
  const std::string sim = shell_quote((dir / "sim.vvp").string());
  // Appended piece by piece (GCC 12's -Wrestrict misfires on "literal" + std::string here).
  std::string cmd = "iverilog -g2012 -o ";
  cmd += sim;
  cmd += " -s ";
  cmd += tb_top;
  cmd += " -I ";
  cmd += shell_quote(kTb);
  cmd += define;
  auto param = [&](const std::string& name, int64_t value) {
    cmd += " -P";
    cmd += tb_top;
    cmd += '.';
    cmd += name;
    cmd += '=';
    cmd += std::to_string(value);
  };
  for (const auto& [name, value] : params) param(name, value);
  param("LAT", latency);
  cmd += ' ';
  cmd += shell_quote(kTb + tb_file);
  for (const std::string& f : rtl) {
    cmd += ' ';
    cmd += shell_quote(kRtl + f);
  }
  cmd += " && vvp -n ";
  cmd += sim;
  cmd += " +vectors=";
  cmd += shell_quote(vec.string());
  cmd += " +n=";
  cmd += std::to_string(n);
  const fs::path log = dir / "sim.log";
  cmd += " >";
  cmd += shell_quote(log.string());
  cmd += " 2>&1";
  const int rc = std::system(cmd.c_str());
  SimResult r;
  r.code = rc != -1 && WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  std::ifstream f(log);
  std::stringstream ss;
  ss << f.rdbuf();
  r.out = ss.str();
  std::error_code ec;
  fs::remove_all(dir, ec);  // the log is in r.out
  const size_t at = r.out.find("iverilog: ");
  for (size_t p = at; p != std::string::npos; p = r.out.find("iverilog: ", p + 1)) {
    size_t a = 0, b = 0;
    if (std::sscanf(r.out.c_str() + p, "iverilog: %zu vectors, %zu mismatches", &a, &b) == 2) {
      r.vectors = a;
      r.mismatches = b;
      r.summary = true;
    }
  }
  return r;
}

fs::path work_dir(const std::string& name) {
  fs::path d =
      fs::temp_directory_path() / ("texsim_iverilog_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

const std::vector<std::string> kHelpers = {"texsim_pipe.v",        "texsim_round_sat.v",
                                           "texsim_op_counters.v", "texsim_mul_rs.v",
                                           "texsim_add_sat.v",     "texsim_mul_tree.v"};

// V(d) P2 or P1 at the generated format: returns the run; `perturb_at` adds one LSB to that
// vector's expected value (negative control).
SimResult run_vd(bool p2, size_t perturb_at = SIZE_MAX) {
  using Fmt = rtl_params::VdFormat;
  using In = Fmt::In;
  const std::vector<uint32_t> d = sample(vd_vectors<Fmt>(2000, 12), 10, sample_size(3000));
  std::vector<std::string> lines;
  lines.reserve(d.size());
  for (size_t i = 0; i < d.size(); ++i) {
    int64_t v = p2 ? VdEvaluatorP2().eval<Fmt>(In::from_raw(d[i])).raw()
                   : VdEvaluatorP1().eval<Fmt>(In::from_raw(d[i])).raw();
    if (i == perturb_at) ++v;
    lines.push_back(vector_line(
        {{d[i], rtl_params::kVdFin}, {static_cast<uint64_t>(v), rtl_params::kVdFc + 1}}));
  }
  const char* block = p2 ? "vd_p2" : "vd_p1";
  const fs::path dir = work_dir(std::string(block) + (perturb_at == SIZE_MAX ? "" : "_neg"));
  const uint32_t lat = p2 ? VdEvaluatorP2().timing(rtl_params::tech()).latency
                          : VdEvaluatorP1().timing(rtl_params::tech()).latency;
  write_vector_file((dir / "vectors.hex").string(), block, "d[FIN], v[FC+1]", lat, lines);
  std::vector<std::string> rtl = kHelpers;
  rtl.push_back(std::string(block) + ".v");
  return simulate("tb_vd", "tb_vd.v", rtl,
                  p2 ? rtl_params::vd_p2_params<>() : rtl_params::vd_p1_params<>(), lat,
                  p2 ? "" : " -DTB_VD_P1", dir / "vectors.hex", lines.size());
}

SimResult run_lerp(size_t n, size_t perturb_at = SIZE_MAX) {
  const BilinearLerp::Config c = rtl_params::kLerp;
  const BilinearLerp core(c);
  const std::vector<LerpIn> in = sample(lerp_vectors(c, n, 21), 175, n);
  const int t = 4 * c.texel_bits;
  std::vector<std::string> lines;
  lines.reserve(in.size());
  for (size_t i = 0; i < in.size(); ++i) {
    OpCounts ops;
    uint64_t out = core.lerp(in[i].quad, in[i].fx, in[i].fy, ops);
    if (i == perturb_at) ++out;
    lines.push_back(vector_line({{in[i].quad[0], t},
                                 {in[i].quad[1], t},
                                 {in[i].quad[2], t},
                                 {in[i].quad[3], t},
                                 {in[i].fx, c.sub_bits},
                                 {in[i].fy, c.sub_bits},
                                 {out, t}}));
  }
  const fs::path dir = work_dir(perturb_at == SIZE_MAX ? "lerp" : "lerp_neg");
  const uint32_t lat = core.timing(rtl_params::tech()).latency;
  write_vector_file((dir / "vectors.hex").string(), "bilinear_lerp",
                    "t00[4T], t10[4T], t01[4T], t11[4T], fx[S], fy[S], out[4T]", lat, lines);
  std::vector<std::string> rtl = kHelpers;
  rtl.push_back("bilinear_lerp.v");
  return simulate("tb_bilinear_lerp", "tb_bilinear_lerp.v", rtl, rtl_params::bilinear_lerp_params(),
                  lat, "", dir / "vectors.hex", lines.size());
}

bool tools_or_skip() { return on_path("iverilog") && on_path("vvp"); }
constexpr const char* kSkip = "iverilog or vvp not found on PATH (Debian: iverilog)";

void expect_all_equal(const SimResult& r) {
  ASSERT_TRUE(r.summary) << r.out;
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_GE(r.vectors, 100u) << r.out;
  EXPECT_EQ(r.mismatches, 0u) << r.out;
}

TEST(RtlIverilog, VdP2EqualsCpp) {
  if (!tools_or_skip()) GTEST_SKIP() << kSkip;
  expect_all_equal(run_vd(true));
}

TEST(RtlIverilog, VdP1EqualsCpp) {
  if (!tools_or_skip()) GTEST_SKIP() << kSkip;
  expect_all_equal(run_vd(false));
}

TEST(RtlIverilog, BilinearLerpEqualsCpp) {
  if (!tools_or_skip()) GTEST_SKIP() << kSkip;
  expect_all_equal(run_lerp(sample_size(600)));
}

// Negative controls: one LSB off in one expected value is exactly one mismatch, at that vector.
TEST(RtlIverilog, OneLsbIsOneMismatch) {
  if (!tools_or_skip()) GTEST_SKIP() << kSkip;
  for (const SimResult& r : {run_vd(true, 77), run_lerp(200, 123)}) {
    ASSERT_TRUE(r.summary) << r.out;
    EXPECT_EQ(r.mismatches, 1u) << r.out;
  }
  EXPECT_NE(run_vd(false, 41).out.find("vector 41 "), std::string::npos);
}

}  // namespace
}  // namespace texsim::rtl
