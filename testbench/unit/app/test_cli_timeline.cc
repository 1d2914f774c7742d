// `texsim run --timeline FILE.vcd`: a small scene's stage activity as a VCD (header, one scope
// per stage, value changes), bounded by --timeline-limit, and nothing else of the run changes.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "testbench/lib/cli_harness.h"
#include "testbench/lib/vcd_reader.h"

namespace {

using namespace cli_harness;  // NOLINT(google-build-using-namespace)

const std::string kSmall = " --no-progress --set output.width=48 --set output.height=32";

TEST_F(Cli, TimelineIsAVcdOfTheStages) {
  const std::string vcd = path("t.vcd");
  const Result r = sh("run" + kSmall + " --out " + path("a") + " --timeline " + vcd);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("timeline: " + vcd), std::string::npos) << r.out;
  const std::string text = slurp(vcd);
  ASSERT_EQ(text.rfind("$version texsim run --timeline $end\n", 0), 0u) << text.substr(0, 200);
  const vcd_reader::Vcd v = vcd_reader::parse(text);
  EXPECT_EQ(v.timescale, "1ns");
  EXPECT_TRUE(v.definitions_ended);
  const Json j = load_json(path("a") + "/report.json");
  const auto frags = static_cast<uint64_t>(num(j, "fragments"));
  ASSERT_GT(frags, 0u);
  ASSERT_LT(frags, 10000u);  // all recorded under the default limit
  for (const char* s : {"lod", "address", "cache", "blend"}) {
    SCOPED_TRACE(s);
    const std::string st = s;
    EXPECT_EQ(v.width.at(st + ".busy"), 1);
    EXPECT_EQ(v.width.at(st + ".items"), 32);
    // Every fragment went through every stage, and at the end none is left in it.
    EXPECT_EQ(v.at(st + ".items", UINT64_MAX), frags);
    EXPECT_EQ(v.at(st + ".inflight", UINT64_MAX), 0u);
    EXPECT_EQ(v.at(st + ".busy", UINT64_MAX), 0u);
    EXPECT_GE(v.changes.at(st + ".busy").size(), 2u);  // rose and fell
  }
  EXPECT_EQ(v.at("lod.busy", 0), 1u);  // the first fragment starts at cycle 0
  // The last stage's last change is the run's last exit.
  EXPECT_EQ(v.changes.at("blend.busy").back().first, static_cast<uint64_t>(num(j, "cycles")));

  // The same run without a timeline gives the same report figures.
  const Result plain = sh("run" + kSmall + " --out " + path("b"));
  ASSERT_EQ(plain.code, 0) << plain.out;
  const Json k = load_json(path("b") + "/report.json");
  EXPECT_EQ(k["cycles"], j["cycles"]);
  EXPECT_EQ(k["stages"], j["stages"]);
  EXPECT_EQ(k["cache"], j["cache"]);
}

// A name ending in .json: the same activity as Chrome trace events (Perfetto): every stage's
// busy slices together take in every fragment once, and the last slice ends at the run's end.
TEST_F(Cli, TimelineJsonIsTraceEvents) {
  const std::string file = path("t.json");
  const Result r = sh("run" + kSmall + " --out " + path("a") + " --timeline " + file);
  ASSERT_EQ(r.code, 0) << r.out;
  const Json t = Json::parse(slurp(file));
  const Json j = load_json(path("a") + "/report.json");
  const auto frags = static_cast<uint64_t>(num(j, "fragments"));
  EXPECT_EQ(t.at("otherData").at("items_recorded").get<uint64_t>(), frags);
  std::map<int, std::string> stage;  // tid -> name
  std::map<std::string, uint64_t> items, end;
  for (const Json& e : t.at("traceEvents")) {
    if (e.at("ph") == "M" && e.at("name") == "thread_name")
      stage[e.at("tid").get<int>()] = e.at("args").at("name").get<std::string>();
  }
  for (const Json& e : t.at("traceEvents")) {
    if (e.at("ph") != "X") continue;
    const std::string s = stage.at(e.at("tid").get<int>());
    items[s] += e.at("args").at("items").get<uint64_t>();
    end[s] = std::max(end[s], e.at("ts").get<uint64_t>() + e.at("dur").get<uint64_t>());
  }
  for (const char* s : {"lod", "address", "cache", "blend"}) {
    SCOPED_TRACE(s);
    EXPECT_EQ(items[s], frags);
  }
  EXPECT_EQ(end["blend"], static_cast<uint64_t>(num(j, "cycles")));
}

TEST_F(Cli, TimelineLimitAndErrors) {
  const std::string vcd = path("t.vcd");
  const Result r =
      sh("run" + kSmall + " --out " + path("a") + " --timeline " + vcd + " --timeline-limit 50");
  ASSERT_EQ(r.code, 0) << r.out;
  const vcd_reader::Vcd v = vcd_reader::parse(slurp(vcd));
  EXPECT_NE(v.comment.find("50 of "), std::string::npos) << v.comment;
  EXPECT_EQ(v.at("blend.items", UINT64_MAX), 50u);
  // Functional runs have no clock; a limit of 0 records nothing: both usage errors.
  EXPECT_EQ(sh("run --functional --timeline " + vcd).code, 2);
  EXPECT_EQ(sh("run --timeline " + vcd + " --timeline-limit 0").code, 2);
  // An unwritable timeline fails the run and leaves no report behind.
  const Result bad =
      sh("run" + kSmall + " --out " + path("c") + " --timeline " + path("nodir/t.vcd"));
  EXPECT_NE(bad.code, 0) << bad.out;
  EXPECT_NE(bad.out.find("nodir/t.vcd"), std::string::npos) << bad.out;
  EXPECT_FALSE(fs::exists(path("c") + "/report.json"));
}

TEST_F(Cli, TimelineHasEveryUnitAndMemoryLevel) {
  // Four units, an L2 over banked DRAM: a scope per unit, and one per level with its requests.
  const std::string vcd = path("t.vcd");
  const Result r = sh("run" + kSmall +
                      " --set pipeline.units=4 --set pipeline.l2.size_bytes=65536"
                      " --set pipeline.dram.model=banked --out " +
                      path("a") + " --timeline " + vcd);
  ASSERT_EQ(r.code, 0) << r.out;
  const vcd_reader::Vcd v = vcd_reader::parse(slurp(vcd));
  const Json j = load_json(path("a") + "/report.json");
  uint64_t items = 0;
  for (int u = 0; u < 4; ++u)
    items += v.at("unit" + std::to_string(u) + ".blend.items", UINT64_MAX);
  EXPECT_EQ(items, static_cast<uint64_t>(num(j, "fragments")));
  // Every request the L2 and the DRAM received, and none outstanding at the end.
  EXPECT_EQ(v.at("memory.l2.items", UINT64_MAX), j["l2"]["accesses"].get<uint64_t>());
  EXPECT_EQ(v.at("memory.dram.items", UINT64_MAX), j["dram"]["requests"].get<uint64_t>());
  EXPECT_GT(j["dram"]["requests"].get<uint64_t>(), 0u);
  for (const char* level : {"memory.l2", "memory.dram"}) {
    EXPECT_EQ(v.at(std::string(level) + ".inflight", UINT64_MAX), 0u) << level;
    EXPECT_GE(v.changes.at(std::string(level) + ".busy").size(), 2u) << level;
  }
}

}  // namespace
