// study objspace on a reduced set of scenes: every method runs on every case, object space
// leaves no holes, and its figures keep the relations the study's claims rest on.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "pipeline/studies/study_objspace.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

ObjspaceStudyOptions small() {
  ObjspaceStudyOptions o;
  o.widths = {96};
  o.tilts = {0, 60, 85};
  o.tilt_size = 96;
  o.grid_cells = {1, 4};
  o.areas = {1, 2};
  o.steps = {3.0};
  o.mesh = false;
  o.scenes_dir = std::string(TEXSIM_SOURCE_DIR) + "/scenes";
  o.reference_supersamples = 2;
  o.images = false;
  return o;
}

TEST(StudyObjspace, EveryMethodOnEveryCaseWithoutHoles) {
  std::ostringstream log;
  const std::vector<ObjspaceRow> rows = measure_objspace_study(small(), "", log);
  // floor + cube, 3 tilts, 2 counts, 2 areas, 1 density; five methods each.
  ASSERT_EQ(rows.size(), (2u + 3u + 2u + 2u + 1u) * 5u);
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
}

}  // namespace
}  // namespace texsim
