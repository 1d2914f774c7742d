#include "rtl_model/synth/synth_flow.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace texsim::synth {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const fs::path p = fs::path(dir.empty() ? "." : dir) / name;
    std::error_code ec;
    if (fs::is_regular_file(p, ec) && ::access(p.c_str(), X_OK) == 0) return p.string();
  }
  return "";
}

std::string quote(const std::string& s) {
  std::string q = "'";
  for (const char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Runs a command line in `dir` with its output in dir/log; true if it exited with 0. Scripts
// and netlists use plain names inside dir, so no path needs quoting inside a yosys script.
bool run(const fs::path& dir, const std::string& command, const std::string& log) {
  const std::string cmd = "cd " + quote(dir.string()) + " && " + command + " >" + log + " 2>&1";
  const int rc = std::system(cmd.c_str());
  return rc != -1 && WIFEXITED(rc) && WEXITSTATUS(rc) == 0;
}

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream f(p);
  f << text;
}

json read_json(const fs::path& p) {
  std::ifstream f(p);
  return json::parse(f, nullptr, /*allow_exceptions=*/false);
}

// Cell counts of the whole design from `stat -json` output.
json cell_types(const fs::path& stat) {
  const json j = read_json(stat);
  if (!j.is_object() || !j.contains("design")) return json::object();
  return j["design"].value("num_cells_by_type", json::object());
}

int count_prefix(const json& cells, const std::string& prefix) {
  int n = 0;
  for (const auto& [type, count] : cells.items()) {
    if (type.rfind(prefix, 0) == 0) n += count.get<int>();
  }
  return n;
}

// read_verilog (the source by its absolute path, includes also from its folder) and hierarchy
// with the job's parameters. yosys takes double-quoted file names in read_verilog.
std::string read_design(const SynthJob& job) {
  const fs::path src = fs::absolute(job.file);
  std::string s = "read_verilog -sv -I \"" + src.parent_path().string() + "\" \"" + src.string() +
                  "\"\nhierarchy -top " + job.top;
  for (const auto& [name, value] : job.params) {
    s += " -chparam " + name + " " + std::to_string(value);
  }
  return s + "\n";
}

// A top module around the block: inputs from a serial shift register, outputs folded into a
// register ring, one clock. Ports come from the block's netlist; a clock input named clk or
// clock is driven by the clock.
std::string wrapper(const SynthJob& job, const json& ports) {
  std::string inst, regs;
  int in_bits = 0, out_bits = 0;
  std::string conns;
  for (const auto& [name, port] : ports.items()) {
    const int w = static_cast<int>(port["bits"].size());
    const std::string dir = port.value("direction", "");
    if (dir == "input" && (name == "clk" || name == "clock")) {
      conns += ", ." + name + "(clk)";
    } else if (dir == "input") {
      conns += ", ." + name + "(in_sr[" + std::to_string(in_bits + w - 1) + ":" +
               std::to_string(in_bits) + "])";
      in_bits += w;
    } else if (dir == "output") {
      conns += ", ." + name + "(out_w[" + std::to_string(out_bits + w - 1) + ":" +
               std::to_string(out_bits) + "])";
      out_bits += w;
    }
  }
  in_bits = std::max(in_bits, 2);
  out_bits = std::max(out_bits, 2);
  std::string params;
  for (const auto& [name, value] : job.params) {
    params +=
        std::string(params.empty() ? "" : ", ") + "." + name + "(" + std::to_string(value) + ")";
  }
  const std::string ni = std::to_string(in_bits), no = std::to_string(out_bits);
  std::ostringstream v;
  v << "module study_wrap(input clk, input sin, output sout);\n"
    << "  reg [" << ni << "-1:0] in_sr;\n"
    << "  always @(posedge clk) in_sr <= {in_sr[" << ni << "-2:0], sin};\n"
    << "  wire [" << no << "-1:0] out_w;\n"
    << "  " << job.top << (params.empty() ? "" : " #(" + params + ")") << " dut("
    << (conns.empty() ? "" : conns.substr(2)) << ");\n"
    << "  reg [" << no << "-1:0] out_r;\n"
    << "  always @(posedge clk) out_r <= out_w ^ {out_r[" << no << "-2:0], out_r[" << no
    << "-1]};\n"
    << "  assign sout = out_r[" << no << "-1];\n"
    << "endmodule\n";
  return v.str();
}

// Lowest achieved Fmax over the clocks of a nextpnr --report file, or < 0.
double report_fmax(const fs::path& report) {
  const json j = read_json(report);
  double f = -1;
  if (!j.is_object() || !j.contains("fmax")) return f;
  for (const auto& [clock, v] : j["fmax"].items()) {
    const double a = v.value("achieved", -1.0);
    if (a > 0 && (f < 0 || a < f)) f = a;
  }
  return f;
}

void place_and_route(const SynthJob& job, const Tools& tools, const json& ports, SynthResult& r) {
  const fs::path dir = job.work_dir;
  write_text(dir / "wrap.v", wrapper(job, ports));
  write_text(dir / "wrap.ys", read_design(job) +
                                  "read_verilog -sv wrap.v\nsynth_ice40 -top study_wrap -dsp "
                                  "-json wrap.json\n");
  if (!run(dir, quote(tools.yosys) + " -q -s wrap.ys", "wrap.log")) {
    r.pnr_error = "yosys could not synthesise the place-and-route wrapper (" +
                  (dir / "wrap.log").string() + ")";
    return;
  }
  for (const int seed : job.seeds) {
    const std::string s = std::to_string(seed);
    const std::string report = "pnr_seed" + s + ".json";
    std::string cmd = quote(tools.nextpnr);
    cmd += " --up5k --package sg48 --freq 12 --timing-allow-fail --seed " + s;
    cmd += " --json wrap.json --report " + report;
    const bool ok = run(dir, cmd, "pnr_seed" + s + ".log");
    const double f = ok ? report_fmax(dir / report) : -1;
    if (f > 0) {
      r.fmax_mhz.push_back(f);
    } else {
      r.pnr_error = "nextpnr-ice40 failed for seed " + s + " (" +
                    (dir / ("pnr_seed" + s + ".log")).string() + ")";
    }
  }
}

}  // namespace

