#pragma once
// `texsim study terrain`: the finite-function terrain evaluator (seed 003 §2.3–2.4;
// docs/derivations/terrain.md) per base function and deformation — the evaluator's costs (the
// 3-multiplication form against the 8-multiplication one: operators, path latency, area), the
// derivative continuity (slope jumps at the nodes), the partition-of-unity ripple on flat
// terrain and the terrace measure on a long monotone slope. The measures are the shared ones
// of blocks/geometry/terrain/terrain_measures.h.
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "blocks/base/op_counts.h"
#include "blocks/geometry/terrain/finite_function.h"

namespace texsim {

struct TerrainStudyRow {
  FiniteBasis basis;
  std::string function, deformation;  // names as in the scene keys
  int32_t heights = 0;                // grid heights read per evaluation (4 or 9)
  OpCounts ops3, ops8;                // per evaluation: the factored form, eq. 2.50 (2 × 2 only)
  bool has_8mul = false;
  double latency3 = 0, latency8 = 0;    // cycles along the critical path (default tech table)
  double area3 = 0, area8 = 0;          // adder-equivalents
  double jump_ratio = 0;                // largest slope jump at a node / |Δ²y| (random data)
  double max_jump = 0;                  // largest slope jump at a node (heights in [0, 10])
  double ripple_1d = 0, ripple_2d = 0;  // flat terrain: max |S - 1| (1-D), |y - 1| (2-D)
  double terrace = 0, terrace_dev = 0;  // T and the largest |y - x| on the ramp h_i = i
};

std::vector<TerrainStudyRow> measure_terrain_study();
int run_study_terrain(const std::string& out_dir, std::ostream& log);

}  // namespace texsim
