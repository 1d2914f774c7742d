#pragma once
// `texsim run` and `texsim trace gen`: drive the texture unit with a scene or a trace and
// write the report, images and accuracy.
#include <iosfwd>
#include <string>

#include "pipeline/report/image_metrics.h"

namespace texsim {

struct RunOptions {
  std::string scene;        // scene file; "" = built-in default scene (or none with a trace)
  std::string trace;        // trace file; "" = fragments from the scene's reference generator
  std::string out = "out";  // output directory
  bool functional = false;  // colours and op counts only: no cache, no clock
  bool progress = false;    // progress line on stderr
  std::string command;      // the command line, for the report's provenance
};

struct RunSummary {
  uint64_t fragments = 0;
  uint64_t cycles = 0;
  AccuracyMetrics accuracy;
};

// Throws InputError on bad input; writes nothing unless the whole run succeeded.
RunSummary run_simulation(const RunOptions& opt, std::ostream& log);

// Writes the scene's reference fragments (exact double coordinates and derivatives) as a trace.
uint64_t generate_scene_trace(const std::string& scene_path, const std::string& out_path);

}  // namespace texsim
