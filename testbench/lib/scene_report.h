#pragma once
// Runs a shipped scene (or a trace with it) in process at a small size and returns its
// report.json: the scene-and-replay tests compare two of these.
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "pipeline/app/run.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {

// scenes/<scene>.toml at 96 × 72, one thread, no truth cache; `trace` "" for the scene's own
// fragments. The outputs go to dir/<out>.
inline nlohmann::json shipped_scene_report(const TempDir& dir, const std::string& scene,
                                           const std::string& trace, const std::string& out) {
  RunOptions opt;
  opt.scene = std::string(TEXSIM_SOURCE_DIR) + "/scenes/" + scene + ".toml";
  opt.trace = trace;
  opt.threads = 1;
  opt.truth_cache = false;
  opt.out = dir.file(out);
  opt.overrides = {"output.width=96", "output.height=72"};
  std::ostringstream log;
  run_simulation(opt, log);
  std::ifstream in(opt.out + "/report.json");
  return nlohmann::json::parse(in);
}

}  // namespace texsim
