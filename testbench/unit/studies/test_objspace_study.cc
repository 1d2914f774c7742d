// study objspace on a reduced set of scenes: every method runs on every case, object space
// leaves no holes, and its figures keep the relations the study's claims rest on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "pipeline/studies/study_objspace.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

ObjspaceStudyOptions small() {
  ObjspaceStudyOptions o;
  o.widths = {64};
  o.tilts = {0, 60, 85};
  o.tilt_size = 64;
  o.grid_cells = {1, 4};
  o.areas = {1, 2};
  o.steps = {3.0};
  o.band_ratios = {0.0};
  o.bands_width = 64;
  o.lane_counts = {};
  o.mesh = false;
  o.scenes_dir = std::string(TEXSIM_SOURCE_DIR) + "/scenes";
  o.reference_supersamples = 2;
  o.images = false;
  return o;
}

TEST(StudyObjspace, EveryMethodOnEveryCaseWithoutHoles) {
  std::ostringstream log;
  const std::vector<ObjspaceRow> rows = measure_objspace_study(small(), "", log);
  // floor + cube, 3 tilts, 2 counts, 2 areas, 1 density, 1 band ratio; five methods each.
  ASSERT_EQ(rows.size(), (2u + 3u + 2u + 2u + 1u + 1u) * 5u);
  for (size_t i = 0; i < rows.size(); i += 5) {
    const ObjspaceRow& o = rows[i];
    ASSERT_EQ(o.method, "object-space");
    if (o.sweep == "density") {
      // A step of 3 pixels breaks the rule: holes appear, counted.
      EXPECT_GT(o.holes, 0u);
      continue;
    }
    EXPECT_EQ(o.holes, 0u) << o.sweep << " " << o.scene;
    EXPECT_GT(o.pixels, 0u);
    EXPECT_GE(o.items, o.pixels);  // a step of at most 3/4 pixel: more samples than pixels
    EXPECT_GT(o.texels, 0u);
    EXPECT_GT(o.buffer_bytes, 0u);
    EXPECT_TRUE(std::isfinite(o.acc.mse));
    for (size_t k = 1; k < 5; ++k) {
      const ObjspaceRow& s = rows[i + k];
      EXPECT_EQ(s.pixels, o.pixels);  // the same pixels compared
      EXPECT_EQ(s.items, s.pixels);   // one fragment per covered pixel
      EXPECT_GT(s.cycles, 0u);
      EXPECT_EQ(s.buffer_bytes, 0u);
    }
    EXPECT_EQ(rows[i + 1].method, "trilinear");
  }
  // Object space's samples hardly change with tilt (the square's area is fixed); screen
  // space's pixels fall with it.
  std::vector<const ObjspaceRow*> tilt;
  for (const ObjspaceRow& r : rows) {
    if (r.sweep == "tilt" && r.method == "object-space") tilt.push_back(&r);
  }
  ASSERT_EQ(tilt.size(), 3u);
  EXPECT_LT(static_cast<double>(tilt[2]->items), 1.6 * static_cast<double>(tilt[0]->items));
  EXPECT_LT(tilt[2]->pixels * 4, tilt[0]->pixels);
  // The thesis's one LOD and one grid step per polygon (band ratio 0) against the default
  // bands on the same floor: one band per polygon, its nearest point's step everywhere, so
  // more samples.
  const ObjspaceRow *banded = nullptr, *one = nullptr;
  for (const ObjspaceRow& r : rows) {
    if (r.method != "object-space" || r.scene != "floor" || r.width != 64) continue;
    if (r.sweep == "resolution") banded = &r;
    if (r.sweep == "bands") one = &r;
  }
  ASSERT_TRUE(banded && one);
  EXPECT_DOUBLE_EQ(one->band_ratio, 0.0);
  EXPECT_EQ(one->bands, one->primitives);  // one band per primitive
  EXPECT_GT(banded->bands, banded->primitives);
  EXPECT_GT(one->items, banded->items);
  EXPECT_EQ(one->pixels, banded->pixels);
}

