#include "rtl_model/synth/equiv_check.h"

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "blocks/base/shell_quote.h"

namespace texsim::synth {

namespace fs = std::filesystem;

namespace {

std::string range(int width) {
  if (width <= 1) return {};
  char b[24];
  std::snprintf(b, sizeof b, "[%d:0] ", width - 1);
  return b;
}

// eq_<side>: the module with the job's parameters, its data output masked by out_valid.
std::string wrapper(const EquivJob& job, const std::string& side, const std::string& module) {
  std::string ports = "input logic clk, input logic rst, input logic in_valid";
  std::string conn = ".clk, .rst, .in_valid";
  for (const EquivPort& p : job.inputs) {
    ports += ", input logic " + range(p.width) + p.name;
    conn += ", ." + p.name;
  }
  const std::string out = job.output.name;
  ports += ", output logic out_valid, output logic " + range(job.output.width) + out;
  std::string params;
  for (const auto& [name, value] : job.params) {
    params += std::string(params.empty() ? "" : ", ") + "." + name + "(";
    // Negative values as 32-bit two's complement, as the study's chparam does.
    params +=
        value < 0 ? "32'd" + std::to_string(static_cast<uint32_t>(value)) : std::to_string(value);
    params += ")";
  }
  std::string t = "module eq_" + side + " (" + ports + ");\n";
  t += "  logic " + range(job.output.width) + "raw;\n";
  t += "  " + module + (params.empty() ? "" : " #(" + params + ")") + " u (" + conn +
       ", .out_valid, ." + out + "(raw), .ops_add(), .ops_mul(), .ops_div(), .ops_cmp(), " +
       ".items());\n";
  t += "  assign " + out + " = out_valid ? raw : '0;\n";
  t += "endmodule\n";
  return t;
}

std::string script(const EquivJob& job) {
  std::string s = "read_verilog -sv";
  for (const std::string& f : job.files) s += " \"" + fs::absolute(f).string() + "\"";
  s += " eq_gold.v eq_gate.v\n";
  for (const std::string& c : job.setup) s += c + "\n";
  s += "hierarchy -check\nproc\nflatten\nmemory\nopt -fast\n";
  s += "miter -equiv -flatten -make_outputs eq_gold eq_gate eq_miter\n";
  s += "hierarchy -top eq_miter\nopt -fast\n";
  s += "sat -tempinduct -prove trigger 0 -set-init-zero -maxsteps " +
       std::to_string(job.max_steps) + " -verify -show-ports\n";
  return s;
}

}  // namespace

EquivResult check_equivalence(const EquivJob& job, const std::string& yosys) {
  EquivResult r;
  const fs::path dir = job.work_dir;
  std::error_code ec;
  fs::create_directories(dir, ec);
  for (const std::string& f : job.files) {
    if (f.find('"') != std::string::npos) {
      r.error = "cannot pass a file name with a double quote to yosys: " + f;
      return r;
    }
  }
  std::ofstream(dir / "eq_gold.v") << wrapper(job, "gold", job.gold);
  std::ofstream(dir / "eq_gate.v") << wrapper(job, "gate", job.gate);
  std::ofstream(dir / "equiv.ys") << script(job);
  r.log = (dir / "equiv.log").string();
  const std::string cmd = "cd " + shell_quote(dir.string()) + " && " + shell_quote(yosys) +
                          " -s equiv.ys >equiv.log 2>&1";
  const int rc = std::system(cmd.c_str());
  if (rc == -1 || !WIFEXITED(rc)) {
    r.error = "could not run yosys";
    return r;
  }
  std::ifstream log(r.log);
  for (std::string line; std::getline(log, line);) {
    if (line.find("Induction step proven: SUCCESS!") != std::string::npos) r.proved = true;
    if (line.find("model found") != std::string::npos && line.find("FAIL!") != std::string::npos)
      r.refuted = true;
  }
  if (WEXITSTATUS(rc) != 0) r.proved = false;
  if (!r.proved && !r.refuted) {
    r.error = "yosys ended without a proof or a counterexample within " +
              std::to_string(job.max_steps) + " steps (" + r.log + ")";
  }
  return r;
}

}  // namespace texsim::synth
