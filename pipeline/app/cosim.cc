#include "pipeline/app/cosim.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/base/printable.h"
#include "rtl_model/link/hid_transport.h"
#include "rtl_model/link/link_host.h"
#include "rtl_model/link/vd_core_block.h"
#include "rtl_model/link/virtual_board.h"
#include "rtl_model/verilator/vd_rtl_block.h"

namespace texsim {

namespace {

using namespace texsim::link;

// The virtual board's blocks: "rtl" or "model" (the board is resolved, never empty here).
std::unique_ptr<Transport> open_link(const CosimOptions& opt, const std::string& board) {
  if (opt.link == "virtual") {
    std::vector<std::unique_ptr<BoardBlock>> blocks;
    if (board == "rtl") {
      for (const std::string& n : rtl_block_names()) blocks.push_back(make_rtl_block(n));
    } else {
      for (const std::string& n : core_block_names()) blocks.push_back(make_core_block(n));
    }
    return std::make_unique<VirtualBoard>(std::move(blocks));
  }
  if (opt.link == "hid") {
    return std::make_unique<HidTransport>(opt.vid ? opt.vid : kDefaultVid,
                                          opt.pid ? opt.pid : kDefaultPid);
  }
  throw LinkError("unknown link '" + opt.link + "' (virtual or hid)");
}

struct Tally {
  uint64_t match = 0, mismatch = 0;
};

// Streams `n` random inputs in chunks, comparing each result with the host's core.
Tally stream_and_compare(LinkHost& host, BoardBlock& core, const CosimOptions& opt,
                         std::ostream& out) {
  // Inputs: every code of d in the evaluators' domain [0, 0.5].
  const uint32_t max_code = 1u << (opt.frac_bits - 1);
  std::mt19937_64 rng(opt.seed);
  std::uniform_int_distribution<uint32_t> dist(0, max_code);
  constexpr uint64_t kChunk = 1 << 16;
  Tally t;
  std::vector<uint32_t> in, want;
  for (uint64_t done = 0; done < opt.vectors; done += in.size()) {
    in.resize(std::min(kChunk, opt.vectors - done));
    for (uint32_t& x : in) x = dist(rng);
    want.resize(in.size());
    core.apply(in, want);
    const std::vector<uint32_t> got = host.stream(in);
    for (size_t i = 0; i < in.size(); ++i) {
      if (got[i] == want[i]) {
        ++t.match;
        continue;
      }
      if (++t.mismatch <= 10) {
        out << "mismatch at vector " << done + i << ": input 0x" << std::hex << in[i]
            << ", board 0x" << got[i] << ", C++ core 0x" << want[i] << std::dec << "\n";
      }
    }
  }
  return t;
}

// What the virtual board runs, said on `out`: by default the RTL when the build has it and it
// is built for the format asked, else the C++ models. An explicit --board rtl that cannot be
// served is an error.
std::string resolve_board(const CosimOptions& opt, std::ostream& out) {
  if (opt.link != "virtual") {
    if (!opt.board.empty()) throw InputError("--board", "applies to --link virtual only");
    return "";
  }
  const bool rtl_fits = rtl_board_available() && opt.frac_bits == rtl_frac_bits();
  if (opt.board == "rtl" && rtl_board_available() && !rtl_fits) {
    throw InputError("--board rtl", "the RTL is built for u0." + std::to_string(rtl_frac_bits()) +
                                        " inputs only, not --frac-bits " +
                                        std::to_string(opt.frac_bits) + " (--board model runs it)");
  }
  if (opt.board == "rtl" && !rtl_board_available()) {
    throw LinkError(
        "--board rtl: texsim was built without Verilator, so the virtual board can run only the "
        "C++ models (--board model); install Verilator and rebuild for the RTL");
  }
  std::string board = opt.board.empty() ? (rtl_fits ? "rtl" : "model") : opt.board;
  if (board == "rtl") {
    out << "virtual board runs the Verilated RTL (rtl_model/rtl), one input per clock\n";
  } else if (!rtl_board_available()) {
    out << "virtual board runs the C++ models (texsim was built without Verilator: no RTL)\n";
  } else {
    out << "virtual board runs the C++ models"
        << (opt.board.empty()
                ? " (the RTL is built for u0." + std::to_string(rtl_frac_bits()) + " inputs only)"
                : std::string())
        << "\n";
  }
  return board;
}

// Usage errors (exit 2): what the command line asks for that no board could serve.
void check_usage(const CosimOptions& opt) {
  if (opt.frac_bits != 16 && opt.frac_bits != 12 && opt.frac_bits != 8) {
    throw InputError("--frac-bits", std::to_string(opt.frac_bits) + ": 16, 12 or 8");
  }
  if (opt.link != "virtual" && opt.link != "hid") {
    throw InputError("--link", "unknown link '" + opt.link + "' (virtual or hid)");
  }
  const std::vector<std::string> names = core_block_names();
  if (std::find(names.begin(), names.end(), opt.block) == names.end()) {
    std::string known;
    for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
    throw InputError("--block", "no block '" + opt.block + "' (blocks: " + known + ")");
  }
}

int cosim(const CosimOptions& opt, std::ostream& out) {
  check_usage(opt);
  const std::string board = resolve_board(opt, out);
  std::unique_ptr<BoardBlock> core = make_core_block(opt.block);
  const std::vector<uint8_t> config = {static_cast<uint8_t>(opt.frac_bits)};
  if (const std::string why = core->configure(config); !why.empty()) throw LinkError(why);

  std::unique_ptr<Transport> transport = open_link(opt, board);
  LinkOptions lo;
  lo.timeout_ms = opt.timeout_ms;
  // Linux hidraw queues at most 64 input reports per open device and drops the rest: keep the
  // responses in flight (2 x 18 reports of a 250-vector STREAM) well below that.
  if (opt.link == "hid") lo.window = 2;
  LinkHost host(*transport, lo);
  const Capabilities& caps = host.capabilities();
  // The transport's description may hold a USB product string: the board's text.
  out << "texsim cosim: " << opt.block << " on the " << printable(transport->describe())
      << " (firmware " << int{caps.fw_major} << "." << int{caps.fw_minor} << "."
      << int{caps.fw_patch} << ", " << caps.packet_size << "-byte reports, "
      << int{caps.max_in_flight} << " requests in flight)\n";
  host.select(opt.block);
  host.configure(config);
  const BlockCaps bc = core->caps();
  out << "block " << bc.name << ": " << int{bc.in_bits} << "-bit inputs (u0." << opt.frac_bits
      << "), " << int{bc.out_bits} << "-bit results, latency " << int{bc.latency} << " cycles\n";

  const auto t0 = std::chrono::steady_clock::now();
  const Tally t = stream_and_compare(host, *core, opt, out);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const Counters c = host.counters();
  const LinkStats& s = host.stats();

  char line[160];
  out << "vectors: " << opt.vectors << " sent, " << t.match << " match, " << t.mismatch
      << " mismatch\n";
  std::snprintf(
      line, sizeof line, "board: %llu vectors, %llu cycles (%.4f per vector), %u bad requests\n",
      static_cast<unsigned long long>(c.vectors), static_cast<unsigned long long>(c.cycles),
      c.vectors ? static_cast<double>(c.cycles) / static_cast<double>(c.vectors) : 0.0,
      c.bad_requests);
  out << line;
  out << "link: " << s.requests << " requests, " << s.reports_out << " reports out, "
      << s.reports_in << " in, " << s.retransmits << " retransmits, " << s.timeouts << " timeouts, "
      << s.malformed << " dropped\n";
  std::snprintf(line, sizeof line, "throughput: %.0f vectors/s over the link (%.3f s wall clock)\n",
                secs > 0 ? static_cast<double>(opt.vectors) / secs : 0.0, secs);
  out << line;
  if (c.vectors != opt.vectors) {
    out << "the board counted " << c.vectors << " vectors, not " << opt.vectors << "\n";
    return 1;
  }
  return t.mismatch == 0 ? 0 : 1;
}

}  // namespace

int run_cosim(const CosimOptions& opt, std::ostream& out, std::ostream& err) {
  // Board text inside the messages (refusals, names) is escaped: it cannot act on a terminal.
  try {
    return cosim(opt, out);
  } catch (const InputError& e) {
    err << "texsim cosim: error: " << printable(e.what()) << "\n";
    return 2;
  } catch (const LinkError& e) {
    err << "texsim cosim: error: " << printable(e.what()) << "\n";
    return 4;
  }
}

CLI::App* add_cosim_command(CLI::App& app, CosimOptions& opt) {
  CLI::App* cmd = app.add_subcommand(
      "cosim",
      "Stream random vectors through a block on a board (virtual or USB HID) and compare every "
      "result with its C++ core (docs/rtl/link.md)");
  cmd->add_option("--block", opt.block, "Block on the board: vd_p2 or vd_p1")
      ->capture_default_str();
  cmd->add_option("--link", opt.link, "virtual (in process) or hid (a board on USB)")
      ->check(CLI::IsMember({"virtual", "hid"}))
      ->capture_default_str();
  cmd->add_option("--board", opt.board,
                  "What the virtual board runs: rtl (the Verilated RTL; the default when texsim "
                  "was built with Verilator) or model (the C++ cores)")
      ->check(CLI::IsMember({"rtl", "model"}));
  cmd->add_option("--vectors", opt.vectors, "Random input vectors to stream")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 32))
      ->capture_default_str();
  cmd->add_option("--seed", opt.seed, "Seed of the random inputs")->capture_default_str();
  cmd->add_option("--frac-bits", opt.frac_bits, "Input fraction bits of the block: 16, 12 or 8")
      ->check(CLI::IsMember({16, 12, 8}))
      ->capture_default_str();
  cmd->add_option("--timeout-ms", opt.timeout_ms, "Wait for a report before retransmitting")
      ->check(CLI::Range(1, 60000))
      ->capture_default_str();
  // Hexadecimal, as lsusb prints them.
  const auto hex16 = [](uint16_t& dst, const char* name) {
    return [&dst, name](const std::string& s) {
      size_t used = 0;
      unsigned long v = 0;
      try {
        v = std::stoul(s, &used, 16);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != s.size() || v == 0 || v > 0xFFFF) {
        throw CLI::ValidationError(name, "'" + s + "' is not a 16-bit hex id (e.g. 1209)");
      }
      dst = static_cast<uint16_t>(v);
    };
  };
  cmd->add_option_function<std::string>("--vid", hex16(opt.vid, "--vid"),
                                        "USB vendor id in hex (default 1209)");
  cmd->add_option_function<std::string>("--pid", hex16(opt.pid, "--pid"),
                                        "USB product id in hex (default 0001)");
  return cmd;
}

}  // namespace texsim
