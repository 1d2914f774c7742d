#include "blocks/base/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"
#include "blocks/base/temp_registry.h"

namespace texsim {

bool writes_in_place(const std::string& path) {
  if (path == "-") return true;
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  return !ec && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st) &&
         !std::filesystem::is_directory(st);
}

std::string scratch_path_for(const std::string& path, const std::string& ext) {
  std::string p = path + ".tmp." + std::to_string(::getpid()) + ext;
  track_temp(p);  // removed if a signal ends the process before the file is
  return p;
}

std::string temp_path_for(const std::string& path, const std::string& ext) {
  if (path == "-") return "/dev/stdout";
  if (writes_in_place(path)) return path;
  return scratch_path_for(path, ext);
}

void commit_temp(const std::string& temp, const std::string& path) {
  if (temp == path || (path == "-" && temp == "/dev/stdout")) return;
  try {
    refuse_overwriting_input(path);
  } catch (const InputError&) {
    remove_temp(temp);
    throw;
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    const std::string err = std::strerror(errno);
    remove_temp(temp);
    throw InputError(path, "cannot write output file: " + err);
  }
  untrack_temp(temp);
}

void discard_temp(const std::string& temp, const std::string& path) {
  if (temp == path || (path == "-" && temp == "/dev/stdout")) return;
  remove_temp(temp);
}

void write_file_atomic(const std::string& path, const std::string& content) {
  AtomicTextFile f(path);
  f.out() << content;
  f.commit();
}

void ensure_dir(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    throw InputError(dir, "cannot create output directory" + (ec ? ": " + ec.message() : ""));
  }
  // Outputs are written at the end of a run: find out now, not after minutes of work, whether
  // files can be created here.
  const std::string probe = scratch_path_for(dir + "/.texsim-write-check", "");
  std::FILE* f = std::fopen(probe.c_str(), "wb");
  if (!f) {
    const std::string reason = std::strerror(errno);
    untrack_temp(probe);
    throw InputError(dir, "cannot write in output directory: " + reason);
  }
  std::fclose(f);
  remove_temp(probe);
}

AtomicTextFile::AtomicTextFile(std::string path)
    : path_(std::move(path)), temp_(temp_path_for(path_)) {
  out_.open(temp_, std::ios::binary | std::ios::trunc);
  if (!out_)
    throw InputError(path_, std::string("cannot open for writing: ") + std::strerror(errno));
}

AtomicTextFile::~AtomicTextFile() {
  if (!committed_) {
    out_.close();
    discard_temp(temp_, path_);
  }
}

void AtomicTextFile::commit() {
  out_.flush();
  if (!out_) throw InputError(path_, "write failed");
  out_.close();
  commit_temp(temp_, path_);
  committed_ = true;
}

}  // namespace texsim
