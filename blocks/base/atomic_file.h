#pragma once
// Output files are written under a temporary name and renamed into place only when complete,
// so a failed run never leaves a half-written report, image or trace behind.
#include <fstream>
#include <string>

namespace texsim {

// True when `path` is written in place rather than through a temporary file: "-" (standard
// output) or an existing file that is not a regular file (a FIFO, a character device such as
// /dev/null, a socket). Renaming onto those would replace the special file.
bool writes_in_place(const std::string& path);
// Path to write while `path` is being written: a temporary sibling (with `ext` appended, so a
// writer that picks its format by extension still sees it), or the target itself when it is
// written in place ("-" gives /dev/stdout).
std::string temp_path_for(const std::string& path, const std::string& ext = "");
// Renames the finished temporary file onto `path` (throws InputError naming `path` and the
// reason on failure); nothing to do for a target written in place.
void commit_temp(const std::string& temp, const std::string& path);
// A scratch file beside `path` (never `path` itself): `path`.tmp.<pid>`ext`, tracked for
// removal on SIGINT/SIGTERM until remove_temp (temp_registry.h), commit_temp or discard_temp.
std::string scratch_path_for(const std::string& path, const std::string& ext);
// Removes an unfinished temporary file; never the target written in place.
void discard_temp(const std::string& temp, const std::string& path);
// Writes `content` to `path` atomically.
void write_file_atomic(const std::string& path, const std::string& content);
// Creates the directory (and parents) and checks that a file can be created in it, or throws
// InputError naming it and the reason.
void ensure_dir(const std::string& dir);

// A text file written atomically: stream into it, then commit(); destruction without commit()
// removes the temporary file.
class AtomicTextFile {
 public:
  explicit AtomicTextFile(std::string path);
  ~AtomicTextFile();
  AtomicTextFile(const AtomicTextFile&) = delete;
  AtomicTextFile& operator=(const AtomicTextFile&) = delete;
  std::ofstream& out() { return out_; }
  void commit();

 private:
  std::string path_, temp_;
  std::ofstream out_;
  bool committed_ = false;
};

}  // namespace texsim
