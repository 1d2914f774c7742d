// Hostile input to `texsim tune`: --shard K/N parsed strictly, tune_shard.json read as a
// regular file within its limits with every field checked (the merge never indexes with a
// number it did not check), shards that overlap or repeat refused, and `tune default` taking
// the built-in scene as `run default` does.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "blocks/base/input_error.h"
#include "pipeline/app/tuner.h"
#include "testbench/lib/cli_harness.h"
#include "testbench/lib/error_of.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

using Json = nlohmann::ordered_json;

TEST(TuneShardSpec, OnlyTwoWholeNumbersWithKWithinN) {
  TuneOptions opt;
  for (const char* s : {"0/0",
                        "0/2",
                        "3/2",
                        "1/2/3",
                        "1.5/2",
                        "1/2.0",
                        "-1/2",
                        "1/-2",
                        "+1/2",
                        " 1/2",
                        "1/2 ",
                        "1/2x",
                        "1",
                        "/",
                        "1/",
                        "/2",
                        "",
                        "a/b",
                        "1e3/2000",
                        "2147483648/2147483648",
                        "1/99999999999999999999"}) {
    const std::string e = error_of([&] { parse_tune_shard(s, opt); });
    EXPECT_NE(e.find("expected K/N: two whole numbers with 1 <= K <= N"), std::string::npos)
        << "'" << s << "': " << e;
  }
  parse_tune_shard("2147483647/2147483647", opt);
  EXPECT_EQ(opt.shard, 2147483647);
  parse_tune_shard("2/3", opt);
  EXPECT_EQ(opt.shard, 2);
  EXPECT_EQ(opt.shards, 3);
}

// A shard as `texsim tune --shard 1/2` writes it for material 0 ("coords") of scene `scene`.
Json valid_shard(const std::string& scene, int k = 1, size_t index = 0,
                 const std::string& name = "coords") {
  Json p = {{"label", "as configured"},
            {"override", "materials." + name + "={ texture = \"checker\" }"},
            {"cycles", 1000.0},
            {"area", 12.5},
            {"psnr_db", 30.0},
            {"nmse", 0.001},
            {"meets", true},
            {"pareto", true}};
  Json m = {{"index", index}, {"name", name},       {"budget", "psnr=24"},
            {"chosen", 0},    {"budget_met", true}, {"points", Json::array({p})}};
  return {{"scene", scene},
          {"budget", "psnr=24"},
          {"cost", "cycles"},
          {"overrides", Json::array()},
          {"families", false},
          {"shard", k},
          {"shards", 2},
          {"runs", 7},
          {"materials", Json::array({m})}};
}

class TuneShardFile : public ::testing::Test {
 protected:
  std::string write(const std::string& text, const std::string& sub = "s") const {
    std::filesystem::create_directories(d_.file(sub));
    std::string path = d_.file(sub) + "/tune_shard.json";
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  std::string error_with(const Json& j) const {
    const std::string path = write(j.dump(1));
    return error_of([&] { read_tune_shard(path); });
  }
  TempDir d_{"tune_inputs"};
};

TEST_F(TuneShardFile, ValidShardReads) {
  const TuneShard s = read_tune_shard(write(valid_shard("s.toml").dump(1)));
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.indices[0], 0u);
  EXPECT_EQ(s.materials[0].name, "coords");
  EXPECT_EQ(s.materials[0].points[0].cycles, 1000.0);
  EXPECT_EQ(s.runs, 7);
}

// The segfault of the merge: `chosen` indexed the points unchecked.
TEST_F(TuneShardFile, ChosenOutOfRangeIsNamed) {
  for (const Json& bad : {Json(1), Json(-1), Json(4294967296), Json(1.5), Json("0"), Json()}) {
    Json j = valid_shard("s.toml");
    j["materials"][0]["chosen"] = bad;
    const std::string e = error_with(j);
    EXPECT_NE(e.find("tune_shard.json: materials[0].chosen: "), std::string::npos) << e;
    EXPECT_NE(e.find("is not a whole number in [0, 0]"), std::string::npos) << e;
  }
}

