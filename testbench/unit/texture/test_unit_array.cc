// Several texture units in a scene run: the image does not depend on how many units filter it,
// the fragments are shared out by screen tile, more units finish sooner, and a bad [pipeline]
// hierarchy is refused before any work, naming the file, line and column.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "pipeline/app/run.h"
#include "testbench/lib/error_of.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

struct Outcome {
  std::unique_ptr<RunCapture> capture = std::make_unique<RunCapture>();
  nlohmann::json report;
};

Outcome run_units(const std::string& scene, int units, const std::string& dir,
                  std::vector<std::string> extra = {}, const std::string& timeline = "",
                  bool whole_fragments = false) {
  RunOptions opt;
  opt.scene = scene;
  opt.reference = "none";
  opt.threads = 1;
  opt.out = dir + "/u" + std::to_string(units);
  opt.timeline = timeline;
  opt.overrides = std::move(extra);
  opt.overrides.push_back("pipeline.units=" + std::to_string(units));
  Outcome o;
  o.capture->write_outputs = true;
  o.capture->whole_fragments = whole_fragments;
  opt.capture = o.capture.get();
  std::ostringstream log;
  run_simulation(opt, log);
  std::ifstream in(opt.out + "/report.json");
  o.report = nlohmann::json::parse(in);
  return o;
}

TEST(UnitArray, ImageIsTheSameAndTheWorkIsSharedByTile) {
  TempDir dir("unit_array");
  const Outcome one = run_units("default", 1, dir.file(""));
  EXPECT_FALSE(one.report.contains("units"));
  uint64_t last_cycles = one.capture->cycles;
  for (int n : {2, 4, 16}) {
    const Outcome o = run_units("default", n, dir.file(""));
    EXPECT_EQ(o.capture->image->rgb, one.capture->image->rgb) << n << " units";
    EXPECT_EQ(o.report["fragments"], one.report["fragments"]);
    const auto& units = o.report["units"];
    ASSERT_EQ(units.size(), static_cast<size_t>(n));
    uint64_t sum = 0, l1 = 0, most = 0;
    for (const auto& u : units) {
      sum += u["fragments"].get<uint64_t>();
      l1 += u["l1"]["accesses"].get<uint64_t>();
      most = std::max(most, u["cycles"].get<uint64_t>());
      EXPECT_GT(u["fragments"].get<uint64_t>(), 0u);  // the floor covers every unit's tiles
    }
    EXPECT_EQ(sum, o.report["fragments"].get<uint64_t>());
    EXPECT_EQ(l1, o.report["cache"]["accesses"].get<uint64_t>());
    EXPECT_EQ(most, o.capture->cycles);  // the frame ends with the last unit
    EXPECT_EQ(o.report["scheduler"]["late_items"].get<uint64_t>(), 0u);
    // Each block's operations are the same work shared out: equal totals.
    EXPECT_EQ(o.report["blocks"]["lod"]["ops"], one.report["blocks"]["lod"]["ops"]);
    EXPECT_LT(o.capture->cycles, last_cycles) << n << " units are not faster";
    last_cycles = o.capture->cycles;
  }
}

// Fragments whose look-ups all hit their unit's L1 are committed at once, out of the global
// cycle order; a run with a timeline commits every fragment in that order. Both must give the
// same report (every cycle, every unit's and level's counters) — with 16 units over an L2 and
// banked DRAM, and with quad merging — and most fragments must have taken the short way.
TEST(UnitArray, FragmentsThatHitTheirL1CommitAtOnceWithTheSameFigures) {
  TempDir dir("unit_array");
  const std::vector<std::vector<std::string>> setups = {
      {"pipeline.l2.size_bytes=65536", "pipeline.dram.model=banked"},
      {"raster.order=tiled", "pipeline.quad_merge=true"}};
  for (const auto& extra : setups) {
    const Outcome local = run_units("default", 16, dir.file("local"), extra);
    const Outcome ordered =
        run_units("default", 16, dir.file("ordered"), extra, dir.file("ordered.vcd"));
    const uint64_t fragments = local.report["fragments"].get<uint64_t>();
    EXPECT_GT(local.report["scheduler"]["local_commits"].get<uint64_t>(), fragments * 9 / 10);
    EXPECT_EQ(ordered.report["scheduler"]["local_commits"].get<uint64_t>(), 0u);
    for (const char* key :
         {"cycles", "units", "cache", "dram", "blocks", "stages", "frames", "energy", "raster"}) {
      ASSERT_TRUE(local.report.contains(key)) << key;
      EXPECT_EQ(local.report[key], ordered.report[key]) << key << " with " << extra[0];
    }
    EXPECT_EQ(local.report.value("l2", nlohmann::json()),
              ordered.report.value("l2", nlohmann::json()));
    EXPECT_EQ(local.capture->image->rgb, ordered.capture->image->rgb);
  }
}

