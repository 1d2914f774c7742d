#pragma once
// Sequential equivalence of two forms of an RTL block with yosys (docs/rtl/blocks.md,
// "Equivalence of retimed blocks"): a retimed block (gate) against the earlier form it
// replaces (gold), with the same parameters and the same latency. Each side is wrapped so that
// its data output reads 0 while out_valid is low (data registers of the retimed forms have no
// reset, so only valid results are comparable); yosys' `miter -equiv` joins the two wrappers
// and `sat -tempinduct` proves the miter's trigger never rises from the all-zero state: the
// base case from reset, the induction step from any state once the pipelines have been
// refilled (a few steps beyond the latency).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace texsim::synth {

struct EquivPort {
  std::string name;
  int width = 1;
};

struct EquivJob {
  std::vector<std::string> files;                       // sources of both modules and their helpers
  std::string gold, gate;                               // module names
  std::vector<std::pair<std::string, int64_t>> params;  // the same for both modules
  // Extra yosys commands run after reading the sources (e.g. chparam of a helper).
  std::vector<std::string> setup;
  std::vector<EquivPort> inputs;  // data inputs, besides clk, rst and in_valid
  EquivPort output;               // the data output, compared while out_valid is high
  int max_steps = 16;             // induction length limit: at least the latency + 1
  std::string work_dir;           // wrapper, script and yosys log go here
};

struct EquivResult {
  bool proved = false;   // induction succeeded: equal in every cycle from reset on
  bool refuted = false;  // a counterexample: a cycle where the valid outputs differ
  std::string error;     // neither (yosys failed, or no result within max_steps), or a bad job
  std::string log;       // the yosys log file
};

// Runs yosys (full path) on the job; the log names the counterexample's inputs when refuted.
EquivResult check_equivalence(const EquivJob& job, const std::string& yosys);

}  // namespace texsim::synth
