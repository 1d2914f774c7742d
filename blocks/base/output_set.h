#pragma once
// The output files of one run, committed together: they are written into a staging directory
// inside the output directory and moved into it only by commit(), after every file was
// written. Without commit() (an error, an exception, SIGINT/SIGTERM) the staging directory and
// its files are removed and the files already in the output directory stay as they were.
// A staging directory that a killed process of this host left behind is removed by the next
// OutputSet in that directory. commit() holds an exclusive flock on the output directory while
// it moves the files: concurrent commits into one directory do not interleave, and a reader
// holding a shared flock on the directory sees the complete set of one run.
#include <string>
#include <vector>

namespace texsim {

class OutputSet {
 public:
  // Creates `dir` if needed and the staging directory `dir`/.texsim-staging.<host>.<pid>; throws
  // InputError naming `dir` and the reason.
  explicit OutputSet(std::string dir);
  ~OutputSet();
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  // Where to write the output `name` (a plain file name) until commit().
  std::string path(const std::string& name);
  // The staging directory, for writers that take a directory.
  const std::string& staging() const { return staging_; }
  // Moves every file named by path() (and any file written into staging()) into the output
  // directory, with SIGINT, SIGTERM and SIGHUP held back until all are moved.
  void commit();

 private:
  void remove_staging();
  std::string dir_, staging_;
  std::vector<std::string> names_;
  bool committed_ = false;
};

}  // namespace texsim
