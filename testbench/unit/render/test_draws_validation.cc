// Validation against the game's own frames (issue: real workloads, item 5): every frame of the
// shipped OpenArena draw trace rendered by texsim (draw renderer, texture unit, colour stage)
// against glretrace's image of the same frame of the same capture (Mesa llvmpipe), shipped
// beside it (traces/samples/README.md).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "pipeline/render/draw_renderer.h"
#include "pipeline/render/frame_compare.h"
#include "testbench/lib/error_of.h"
#include "traces/draw_trace.h"

namespace texsim {
namespace {

const std::string kSamples = std::string(TEXSIM_SOURCE_DIR) + "/traces/samples/";

TEST(DrawsValidation, EveryShippedFrameMatchesTheGamesImage) {
  const DrawTrace trace = read_draw_trace(kSamples + "openarena-aggressor.draws");
  ASSERT_EQ(trace.frames.size(), 3u);
  std::vector<size_t> all;
  for (size_t i = 0; i < trace.frames.size(); ++i) all.push_back(i);
  static const toml::table kNone;
  // Timed, as `texsim run --draws` runs it: the frames in order through one unit.
  DrawRenderer r(trace, all, PipelineSetup::from_toml(kNone, "test"), TechTable::defaults(), true,
                 "openarena-aggressor.draws");
  for (size_t i = 0; i < trace.frames.size(); ++i) {
    const RenderedFrame f = r.render(i);
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04u.png", f.number);
    const std::string ref_path = kSamples + "openarena-aggressor/" + name;
    const FrameComparison c = compare_frame(f, read_rgb8_image(ref_path), ref_path);
    const auto u = [](uint64_t v) { return static_cast<unsigned long long>(v); };
    std::printf(
        "frame %u: pixels drawn agree on %.4f %% (texsim only %llu, reference only %llu), "
        "PSNR %.2f dB over %llu pixels (%llu equal), mean |d| %.3f, max |d| %llu (8-bit), %llu "
        "off by more than 8\n",
        f.number, c.drawn_agreement_pct, u(c.drawn_texsim_only), u(c.drawn_reference_only),
        c.psnr_db, u(c.drawn_both), u(c.equal), c.mean_abs, u(c.max_abs), u(c.off_by_more_than_8));
    // The targets: the set of pixels drawn equal on >= 99.9 %, PSNR >= 30 dB over them.
    EXPECT_GE(c.drawn_agreement_pct, 99.9) << name;
    EXPECT_GE(c.psnr_db, 30.0) << name;
    // Regression guards below what is measured (100 %, 49.5 dB on each frame; docs/validation
    // in docs/architecture.md, "Draw traces"): a filtering or rasterisation change that moves
    // the image away from Mesa's shows here first.
    EXPECT_EQ(c.drawn_texsim_only + c.drawn_reference_only, 0u) << name;
    EXPECT_GE(c.psnr_db, 47.0) << name;
    EXPECT_LE(c.max_abs, 24u) << name;
    // The frame is a real workload for the unit: most of the window, two textures per pixel.
    EXPECT_GT(c.drawn_both, 150000u) << name;
    EXPECT_GT(f.counts.lookups, f.counts.written) << name;
  }
  EXPECT_GT(r.units().cycles(), r.units().fragments());  // timed: cycles and cache figures
  EXPECT_GT(r.units().l1_totals().misses, 0u);
}

// The reference image of --compare is opened like every input: a FIFO or a directory is a
// clear error at once, never a hang.
TEST(DrawsValidation, AReferenceImageThatIsNotARegularFileIsRefused) {
  const auto dir = std::filesystem::temp_directory_path() / "texsim_compare_inputs";
  std::filesystem::create_directories(dir);
  const std::string fifo = (dir / "ref.png").string();
  std::filesystem::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string e = error_of([&] { read_rgb8_image(fifo); });
  EXPECT_NE(e.find("FIFO"), std::string::npos) << e;
  EXPECT_NE(error_of([&] { read_rgb8_image(dir.string()); }).find("directory"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace texsim
