#include "pipeline/app/study_runs.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "blocks/base/input_error.h"
#include "blocks/base/shell_quote.h"

namespace texsim {

const StudySet& study_base_set() {
  static const StudySet s = {{"pipeline.units", "1"},
                             {"pipeline.unit_tile", "16"},
                             {"pipeline.layout", "tiled4x4"},
                             {"pipeline.quad_merge", "false"},
                             {"pipeline.cache.size_bytes", "16384"},
                             {"pipeline.cache.ways", "4"},
                             {"pipeline.cache.line_bytes", "64"},
                             {"pipeline.cache.miss_queue", "32"},
                             {"pipeline.dram.model", "flat"},
                             {"raster.order", "rows"}};
  return s;
}

StudySet with(StudySet s, const StudySet& more) {
  for (const auto& [k, v] : more) s[k] = v;
  return s;
}

std::vector<std::string> overrides_of(const StudySet& set) {
  std::vector<std::string> o;
  o.reserve(set.size());
  for (const auto& [k, v] : set) {
    std::string e = k;
    e.append("=").append(v);
    o.push_back(std::move(e));
  }
  return o;
}

void run_study_row(RunOptions o, const std::string& dir, const std::string& flags,
                   const std::function<void(const nlohmann::json&)>& read) {
  o.threads = 1;
  o.out = dir;
  o.command = "texsim run " + shell_quote(o.scene) + flags;
  for (const std::string& s : o.overrides) o.command.append(" --set ").append(shell_quote(s));
  std::ostringstream quiet;
  run_simulation(o, quiet);
  std::ifstream in(dir + "/report.json");
  try {
    read(nlohmann::json::parse(in));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(dir + "/report.json", std::string("unexpected report: ") + e.what());
  }
  std::filesystem::remove_all(dir);
}

}  // namespace texsim
