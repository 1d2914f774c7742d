#pragma once
// `texsim run` and `texsim trace gen`: drive the texture unit with a scene or a trace and
// write the report, images and accuracy.
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "pipeline/report/image_metrics.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {

// What a run hands back to a caller that compares runs (the error ledger, the tuner).
struct RunCapture {
  bool write_outputs = false;                  // false: the run writes no files
  std::unique_ptr<ImageRgb> image, reference;  // the imaged frame
  AccuracyMetrics total;
  std::vector<AccuracyMetrics> materials;  // per material of the unit
  std::vector<std::string> material_names;
  uint64_t cycles = 0;
  double area = 0;               // sum of the unit's blocks' areas
  std::vector<BlockUse> blocks;  // the unit's blocks
  // The rasterisers' own coordinate blocks (rect_scan's constant-depth rows), one per material
  // that has one, with their operations over the run (not in `area`: outside the unit).
  std::vector<BlockUse> raster_blocks;
  // Set by the caller: several units hold each waiting fragment whole (UnitArray's
  // `whole_fragments`), to compare with the usual way.
  bool whole_fragments = false;
  // --board: the fragments the board sampled and the STREAM messages that carried them.
  uint64_t board_fragments = 0, board_streams = 0, board_lerps = 0;
};

struct RunOptions {
  std::string scene;        // scene file; "" = built-in default scene (or none with a trace)
  std::string trace;        // trace file; "" = fragments from the scene's reference generator
  std::string out = "out";  // output directory
  bool functional = false;  // colours and op counts only: no cache, no clock
  bool progress = false;    // progress line on stderr
  std::vector<std::string> overrides;  // --set KEY=VALUE, applied to the scene
  std::string command;                 // the command line, for the report's provenance
  int threads = 0;                     // threads for the ground truth; 0: one per hardware thread
  std::string reference = "scene";     // --reference: "scene" ([reference]) or "none" (no truth)
  double error_scale = 0;  // error.png: the error drawn white; 0: the imaged frame's largest
  int64_t frame = -1;      // the frame whose images are written; -1: the first frame
  uint64_t max_memory = uint64_t{4} << 30;  // refuse runs estimated to need more (bytes)
  std::string timeline;                     // VCD of the pipeline's stage activity; "" = none
  uint64_t timeline_limit = 10000;          // fragments recorded in the timeline (the first ones)
  bool ledger = false;                      // per-block error ledger in the report (docs/ledger.md)
  bool ledger_maps = false;                 // with the ledger: one error map per block
  RunCapture* capture = nullptr;            // set: filled with the run's images and figures
  // The report's workload characterisation (--no-workload: off).
  bool workload = true;
  // Ground truths from and into the truth cache (docs/truth-cache.md; --no-truth-cache: off).
  bool truth_cache = true;
  // A scene's TOML text instead of a file (the Python module's texsim.run): `scene` is then its
  // name in messages and relative paths in it are relative to the working directory.
  std::string scene_text;
  // --board virtual|hid: the fixed-arithmetic materials' fragments sampled by the RTL sampler
  // on a board (board_sampler.h); "": in process.
  std::string board;
};

struct RunSummary {
  uint64_t fragments = 0;
  uint64_t cycles = 0;
  AccuracyMetrics accuracy;
};

struct Scene;

// The run's scene: opt.scene_text, the file opt.scene or the built-in default, with overrides.
Scene load_run_scene(const RunOptions& opt);

// Throws InputError on bad input; writes nothing unless the whole run succeeded.
RunSummary run_simulation(const RunOptions& opt, std::ostream& log);

// Writes the scene's reference fragments (exact double coordinates and derivatives) as a trace.
uint64_t generate_scene_trace(const std::string& scene_path, const std::string& out_path,
                              const std::vector<std::string>& overrides = {});

}  // namespace texsim
