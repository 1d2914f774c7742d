#pragma once
// Runs the texsim binary (TEXSIM_BINARY, set per test executable) and reads what it wrote: the
// `Cli` fixture gives each test its own temporary directory; `find`/`num` read report.json keys
// by dotted path.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace cli_harness {

struct Result {
  int code;
  std::string out;
};

// Runs a shell command line, its standard output and error captured together.
inline Result shell(const std::string& command) {
  const fs::path log =
      fs::temp_directory_path() / ("texsim_cli_" + std::to_string(::getpid()) + ".log");
  const std::string cmd = "{ " + command + "; } >" + log.string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  std::ifstream in(log);
  std::stringstream ss;
  ss << in.rdbuf();
  fs::remove(log);
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, ss.str()};
}

// Runs texsim with `args`.
inline Result sh(const std::string& args) { return shell(std::string(TEXSIM_BINARY) + " " + args); }

// The whole content of a file (empty if it cannot be read).
inline std::string slurp(const std::string& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("texsim_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  void write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
  }
  // The output directory must hold no report and no temporary file after a failed run.
  void expect_no_outputs(const std::string& out) const {
    if (!fs::exists(out)) return;
    for (const auto& e : fs::directory_iterator(out)) ADD_FAILURE() << "left behind: " << e.path();
  }
  fs::path dir_;
};

using Json = nlohmann::json;

inline Json load_json(const std::string& path) {
  std::ifstream in(path);
  return Json::parse(in);
}

// Value at a dotted path ("blocks.lod.ops.lut"); block names contain dots, so the longest
// matching key wins at each level.
inline const Json* find(const Json& j, const std::string& path) {
  if (path.empty()) return &j;
  if (!j.is_object()) return nullptr;
  for (size_t end = path.size(); end != std::string::npos && end > 0;
       end = path.rfind('.', end - 1)) {
    const std::string key = path.substr(0, end);
    if (j.contains(key)) {
      const Json* r = find(j[key], end == path.size() ? "" : path.substr(end + 1));
      if (r) return r;
    }
    if (end == 0) break;
  }
  return nullptr;
}

inline double num(const Json& j, const std::string& path) {
  const Json* n = find(j, path);
  if (n && n->is_number()) return n->get<double>();
  ADD_FAILURE() << "missing numeric key " << path;
  return 0;
}

}  // namespace cli_harness
