// A run's outputs are committed as a set (all or none, older files untouched otherwise), and
// SIGINT/SIGTERM remove the temporary files and staging directory of an unfinished write.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"
#include "blocks/base/output_set.h"
#include "blocks/base/temp_registry.h"
#include "testbench/lib/temp_dir.h"

extern char** environ;

namespace texsim {
namespace {

namespace fs = std::filesystem;

std::set<std::string> listing(const std::string& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

std::string read(const std::string& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

TEST(OutputSet, FilesAppearTogetherOnCommit) {
  TempDir d("outset");
  write_file_atomic(d.file("report.json"), "old");
  OutputSet set(d.file(""));
  write_file_atomic(set.path("image.png"), "new image");
  write_file_atomic(set.path("report.json"), "new report");
  // Before the commit the output directory still holds only the old run's file.
  EXPECT_EQ(read(d.file("report.json")), "old");
  EXPECT_FALSE(fs::exists(d.file("image.png")));
  set.commit();
  EXPECT_EQ(listing(d.file("")), (std::set<std::string>{"image.png", "report.json"}));
  EXPECT_EQ(read(d.file("report.json")), "new report");
}

TEST(OutputSet, AFailureBeforeCommitLeavesTheOldFilesAndNoStaging) {
  TempDir d("outset");
  write_file_atomic(d.file("report.json"), "old");
  try {
    OutputSet set(d.file(""));
    write_file_atomic(set.path("image.png"), "new image");
    throw std::runtime_error("the report could not be written");
  } catch (const std::runtime_error&) {
  }
  EXPECT_EQ(listing(d.file("")), std::set<std::string>{"report.json"});
  EXPECT_EQ(read(d.file("report.json")), "old");
}

TEST(OutputSet, ADirectoryInTheWayMovesNothing) {
  TempDir d("outset");
  fs::create_directory(d.file("report.md"));
  OutputSet set(d.file(""));
  write_file_atomic(set.path("image.png"), "new image");
  write_file_atomic(set.path("report.md"), "new report");
  EXPECT_THROW(set.commit(), InputError);
  EXPECT_EQ(listing(d.file("")), std::set<std::string>{"report.md"});  // the directory only
}

TEST(OutputSet, RunThatCannotCommitKeepsThePreviousRunWhole) {
  TempDir d("outset");
  const std::string bin = TEXSIM_BINARY, out = d.file("out");
  ASSERT_EQ(std::system((bin + " run --no-progress --out " + out + " >/dev/null").c_str()), 0);
  const std::string image = read(out + "/image.png"), json = read(out + "/report.json");
  fs::remove(out + "/report.md");
  fs::create_directory(out + "/report.md");
  // A different run (the sample trace) into the same directory: report.md cannot be replaced,
  // so none of its files may replace the earlier run's.
  const std::string cmd = bin + " run --no-progress --trace " + TEXSIM_SOURCE_DIR +
                          "/traces/samples/basic.csv --out " + out + " 2>" + d.file("err");
  const int rc = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(rc), 2);
  EXPECT_NE(read(d.file("err")).find("report.md: is a directory: no output was moved"),
            std::string::npos)
      << read(d.file("err"));
  EXPECT_EQ(read(out + "/image.png"), image);
  EXPECT_EQ(read(out + "/report.json"), json);
  EXPECT_EQ(listing(out), (std::set<std::string>{"error.png", "image.png", "reference.png",
                                                 "report.json", "report.md"}));
}

// A run killed with SIGKILL leaves its staging directory; the next OutputSet in that directory
// removes it, and leaves alone the staging directory of a run that is still going.
TEST(OutputSet, StagingOfAKilledRunIsRemovedByTheNextRun) {
  TempDir d("outset");
  const std::string dir = d.file("");
  auto child = [&](int hold_fd) {
    const pid_t pid = ::fork();
    if (pid == 0) {
      OutputSet set(dir);
      write_file_atomic(set.path("report.json"), "unfinished");
      char c = 0;
      if (hold_fd >= 0) (void)!::read(hold_fd, &c, 1);  // alive until the parent writes
      ::_exit(0);                                       // no destructor: as if killed
    }
    return pid;
  };
  int hold[2];
  ASSERT_EQ(::pipe(hold), 0);
  const pid_t dead = child(-1);
  int status = 0;
  ASSERT_EQ(::waitpid(dead, &status, 0), dead);
  ASSERT_EQ(listing(dir).size(), 1U);  // the killed run's staging directory
  // The next run (still going) removes it when it starts.
  const pid_t alive = child(hold[0]);
  const std::string alive_tag = "." + std::to_string(alive);
  auto alive_staging = [&] {
    const std::set<std::string> l = listing(dir);
    return l.size() == 1 && l.begin()->find(alive_tag) != std::string::npos;
  };
  for (int i = 0; i < 2000 && !alive_staging(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_TRUE(alive_staging());
  {
    OutputSet next(dir);
    write_file_atomic(next.path("report.json"), "done");
    next.commit();
  }
  // The live run's staging directory stays beside the committed report.
  std::set<std::string> left = listing(dir);
  EXPECT_EQ(left.erase("report.json"), 1U);
  EXPECT_EQ(left.size(), 1U);
  if (!left.empty()) {
    EXPECT_NE(left.begin()->find(alive_tag), std::string::npos) << *left.begin();
  }
  ASSERT_EQ(::write(hold[1], "x", 1), 1);
  ASSERT_EQ(::waitpid(alive, &status, 0), alive);
  ::close(hold[0]);
  ::close(hold[1]);
}

// Two processes commit sets into one directory over and over; a reader holding a shared flock
// on the directory always finds the files of one run only.
TEST(OutputSet, AReaderHoldingTheDirectoryLockSeesOneRunsSet) {
  TempDir d("outset");
  const std::string dir = d.file("");
  const std::vector<std::string> names = {"a.json", "b.md", "c.png", "d.png", "e.png"};
  auto writer = [&](char who) {
    const pid_t pid = ::fork();
    if (pid == 0) {
      for (int i = 0; i < 60; ++i) {
        OutputSet set(dir);
        const std::string tag = std::string(1, who) + std::to_string(i);
        for (const std::string& n : names) write_file_atomic(set.path(n), tag);
        set.commit();
      }
      ::_exit(0);
    }
    return pid;
  };
  const pid_t a = writer('A'), b = writer('B');
  int checked = 0, mixed = 0;
  for (int round = 0; round < 400; ++round) {
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::flock(fd, LOCK_SH), 0);
    std::set<std::string> tags;
    for (const std::string& n : names)
      if (fs::exists(d.file(n))) tags.insert(read(d.file(n)));
    ::close(fd);
    if (tags.size() > 1) ++mixed;
    if (!tags.empty()) ++checked;
  }
  int status = 0;
  ASSERT_EQ(::waitpid(a, &status, 0), a);
  ASSERT_EQ(::waitpid(b, &status, 0), b);
  EXPECT_EQ(mixed, 0) << "of " << checked << " locked reads";
}

// In a child: a staging directory with one file, a temporary trace file, then `sig`.
void child_interrupted(const std::string& dir, int sig) {
  install_temp_cleanup();
  OutputSet set(dir);
  write_file_atomic(set.path("image.png"), "half a run");
  const std::string tmp = temp_path_for(dir + "/x.trc");
  std::ofstream(tmp) << "partial";
  std::raise(sig);
  ::_exit(0);  // not reached
}

TEST(TempRegistry, SignalsRemoveStagingAndTemporaryFiles) {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    TempDir d("outset");
    write_file_atomic(d.file("report.json"), "old");
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) child_interrupted(d.file(""), sig);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << "status " << status;
    EXPECT_EQ(listing(d.file("")), std::set<std::string>{"report.json"}) << "signal " << sig;
  }
}

// `texsim trace gen` of a large scene, interrupted while its temporary file is being written.
TEST(TempRegistry, InterruptedTraceGenLeavesNothing) {
  TempDir d("outset");
  std::ofstream(d.file("big.toml"))
      << "[output]\nwidth = 8192\nheight = 8192\n[textures.t]\nsource = "
         "\"procedural:checker?size=64\"\n[materials.m]\ntexture = \"t\"\n[[planes]]\n"
         "material = \"m\"\norigin = [-500.0, -1.0, -0.5]\nedge_u = [1000.0, 0.0, 0.0]\n"
         "edge_v = [0.0, 0.0, -1000.0]\n";
  fs::create_directory(d.file("out"));
  const std::string scene = d.file("big.toml"), out = d.file("out/big.trc");
  std::vector<const char*> argv = {TEXSIM_BINARY, "trace",     "gen",  scene.c_str(),
                                   "-o",          out.c_str(), nullptr};
  pid_t pid = 0;
  ASSERT_EQ(::posix_spawn(&pid, TEXSIM_BINARY, nullptr, nullptr,
                          const_cast<char* const*>(argv.data()), environ),
            0);
  // Wait until the temporary file exists (the scene takes seconds to write), then interrupt.
  bool seen = false;
  for (int i = 0; i < 2000 && !seen; ++i) {
    seen = !listing(d.file("out")).empty();
    if (!seen) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(seen);
  ::kill(pid, SIGINT);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << "status " << status;
  EXPECT_TRUE(listing(d.file("out")).empty());
}

}  // namespace
}  // namespace texsim
