// The stage timeline (pipeline/kernel/stage_timeline.h): each item's start and leave cycle per
// stage, as the kernel timed them, written as a VCD whose values follow from them.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "pipeline/kernel/stage_timeline.h"
#include "testbench/lib/cli_harness.h"
#include "testbench/lib/vcd_reader.h"

namespace texsim {
namespace {

StageConfig stage(const char* name, uint32_t lat) {
  StageConfig c;
  c.name = name;
  c.timing.latency = lat;
  return c;
}

TEST(StageTimeline, LastItemIsWhatTheKernelTimed) {
  ClockedPipeline p({stage("a", 2), stage("b", 3)});
  // Item k starts in a at k, leaves it at k + 2, starts in b there and leaves at k + 5.
  for (uint64_t k = 0; k < 3; ++k) {
    EXPECT_EQ(p.issue(), k + 5);
    EXPECT_EQ(p.last_item(0).start, k);
    EXPECT_EQ(p.last_item(0).leave, k + 2);
    EXPECT_EQ(p.last_item(1).start, k + 2);
    EXPECT_EQ(p.last_item(1).finish, k + 5);
    EXPECT_EQ(p.last_item(1).leave, k + 5);
  }
}

TEST(StageTimeline, VcdHeaderAndValueChanges) {
  ClockedPipeline p({stage("a", 2), stage("b.x", 3)});
  StageTimeline tl(10);
  for (int k = 0; k < 3; ++k) {
    p.issue();
    tl.observe(p);
    tl.observe(p);  // no new item: nothing recorded twice
  }
  EXPECT_EQ(tl.recorded(), 3u);
  const std::string file =
      (std::filesystem::temp_directory_path() / "texsim_stage_timeline.vcd").string();
  tl.write_vcd(file);
  const vcd_reader::Vcd v = vcd_reader::parse(cli_harness::slurp(file));
  std::filesystem::remove(file);
  EXPECT_EQ(v.timescale, "1ns");
  EXPECT_TRUE(v.definitions_ended);
  EXPECT_NE(v.comment.find("3 of 3 items"), std::string::npos) << v.comment;
  EXPECT_EQ(v.width.at("a.busy"), 1);
  EXPECT_EQ(v.width.at("a.items"), 32);
  EXPECT_EQ(v.width.at("b_x.inflight"), 16);  // names made VCD-safe
  // a: starts 0, 1, 2; leaves 2, 3, 4. b: starts 2, 3, 4; leaves 5, 6, 7.
  EXPECT_EQ(v.at("a.busy", 0), 1u);
  EXPECT_EQ(v.at("a.items", 1), 2u);
  EXPECT_EQ(v.at("a.inflight", 1), 2u);
  EXPECT_EQ(v.at("a.inflight", 2), 2u);  // one in, one out
  EXPECT_EQ(v.at("a.busy", 3), 1u);
  EXPECT_EQ(v.at("a.busy", 4), 0u);
  EXPECT_EQ(v.at("b_x.busy", 1), 0u);
  EXPECT_EQ(v.at("b_x.busy", 2), 1u);
  EXPECT_EQ(v.at("b_x.inflight", 4), 3u);
  EXPECT_EQ(v.at("b_x.items", 100), 3u);
  EXPECT_EQ(v.at("b_x.busy", 6), 1u);
  EXPECT_EQ(v.at("b_x.busy", 7), 0u);
  // Only changes are written: a's busy rises once and falls once.
  EXPECT_EQ(v.changes.at("a.busy").size(), 3u);  // $dumpvars 0, then 1 at #0, 0 at #4
}

TEST(StageTimeline, LimitKeepsTheFirstItems) {
  ClockedPipeline p({stage("a", 2)});
  StageTimeline tl(2);
  for (int k = 0; k < 5; ++k) {
    p.issue();
    tl.observe(p);
  }
  EXPECT_EQ(tl.recorded(), 2u);
  EXPECT_EQ(tl.seen(), 5u);
  const std::string file =
      (std::filesystem::temp_directory_path() / "texsim_stage_timeline_limit.vcd").string();
  tl.write_vcd(file);
  const vcd_reader::Vcd v = vcd_reader::parse(cli_harness::slurp(file));
  std::filesystem::remove(file);
  EXPECT_NE(v.comment.find("2 of 5 items"), std::string::npos) << v.comment;
  EXPECT_EQ(v.at("a.items", 1000), 2u);
  EXPECT_EQ(v.at("a.busy", 3), 0u);
}

// Several units: each unit's stages under a scope of its own, with that unit's items only.
TEST(StageTimeline, SeveralUnitsGetAScopeEach) {
  ClockedPipeline p0({stage("a", 2)}), p1({stage("a", 5)});
  StageTimeline tl(10);
  p1.issue();  // unit 1's first item before unit 0's: scopes still in unit order
  tl.observe(p1, 1);
  for (int k = 0; k < 2; ++k) {
    p0.issue();
    tl.observe(p0, 0);
  }
  EXPECT_EQ(tl.recorded(), 3u);
  EXPECT_EQ(tl.seen(), 3u);
  const std::string file =
      (std::filesystem::temp_directory_path() / "texsim_stage_timeline_units.vcd").string();
  tl.write_vcd(file);
  const std::string text = cli_harness::slurp(file);
  const vcd_reader::Vcd v = vcd_reader::parse(text);
  std::filesystem::remove(file);
  EXPECT_LT(text.find("unit0"), text.find("unit1"));
  // Unit 0: starts 0, 1; leaves 2, 3. Unit 1: one item from 0 to 5.
  EXPECT_EQ(v.at("unit0.a.items", 1), 2u);
  EXPECT_EQ(v.at("unit0.a.busy", 3), 0u);
  EXPECT_EQ(v.at("unit1.a.items", 1), 1u);
  EXPECT_EQ(v.at("unit1.a.busy", 4), 1u);
  EXPECT_EQ(v.at("unit1.a.busy", 5), 0u);
}

// The same activity as Chrome trace events: a busy slice per stretch of cycles with an item in
// the stage, in-flight counter samples where the count changes, names per process and thread.
TEST(StageTimeline, TraceEventsFollowTheItemTimes) {
  ClockedPipeline p0({stage("a", 2), stage("b", 3)}), p1({stage("a", 5)});
  StageTimeline tl(10);
  for (int k = 0; k < 3; ++k) {
    p0.issue();
    tl.observe(p0, 0);
  }
  p1.issue();
  tl.observe(p1, 1);
  const int dram = tl.memory_track("dram");
  tl.observe_request(dram, 10, 30);
  tl.observe_request(dram, 12, 20);  // answers out of order: the level's copy is sorted
  const std::string file =
      (std::filesystem::temp_directory_path() / "texsim_stage_timeline.json").string();
  tl.write(file);  // by its name: trace events
  const nlohmann::json j = nlohmann::json::parse(cli_harness::slurp(file));
  std::filesystem::remove(file);
  EXPECT_EQ(j.at("otherData").at("items_recorded"), 4);
  std::map<std::pair<int, int>, std::string> thread;
  std::map<int, std::string> process;
  std::vector<nlohmann::json> busy, counters;
  for (const nlohmann::json& e : j.at("traceEvents")) {
    const std::string ph = e.at("ph");
    if (ph == "M" && e.at("name") == "thread_name")
      thread[{e.at("pid"), e.at("tid")}] = e.at("args").at("name");
    if (ph == "M" && e.at("name") == "process_name") process[e.at("pid")] = e.at("args").at("name");
    if (ph == "X") busy.push_back(e);
    if (ph == "C") counters.push_back(e);
  }
  EXPECT_EQ(process.at(0), "unit 0");
  EXPECT_EQ(process.at(1), "unit 1");
  EXPECT_EQ(process.at(2), "memory");
  ASSERT_EQ(thread.size(), 4u);
  // Unit 0 stage a: starts 0, 1, 2, leaves 2, 3, 4 -> one slice [0, 4) with 3 items; stage b:
  // starts 2, 3, 4, leaves 5, 6, 7 -> [2, 7). Unit 1: [0, 5). dram: requests 10-30, 12-20.
  std::map<std::string, std::tuple<int, int, int>> slice;  // thread -> ts, dur, items
  for (const nlohmann::json& e : busy)
    slice[thread.at({e.at("pid"), e.at("tid")}) + "@" + std::to_string(int(e.at("pid")))] = {
        e.at("ts"), e.at("dur"), e.at("args").at("items")};
  ASSERT_EQ(slice.size(), 4u);
  EXPECT_EQ(slice.at("a@0"), std::make_tuple(0, 4, 3));
  EXPECT_EQ(slice.at("b@0"), std::make_tuple(2, 5, 3));
  EXPECT_EQ(slice.at("a@1"), std::make_tuple(0, 5, 1));
  EXPECT_EQ(slice.at("dram@2"), std::make_tuple(10, 20, 2));
  // Unit 0 stage a's counter: 1 at 0, 2 at 1, (2 at 2: unchanged, not written), 1 at 3, 0 at 4.
  std::vector<std::pair<int, int>> a0;
  for (const nlohmann::json& e : counters)
    if (e.at("pid") == 0 && e.at("name") == "a in flight")
      a0.emplace_back(e.at("ts"), e.at("args").at("items"));
  const std::vector<std::pair<int, int>> want = {{0, 1}, {1, 2}, {3, 1}, {4, 0}};
  EXPECT_EQ(a0, want);
}

}  // namespace
}  // namespace texsim