// The thesis's "GPU cores": object space with 1, 4 and 16 lanes per block on the floor. The
// lane-wide stages' cycles fall with the lanes, their area grows, the image is the same; the
// frame cannot go below the one texture unit's cycles.
TEST(StudyObjspace, LaneSweepScalesTheStagesNotTheImage) {
  ObjspaceStudyOptions o = small();
  o.widths = {};
  o.tilts = {};
  o.grid_cells = {};
  o.areas = {};
  o.steps = {};
  o.band_ratios = {};
  o.cube = false;
  o.lane_counts = {1, 4, 16};
  o.lanes_width = 64;
  std::ostringstream log;
  const std::vector<ObjspaceRow> rows = measure_objspace_study(o, "", log);
  ASSERT_EQ(rows.size(), 3u);
  const ObjspaceRow &k1 = rows[0], &k4 = rows[1], &k16 = rows[2];
  for (const ObjspaceRow& r : rows) {
    EXPECT_EQ(r.sweep, "lanes");
    EXPECT_EQ(r.method, "object-space");
    EXPECT_GE(r.cycles, std::max(r.texture_cycles, r.lane_cycles));
    EXPECT_EQ(r.acc.mse, k1.acc.mse);  // lanes change the cost, not the arithmetic
    EXPECT_EQ(r.items, k1.items);
  }
  EXPECT_EQ(k4.lanes, 4);
  EXPECT_NEAR(static_cast<double>(k4.lane_cycles), static_cast<double>(k1.lane_cycles) / 4,
              0.05 * static_cast<double>(k1.lane_cycles) / 4 + 64);
  EXPECT_LT(k16.lane_cycles, k4.lane_cycles);
  // Each lane adds its operators; the set-up units beside the lanes are there once.
  EXPECT_GT(k4.block_area, 1.8 * k1.block_area);
  EXPECT_GT(k16.block_area, 2.5 * k4.block_area);
  EXPECT_LE(k4.cycles, k1.cycles);
  EXPECT_LE(k16.cycles, k4.cycles);
  EXPECT_EQ(k16.texture_cycles, k1.texture_cycles);  // one texture unit whatever the lanes
}

// The cells of a CSV line (objspace.csv quotes none).
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out(1);
  for (char ch : line) {
    if (ch == ',') {
      out.emplace_back();
    } else {
      out.back() += ch;
    }
  }
  return out;
}

TEST(StudyObjspace, WritesTableMarkdownAndPlots) {
  const TempDir dir("objspace_study");
  std::ostringstream log;
  ObjspaceStudyOptions o = small();
  o.cube = false;
  o.tilts = {0, 45};
  ASSERT_EQ(run_study_objspace(dir.file("out"), log, o), 0);
  for (const char* f : {"objspace.csv", "objspace.md", "objspace_tilt.png",
                        "objspace_resolution.png", "objspace_count.png"})
    EXPECT_TRUE(std::filesystem::exists(dir.file(std::string("out/") + f))) << f;
  // The derived columns of objspace.csv against the columns they derive from.
  std::ifstream in(dir.file("out/objspace.csv"));
  std::string line;
  std::getline(in, line);
  std::map<std::string, size_t> col;
  const std::vector<std::string> head = cells(line);
  for (size_t i = 0; i < head.size(); ++i) col[head[i]] = i;
  for (const char* c : {"pixels", "cycles", "cycles per pixel", "ops", "add", "mem"})
    ASSERT_TRUE(col.count(c)) << c;
  int rows = 0;
  while (std::getline(in, line)) {
    const std::vector<std::string> c = cells(line);
    ASSERT_EQ(c.size(), head.size()) << line;
    const double pixels = std::stod(c[col["pixels"]]), cycles = std::stod(c[col["cycles"]]);
    const double cpp = std::stod(c[col["cycles per pixel"]]);  // 3 significant digits
    EXPECT_NEAR(cpp, cycles / std::max(pixels, 1.0), 5e-3 * cpp) << line;
    uint64_t ops = 0;
    for (const char* k : {"add", "mul", "div", "rcp", "sqrt", "lut", "cmp", "mem"})
      ops += std::stoull(c[col[k]]);
    EXPECT_EQ(std::stoull(c[col["ops"]]), ops) << line;
    ++rows;
  }
  EXPECT_GT(rows, 0);
}

}  // namespace
}  // namespace texsim
