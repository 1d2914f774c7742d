#pragma once
// `texsim study memory`: the texture memory hierarchy on the shipped scenes, timed, without a
// ground truth. Each row is one run: a scene and a list of `--set` overrides on top of a fixed
// base (one unit, 16 KB 4-way L1 of 64-byte lines, tiled4x4 texels, row raster order, flat
// DRAM). Sweeps: L1 size × ways × line; texel layout × raster order × L1 size; units 1..16 with
// flat DRAM, banked DRAM and a shared L2 over banked DRAM; unit tile; L2 size × slices and
// prefetch; the L1's miss queue (latency hiding); screen resolution × raster order; photo's
// floor isotropic against anisotropic; quad merging. Per row: L1 hit rate, DRAM
// bytes, cycles and energy per fragment, L2 and DRAM row-buffer hit rates, the scheduler's
// late items (docs/studies/study-memory.md).
#include <cstdint>
#include <map>
#include <ostream>
#include <string>
#include <vector>

namespace texsim {

struct StudyMemoryOptions {
  // Scene files ("default": the built-in scene); empty: the built-in scene, photo, flight and
  // bunny (--quick: the built-in scene only).
  std::vector<std::string> scenes;
  bool quick = false;  // a few rows on the built-in scene (a CI check, seconds)
  int threads = 0;     // runs in parallel (0: one per core); the outputs do not depend on it
};

struct MemoryStudyRow {
  // The plan.
  std::string scene;  // short name: "default", "photo", ...
  std::string scene_path;
  std::string sweep;  // "l1", "layout", "units", "unit_tile", "l2", "miss_queue", ...
  std::map<std::string, std::string> set;  // every override of the run (base and row)
  int units = 1;
  uint32_t l1_bytes = 0, l1_ways = 0, l1_line = 0;
  std::string layout, order, behind;  // texel layout, raster order, what is behind the L1s
  std::string other;                  // any other setting the row changes
  // The run's figures (report.json).
  uint64_t fragments = 0, cycles = 0;
  uint64_t l1_accesses = 0, l1_hits = 0, l1_misses = 0;
  double l1_hit_rate = 0;
  uint64_t dram_bytes = 0;
  bool has_l2 = false, banked = false;
  double l2_hit_rate = 0, row_hit_rate = 0;
  double energy_pj = 0;  // per fragment
  uint64_t late_items = 0, forced_commits = 0;
  uint64_t quad_merged = 0;  // tag look-ups saved by quad merging

  std::vector<std::string> overrides() const;  // KEY=VALUE, in key order
  double per_fragment(double v) const { return fragments ? v / static_cast<double>(fragments) : 0; }
};

// The rows to run, in table order (no figures yet).
std::vector<MemoryStudyRow> memory_study_plan(const StudyMemoryOptions& opt);

// Runs every row (on the study pool), writes memory.csv, memory.md and the plots into out_dir;
// returns 0. With `rows` set, the measured rows are copied there.
int run_study_memory(const std::string& out_dir, std::ostream& log, const StudyMemoryOptions& opt,
                     std::vector<MemoryStudyRow>* rows = nullptr);

}  // namespace texsim
