#pragma once
// `texsim study workloads`: the workload characterisation (docs/reports.md "workload") of the
// shipped scenes and of fragment traces side by side: fragments, texels and lines per frame,
// LOD and anisotropy, magnification, reuse distance (docs/studies/study-workloads.md).
#include <array>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "pipeline/report/workload_stats.h"

namespace texsim {

struct StudyWorkloadsOptions {
  // Scene files ("default": the built-in scene); empty: the built-in scene and the shipped
  // scenes of kWorkloadScenes (--quick: the built-in scene at 160x120 only).
  std::vector<std::string> scenes;
  std::vector<std::string> traces;  // fragment traces, characterised as given
  // Draw traces (real frames, traces/DRAWS.md): every frame rendered, its texture look-ups
  // characterised; empty: the shipped sample (traces/samples/openarena-aggressor.draws) unless
  // --quick.
  std::vector<std::string> draws;
  bool quick = false;
  int threads = 0;  // rows in parallel (0: one per core); the outputs do not depend on it
};

struct WorkloadStudyRow {
  std::string name, source, kind;  // kind: "scene", "trace" or "draws"
  size_t frames = 0;
  FrameWorkload total;  // distinct counts summed over frames
  double per_frame(double v) const { return frames ? v / static_cast<double>(frames) : 0; }
};

// Runs every row (scenes through `texsim run`, functional, no ground truth, tiled4x4; traces
// read directly; draw traces rendered functionally at tiled4x4 addresses), writes workloads.csv,
// workloads.md, workloads_lod.png and workloads_reuse.png into out_dir; returns 0. With `rows` set,
// the rows are copied there.
int run_study_workloads(const std::string& out_dir, std::ostream& log,
                        const StudyWorkloadsOptions& opt,
                        std::vector<WorkloadStudyRow>* rows = nullptr);

}  // namespace texsim