TEST_F(TuneShardFile, EveryFieldsTypeAndRangeIsChecked) {
  const std::pair<std::string, Json> cases[] = {
      {"scene", 3},
      {"overrides", "x"},
      {"families", 1},
      {"shard", 3},
      {"shards", 0},
      {"runs", -1},
      {"materials", Json::object()},
  };
  for (const auto& [key, value] : cases) {
    Json j = valid_shard("s.toml");
    j[key] = value;
    EXPECT_NE(error_with(j).find("tune_shard.json: " + key + ": "), std::string::npos)
        << key << ": " << error_with(j);
  }
  const std::pair<std::string, Json> point_cases[] = {
      {"cycles", -1},       {"cycles", "1"}, {"area", nullptr}, {"psnr_db", Json::array()},
      {"nmse", -0.5},       {"meets", 1},    {"label", 7},      {"label", "a|b"},
      {"label", "a\x1b[2J"}};
  for (const auto& [key, value] : point_cases) {
    Json j = valid_shard("s.toml");
    j["materials"][0]["points"][0][key] = value;
    EXPECT_NE(error_with(j).find("materials[0].points[0]." + key + ": "), std::string::npos)
        << key << "=" << value.dump() << ": " << error_with(j);
  }
  // A JSON number beyond a double is refused by the parser.
  std::string text = valid_shard("s.toml").dump();
  text.replace(text.find("\"cycles\":1000.0"), 15, "\"cycles\":1e400");
  const std::string path = write(text);
  EXPECT_NE(error_of([&] { read_tune_shard(path); }).find("number overflow parsing '1e400'"),
            std::string::npos)
      << error_of([&] { read_tune_shard(path); });
  Json j = valid_shard("s.toml");
  j["materials"][0].erase("points");
  EXPECT_NE(error_with(j).find("materials[0].points: missing"), std::string::npos);
  j = valid_shard("s.toml");
  j["materials"][0]["points"] = Json::array();
  EXPECT_NE(error_with(j).find("materials[0].points: empty"), std::string::npos);
  EXPECT_NE(error_with(Json::array()).find("(top level): expected an object"), std::string::npos);
}

TEST_F(TuneShardFile, InconsistentMaterialsAreRefused) {
  Json j = valid_shard("s.toml");
  j["materials"][0]["points"][0]["meets"] = false;  // PSNR 30 meets psnr=24
  EXPECT_NE(error_with(j).find("points[0].meets: disagrees"), std::string::npos);
  j = valid_shard("s.toml");
  j["materials"][0]["budget_met"] = false;
  EXPECT_NE(error_with(j).find("materials[0].budget_met: disagrees"), std::string::npos);
  j = valid_shard("s.toml");
  j["materials"][0]["points"][0]["override"] = "output.width=9";
  EXPECT_NE(error_with(j).find("override: does not set materials.coords"), std::string::npos);
  j = valid_shard("s.toml");
  j["materials"][0]["budget"] = "psnr=x";
  EXPECT_NE(error_with(j).find("materials[0].budget: "), std::string::npos);
  j = valid_shard("s.toml");
  j["materials"][0]["index"] = 1;  // shard 1/2 holds the even indices
  EXPECT_NE(error_with(j).find("materials[0].index: 1 is not in shard 1/2"), std::string::npos);
  j = valid_shard("s.toml");
  j["materials"].push_back(j["materials"][0]);
  EXPECT_NE(error_with(j).find("materials[1].index: material 0 appears twice"), std::string::npos);
}

// The parser stops at the depth limit; 100,000 levels neither crash nor get far.
TEST_F(TuneShardFile, DeepNestingIsRefused) {
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  EXPECT_NE(error_of([&] { read_tune_shard(write(deep)); }).find("nested deeper than 64 levels"),
            std::string::npos);
  const std::string deep_obj = "{\"scene\":" + std::string(65, '[') + std::string(65, ']') + "}";
  EXPECT_NE(error_of([&] { read_tune_shard(write(deep_obj)); }).find("nested deeper"),
            std::string::npos);
  EXPECT_NE(error_of([&] { read_tune_shard(write("{\"scene\": tru")); }).find("not JSON"),
            std::string::npos);
}

// A directory, a FIFO or /dev/zero where the shard is expected: an error at once, no read.
TEST_F(TuneShardFile, OnlyARegularFileIsRead) {
  const std::string dir = d_.file("d") + "/tune_shard.json";
  std::filesystem::create_directories(dir);
  EXPECT_NE(error_of([&] { read_tune_shard(dir); }).find(dir + ": "), std::string::npos);
  std::filesystem::create_directories(d_.file("f"));
  const std::string fifo = d_.file("f") + "/tune_shard.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_NE(error_of([&] { read_tune_shard(fifo); }).find(fifo + ": "), std::string::npos);
  std::filesystem::create_directories(d_.file("z"));
  const std::string zero = d_.file("z") + "/tune_shard.json";
  std::filesystem::create_symlink("/dev/zero", zero);
  EXPECT_NE(error_of([&] { read_tune_shard(zero); }).find(zero + ": "), std::string::npos);
}

// The merge against the scene and the other shards: all refused before any run.
class TuneMerge : public TuneShardFile {
 protected:
  void SetUp() override {
    scene_ = d_.file("s.toml");
    std::ofstream(scene_) << R"([output]
width = 16
height = 12
[textures.checker]
source = "procedural:checker?size=64&cells=8"
[materials.coords]
texture = "checker"
[materials.plain]
texture = "checker"
[[planes]]
material = "coords"
origin = [-2.5, 0.0, -0.5]
edge_u = [2.5, 0.0, 0.0]
edge_v = [0.0, 0.0, -40.0]
[[planes]]
material = "plain"
origin = [0.0, 0.0, -0.5]
edge_u = [2.5, 0.0, 0.0]
edge_v = [0.0, 0.0, -40.0]
)";
    opt_.scene = scene_;
    opt_.budget = "psnr=24";
    opt_.out = d_.file("out");
  }
  std::string merge_error(const std::vector<std::string>& dirs) {
    opt_.merge = dirs;
    std::ostringstream log;
    return error_of([&] { run_tune(opt_, log); });
  }
  std::string scene_;
  TuneOptions opt_;
};

