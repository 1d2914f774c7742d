// report.json and report.md say how to reproduce a run: texsim version, command, a SHA-1 of
// every input file (checked against sha1sum), the resolved configuration with every default
// written out, and physical figures at the clock; the same command gives the same bytes.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "testbench/lib/cli_harness.h"

namespace {

using namespace cli_harness;  // NOLINT(google-build-using-namespace)
namespace fs = std::filesystem;

// sha1sum's digest of a file: an oracle outside texsim.
std::string sha1sum(const std::string& file) {
  std::string out;
  FILE* p = ::popen(("sha1sum '" + file + "'").c_str(), "r");
  if (p == nullptr) return "";
  char buf[256];
  while (std::fgets(buf, sizeof buf, p) != nullptr) out += buf;
  EXPECT_EQ(::pclose(p), 0) << out;
  return out.substr(0, out.find(' '));
}

const char* kScene = R"(
[output]
width = 64
height = 48
[textures.crate]
source = "crate.png"
[textures.grid]
source = "procedural:grid?size=64"
[materials.floor]
texture = "crate"
[materials.wall]
texture = "grid"
[[planes]]
material = "floor"
origin = [-4.0, 0.0, -0.5]
edge_u = [8.0, 0.0, 0.0]
edge_v = [0.0, 0.0, -8.0]
[[planes]]
material = "wall"
origin = [-1.0, 0.0, -6.0]
edge_u = [2.0, 0.0, 0.0]
edge_v = [0.0, 2.0, 0.0]
[pipeline]
fifo_depth = 7
[tech]
clock_mhz = 250.0
)";

TEST_F(Cli, ReportRecordsVersionCommandDigestsAndResolvedConfiguration) {
  fs::copy_file("/usr/share/glmark2/textures/crate-base.png", path("crate.png"));
  write("s.toml", kScene);
  const std::string out = path("out");
  const std::string args = "run " + path("s.toml") + " --no-progress --out " + out;
  const Result r = sh(args);
  ASSERT_EQ(r.code, 0) << r.out;
  const Json j = load_json(out + "/report.json");
  const Json& p = j.at("provenance");

  const Result v = sh("--version");
  EXPECT_EQ(v.out, "texsim " + p.at("texsim_version").get<std::string>() + "\n");
  EXPECT_EQ(p.at("command"), "texsim " + args);

  ASSERT_EQ(p.at("inputs").size(), 3u) << p.dump(1);
  EXPECT_EQ(p["inputs"][0]["role"], "scene");
  EXPECT_EQ(p["inputs"][0]["sha1"], sha1sum(path("s.toml")));
  EXPECT_EQ(p["inputs"][0]["bytes"], fs::file_size(path("s.toml")));
  EXPECT_EQ(p["inputs"][1]["role"], "texture crate");
  EXPECT_EQ(p["inputs"][1]["sha1"], sha1sum(path("crate.png")));
  EXPECT_EQ(p["inputs"][2]["path"], "procedural:grid?size=64");
  EXPECT_FALSE(p["inputs"][2].contains("sha1"));  // not a file

  // What the scene set, and the defaults it did not set, written out.
  EXPECT_EQ(num(p, "pipeline.fifo_depth"), 7);
  EXPECT_EQ(num(p, "pipeline.dram.latency"), 100);
  EXPECT_EQ(num(p, "pipeline.cache.hit_latency"), 4);
  EXPECT_EQ(num(p, "pipeline.cache.texels_per_cycle"), 4);
  EXPECT_EQ(p.at("pipeline").at("layout"), "tiled4x4");
  EXPECT_EQ(num(p, "tech.clock_mhz"), 250);
  EXPECT_EQ(num(p, "tech.latency.mul"), 3);
  EXPECT_EQ(num(p, "tech.area.div"), 24);

  // Physical figures at the clock, and the area as the sum of the blocks listed.
  const double cycles = num(j, "cycles");
  EXPECT_DOUBLE_EQ(num(j, "physical.time_us"), cycles / 250.0);
  EXPECT_DOUBLE_EQ(num(j, "physical.fragments_per_second"), num(j, "fragments") / (cycles / 250e6));
  double area = 0;
  for (const auto& [name, b] : j.at("blocks").items()) area += b.at("area").get<double>();
  EXPECT_DOUBLE_EQ(num(j, "area_total"), area);
  ASSERT_EQ(j.at("frames").size(), 1u);
  EXPECT_DOUBLE_EQ(num(j.at("frames")[0], "time_us"), cycles / 250.0);

  const std::string md = slurp(out + "/report.md");
  EXPECT_NE(md.find(sha1sum(path("crate.png"))), std::string::npos) << md;
  EXPECT_NE(md.find("FIFO depth 7"), std::string::npos) << md;

  // Nothing in the reports changes between two runs of the same command.
  const std::string json1 = slurp(out + "/report.json");
  ASSERT_EQ(sh(args).code, 0);
  EXPECT_EQ(slurp(out + "/report.json"), json1);
  EXPECT_EQ(slurp(out + "/report.md"), md);
}

TEST_F(Cli, FunctionalRunHasNoPhysicalTime) {
  const Result r = sh("run --functional --no-progress --out " + path("out"));
  ASSERT_EQ(r.code, 0) << r.out;
  const Json j = load_json(path("out") + "/report.json");
  EXPECT_FALSE(j.contains("physical"));
  EXPECT_EQ(j.at("provenance").at("inputs")[0].at("path"), "<built-in default scene>");
}

}  // namespace

namespace {

TEST_F(Cli, AnyThreadCountGivesTheSameOutputs) {
  // The photo scene: two materials, a file texture, anisotropic filtering.
  const std::string scene = std::string(TEXSIM_SOURCE_DIR) + "/scenes/photo.toml";
  for (const char* t : {"1", "2", "3"}) {
    const Result r = sh("run " + scene + " --no-progress --threads " + t + " --out " + path(t));
    ASSERT_EQ(r.code, 0) << r.out;
  }
  // The adaptive ground truth (the default) included: each pixel's samples depend on it alone.
  for (const char* t : {"2", "3"}) {
    for (const char* f : {"image.png", "reference.png", "error.png"}) {
      EXPECT_EQ(slurp(path("1/") + f), slurp(path(t) + "/" + f)) << f << ", threads " << t;
    }
    Json a = load_json(path("1/report.json")), b = load_json(path(t) + "/report.json");
    a["provenance"].erase("command");
    b["provenance"].erase("command");
    EXPECT_EQ(a, b) << "threads " << t;
  }
}

TEST_F(Cli, SetOverridesAKeyAndIsValidatedLikeTheFile) {
  const Result r =
      sh("run --no-progress --set pipeline.fifo_depth=9 --set tech.latency.mul=4 "
         "--out " +
         path("o"));
  ASSERT_EQ(r.code, 0) << r.out;
  const Json j = load_json(path("o/report.json"));
  EXPECT_EQ(num(j, "provenance.pipeline.fifo_depth"), 9);
  EXPECT_EQ(num(j, "provenance.tech.latency.mul"), 4);
  const Result bad = sh("run --no-progress --set pipeline.fifo_depth=0 --out " + path("b"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.out.find("texsim: error: --set pipeline.fifo_depth: pipeline.fifo_depth: value 0 "
                         "out of range"),
            std::string::npos)
      << bad.out;
  expect_no_outputs(path("b"));
}

}  // namespace
