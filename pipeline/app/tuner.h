#pragma once
// `texsim tune SCENE --budget psnr=40` (docs/tune.md): for each material, the cheapest
// configuration of its existing knobs (coordinate method and format, derivative method,
// filter and its parameters, sub-texel and mipmap bits, V(d) evaluator and format) whose
// accuracy meets the budget. Each point is a `texsim run` of the scene with the material's
// table replaced through a `--set` override (the other materials as configured), so the
// search is the run machinery's and deterministic: fixed knob order, fixed value order.
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace texsim {

struct TuneOptions {
  std::string scene;
  std::string out = "out/tune";
  std::string budget = "psnr=40";      // psnr=<dB> (at least) or nmse=<value> (at most)
  std::string cost = "cycles";         // cycles or area
  std::vector<std::string> overrides;  // --set, applied to the scene first
  int threads = 0;
  bool ledger = true;  // run the chosen scene with the error ledger
  // Runs evaluated at once: a knob's candidate values run as tasks on a pool of `jobs`
  // threads (0: one per core); the points, their order and the choice do not depend on it.
  int jobs = 1;
  // Shard `shard` of `shards` (1-based; 0: all): only materials i with i % shards ==
  // shard - 1 are searched, and opt.out gets their points (tune_shard.json) for --merge.
  int shard = 0, shards = 0;
  // Also search the filter family: after the descent from the material as configured, one
  // descent from each other family (classic LOD + filter path, ewa, spaf, feline,
  // multi_probe, each footprint filter with its defaults); the choice is the best of all.
  bool families = false;
  // Candidates share one ground truth through the truth cache (--no-truth-cache: false).
  bool truth_cache = true;
  // Shard directories to assemble (instead of searching): the outputs of one unsharded run.
  std::vector<std::string> merge;
};

// One evaluated configuration of one material.
struct TunePoint {
  std::string label;     // the knobs changed from the material's own table ("as configured")
  std::string override;  // the --set that selects it
  double cycles = 0, area = 0, psnr_db = 0, nmse = 0;
  bool meets = false;
  bool pareto = false;
};

struct TuneMaterial {
  std::string name;
  std::string budget;             // the budget applied: the material's own, else --budget
  std::vector<TunePoint> points;  // in evaluation order; points[0] is the material as configured
  int chosen = 0;                 // index into points
  bool budget_met = false;        // false: no point met the budget; chosen is the most accurate
};

struct TuneResult {
  std::vector<TuneMaterial> materials;
  double default_cycles = 0, default_area = 0, default_psnr_db = 0;
  double tuned_cycles = 0, tuned_area = 0, tuned_psnr_db = 0;
  int runs = 0;
};

// Sets opt.shard and opt.shards from "K/N"; throws InputError unless 1 <= K <= N.
void parse_tune_shard(const std::string& text, TuneOptions& opt);

// One shard's tune_shard.json (docs/tune.md), as read by --merge.
struct TuneShard {
  std::string scene, budget, cost;
  std::vector<std::string> overrides;
  bool families = false;
  int shard = 0, shards = 0, runs = 0;
  std::vector<size_t> indices;          // each material's index in the scene
  std::vector<TuneMaterial> materials;  // in the file's order
};

// Limits of a tune shard (docs/cli.md#input-limits): its size is kMaxJsonInput.
inline constexpr int kMaxShardDepth = 64;             // nesting of arrays and objects
inline constexpr int64_t kMaxShardRuns = 1000000000;  // `runs`

// Reads and checks one tune_shard.json on its own (the merge then checks it against the scene
// and the other shards): a regular file within kMaxJsonInput, JSON nested at most
// kMaxShardDepth deep, every field of the expected type and range, `chosen` a point of its
// material, each point's override of its material, `meets` and `budget_met` consistent with
// the budget, each material index in this shard and only once. Throws InputError naming the
// file and the field.
TuneShard read_tune_shard(const std::string& path);

// The cost of a point under opt.cost.
double tune_cost(const TuneOptions& opt, const TunePoint& p);

// Searches and writes opt.out: tuned.toml, points.csv, pareto.csv, pareto.png, tune.md and
// (with opt.ledger) tuned/ (the chosen scene's run with its ledger); a shard writes only
// tune_shard.json; with opt.merge, the shards' points are read instead of searched and the
// outputs are those of the unsharded run. Throws InputError.
TuneResult run_tune(const TuneOptions& opt, std::ostream& log);

}  // namespace texsim
