#include "rtl_model/verilator/rtl_harness.h"

#include <cstdlib>

namespace texsim::rtl {

std::string trace_path_for(const std::string& name, const std::string& explicit_path) {
  if (!explicit_path.empty()) return explicit_path;
  const char* dir = std::getenv("TEXSIM_RTL_TRACE");  // NOLINT(concurrency-mt-unsafe)
  if (dir == nullptr || *dir == '\0') return "";
  return std::string(dir) + "/" + name + ".vcd";
}

}  // namespace texsim::rtl