std::string Tools::missing() const {
  std::string m;
  if (yosys.empty()) m = "yosys";
  if (nextpnr.empty()) m += std::string(m.empty() ? "" : " and ") + "nextpnr-ice40";
  return m.empty() ? "" : m + " not found on PATH";
}

Tools find_tools() { return {on_path("yosys"), on_path("nextpnr-ice40")}; }

SynthResult run_synth(const SynthJob& job, const Tools& tools) {
  SynthResult r;
  const fs::path dir = job.work_dir;
  fs::create_directories(dir);
  if (fs::absolute(job.file).string().find('"') != std::string::npos) {
    r.error = "cannot pass a file name with a double quote to yosys: " + job.file;
    return r;
  }
  // Generic: $mul count after proc/opt, then cells after `synth`.
  write_text(dir / "generic.ys", read_design(job) +
                                     "proc\nopt\ntee -q -o pre.json stat -json\nsynth -top " +
                                     job.top + "\ntee -q -o generic.json stat -json\n");
  write_text(dir / "ice40.ys", read_design(job) + "synth_ice40 -top " + job.top +
                                   " -dsp -json ice40_net.json\ntee -q -o ice40.json stat -json\n");
  for (const std::string step : {"generic", "ice40"}) {
    if (!run(dir, quote(tools.yosys) + " -q -s " + step + ".ys", step + ".log")) {
      r.error = "yosys " + step + " synthesis failed (" + (dir / (step + ".log")).string() + ")";
      return r;
    }
  }
  r.multipliers = count_prefix(cell_types(dir / "pre.json"), "$mul");
  const json generic = read_json(dir / "generic.json");
  if (generic.is_object() && generic.contains("design")) {
    r.generic_cells = generic["design"].value("num_cells", 0);
  }
  const json ice = cell_types(dir / "ice40.json");
  r.lut4 = count_prefix(ice, "SB_LUT4");
  r.dff = count_prefix(ice, "SB_DFF");
  r.carry = count_prefix(ice, "SB_CARRY");
  r.mac16 = count_prefix(ice, "SB_MAC16");
  r.ram = count_prefix(ice, "SB_RAM") + count_prefix(ice, "SB_SPRAM");
  if (tools.nextpnr.empty()) return r;
  const json net = read_json(dir / "ice40_net.json");
  const std::string key = job.top;
  if (!net.is_object() || !net["modules"].contains(key)) {
    r.pnr_error = "no module " + key + " in the iCE40 netlist";
    return r;
  }
  place_and_route(job, tools, net["modules"][key].value("ports", json::object()), r);
  return r;
}

}  // namespace texsim::synth
