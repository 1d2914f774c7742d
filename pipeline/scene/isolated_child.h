#pragma once
// A function run in a forked child process, its output streamed to the parent through a pipe,
// so that third-party code reading untrusted input (Assimp, model_loader.cc) can crash, hang or
// exhaust memory without taking texsim with it. The parent reads with a deadline; a child that
// is killed by a signal, exits non-zero, runs past the time limit (then SIGKILL) or sends what
// the parent's reader refuses becomes a ChildFailure naming the file and which of these it was.
// The child is a copy of a process that may have threads: it runs only the given function,
// then _exit()s (no atexit handlers, no stdio flush); what it may use is what stays usable after
// fork (glibc's malloc and stdio; texsim's input registry, input_file.cc). Crash signals take
// their default action in it, it dumps no core, and its address space is capped (RLIMIT_AS).
// POSIX: fork, pipe, poll, waitpid, setrlimit.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

#include "blocks/base/input_error.h"

namespace texsim {

// Bytes in: read_some returns 1 to n bytes, 0 at the end of the stream.
class ByteSource {
 public:
  virtual ~ByteSource() = default;
  virtual size_t read_some(void* buf, size_t n) = 0;
};

// Bytes out (all n, or an exception).
class ByteSink {
 public:
  virtual ~ByteSink() = default;
  virtual void write(const void* buf, size_t n) = 0;
};

// The child failed: what() is "FILE: WHO crashed (SIGSEGV: …)", "… timed out …", "… exited
// with status N" or "… sent malformed data: …".
class ChildFailure : public InputError {
 public:
  enum class Kind { Signal, Timeout, Exit, Malformed };
  ChildFailure(Kind k, const std::string& file, const std::string& what)
      : InputError(file, what), kind(k) {}
  Kind kind;
};

struct ChildLimits {
  int timeout_ms = 30'000;
  // RLIMIT_AS of the child: its address space may grow by this much over the parent's size at
  // the fork (/proc/self/statm; no cap where that cannot be read). 0: no cap.
  uint64_t extra_address_space = uint64_t{4} << 30;
};

// Runs `child(sink)` in a forked process and `parent(source)` here on what the child writes;
// afterwards the stream must end and the child exit with status 0. `file` and `who` ("the model
// importer (Assimp)") name them in errors. When the child failed, its failure replaces an
// InputError `parent` throws (a crash mid-stream shows as a short stream to the reader).
void run_isolated(const std::string& file, const std::string& who,
                  const std::function<void(ByteSink&)>& child,
                  const std::function<void(ByteSource&)>& parent, const ChildLimits& limits = {});

}  // namespace texsim
