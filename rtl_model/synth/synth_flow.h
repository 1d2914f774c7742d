#pragma once
// The FPGA flow of `texsim study rtl` (docs/rtl/study.md): yosys generic synthesis (cell count),
// yosys synth_ice40 for the iCE40 UP5K (LUT4, flip-flops, carries, SB_MAC16 DSPs) and
// nextpnr-ice40 place and route with several placer seeds (Fmax per seed). Place and route
// wraps the block in shift registers so that any number of ports fits the package's pins and
// every path starts and ends at a flip-flop; the resource counts are the block's alone.
#include <string>
#include <utility>
#include <vector>

namespace texsim::synth {

struct Tools {
  std::string yosys, nextpnr;  // full paths, empty when not on PATH
  // "yosys and nextpnr-ice40 not found" or "" when both are there.
  std::string missing() const;
};
Tools find_tools();

struct SynthJob {
  std::string file;                                 // Verilog/SystemVerilog source
  std::string top;                                  // module name
  std::vector<std::pair<std::string, int>> params;  // parameter overrides
  std::string work_dir;                             // scripts, netlists and logs go here
  std::vector<int> seeds = {1, 2, 3, 4, 5};
};

struct SynthResult {
  std::string error;      // empty on success; else what failed and which log says why
  int generic_cells = 0;  // yosys `synth` cells
  int multipliers = 0;    // $mul cells before technology mapping
  int lut4 = 0, dff = 0, carry = 0, mac16 = 0, ram = 0;
  std::vector<double> fmax_mhz;  // one per seed that routed (the slowest clock of each)
  std::string pnr_error;         // place and route failed for some seed: why
};

// Runs the flow (yosys needed; without nextpnr, fmax_mhz stays empty).
SynthResult run_synth(const SynthJob& job, const Tools& tools);

}  // namespace texsim::synth
