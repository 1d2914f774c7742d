#include "blocks/base/input_file.h"

#include <fcntl.h>
#include <pthread.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <map>
#include <mutex>
#include <utility>

#include "blocks/base/input_error.h"

namespace texsim {

namespace {

// Every input opened by this process: (device, inode) and the modification time it had. An inode
// number of a deleted input can come back as a new file, which then is not the input (a new
// file has a new modification time; a link or chmod of the input changes its ctime, not its
// mtime). Keyed by inode, so reading one file again (a fuzzer rewrites its input file for every
// run) updates its entry instead of adding one.
using FileKey = std::pair<dev_t, ino_t>;
using FileTime = std::pair<int64_t, int64_t>;
FileTime mtime_of(const struct stat& st) { return {st.st_mtim.tv_sec, st.st_mtim.tv_nsec}; }
std::mutex g_inputs_mutex;
std::map<FileKey, FileTime>& inputs_read() {
  static std::map<FileKey, FileTime> m;
  return m;
}
// A model import's child process (pipeline/scene/isolated_child.h) opens inputs: the lock is
// held across fork, so the child never starts with it held by a thread it does not have.
[[maybe_unused]] const int g_fork_safe =
    ::pthread_atfork([] { g_inputs_mutex.lock(); }, [] { g_inputs_mutex.unlock(); },
                     [] { g_inputs_mutex.unlock(); });

const char* kind_of(mode_t m) {
  if (S_ISDIR(m)) return "is a directory";
  if (S_ISFIFO(m)) return "is a FIFO (named pipe), not a regular file";
  if (S_ISCHR(m) || S_ISBLK(m)) return "is a device, not a regular file";
  if (S_ISSOCK(m)) return "is a socket, not a regular file";
  return "is not a regular file";
}

// Opens without blocking (a FIFO with no writer would block a plain open), checks the kind and
// size on the open descriptor (no race with a rename in between), then makes it blocking.
int open_checked(const std::string& path, std::string_view what, uint64_t max_bytes,
                 uint64_t* size) {
  const std::string w(what);
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    const int e = errno;
    struct stat st {};
    // A socket cannot be opened at all (ENXIO): name what it is, as for the other kinds.
    if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
      throw InputError(path, "cannot read " + w + ": " + kind_of(st.st_mode));
    throw InputError(path, "cannot open " + w + ": " +
                               (e == ENOENT ? std::string("no such file") : std::strerror(e)));
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const int e = errno;
    ::close(fd);
    throw InputError(path, "cannot open " + w + ": " + std::strerror(e));
  }
  if (!S_ISREG(st.st_mode)) {
    ::close(fd);
    throw InputError(path, "cannot read " + w + ": " + kind_of(st.st_mode));
  }
  const auto bytes = static_cast<uint64_t>(st.st_size);
  if (bytes > max_bytes) {
    ::close(fd);
    throw InputError(path, w + " is " + std::to_string(bytes) + " bytes, more than the limit of " +
                               std::to_string(max_bytes) + " bytes");
  }
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
  {
    const std::lock_guard<std::mutex> lock(g_inputs_mutex);
    inputs_read()[{st.st_dev, st.st_ino}] = mtime_of(st);
  }
  if (size != nullptr) *size = bytes;
  return fd;
}

}  // namespace

void FileCloser::operator()(std::FILE* f) const {
  if (f != nullptr) std::fclose(f);
}

InputFilePtr open_input_file(const std::string& path, std::string_view what, uint64_t max_bytes,
                             uint64_t* size) {
  const int fd = open_checked(path, what, max_bytes, size);
  std::FILE* f = ::fdopen(fd, "rb");
  if (f == nullptr) {
    const int e = errno;
    ::close(fd);
    throw InputError(path, "cannot open " + std::string(what) + ": " + std::strerror(e));
  }
  return InputFilePtr(f);
}

std::string read_input_file(const std::string& path, std::string_view what, uint64_t max_bytes) {
  uint64_t size = 0;
  const InputFilePtr f = open_input_file(path, what, max_bytes, &size);
  std::string text;
  text.resize(static_cast<size_t>(size));
  const size_t got = size == 0 ? 0 : std::fread(text.data(), 1, text.size(), f.get());
  if (std::ferror(f.get()) != 0) {
    throw InputError(path, "read error in " + std::string(what) + ": " + std::strerror(errno));
  }
  // A file that shrank while read is read as it now is; one that grew is still bounded.
  text.resize(got);
  return text;
}

uint64_t check_input_file(const std::string& path, std::string_view what, uint64_t max_bytes) {
  uint64_t size = 0;
  ::close(open_checked(path, what, max_bytes, &size));
  return size;
}

void refuse_overwriting_input(const std::string& target) {
  struct stat st {};
  if (::stat(target.c_str(), &st) != 0) return;  // nothing there to overwrite
  bool input = false;
  {
    const std::lock_guard<std::mutex> lock(g_inputs_mutex);
    const auto it = inputs_read().find({st.st_dev, st.st_ino});
    input = it != inputs_read().end() && it->second == mtime_of(st);
  }
  if (input) {
    throw InputError(target,
                     "is an input of this run: refusing to overwrite it (write the output "
                     "somewhere else, e.g. another --out)");
  }
}

}  // namespace texsim
