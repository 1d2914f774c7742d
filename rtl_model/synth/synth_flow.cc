#include "rtl_model/synth/synth_flow.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "blocks/base/shell_quote.h"

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

// Runs a command line in `dir` with its output in dir/log; true if it exited with 0. Scripts
// and netlists use plain names inside dir, so no path needs quoting inside a yosys script.
bool run(const fs::path& dir, const std::string& command, const std::string& log) {
  const std::string cmd =
      "cd " + shell_quote(dir.string()) + " && " + command + " >" + log + " 2>&1";
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

// A parameter value as yosys' chparam reads it: a decimal, or a negative one as its 32-bit
// two's complement in hex (chparam takes no minus sign); parameters are 32-bit ints.
std::string param_literal(int64_t v) {
  if (v >= 0) return std::to_string(v);
  char b[16];
  std::snprintf(b, sizeof b, "32'h%08X", static_cast<uint32_t>(v));
  return b;
}

// Reads every source (double-quoted absolute paths; the include folders with -I), sets the
// job's parameters on the top, elaborates it and renames the result `study_top`, so that the
// scripts below and the place-and-route wrapper name one module whatever the parameters.
std::string read_design(const SynthJob& job) {
  std::string s = "read_verilog -sv";
  for (const std::string& dir : job.includes) s += " -I \"" + fs::absolute(dir).string() + "\"";
  for (const std::string& f : job.files) s += " \"" + fs::absolute(f).string() + "\"";
  s += "\n";
  if (!job.params.empty()) {
    s += "chparam";
    for (const auto& [name, value] : job.params) s += " -set " + name + " " + param_literal(value);
    s += " " + job.top + "\n";
  }
  return s + "hierarchy -top " + job.top + "\nrename -top study_top\n";
}

// The generic script: $mul cells after flatten/opt/wreduce (pre_net.json), then yosys'
// multiplier-to-DSP split with synth_ice40 -dsp's settings (what stays in LUTs:
// $__soft_mul), then plain `synth` on the saved design for the generic cell count.
std::string generic_script(const SynthJob& job) {
  return read_design(job) +
         "proc\nflatten\nopt\nwreduce\nopt_clean\nwrite_json pre_net.json\n"
         "design -save pre\n"
         "techmap -map +/mul2dsp.v -map +/ice40/dsp_map.v -D DSP_A_MAXWIDTH=16 "
         "-D DSP_B_MAXWIDTH=16 -D DSP_A_MINWIDTH=2 -D DSP_B_MINWIDTH=2 -D DSP_Y_MINWIDTH=11 "
         "-D DSP_NAME=$__MUL16X16\n"
         "tee -q -o dsp_split.json stat -json\n" +
         (job.generic_cells
              ? "design -load pre\nsynth -top study_top\ntee -q -o generic.json stat -json\n"
              : "");
}

long long json_int(const json& v) {
  if (v.is_number_integer()) return v.get<long long>();
  if (v.is_string()) return std::stoll(v.get<std::string>(), nullptr, 2);
  return 0;
}

// "AxB" (with "s" when signed) of every $mul cell of the flattened top.
std::vector<std::string> multiplier_shapes(const fs::path& netlist) {
  std::vector<std::string> out;
  const json j = read_json(netlist);
  if (!j.is_object() || !j.contains("modules") || !j["modules"].contains("study_top")) return out;
  const json& cells = j["modules"]["study_top"]["cells"];
  if (!cells.is_object()) return out;
  for (const auto& [name, cell] : cells.items()) {
    if (cell.value("type", "") != "$mul") continue;
    const json& p = cell["parameters"];
    out.push_back(std::to_string(json_int(p["A_WIDTH"])) + "x" +
                  std::to_string(json_int(p["B_WIDTH"])) + (json_int(p["A_SIGNED"]) ? "s" : ""));
  }
  std::sort(out.begin(), out.end());
  return out;
}

// A top module around the block: inputs from a serial shift register, outputs folded into a
// register ring, one clock. Ports come from the block's netlist; a clock input named clk or
// clock is driven by the clock. The block is `study_top`, already built with its parameters.
std::string wrapper(const json& ports) {
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
  const std::string ni = std::to_string(in_bits), no = std::to_string(out_bits);
  std::ostringstream v;
  v << "module study_wrap(input clk, input sin, output sout);\n"
    << "  reg [" << ni << "-1:0] in_sr;\n"
    << "  always @(posedge clk) in_sr <= {in_sr[" << ni << "-2:0], sin};\n"
    << "  wire [" << no << "-1:0] out_w;\n"
    << "  study_top dut(" << (conns.empty() ? "" : conns.substr(2)) << ");\n"
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

// The first over-100% utilisation line ("ICESTORM_LC: 8533/ 5280 161%") of a nextpnr log, or
// "" when the design fits.
std::string overfull_cells(const fs::path& log) {
  std::ifstream f(log);
  for (std::string line; std::getline(f, line);) {
    const size_t at = line.find("ICESTORM_");
    const size_t pct = line.rfind('%');
    if (at != std::string::npos && pct != std::string::npos && pct > at) {
      const size_t start = line.find_last_of(' ', pct);
      if (start != std::string::npos && std::atoi(line.c_str() + start + 1) > 100) {
        std::string fit;  // with runs of blanks collapsed
        for (const char c : line.substr(at)) {
          if (c != ' ' || (!fit.empty() && fit.back() != ' ')) fit += c;
        }
        return fit;
      }
    }
  }
  return "";
}

void place_and_route(const SynthJob& job, const Tools& tools, const json& ports, SynthResult& r) {
  const fs::path dir = job.work_dir;
  write_text(dir / "wrap.v", wrapper(ports));
  // More multipliers than the UP5K has DSPs: place the block with LUT multipliers instead.
  r.pnr_without_dsp = r.mac16 > kUp5kDsps;
  write_text(dir / "wrap.ys", read_design(job) + "read_verilog -sv wrap.v\nsynth_ice40 -top " +
                                  "study_wrap" + (r.pnr_without_dsp ? "" : " -dsp") +
                                  " -json wrap.json\n");
  if (!run(dir, shell_quote(tools.yosys) + " -q -s wrap.ys", "wrap.log")) {
    r.pnr_error = "yosys could not synthesise the place-and-route wrapper (" +
                  (dir / "wrap.log").string() + ")";
    return;
  }
  for (const int seed : job.seeds) {
    const std::string s = std::to_string(seed);
    const std::string report = "pnr_seed" + s + ".json";
    std::string cmd = shell_quote(tools.nextpnr);
    cmd += " --up5k --package sg48 --freq 12 --timing-allow-fail --seed " + s;
    cmd += " --json wrap.json --report " + report;
    const bool ok = run(dir, cmd, "pnr_seed" + s + ".log");
    const double f = ok ? report_fmax(dir / report) : -1;
    if (f > 0) {
      r.fmax_mhz.push_back(f);
    } else if (const std::string lc = overfull_cells(dir / ("pnr_seed" + s + ".log"));
               !lc.empty()) {
      r.pnr_error = "does not fit the UP5K: " + lc;
      return;  // the same for every seed
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

std::string generated_include_dir() {
  std::error_code ec;
  const std::string dir = TEXSIM_RTL_PARAMS_DIR;
  return fs::is_directory(dir, ec) ? dir : "";
}

std::string up5k_fit(const SynthResult& r) {
  if (!r.error.empty()) return "-";
  std::string over;
  const auto check = [&over](const char* what, int used, int limit) {
    if (used > limit) {
      over += std::string(over.empty() ? "" : ", ") + what + " " + std::to_string(used) + "/" +
              std::to_string(limit);
    }
  };
  check("SB_LUT4", r.lut4, kUp5kLogicCells);
  check("DFF", r.dff, kUp5kLogicCells);
  check("SB_MAC16", r.mac16, kUp5kDsps);
  check("BRAM", r.ram, kUp5kBrams);
  const std::string lc = "does not fit the UP5K: ";
  if (r.pnr_error.rfind(lc, 0) == 0) {
    over += std::string(over.empty() ? "" : ", ") + r.pnr_error.substr(lc.size());
  }
  if (over.empty()) return "yes";
  if (r.pnr_without_dsp && !r.fmax_mhz.empty()) over += "; fits with LUT multipliers";
  return "no: " + over;
}

SynthResult run_synth(const SynthJob& job, const Tools& tools) {
  SynthResult r;
  const fs::path dir = job.work_dir;
  fs::create_directories(dir);
  for (const std::string& f : job.files) {
    if (fs::absolute(f).string().find('"') != std::string::npos) {
      r.error = "cannot pass a file name with a double quote to yosys: " + f;
      return r;
    }
  }
  for (const auto& [name, value] : job.params) {
    if (value < INT32_MIN || value > INT32_MAX) {
      r.error = "parameter " + name + " = " + std::to_string(value) + " does not fit 32 bits";
      return r;
    }
  }
  write_text(dir / "generic.ys", generic_script(job));
  write_text(dir / "ice40.ys", read_design(job) +
                                   "synth_ice40 -top study_top -dsp -json ice40_net.json\n"
                                   "tee -q -o ice40.json stat -json\n");
  for (const std::string step : {"generic", "ice40"}) {
    if (!run(dir, shell_quote(tools.yosys) + " -q -s " + step + ".ys", step + ".log")) {
      r.error = "yosys " + step + " synthesis failed (" + (dir / (step + ".log")).string() + ")";
      return r;
    }
  }
  r.multipliers = multiplier_shapes(dir / "pre_net.json");
  const json split = cell_types(dir / "dsp_split.json");
  r.lut_multipliers = count_prefix(split, "$__soft_mul") + count_prefix(split, "$mul");
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
  // A logic cell holds one LUT4 and one flip-flop: more of either than the device's cells
  // cannot be placed, whatever the multipliers become.
  if (r.lut4 > kUp5kLogicCells || r.dff > kUp5kLogicCells) {
    const bool luts = r.lut4 > kUp5kLogicCells;
    r.pnr_error = "not placed: " + std::to_string(luts ? r.lut4 : r.dff) +
                  (luts ? " SB_LUT4" : " flip-flops") + " > the UP5K's " +
                  std::to_string(kUp5kLogicCells) + " logic cells";
    return r;
  }
  const json net = read_json(dir / "ice40_net.json");
  if (!net.is_object() || !net["modules"].contains("study_top")) {
    r.pnr_error = "no module study_top in the iCE40 netlist";
    return r;
  }
  place_and_route(job, tools, net["modules"]["study_top"].value("ports", json::object()), r);
  return r;
}

}  // namespace texsim::synth
