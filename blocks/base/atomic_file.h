#pragma once
// Output files are written under a temporary name and renamed into place only when complete,
// so a failed run never leaves a half-written report, image or trace behind.
#include <fstream>
#include <string>

namespace texsim {

// Path of the temporary sibling used while `path` is being written.
std::string temp_path_for(const std::string& path);
// Renames the finished temporary file onto `path` (throws InputError naming `path` on failure).
void commit_temp(const std::string& temp, const std::string& path);
// Writes `content` to `path` atomically.
void write_file_atomic(const std::string& path, const std::string& content);
// Creates the directory (and parents) or throws InputError naming it.
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
