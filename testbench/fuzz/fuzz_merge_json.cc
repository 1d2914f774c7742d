// libFuzzer harness: a job.json and a report.json through `texsim merge`: the checked reader
// (size, nesting depth), the type checks, merged.csv and merged.md, and the SQLite ledger, in
// a scratch directory (the plot is left out: it runs gnuplot). The input is job.json, a NUL
// byte, then report.json; without a NUL it is the report.json of a fixed valid job. Bad input
// must end in InputError.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "pipeline/app/sweep.h"
#include "testbench/fuzz/fuzz_input.h"

namespace {

namespace fs = std::filesystem;

const char* kJob = R"({"job": 0, "scene": "default", "trace": "", "overrides": ["a=1"]})";

void merge_pair(const std::string& input) {
  static const fs::path dir =
      (fs::is_directory("/dev/shm") ? fs::path("/dev/shm") : fs::path("/tmp")) /
      ("texsim-fuzz-merge-" + std::to_string(static_cast<long>(::getpid())));
  const size_t nul = input.find('\0');
  const std::string job = nul == std::string::npos ? kJob : input.substr(0, nul);
  const std::string report = nul == std::string::npos ? input : input.substr(nul + 1);
  fs::create_directories(dir / "in/job-00000");
  std::ofstream(dir / "in/job-00000/job.json", std::ios::binary) << job;
  std::ofstream(dir / "in/job-00000/report.json", std::ios::binary) << report;
  fs::remove(dir / "out/ledger.sqlite");  // each input alone in the ledger
  std::ostringstream log;
  (void)texsim::merge_sweeps({(dir / "in").string()}, (dir / "out").string(), log, false);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  texsim::fuzz::expect_clean([&] { merge_pair(input); });
  return 0;
}
