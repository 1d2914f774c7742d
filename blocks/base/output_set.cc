#include "blocks/base/output_set.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
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

namespace {

// Staging directories are named .texsim-staging.<host>.<pid>: on a file system shared by
// several machines (Slurm), only a directory of this host whose process is gone is stale.
std::string host_name() {
  char h[256] = {};
  if (::gethostname(h, sizeof h - 1) != 0 || h[0] == '\0') return "host";
  std::string s(h);
  for (char& c : s)
    if (c == '/' || c == '.') c = '_';
  return s;
}

constexpr const char* kStagingPrefix = ".texsim-staging.";

// Removes the staging directories that killed runs of this host left behind (SIGKILL, a power
// cut): their process no longer exists.
void remove_stale_staging(const std::string& dir, const std::string& host) {
  std::error_code ec;
  const std::string mine = std::string(kStagingPrefix) + host + ".";
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string n = e.path().filename().string();
    if (n.rfind(mine, 0) != 0) continue;
    const std::string pid_text = n.substr(mine.size());
    long pid = 0;
    const auto [end, err] =
        std::from_chars(pid_text.data(), pid_text.data() + pid_text.size(), pid);
    if (err != std::errc() || end != pid_text.data() + pid_text.size() || pid <= 0) continue;
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
    std::error_code rm;
    fs::remove_all(e.path(), rm);
  }
}

// Holds an exclusive flock on the output directory itself while a set is moved in: two runs
// committing into one directory do not interleave, and a reader that takes a shared lock on the
// directory (`flock -s DIR cat DIR/report.json`) sees one run's complete set.
class DirLock {
 public:
  explicit DirLock(const std::string& dir)
      : fd_(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)) {
    if (fd_ >= 0) {
      while (::flock(fd_, LOCK_EX) != 0 && errno == EINTR) {
      }
    }
  }
  ~DirLock() {
    if (fd_ >= 0) ::close(fd_);  // closing releases the lock
  }
  DirLock(const DirLock&) = delete;
  DirLock& operator=(const DirLock&) = delete;

 private:
  int fd_;
};

}  // namespace

OutputSet::OutputSet(std::string dir) : dir_(std::move(dir)) {
  const std::string host = host_name();
  staging_ = dir_ + "/" + std::string(kStagingPrefix) + host + "." + std::to_string(::getpid());
  ensure_dir(dir_);
  remove_stale_staging(dir_, host);
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
  const DirLock lock(dir_);
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
