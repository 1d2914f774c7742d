// study frames on two frames of the shipped OpenArena sample, without the ground truth (the
// truth has its own tests in test_draw_renderer): a row holds what a fresh render of its frame
// gives (each frame is a task of its own, caches cold), the game's images beside the trace are
// found and compared, and the outputs are written.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "pipeline/app/study_frames.h"
#include "testbench/lib/temp_dir.h"
#include "traces/draw_trace.h"

namespace texsim {
namespace {

const std::string kDraws =
    std::string(TEXSIM_SOURCE_DIR) + "/traces/samples/openarena-aggressor.draws";

TEST(StudyFrames, RowsAreTheirFramesRenderedAlone) {
  TempDir dir("study_frames");
  StudyFramesOptions opt;
  opt.draws = kDraws;
  opt.frames = "111-112";
  opt.truth = false;
  opt.threads = 2;
  std::vector<FrameStudyRow> rows;
  std::ostringstream log;
  ASSERT_EQ(run_study_frames(dir.file("out"), log, opt, &rows), 0);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].frame, 111u);
  EXPECT_EQ(rows[1].frame, 112u);

  const DrawTrace trace = read_draw_trace(kDraws);
  static const toml::table kNone;
  DrawRenderer alone(trace, {2}, PipelineSetup::from_toml(kNone, "test"), TechTable::defaults(),
                     true, kDraws);
  const RenderedFrame f = alone.render(2);
  ASSERT_EQ(f.number, 112u);
  EXPECT_EQ(rows[1].lookups, alone.units().fragments());
  EXPECT_EQ(rows[1].cycles, alone.units().cycles());
  EXPECT_EQ(rows[1].l1_hits, alone.units().l1_totals().hits);
  EXPECT_EQ(rows[1].counts.written, f.counts.written);
  EXPECT_EQ(rows[1].accuracy.lookups, 0u);  // no truth asked for
  for (const FrameStudyRow& r : rows) {
    EXPECT_TRUE(r.has_image) << r.frame;  // traces/samples/openarena-aggressor/frame_NNNN.png
    EXPECT_DOUBLE_EQ(r.image.drawn_agreement_pct, 100.0);
    EXPECT_GT(r.image.psnr_db, 45);
  }
  for (const char* out : {"frames.csv", "frames.md", "frames_psnr.png", "frames_cycles.png"})
    EXPECT_TRUE(std::filesystem::is_regular_file(dir.file(std::string("out/") + out))) << out;
}

TEST(StudyFrames, AFrameRangeOutsideTheTraceIsAnError) {
  TempDir dir("study_frames_bad");
  StudyFramesOptions opt;
  opt.draws = kDraws;
  opt.frames = "5-9";
  std::ostringstream log;
  EXPECT_THROW(run_study_frames(dir.file("out"), log, opt), InputError);
  opt.frames = "";
  opt.images = dir.file("no-such-folder");
  EXPECT_THROW(run_study_frames(dir.file("out"), log, opt), InputError);
}

}  // namespace
}  // namespace texsim
