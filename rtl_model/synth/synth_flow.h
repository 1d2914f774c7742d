#pragma once
// The FPGA flow of `texsim study rtl` (docs/rtl/study.md): yosys generic synthesis (cell count),
// yosys synth_ice40 for the iCE40 UP5K (LUT4, flip-flops, carries, SB_MAC16 DSPs) and
// nextpnr-ice40 place and route with several placer seeds (Fmax per seed). Place and route
// wraps the block in shift registers so that any number of ports fits the package's pins and
// every path starts and ends at a flip-flop; the resource counts are the block's alone.
#include <cstdint>
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

// The build's generated RTL parameter folder (texsim_params.vh; docs/rtl/blocks.md), or "" when
// this build has none (no Verilator).
std::string generated_include_dir();

struct SynthJob {
  std::vector<std::string> files;     // Verilog/SystemVerilog sources: the top's and its helpers
  std::vector<std::string> includes;  // `include search folders (yosys -I)
  std::string top;                    // module name
  std::vector<std::pair<std::string, int64_t>> params;  // overrides; each must fit 32 bits
  std::string work_dir;                                 // scripts, netlists and logs go here
  std::vector<int> seeds = {1, 2, 3, 4, 5};
  // yosys' generic `synth` for the generic cell count; false leaves it out (0 cells): on the
  // sampler it takes as long as the iCE40 synthesis (about 5 min).
  bool generic_cells = true;
};

// iCE40 UP5K (the place-and-route target): logic cells, SB_MAC16 DSPs, 4-kbit block RAMs.
inline constexpr int kUp5kLogicCells = 5280;
inline constexpr int kUp5kDsps = 8;
inline constexpr int kUp5kBrams = 30;

struct SynthResult {
  std::string error;      // empty on success; else what failed and which log says why
  int generic_cells = 0;  // yosys `synth` cells
  // $mul cells before technology mapping (after flatten, opt, wreduce), as "AxB" with an "s"
  // for a signed operand pair, e.g. "18x17s".
  std::vector<std::string> multipliers;
  // $mul cells (or pieces of split ones) yosys left for LUTs after the iCE40 DSP mapping.
  int lut_multipliers = 0;
  int lut4 = 0, dff = 0, carry = 0, mac16 = 0, ram = 0;
  std::vector<double> fmax_mhz;  // one per seed that routed (the slowest clock of each)
  bool pnr_without_dsp = false;  // more SB_MAC16 than the UP5K has: placed with LUT multipliers
  std::string pnr_error;         // place and route skipped or failed for some seed: why
};

// Whether a synthesised block fits the UP5K: "yes", or "no: " and each resource over the
// device's (SB_LUT4 and flip-flops against its 5280 logic cells, SB_MAC16 against 8, block RAM
// against 30), or the logic cells
// nextpnr found over-full; a block over the DSPs that placed with LUT multipliers says so.
std::string up5k_fit(const SynthResult& r);

// Runs the flow (yosys needed; without nextpnr, fmax_mhz stays empty).
SynthResult run_synth(const SynthJob& job, const Tools& tools);

}  // namespace texsim::synth
