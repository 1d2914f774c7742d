#include "blocks/base/output_set.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"
#include "blocks/base/temp_registry.h"

namespace texsim {

namespace fs = std::filesystem;

OutputSet::OutputSet(std::string dir)
    : dir_(std::move(dir)), staging_(dir_ + "/.texsim-staging." + std::to_string(::getpid())) {
  ensure_dir(dir_);
  std::error_code ec;
  fs::remove_all(staging_, ec);  // left by an earlier process with this pid that was killed
  track_temp(staging_);
  if (!fs::create_directory(staging_, ec)) {
    untrack_temp(staging_);
    throw InputError(dir_, "cannot create a staging directory: " + ec.message());
  }
}

OutputSet::~OutputSet() {
  if (!committed_) remove_staging();
}

std::string OutputSet::path(const std::string& name) {
  if (std::find(names_.begin(), names_.end(), name) == names_.end()) names_.push_back(name);
  std::string p = staging_ + "/" + name;
  track_temp(p);
  return p;
}

void OutputSet::remove_staging() {
  for (const std::string& n : names_) untrack_temp(staging_ + "/" + n);
  std::error_code ec;
  fs::remove_all(staging_, ec);
  untrack_temp(staging_);
}

void OutputSet::commit() {
  // Files written into staging() without path(), too.
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(staging_, ec)) {
    const std::string n = e.path().filename().string();
    if (std::find(names_.begin(), names_.end(), n) == names_.end()) names_.push_back(n);
  }
  // What a rename would refuse is found before anything moves: a directory in the way.
  // and a file this run read as its input (texsim run DIR/report.json --out DIR).
  for (const std::string& n : names_) {
    if (fs::is_directory(dir_ + "/" + n, ec)) {
      remove_staging();
      committed_ = true;
      throw InputError(dir_ + "/" + n, "is a directory: no output was moved into " + dir_);
    }
    try {
      refuse_overwriting_input(dir_ + "/" + n);
    } catch (const InputError&) {
      remove_staging();
      committed_ = true;
      throw;
    }
  }
  sigset_t hold, old;
  sigemptyset(&hold);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&hold, sig);
  ::sigprocmask(SIG_BLOCK, &hold, &old);
  std::string failed;
  for (const std::string& n : names_) {
    const std::string from = staging_ + "/" + n, to = dir_ + "/" + n;
    if (failed.empty() && std::rename(from.c_str(), to.c_str()) != 0) {
      failed = to + ": " + std::strerror(errno);
    }
    untrack_temp(from);
  }
  remove_staging();
  committed_ = true;
  ::sigprocmask(SIG_SETMASK, &old, nullptr);
  if (!failed.empty()) throw InputError(dir_, "cannot move the outputs into place: " + failed);
}

}  // namespace texsim
