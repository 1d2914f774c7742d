// libFuzzer harness: sweep TOML through everything `texsim sweep` does before a job runs: the
// sweep file's reader, the grid's expansion with its job-count and size limits, the job list
// (--list) and the Slurm script (--slurm, into a scratch directory). Bad input must end in
// InputError.
#include <unistd.h>

#include <cstdint>
#include <sstream>
#include <string>

#include "pipeline/app/sweep.h"
#include "testbench/fuzz/fuzz_input.h"

namespace {

// Sweeps with more jobs are expanded (and checked) but not listed or scripted, so each input
// stays fast.
constexpr size_t kMaxListedJobs = 4096;

void run_sweep_file(const std::string& path) {
  const texsim::Sweep sweep = texsim::load_sweep(path);
  if (sweep.jobs.size() > kMaxListedJobs) return;
  std::ostringstream log;
  texsim::SweepOptions opt;
  opt.list = true;
  (void)texsim::run_sweep(path, opt, log);
  opt.list = false;
  opt.slurm = true;
  opt.out = "/tmp/texsim-fuzz-sweep-" + std::to_string(static_cast<long>(::getpid()));
  opt.command = "/usr/local/bin/texsim";
  (void)texsim::run_sweep(path, opt, log);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = texsim::fuzz::write_input(data, size, ".toml");
  texsim::fuzz::expect_clean([&] { run_sweep_file(path); });
  return 0;
}
