// study workloads --quick with a tiny trace beside the built-in scene: the trace's row holds the
// figures worked out by hand, the scene's row its run's, and the outputs are written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "pipeline/app/study_workloads.h"
#include "pipeline/report/workload_report.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

TEST(StudyWorkloads, QuickWithATrace) {
  TempDir dir("study_workloads");
  // Four fragments of an 8x8 texture: frame 0 at λ = 0, 0 and -1 (pixels (0,0), (1,0): one quad;
  // (2,0): another), frame 1 at λ = 2 with η = 4.
  std::ofstream(dir.file("t.csv"))
      << "# texture 0 checker \"procedural:checker?size=8&cells=2\" 8 8\n"
         "frame,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy\n"
         "0,0,0,0,0,0.125,0.125,0.125,0,0,0.125\n"
         "0,0,1,0,0,0.375,0.125,0.125,0,0,0.125\n"
         "0,0,2,0,0,0.875,0.125,0.0625,0,0,0.0625\n"
         "1,0,0,0,0,0.25,0.25,0.5,0,0,0.125\n";
  StudyWorkloadsOptions opt;
  opt.quick = true;
  opt.threads = 2;
  opt.traces = {dir.file("t.csv")};
  std::vector<WorkloadStudyRow> rows;
  std::ostringstream log;
  ASSERT_EQ(run_study_workloads(dir.file("out"), log, opt, &rows), 0);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].name, "default");
  EXPECT_EQ(rows[0].frames, 1u);
  EXPECT_EQ(rows[0].total.fragments, rows[0].total.magnified + rows[0].total.minified);
  EXPECT_GT(rows[0].total.fragments, 1000u);  // 160x120, most of it covered
  const WorkloadStudyRow& t = rows[1];
  EXPECT_EQ(t.kind, "trace");
  EXPECT_EQ(t.frames, 2u);
  EXPECT_EQ(t.total.fragments, 4u);
  EXPECT_EQ(t.total.quads, 3u);
  EXPECT_EQ(t.total.magnified, 1u);
  EXPECT_EQ(t.total.lod[8], 2u);
  EXPECT_EQ(t.total.lod[6], 1u);
  EXPECT_EQ(t.total.lod[12], 1u);
  EXPECT_EQ(t.total.aniso[2], 1u);
  // Frame 0 at level 0: texel columns 0-3 and 6-7 of rows 0-1, all in the first 4x4 tiles;
  // frame 1: the 2x2 level's four texels.
  EXPECT_EQ(t.total.texels_lod, 12u + 4u);
  // One 64-byte line is one 4x4 tile: columns 0-1 and 2-3 both in tile 0 (a reuse at distance
  // 0), 6-7 in tile 1; frame 1's level in a tile of its own.
  EXPECT_EQ(t.total.line_uses, 4u);
  EXPECT_EQ(t.total.first_uses, 3u);
  EXPECT_EQ(t.total.reuse[0], 1u);
  EXPECT_DOUBLE_EQ(reuse_within(t.total, 1), 1.0);
  for (const char* f :
       {"workloads.csv", "workloads.md", "workloads_lod.png", "workloads_reuse.png"})
    EXPECT_TRUE(std::filesystem::exists(dir.file("out/") + f)) << f;
  // `texsim trace info`'s lines for the same trace.
  std::ostringstream info;
  print_trace_workload(dir.file("t.csv"), info);
  EXPECT_NE(info.str().find("frame 0: 3 fragments, 2 quads, 1 textures, distinct texels 12 "
                            "(level 0) 12 (λ level), 4 texels/fragment"),
            std::string::npos)
      << info.str();
  EXPECT_NE(info.str().find("frame 1: 1 fragments, 1 quads"), std::string::npos) << info.str();
  std::ifstream csv(dir.file("out/workloads.csv"));
  std::string line;
  int lines = 0;
  while (std::getline(csv, line)) ++lines;
  EXPECT_EQ(lines, 3);
}

// The shipped draw trace's frames: every look-up the renderer sends is characterised.
TEST(StudyWorkloads, RealFramesOfTheSampleDrawTrace) {
  TempDir dir("study_workloads_draws");
  StudyWorkloadsOptions opt;
  opt.quick = true;
  opt.draws = {std::string(TEXSIM_SOURCE_DIR) + "/traces/samples/openarena-aggressor.draws"};
  std::vector<WorkloadStudyRow> rows;
  std::ostringstream log;
  ASSERT_EQ(run_study_workloads(dir.file("out"), log, opt, &rows), 0);
  ASSERT_EQ(rows.size(), 2u);
  const WorkloadStudyRow& r = rows[1];
  EXPECT_EQ(r.kind, "draws");
  EXPECT_EQ(r.frames, 3u);
  EXPECT_GT(r.total.fragments, 100000u);
  EXPECT_EQ(r.total.magnified + r.total.minified, r.total.fragments);
  EXPECT_GT(r.total.magnified, 0u);
  EXPECT_GT(r.total.textures, 3u);
  EXPECT_LE(r.total.texels_lod, 4 * r.total.fragments);
}

}  // namespace
}  // namespace texsim
