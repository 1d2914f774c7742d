// gen_rtl_params OUT_DIR: writes the Verilog side of the RTL parameters from rtl_params.h:
// OUT_DIR/texsim_params.vh (localparams <MODULE>_<NAME> and <MODULE>_LATENCY, for synthesis
// scripts and hand instantiation), OUT_DIR/<module>.vc (the module's -G overrides, read by
// Verilator with -f) and OUT_DIR/texsim_sampler_log2.v (the sampler's log2 table). Files are
// rewritten only when their text changes, so an unchanged parameter set does not re-verilate
// anything.
#include <cctype>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "rtl_model/params/rtl_params.h"

namespace {

constexpr const char* kBanner =
    "// generated — do not edit: written by gen_rtl_params from rtl_model/params/rtl_params.h\n";

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

bool write_if_changed(const std::string& path, const std::string& text) {
  {
    std::ifstream in(path, std::ios::binary);
    std::stringstream old;
    old << in.rdbuf();
    if (in && old.str() == text) return true;
  }
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  return static_cast<bool>(out);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: gen_rtl_params OUT_DIR\n";
    return 2;
  }
  const std::string dir = argv[1];
  try {
    std::ostringstream vh;
    vh << kBanner << "`ifndef TEXSIM_PARAMS_VH\n`define TEXSIM_PARAMS_VH\n";
    bool ok = true;
    for (const auto& b : texsim::rtl_params::rtl_blocks()) {
      std::ostringstream vc;
      vc << kBanner;
      for (const auto& [name, value] : b.params) {
        vh << "localparam longint " << upper(b.module) << "_" << name << " = " << value << ";\n";
        vc << "-G" << name << "=" << value << "\n";
      }
      vh << "localparam int " << upper(b.module) << "_LATENCY = " << b.latency << ";\n";
      ok = write_if_changed(dir + "/" + b.module + ".vc", vc.str()) && ok;
    }
    vh << "`endif\n";
    ok = write_if_changed(dir + "/texsim_params.vh", vh.str()) && ok;
    ok = write_if_changed(dir + "/texsim_sampler_log2.v",
                          std::string(kBanner) + texsim::rtl_params::sampler_log2_v()) &&
         ok;
    if (!ok) {
      std::cerr << "gen_rtl_params: cannot write into " << dir << "\n";
      return 1;
    }
  } catch (const std::exception& e) {
    std::cerr << "gen_rtl_params: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
