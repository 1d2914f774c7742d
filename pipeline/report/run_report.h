#pragma once
// report.json and report.md of a `texsim run` (docs/reports.md lists every key).
#include <string>
#include <vector>

#include "pipeline/report/image_metrics.h"
#include "pipeline/report/provenance.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {

struct RunInfo {
  std::string scene;      // scene file or "<built-in default scene>"
  std::string trace;      // trace file, or "" when fragments came from the scene
  std::string reference;  // how the ground truth was made
  int width = 0, height = 0;
  std::vector<std::string> textures;
  std::vector<AccuracyMetrics> material_accuracy;  // per material of the texture unit
  Provenance provenance;
};

// Writes DIR/report.json and DIR/report.md (atomically).
void write_run_reports(const std::string& dir, const RunInfo& info, const TextureUnit& unit,
                       const AccuracyMetrics& acc);

}  // namespace texsim
