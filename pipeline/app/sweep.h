#pragma once
// `texsim sweep` and `texsim merge`: a grid of runs (scenes or traces × scene-key overrides)
// expanded into numbered jobs, run on a local pool, one shard of them (for GNU parallel), one
// job (for a Slurm array task), or written as a Slurm job-array script; and the merge of the
// jobs' report.json files into one table (docs/sweeps.md).
#include <cstddef>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

namespace texsim {

// Limits (docs/cli.md#input-limits): jobs in one sweep (their directories are numbered with
// five digits), the text of all jobs' inputs and overrides together, and how deeply merge
// lets a report.json or job.json nest.
inline constexpr size_t kMaxSweepJobs = 100000;
inline constexpr size_t kMaxSweepJobText = size_t{256} << 20;
inline constexpr int kMaxMergeJsonDepth = 64;

struct SweepJob {
  int id = 0;
  std::string scene;                   // scene file or "default" ("" with a trace alone)
  std::string trace;                   // trace file or ""
  std::vector<std::string> overrides;  // KEY=VALUE, one per grid axis
};

struct Sweep {
  std::string path;  // the sweep file
  std::string out;   // default output directory ([sweep] out, relative to the sweep file)
  std::vector<SweepJob> jobs;
};

// Reads SWEEP.toml: [sweep] scenes = [...], traces = [...] (optional), out = "..." and
// [grid] "KEY" = [values...]. Jobs are inputs × the grid's cartesian product, the last grid
// key varying fastest (keys in name order, as TOML tables keep them). Throws InputError with
// file:line:column. The file is read through read_input_file (a regular file of at most
// kMaxTextInput bytes); a grid of more than kMaxSweepJobs jobs is refused before any is made.
Sweep load_sweep(const std::string& path);

// `--shard K/N`: two whole numbers, 1 <= K <= N, nothing else; InputError otherwise.
void parse_sweep_shard(std::string_view text, int& shard, int& shards);
// `--job J`: a whole number from 0; InputError otherwise.
int parse_sweep_job(std::string_view text);

struct SweepOptions {
  std::string out;  // "" = the sweep's
  int jobs = 0;     // local pool size; 0 = one per hardware thread
  int shard = 0;    // 1-based shard of `shards`; 0 = all jobs
  int shards = 0;
  int job = -1;             // run this job only
  bool slurm = false;       // write OUT/sweep.sbatch instead of running
  bool list = false;        // print the jobs
  std::string command;      // how to call texsim again (argv[0]), for the Slurm script
  bool truth_cache = true;  // --no-truth-cache: false
};

// Runs (or lists, or scripts) the sweep; returns the exit status (2 if any job failed).
int run_sweep(const std::string& sweep_path, const SweepOptions& opt, std::ostream& log);

// Reads DIR/job-*/job.json and report.json under each directory and writes OUT/merged.csv,
// OUT/merged.md, OUT/merged.png (unless `plot` is false) and adds the jobs to
// OUT/ledger.sqlite; returns the rows written. Each JSON file is checked before use: a regular
// file of at most kMaxJsonInput bytes, nested at most kMaxMergeJsonDepth levels, the fields
// merge reads of the types it expects; the same directory given twice is refused.
int merge_sweeps(const std::vector<std::string>& dirs, const std::string& out, std::ostream& log,
                 bool plot = true);

}  // namespace texsim
