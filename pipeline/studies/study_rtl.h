#pragma once
// `texsim study rtl`: what each RTL block costs on an FPGA (docs/rtl/study.md). Every Verilog
// file of a folder (default rtl_model/rtl) is synthesised with yosys (generic cells, and LUT4 /
// flip-flops / carries / SB_MAC16 for the iCE40 UP5K), at each value of the swept parameters,
// with the shared helpers (texsim_*.v, not blocks themselves) read alongside,
// and placed and routed with nextpnr-ice40 at several seeds (median, min and max Fmax). Writes
// rtl.csv, rtl.md and rtl.png; missing tools or no Verilog files: says so and writes nothing.
#include <functional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace texsim {

struct StudyRtlOptions {
  std::string rtl_dir = "rtl_model/rtl";
  // NAME -> values: each block that declares parameter NAME is built at every value.
  std::vector<std::pair<std::string, std::vector<int>>> params;
  int seeds = 5;  // placer seeds 1..seeds
  // The blocks' op counters (texsim_op_counters: five 64-bit accumulators that check the RTL
  // against the C++ OpCounts) are a verification aid: by default a stub with zero outputs
  // replaces them, so the table measures the datapath. true: synthesise them too.
  bool with_counters = false;
  std::vector<std::string> blocks;  // only these modules; empty: every block of the folder
  // Also build the earlier form of each block that has one (ref/<block>_comb.v beside it, the
  // form a retimed block replaced) at the same parameters, as a row named <block>_comb.
  bool with_earlier = false;
  // The generic cell count (yosys `synth`); false: "-" in that column, half the sampler's time.
  bool generic_cells = true;
  // The sampler's (texsim_sampler) error column at sub-texel bits S and mipmap bits M: the C++
  // FixedSampler, bit-exact with the RTL, on a shipped scene against its ground truth (set by
  // the application, which runs scenes; unset: no error figure).
  std::function<std::string(int sub_bits, int mip_bits)> sampler_error;
};

// Parses "NAME=v1,v2,..." (the --param option); throws InputError.
std::pair<std::string, std::vector<int>> parse_rtl_param(const std::string& text);

// Median of a non-empty list.
double median_of(std::vector<double> v);

int run_study_rtl(const std::string& out_dir, const StudyRtlOptions& opt, std::ostream& log);

}  // namespace texsim
