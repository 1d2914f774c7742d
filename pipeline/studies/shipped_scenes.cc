#include "pipeline/studies/shipped_scenes.h"

#include <filesystem>
#include <system_error>

namespace texsim {

namespace {

// The installed scenes relative to the running executable (a moved install still finds them),
// then at the configured prefix, then the source tree's.
std::string find_scenes_dir() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path rel = (exe.parent_path() / TEXSIM_BIN_TO_SCENES).lexically_normal();
    if (fs::is_directory(rel, ec)) return rel.string();
  }
  if (fs::is_directory(TEXSIM_SOURCE_SCENES_DIR, ec)) return TEXSIM_SOURCE_SCENES_DIR;
  return TEXSIM_INSTALL_SCENES_DIR;
}

}  // namespace

const std::string& shipped_scenes_dir() {
  static const std::string dir = find_scenes_dir();
  return dir;
}

}  // namespace texsim