// A unit filters each fragment as it comes and only its timing (a few words) waits for its
// turn; holding each waiting fragment whole must give the same report, byte for byte (its L1
// sees the same look-ups in the same order, the shared levels the same requests at the same
// cycles): trilinear on the fixed slots over an L2 and banked DRAM, and relief with lighting
// and anisotropic taps (any slots; groups of lines recorded) on a terrain.
TEST(UnitArray, FragmentsFilteredAsTheyComeGiveTheFiguresOfFragmentsHeldWhole) {
  TempDir dir("unit_array");
  const std::string terrain = std::string(TEXSIM_SOURCE_DIR) + "/scenes/terrain_dem.toml";
  const std::vector<std::pair<std::string, std::vector<std::string>>> runs = {
      {"default", {"pipeline.l2.size_bytes=65536", "pipeline.dram.model=banked"}},
      {terrain, {"output.width=96", "output.height=64"}}};
  for (const auto& [scene, extra] : runs) {
    const Outcome queued = run_units(scene, 16, dir.file("run"), extra);
    const Outcome whole = run_units(scene, 16, dir.file("run"), extra, "", true);
    EXPECT_GT(queued.report["scheduler"]["local_commits"].get<uint64_t>(), 0u);
    EXPECT_EQ(queued.report.size(), whole.report.size());
    for (const auto& [key, value] : queued.report.items())
      EXPECT_EQ(value, whole.report.value(key, nlohmann::json())) << key << " of " << scene;
    EXPECT_EQ(queued.capture->image->rgb, whole.capture->image->rgb) << scene;
  }
}

// Quad merging takes look-ups away, never colours: every look-up it saves is one the unit made
// without it (a line an earlier lane of the same quad had looked up).
TEST(UnitArray, QuadMergingSavesLookupsAndKeepsTheImage) {
  TempDir dir("unit_array");
  for (int units : {1, 4}) {
    const std::vector<std::string> tiled = {"raster.order=tiled"};
    std::vector<std::string> merged = tiled;
    merged.push_back("pipeline.quad_merge=true");
    const Outcome off = run_units("default", units, dir.file("off"), tiled);
    const Outcome on = run_units("default", units, dir.file("on"), merged);
    EXPECT_EQ(on.capture->image->rgb, off.capture->image->rgb);
    const auto saved = on.report["quads"]["merged_lookups"].get<uint64_t>();
    EXPECT_GT(saved, on.report["fragments"].get<uint64_t>() / 4) << units << " units";
    EXPECT_EQ(on.report["cache"]["accesses"].get<uint64_t>() + saved,
              off.report["cache"]["accesses"].get<uint64_t>())
        << units << " units";
  }
}

// Derivatives from quad differences: in the tiled order the quads are the rasteriser's own
// (the same count as the raster section's, from an independent count), and the image moves
// only slightly from the exact derivatives' (the floor is a plane: differences of u and v
// across a pixel are the derivatives up to the perspective's curvature).
TEST(UnitArray, QuadDerivativesUseTheRasterisersQuads) {
  TempDir dir("unit_array");
  const Outcome own = run_units("default", 1, dir.file("own"), {"raster.order=tiled"});
  for (const char* mode : {"coarse", "fine"}) {
    const Outcome q =
        run_units("default", 1, dir.file(mode),
                  {"raster.order=tiled", std::string("pipeline.derivatives=") + mode});
    uint64_t raster_quads = 0;
    for (const auto& [name, m] : q.report["raster"].items())
      if (m.contains("quads")) raster_quads += m["quads"].get<uint64_t>();
    EXPECT_EQ(q.report["quads"]["quads"].get<uint64_t>(), raster_quads) << mode;
    // A LOD step at a checker edge can move one pixel far; on average the image barely moves.
    double sum = 0;
    for (size_t i = 0; i < own.capture->image->rgb.size(); ++i)
      sum += std::abs(double(q.capture->image->rgb[i]) - own.capture->image->rgb[i]);
    const double mean = sum / static_cast<double>(own.capture->image->rgb.size());
    EXPECT_GT(mean, 0.0) << mode;
    EXPECT_LT(mean, 0.005) << mode;
  }
}