TEST_F(TuneMerge, OverlappingOrRepeatedShardsAreRefused) {
  write(valid_shard(scene_).dump(1), "a");
  write(valid_shard(scene_).dump(1), "b");
  EXPECT_NE(merge_error({d_.file("a"), d_.file("a")}).find("given twice"), std::string::npos);
  EXPECT_NE(merge_error({d_.file("a"), d_.file("s/../a")}).find("given twice"), std::string::npos);
  // Two copies of one shard: the same shard number twice.
  EXPECT_NE(merge_error({d_.file("a"), d_.file("b")}).find("shard 1/2 is also"), std::string::npos);
  // A material in two shards: only possible with shards of two different splits (within one
  // split, each shard file holds only its own indices).
  Json other = valid_shard(scene_, 2, 1, "plain");
  other["materials"].push_back(valid_shard(scene_)["materials"][0]);
  other["shard"] = 1;
  other["shards"] = 1;
  write(other.dump(1), "c");
  EXPECT_NE(merge_error({d_.file("a"), d_.file("c")}).find("another split"), std::string::npos);
}

TEST_F(TuneMerge, ShardsMustMatchTheScene) {
  write(valid_shard(scene_, 1, 0, "plain").dump(1), "a");
  EXPECT_NE(merge_error({d_.file("a")})
                .find("materials[0].name: 'plain', the scene's material 0 "
                      "is 'coords'"),
            std::string::npos);
  write(valid_shard(scene_, 1, 2, "coords").dump(1), "b");
  EXPECT_NE(merge_error({d_.file("b")}).find("materials[0].index: 2 is out of range"),
            std::string::npos);
  write(valid_shard(scene_).dump(1), "c");
  EXPECT_NE(merge_error({d_.file("c")}).find("no shard has material 1"), std::string::npos);
  EXPECT_NE(merge_error({d_.file("nothing")}).find("no tune shard here"), std::string::npos);
  opt_.budget = "psnr=25";
  EXPECT_NE(merge_error({d_.file("c")}).find("budget differs"), std::string::npos);
}

// `tune default` searches and writes the built-in scene, as `run default` runs it: here the
// merge of a shard (no search) down to tuned.toml.
TEST_F(TuneShardFile, DefaultSceneIsTheBuiltInScene) {
  TuneOptions opt;
  opt.scene = "default";
  opt.budget = "psnr=24";
  opt.overrides = {"output.width=24", "output.height=16"};
  opt.ledger = false;
  opt.out = d_.file("out");
  Json j = valid_shard("default");
  j["shards"] = 1;
  j["overrides"] = opt.overrides;
  j["materials"] = Json::array();
  const char* tables[][2] = {
      {"floor", R"({ texture = "checker", filter = { mode = "bilinear", address = "wrap" } })"},
      {"panel", R"({ texture = "grid", filter = { mode = "bilinear", address = "clamp" } })"},
      {"wall", R"({ texture = "noise", filter = { mode = "trilinear", address = "mirror" } })"}};
  for (size_t i = 0; i < 3; ++i) {
    Json m = valid_shard("default", 1, i, tables[i][0])["materials"][0];
    m["points"][0]["override"] = std::string("materials.") + tables[i][0] + "=" + tables[i][1];
    j["materials"].push_back(m);
  }
  write(j.dump(1), "shard");
  opt.merge = {d_.file("shard")};
  std::ostringstream log;
  const TuneResult res = run_tune(opt, log);
  EXPECT_EQ(res.materials.size(), 3u);
  const std::string tuned = cli_harness::slurp(d_.file("out") + "/tuned.toml");
  EXPECT_EQ(tuned.rfind("# texsim tune default ", 0), 0u) << tuned;
  EXPECT_NE(tuned.find("floor = { filter = { address = 'wrap', mode = 'bilinear' }"),
            std::string::npos)
      << tuned;
}

// `tune default` reads the built-in scene (it said "cannot open scene file"); a bad --shard on
// the command line is a usage error (exit 2), not an internal error.
TEST(TuneCli, DefaultSceneAndBadShard) {
  TempDir d("tune_cli");
  const auto bad = cli_harness::sh("tune default --shard 0/0 --out " + d.file("o"));
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find("--shard 0/0: expected K/N"), std::string::npos) << bad.out;
  const auto merge =
      cli_harness::sh("tune default --merge " + d.file("none") + " --out " + d.file("o"));
  EXPECT_EQ(merge.code, 2) << merge.out;
  EXPECT_EQ(merge.out.find("cannot open scene"), std::string::npos) << merge.out;
  EXPECT_NE(merge.out.find("no tune shard here"), std::string::npos) << merge.out;
}

}  // namespace
}  // namespace texsim
