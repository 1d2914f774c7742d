#pragma once
// report.json and report.md of a `texsim run` (docs/reports.md lists every key).
#include <string>
#include <vector>

#include "pipeline/report/energy_report.h"
#include "pipeline/report/error_ledger_report.h"
#include "pipeline/report/image_metrics.h"
#include "pipeline/report/object_space_report.h"
#include "pipeline/report/provenance.h"
#include "pipeline/report/subsystems_report.h"
#include "pipeline/report/workload_stats.h"
#include "pipeline/texture/unit_array.h"

namespace texsim {

struct FrameAccuracy {
  uint32_t frame = 0;
  AccuracyMetrics accuracy;
};

// Quads in the texture unit ([pipeline] derivatives, quad_merge); reported when either is on.
struct QuadInfo {
  QuadDerivatives derivatives = QuadDerivatives::Own;
  bool merge = false;
  QuadCounts counts;            // the quads derivatives were taken from (derivatives != fragment)
  uint64_t merged_lookups = 0;  // tag look-ups a quad's earlier lane had made (quad_merge)
  bool active() const { return derivatives != QuadDerivatives::Own || merge; }
};

struct RunInfo {
  // --board: the link, the blocks that ran on the board, and the fragments they sampled.
  std::string board_link;
  std::vector<std::string> board_blocks;
  uint64_t board_fragments = 0;
  uint64_t board_streams = 0;           // STREAM messages that carried them
  uint64_t board_lerps = 0;             // through the board's bilinear_lerp, each checked
  std::string scene;                    // scene file or "<built-in default scene>"
  std::string trace;                    // trace file, or "" when fragments came from the scene
  std::string reference;                // how the ground truth was made
  std::string reference_pixel = "box";  // its pixel model ([reference] pixel)
  bool has_truth = true;  // false with --reference none: no accuracy figures, no error images
  int width = 0, height = 0;
  std::vector<std::string> textures;
  std::vector<AccuracyMetrics> material_accuracy;  // per material of the texture unit
  std::vector<FrameAccuracy> frames;               // each frame against its own ground truth
  uint32_t image_frame = 0;                        // the frame the images show
  double error_scale = 0;                          // error.png: the error drawn white
  bool error_scale_auto = true;                    // scale = the largest error of the imaged frame
  int error_bar_rows = 0;                          // colour bar rows below error.png's image
  SubsystemsInfo subsystems;                       // geometry and rasterisation of a scene run
  ErrorLedger ledger;  // per-block error ledger (texsim run --ledger); empty: not reported
  ObjectSpaceInfo object_space;  // materials drawn object-space; empty: none
  Provenance provenance;
  QuadInfo quads;
  const WorkloadStats* workload = nullptr;  // the fragments' characterisation; null: none
};

// Writes DIR/report.json and DIR/report.md (atomically).
void write_run_reports(const std::string& dir, const RunInfo& info, const UnitArray& unit,
                       const AccuracyMetrics& acc);

}  // namespace texsim
