#pragma once
// `texsim sweep` and `texsim merge`: a grid of runs (scenes or traces × scene-key overrides)
// expanded into numbered jobs, run on a local pool, one shard of them (for GNU parallel), one
// job (for a Slurm array task), or written as a Slurm job-array script; and the merge of the
// jobs' report.json files into one table (docs/sweeps.md).
#include <iosfwd>
#include <string>
#include <vector>

namespace texsim {

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
// file:line:column.
Sweep load_sweep(const std::string& path);

struct SweepOptions {
  std::string out;  // "" = the sweep's
  int jobs = 0;     // local pool size; 0 = one per hardware thread
  int shard = 0;    // 1-based shard of `shards`; 0 = all jobs
  int shards = 0;
  int job = -1;         // run this job only
  bool slurm = false;   // write OUT/sweep.sbatch instead of running
  bool list = false;    // print the jobs
  std::string command;  // how to call texsim again (argv[0]), for the Slurm script
};

// Runs (or lists, or scripts) the sweep; returns the exit status (2 if any job failed).
int run_sweep(const std::string& sweep_path, const SweepOptions& opt, std::ostream& log);

// Reads DIR/job-*/job.json and report.json under each directory and writes OUT/merged.csv and
// OUT/merged.md, one row per job; returns the rows written.
int merge_sweeps(const std::vector<std::string>& dirs, const std::string& out, std::ostream& log);

}  // namespace texsim
