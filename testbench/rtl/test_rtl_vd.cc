// Lockstep of the V(d) evaluators P2 and P1 (rtl_model/rtl/vd_p2.v, vd_p1.v) against the C++
// cores (blocks/texture/subtexel/vd_evaluator_p2.h, vd_evaluator_p1.h) in the format of
// rtl_model/params/rtl_params.h: every u0.16 code once (the directed corner cases are among
// them: 0, the P1 breakpoints and their neighbours, 0.5 and the largest code), then seeded
// random codes with random idle cycles.
#include <Vvd_p1.h>
#include <Vvd_p2.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "blocks/base/input_error.h"
#include "rtl_model/params/rtl_params.h"
#include "testbench/rtl/lockstep.h"
#include "testbench/rtl/rtl_vectors.h"

namespace texsim::rtl {
namespace {

using Fmt = rtl_params::VdFormat;
using In = Fmt::In;

template <class Model, class Core>
Scoreboard run_vd(const char* name, const Core& core, uint32_t latency, uint64_t n_random,
                  int64_t perturb = 0, size_t perturb_at = 0) {
  RtlHarness<Model> h(name);
  h.reset();
  Scoreboard sb(name, latency);
  const std::vector<uint32_t> vectors = vd_vectors<Fmt>(n_random, 12);
  stream_lockstep(
      h, sb, vectors,
      [](Model& top, uint32_t d) {
        top.d = static_cast<std::remove_reference_t<decltype(top.d)>>(d);
      },
      [](Model& top) { return OutWords{static_cast<int64_t>(top.v)}; },
      [&](uint32_t d, OpCounts& ops) {
        ops += Core::ops_per_item();
        const auto v = core.template eval<Fmt>(In::from_raw(d));
        return OutWords{v.raw()};
      },
      34, 0.125, perturb, perturb_at);
  std::cout << sb.summary() << "\n" << sb.report();
  return sb;
}

uint32_t p2_latency() { return VdEvaluatorP2().timing(rtl_params::tech()).latency; }
uint32_t p1_latency() { return VdEvaluatorP1().timing(rtl_params::tech()).latency; }

TEST(RtlLockstep, VdP2MatchesCppBitForBit) {
  const Scoreboard sb = run_vd<Vvd_p2>("vd_p2", VdEvaluatorP2(), p2_latency(), lockstep_vectors());
  EXPECT_EQ(sb.mismatches(), 0u) << sb.report();
  EXPECT_GT(sb.compared(), 65536u);
}

TEST(RtlLockstep, VdP1MatchesCppBitForBit) {
  const Scoreboard sb = run_vd<Vvd_p1>("vd_p1", VdEvaluatorP1(), p1_latency(), lockstep_vectors());
  EXPECT_EQ(sb.mismatches(), 0u) << sb.report();
  EXPECT_GT(sb.compared(), 65536u);
}

// Negative controls: the scoreboard catches a one-LSB difference in one transaction, and a
// latency other than the C++ timing spec's.
TEST(RtlLockstep, VdScoreboardCatchesOneLsb) {
  const auto at = static_cast<size_t>(In::kRawMax / 2 + 7);  // inside the exhaustive sweep
  const Scoreboard sb = run_vd<Vvd_p2>("vd_p2", VdEvaluatorP2(), p2_latency(), 1000, 1, at);
  EXPECT_EQ(sb.mismatches(), 1u);
  EXPECT_NE(sb.report().find("transaction " + std::to_string(at) + " "), std::string::npos)
      << sb.report();
}

TEST(RtlLockstep, VdScoreboardCatchesLatency) {
  const Scoreboard sb = run_vd<Vvd_p1>("vd_p1", VdEvaluatorP1(), p1_latency() + 1, 0);
  EXPECT_EQ(sb.mismatches(), sb.compared());
  EXPECT_NE(sb.report().find("latency"), std::string::npos) << sb.report();
}

// Waveforms are switched at run time: a trace path writes a VCD of the block's signals.
TEST(RtlHarness, WritesVcdWhenAsked) {
  const std::string path = testing::TempDir() + "texsim_vd_p2_trace.vcd";
  {
    RtlHarness<Vvd_p2> h("vd_p2", path);
    h.reset();
    h.top().in_valid = 1;
    const int64_t half = In::kRawMax / 2 + 1;  // d = 0.5
    h.top().d = static_cast<uint16_t>(half);
    for (uint32_t i = 0; i < p2_latency(); ++i) h.step();
    EXPECT_EQ(h.top().v, VdEvaluatorP2().eval<Fmt>(In::from_raw(half)).raw());
  }
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("$var wire " + std::to_string(rtl_params::kVdFin) + " "),
            std::string::npos);
  EXPECT_NE(text.str().find("out_valid"), std::string::npos);
  std::remove(path.c_str());
  RtlHarness<Vvd_p1> quiet("vd_p1", "");
  EXPECT_EQ(quiet.trace_path().empty(), std::getenv("TEXSIM_RTL_TRACE") == nullptr);
}

// TEXSIM_RTL_TRACE naming something that is not a writable directory used to give no
// waveform and no word: now an InputError naming the variable and the path.
TEST(RtlHarness, TraceVariableThatCannotBeWrittenIsAnError) {
  namespace fs = std::filesystem;
  const char* saved = std::getenv("TEXSIM_RTL_TRACE");  // NOLINT(concurrency-mt-unsafe)
  const std::string keep = saved ? saved : "";
  const fs::path base = fs::path(testing::TempDir()) / "texsim_rtl_trace_env";
  fs::remove_all(base);
  fs::create_directories(base / "ok");
  std::ofstream(base / "file") << "x";
  const auto message_for = [](const fs::path& dir) {
    ::setenv("TEXSIM_RTL_TRACE", dir.c_str(), 1);  // NOLINT(concurrency-mt-unsafe)
    try {
      RtlHarness<Vvd_p2> h("vd_p2");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string missing = message_for(base / "missing");
  EXPECT_NE(missing.find("TEXSIM_RTL_TRACE=" + (base / "missing").string() + ": no such directory"),
            std::string::npos)
      << missing;
  const std::string file = message_for(base / "file");
  EXPECT_NE(file.find("TEXSIM_RTL_TRACE=" + (base / "file").string() + ": not a directory"),
            std::string::npos)
      << file;
  if (::geteuid() != 0) {  // root may write anywhere
    fs::create_directories(base / "ro");
    fs::permissions(base / "ro", fs::perms::owner_read | fs::perms::owner_exec);
    const std::string ro = message_for(base / "ro");
    EXPECT_NE(ro.find("may not write"), std::string::npos) << ro;
    fs::permissions(base / "ro", fs::perms::owner_all);
  }
  EXPECT_EQ(message_for(base / "ok"), "");
  EXPECT_TRUE(fs::exists(base / "ok" / "vd_p2.vcd"));
  // An explicit path that cannot be opened.
  ::unsetenv("TEXSIM_RTL_TRACE");  // NOLINT(concurrency-mt-unsafe)
  try {
    RtlHarness<Vvd_p2> h("vd_p2", (base / "missing" / "x.vcd").string());
    ADD_FAILURE() << "an unopened waveform was ignored";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open the waveform file"), std::string::npos)
        << e.what();
  }
  if (saved) ::setenv("TEXSIM_RTL_TRACE", keep.c_str(), 1);  // NOLINT(concurrency-mt-unsafe)
  fs::remove_all(base);
}

}  // namespace
}  // namespace texsim::rtl
