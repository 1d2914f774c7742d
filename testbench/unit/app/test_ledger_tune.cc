// The error ledger and the error-budget tuner on a small scene: the ledger reports one entry
// per block the materials have (and nothing without --ledger); the tuner's choice meets the
// budget and no cheaper evaluated point does.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "pipeline/app/run.h"
#include "pipeline/app/tuner.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

// Two strips of a tilted checkerboard: one with a fixed-point coordinate unit, one classic.
const char* kScene = R"([output]
width = 64
height = 48
[camera]
position = [0.0, 3.0, 0.0]
look_at = [0.0, 0.0, -9.0]
fov_y = 60.0
[textures.checker]
source = "procedural:checker?size=64&cells=8"
[materials.coords]
texture = "checker"
filter = { mode = "trilinear" }
lod = { aniso = "vulkan", max_aniso = 4 }
coords = { method = "incremental", derivs = "iterative", format = "s16.16" }
[materials.plain]
texture = "checker"
filter = { mode = "trilinear" }
[[planes]]
material = "coords"
origin = [-2.5, 0.0, -0.5]
edge_u = [2.5, 0.0, 0.0]
edge_v = [0.0, 0.0, -40.0]
uv_scale = [1.0, 16.0]
[[planes]]
material = "plain"
origin = [0.0, 0.0, -0.5]
edge_u = [2.5, 0.0, 0.0]
edge_v = [0.0, 0.0, -40.0]
uv_scale = [1.0, 16.0]
)";

nlohmann::json report(const std::string& dir) {
  std::ifstream in(dir + "/report.json");
  return nlohmann::json::parse(in);
}

TEST(ErrorLedger, OneEntryPerBlockOnlyWithTheFlag) {
  TempDir d("ledger");
  std::ofstream(d.file("s.toml")) << kScene;
  RunOptions opt;
  opt.scene = d.file("s.toml");
  opt.out = d.file("plain");
  std::ostringstream log;
  run_simulation(opt, log);
  EXPECT_FALSE(report(opt.out).contains("ledger"));
  opt.out = d.file("ledger");
  opt.ledger = opt.ledger_maps = true;
  run_simulation(opt, log);
  const nlohmann::json j = report(opt.out);
  ASSERT_TRUE(j.contains("ledger")) << log.str();
  for (const char* b : {"coords", "derivs", "lod", "subtexel", "texels"})
    EXPECT_TRUE(j["ledger"].contains(b)) << b;
  EXPECT_FALSE(j["ledger"].contains("vd"));
  EXPECT_EQ(j["ledger"]["coords"]["materials"], nlohmann::json({"coords"}));
  // s16.16 coordinates are this scene's largest error: exact ones gain accuracy.
  EXPECT_GT(j["ledger"]["coords"]["alone"]["dpsnr_db"].get<double>(), 0.0);
  EXPECT_GT(j["ledger"]["coords"]["alone"]["pixels_changed"].get<uint64_t>(), 0u);
  EXPECT_GE(j["ledger_setup"]["all_exact"]["psnr_db"].get<double>(),
            j["ledger_setup"]["hardware"]["psnr_db"].get<double>());
  EXPECT_TRUE(std::ifstream(opt.out + "/ledger_coords.png").good());
  std::ifstream md(opt.out + "/report.md");
  const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("## Error ledger"), std::string::npos);
}

TEST(Tuner, ChoiceMeetsTheBudgetAndNoCheaperPointDoes) {
  TempDir d("tune");
  std::ofstream(d.file("s.toml")) << kScene;
  TuneOptions opt;
  opt.scene = d.file("s.toml");
  opt.out = d.file("out");
  opt.budget = "psnr=24";
  opt.ledger = false;
  std::ostringstream log;
  const TuneResult r = run_tune(opt, log);
  ASSERT_EQ(r.materials.size(), 2u);
  for (const TuneMaterial& m : r.materials) {
    SCOPED_TRACE(m.name);
    ASSERT_GT(m.points.size(), 5u);
    const TunePoint& c = m.points[static_cast<size_t>(m.chosen)];
    ASSERT_TRUE(m.budget_met) << log.str();
    EXPECT_GE(c.psnr_db, 24.0);
    for (const TunePoint& p : m.points) {
      if (p.meets) {
        EXPECT_GE(p.cycles, c.cycles) << p.label;
      }
    }
    EXPECT_TRUE(c.pareto || std::any_of(m.points.begin(), m.points.end(), [&](const TunePoint& p) {
                  return p.pareto && p.cycles == c.cycles && p.nmse == c.nmse;
                }));
  }
  for (const char* f : {"tuned.toml", "points.csv", "pareto.csv", "pareto.png", "tune.md"})
    EXPECT_TRUE(std::ifstream(opt.out + "/" + f).good()) << f;
  // The written scene runs and gives the tuned figures.
  RunOptions again;
  again.scene = opt.out + "/tuned.toml";
  again.out = d.file("again");
  EXPECT_EQ(static_cast<double>(run_simulation(again, log).cycles), r.tuned_cycles);
}

TEST(Tuner, RejectsBadBudgets) {
  TuneOptions opt;
  opt.scene = "x.toml";
  std::ostringstream log;
  for (const char* b : {"psnr", "psnr=", "ssim=3", "nmse=-1", "psnr=40dB"}) {
    opt.budget = b;
    EXPECT_ANY_THROW(run_tune(opt, log)) << b;
  }
}

}  // namespace
}  // namespace texsim