TEST(UnitArray, AFunctionalRunIgnoresTheUnitCount) {
  TempDir dir("unit_array");
  RunOptions opt;
  opt.scene = "default";
  opt.reference = "none";
  opt.functional = true;
  opt.threads = 1;
  opt.out = dir.file("") + "/f";
  opt.overrides = {"pipeline.units=8"};
  RunCapture c;
  c.write_outputs = false;
  opt.capture = &c;
  std::ostringstream log;
  EXPECT_NO_THROW(run_simulation(opt, log));
  EXPECT_EQ(c.cycles, 0u);
}

std::string scene_error(const std::string& pipeline_lines) {
  TempDir dir("unit_array");
  const std::string path = dir.file("") + "/s.toml";
  std::ofstream(path) << "[pipeline]\n" << pipeline_lines << "\n";
  RunOptions opt;
  opt.scene = path;
  opt.reference = "none";
  opt.out = dir.file("") + "/out";
  std::ostringstream log;
  std::string e = error_of([&] { run_simulation(opt, log); });
  EXPECT_FALSE(std::filesystem::exists(opt.out + "/report.json"));
  return e;
}

TEST(UnitArray, AnImpossibleUnitCountOrTileIsAnErrorAtItsLine) {
  EXPECT_NE(scene_error("units = 0").find("s.toml:2:"), std::string::npos);
  EXPECT_NE(scene_error("units = 0").find("units"), std::string::npos);
  EXPECT_NE(scene_error("units = 65").find("units"), std::string::npos);
  const std::string tile = scene_error("units = 4\nunit_tile = 12");
  EXPECT_NE(tile.find("s.toml:3:"), std::string::npos) << tile;
  EXPECT_NE(tile.find("power of two"), std::string::npos) << tile;
  // An L2 line smaller than the L1's, a DRAM row smaller than the line read from it, MSHRs 0.
  const std::string l2 = scene_error("[pipeline.l2]\nline_bytes = 32");
  EXPECT_NE(l2.find("s.toml:3:"), std::string::npos) << l2;
  EXPECT_NE(l2.find("line_bytes"), std::string::npos) << l2;
  const std::string row =
      scene_error("[pipeline.dram]\nmodel = \"banked\"\nrow_bytes = 32\ninterleave_bytes = 32");
  EXPECT_NE(row.find("s.toml:"), std::string::npos) << row;
  EXPECT_NE(row.find("row_bytes"), std::string::npos) << row;
  const std::string mshrs = scene_error("[pipeline.l2]\nmshrs = 0");
  EXPECT_NE(mshrs.find("s.toml:3:"), std::string::npos) << mshrs;
  EXPECT_NE(mshrs.find("mshrs"), std::string::npos) << mshrs;
  const std::string model = scene_error("[pipeline.dram]\nmodel = \"hbm\"");
  EXPECT_NE(model.find("model"), std::string::npos) << model;
}

// A scene whose materials compute their own coordinates: unit 0 runs the coordinate units and
// each fragment (and each fragment dropped after the front end) goes to its tile's unit; the
// image and the front end's counts do not depend on the unit count.
TEST(UnitArray, ACoordinateFrontEndFeedsEveryUnit) {
  TempDir dir("unit_array");
  const std::string scene = std::string(TEXSIM_SOURCE_DIR) + "/scenes/coords.toml";
  const Outcome one = run_units(scene, 1, dir.file("one"));
  const Outcome four = run_units(scene, 4, dir.file("four"));
  EXPECT_EQ(four.capture->image->rgb, one.capture->image->rgb);
  EXPECT_EQ(four.report["front_end"], one.report["front_end"]);
  EXPECT_EQ(four.report["fragments"], one.report["fragments"]);
  for (const auto& u : four.report["units"]) EXPECT_GT(u["fragments"].get<uint64_t>(), 0u);
  EXPECT_LT(four.capture->cycles, one.capture->cycles);
  EXPECT_EQ(four.report["scheduler"]["late_items"].get<uint64_t>(), 0u);
}

}  // namespace
}  // namespace texsim
