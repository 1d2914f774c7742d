#include "rtl_model/verilator/rtl_harness.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "blocks/base/input_error.h"

namespace texsim::rtl {

std::string trace_path_for(const std::string& name, const std::string& explicit_path) {
  if (!explicit_path.empty()) return explicit_path;
  const char* dir = std::getenv("TEXSIM_RTL_TRACE");  // NOLINT(concurrency-mt-unsafe)
  if (dir == nullptr || *dir == '\0') return "";
  // A waveform was asked for: say so when it cannot be written rather than run without it.
  const std::string where = std::string("TEXSIM_RTL_TRACE=") + dir;
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(dir, ec);
  if (!std::filesystem::exists(st)) {
    throw InputError(where, "no such directory (create it, or unset TEXSIM_RTL_TRACE)");
  }
  if (!std::filesystem::is_directory(st)) {
    throw InputError(where, "not a directory: the waveforms go to DIR/<block>.vcd");
  }
  if (::access(dir, W_OK | X_OK) != 0) {
    throw InputError(where, "this user may not write into the directory");
  }
  return std::string(dir) + "/" + name + ".vcd";
}

void throw_unopened_trace(const std::string& path) {
  throw InputError(path, "cannot open the waveform file for writing");
}

}  // namespace texsim::rtl
