#pragma once
// `texsim cosim`: streams random input vectors through a block on a board (the virtual board in
// process, or a real one over USB HID) and compares every result with the block's C++ core on
// the host (docs/rtl/link.md).
#include <cstdint>
#include <ostream>
#include <string>

namespace CLI {
class App;
}

namespace texsim {

struct CosimOptions {
  std::string block = "vd_p2";
  std::string link = "virtual";  // "virtual" or "hid"
  // What the virtual board runs: "rtl" (the Verilated RTL), "model" (the C++ cores), or ""
  // for rtl when this build has Verilator and model otherwise.
  std::string board;
  uint64_t vectors = 100000;
  uint64_t seed = 1;
  int frac_bits = 16;         // the block's configuration: input fraction bits (16, 12, 8)
  uint16_t vid = 0, pid = 0;  // 0: the defaults of rtl_model/link/hid_transport.h
  int timeout_ms = 250;
};

// Exit status: 0 every result matched, 1 some did not, 2 a usage error (an unknown block,
// --board with --link hid, --board rtl for a format the RTL is not built for), 4 the link
// failed (no device, no valid answer within the link's bounds, a refusal); the reason goes to
// `err`, with control characters escaped.
int run_cosim(const CosimOptions& opt, std::ostream& out, std::ostream& err);

// Adds the `cosim` subcommand, its options written into `opt`.
CLI::App* add_cosim_command(CLI::App& app, CosimOptions& opt);

}  // namespace texsim
