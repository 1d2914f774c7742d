#include "pipeline/scene/isolated_child.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <stdexcept>

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TEXSIM_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define TEXSIM_SANITIZED 1
#endif
#ifdef TEXSIM_SANITIZED
#include <sanitizer/common_interface_defs.h>
#endif

namespace texsim {

namespace {

using Clock = std::chrono::steady_clock;

struct DeadlinePassed {};  // thrown by PipeSource; run_isolated turns it into the message

// The child's exit status, reaped at most once.
struct ChildState {
  pid_t pid = -1;
  bool reaped = false;
  int status = 0;
  bool try_reap() {
    if (reaped) return true;
    int st = 0;
    const pid_t r = ::waitpid(pid, &st, WNOHANG);
    if (r == pid) {
      reaped = true;
      status = st;
    } else if (r < 0 && errno != EINTR) {
      reaped = true;  // not ours to wait for any more (ECHILD): nothing to report
    }
    return reaped;
  }
  void kill_and_reap() {
    if (reaped) return;
    ::kill(pid, SIGKILL);  // our own child, by its id
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    reaped = true;
  }
  // Waits for the child to exit until `deadline`; false if it had not by then.
  bool reap_until(Clock::time_point deadline) {
    auto pause = std::chrono::microseconds(100);
    while (!try_reap()) {
      if (Clock::now() >= deadline) return false;
      const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(pause).count();
      const timespec ts{0, static_cast<long>(ns)};
      ::nanosleep(&ts, nullptr);
      pause = std::min(pause * 2, std::chrono::microseconds(10'000));
    }
    return true;
  }
};

// The pipe's read end with the deadline. Another process forked meanwhile (by another thread)
// may hold the write end too, so the end of the stream is also "the child has exited and nothing
// is left to read", checked every 100 ms.
class PipeSource final : public ByteSource {
 public:
  PipeSource(int fd, ChildState& child, Clock::time_point deadline)
      : fd_(fd), child_(child), deadline_(deadline) {}
  size_t read_some(void* buf, size_t n) override {
    for (;;) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline_ - Clock::now());
      if (left.count() <= 0) throw DeadlinePassed{};
      const bool exited = child_.reaped;
      pollfd p{fd_, POLLIN, 0};
      const int r =
          ::poll(&p, 1, exited ? 0 : static_cast<int>(std::min<int64_t>(left.count(), 100)));
      if (r < 0 && errno != EINTR) return 0;
      if (r > 0) {
        const ssize_t got = ::read(fd_, buf, n);
        if (got > 0) return static_cast<size_t>(got);
        if (got == 0 || (errno != EINTR && errno != EAGAIN)) return 0;
      } else if (r == 0) {
        if (exited) return 0;  // polled after the exit: all it wrote has been read
        child_.try_reap();
      }
    }
  }
  // Reads and discards the rest (a child blocked on a full pipe can then exit).
  void drain() {
    char sink[65536];
    while (read_some(sink, sizeof sink) != 0) {
    }
  }

 private:
  int fd_;
  ChildState& child_;
  Clock::time_point deadline_;
};

// The child's output: buffered writes to the pipe.
class PipeSink final : public ByteSink {
 public:
  explicit PipeSink(int fd) : fd_(fd) {}
  void write(const void* buf, size_t n) override {
    const auto* p = static_cast<const char*>(buf);
    if (used_ + n > sizeof buf_) flush();
    if (n >= sizeof buf_) return write_all(p, n);
    std::memcpy(buf_ + used_, p, n);
    used_ += n;
  }
  void flush() {
    write_all(buf_, used_);
    used_ = 0;
  }

 private:
  void write_all(const char* p, size_t n) {
    while (n > 0) {
      const ssize_t w = ::write(fd_, p, n);
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) throw std::runtime_error("write to the parent failed");
      p += w;
      n -= static_cast<size_t>(w);
    }
  }
  int fd_;
  size_t used_ = 0;
  char buf_[65536];
};

// Bytes of this process's address space (0 when unknown).
uint64_t address_space_now() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (f == nullptr) return 0;
  unsigned long long pages = 0;
  const bool ok = std::fscanf(f, "%llu", &pages) == 1;
  std::fclose(f);
  const long page = ::sysconf(_SC_PAGESIZE);
  return ok && page > 0 ? pages * static_cast<uint64_t>(page) : 0;
}

#ifdef TEXSIM_SANITIZED
// A sanitizer's report in the child ends it by SIGABRT, not by the host's handlers (libFuzzer
// would save the input as its own crash).
void die_by_abort() {
  ::signal(SIGABRT, SIG_DFL);
  ::raise(SIGABRT);
  ::_exit(134);
}
#endif

[[noreturn]] void run_child(int fd, const std::function<void(ByteSink&)>& child,
                            uint64_t address_cap) {
  // Crash signals take their default action (the host may have handlers: texsim's, a
  // fuzzer's), so the parent sees which signal it was; so do SIGINT, SIGTERM and SIGHUP, whose
  // texsim handler would remove the parent's temporary files (temp_registry.h).
  for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGTRAP, SIGSYS, SIGPIPE, SIGXCPU,
                        SIGXFSZ, SIGINT, SIGTERM, SIGHUP})
    ::signal(sig, SIG_DFL);
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
#ifdef TEXSIM_SANITIZED
  __sanitizer_set_death_callback(die_by_abort);
#endif
  const rlimit no_core{0, 0};  // a crash must not write a core file as a side effect
  ::setrlimit(RLIMIT_CORE, &no_core);
  rlimit as{};
  if (address_cap != 0 && ::getrlimit(RLIMIT_AS, &as) == 0 &&
      (as.rlim_cur == RLIM_INFINITY || as.rlim_cur > address_cap)) {
    as.rlim_cur = static_cast<rlim_t>(address_cap);
    ::setrlimit(RLIMIT_AS, &as);
  }
  int code = 0;
  try {
    PipeSink sink(fd);
    child(sink);
    sink.flush();
  } catch (...) {
    code = 3;
  }
  ::_exit(code);
}

std::string signal_text(int sig) {
  struct Name {
    int sig;
    const char* name;
    const char* what;
  };
  static const Name kNames[] = {
      {SIGSEGV, "SIGSEGV", "segmentation fault"},
      {SIGBUS, "SIGBUS", "bus error"},
      {SIGABRT, "SIGABRT", "aborted"},
      {SIGFPE, "SIGFPE", "arithmetic exception"},
      {SIGILL, "SIGILL", "illegal instruction"},
      {SIGTRAP, "SIGTRAP", "trap"},
      {SIGSYS, "SIGSYS", "bad system call"},
      {SIGPIPE, "SIGPIPE", "broken pipe"},
      {SIGXCPU, "SIGXCPU", "CPU time limit"},
      {SIGTERM, "SIGTERM", "terminated"},
      {SIGINT, "SIGINT", "interrupted"},
      {SIGHUP, "SIGHUP", "hangup"},
      {SIGKILL, "SIGKILL", "killed, e.g. by the kernel when memory ran out"},
  };
  for (const Name& n : kNames)
    if (n.sig == sig) return std::string(n.name) + ": " + n.what;
  return "signal " + std::to_string(sig);
}

std::string duration_text(int ms) {
  return ms % 1000 == 0 ? std::to_string(ms / 1000) + " s" : std::to_string(ms) + " ms";
}

// The child's failure from its wait status, or none (exit status 0).
void throw_if_failed(const ChildState& c, const std::string& file, const std::string& who) {
  if (WIFSIGNALED(c.status)) {
    throw ChildFailure(ChildFailure::Kind::Signal, file,
                       who + " crashed (" + signal_text(WTERMSIG(c.status)) +
                           "): the file is not one it reads safely");
  }
  if (WIFEXITED(c.status) && WEXITSTATUS(c.status) != 0) {
    throw ChildFailure(ChildFailure::Kind::Exit, file,
                       who + " exited with status " + std::to_string(WEXITSTATUS(c.status)));
  }
}

}  // namespace

void run_isolated(const std::string& file, const std::string& who,
                  const std::function<void(ByteSink&)>& child,
                  const std::function<void(ByteSource&)>& parent, const ChildLimits& limits) {
  int fds[2];
  // Close-on-exec: a program another thread spawns meanwhile must not hold the pipe open.
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw InputError(file, who + " cannot start: no pipe: " + std::strerror(errno));
  const uint64_t now_size = limits.extra_address_space != 0 ? address_space_now() : 0;
  const uint64_t cap = now_size != 0 ? now_size + limits.extra_address_space : 0;
  const Clock::time_point deadline = Clock::now() + std::chrono::milliseconds(limits.timeout_ms);
  const pid_t parent_pid = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int e = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    throw InputError(file, who + " cannot start: fork: " + std::strerror(e));
  }
  if (pid == 0) {
    // Killed if the thread that forked it goes (a parent that ends without reaping it, e.g. by
    // std::terminate): an orphan would live on, holding whatever pipe its parent's output is.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent_pid) ::_exit(137);  // the parent went before prctl
    ::close(fds[0]);
    run_child(fds[1], child, cap);
  }
  ::close(fds[1]);
  ChildState state;
  state.pid = pid;
  // Whatever leaves this function, the child is gone and the pipe closed.
  struct Guard {
    ChildState& c;
    int fd;
    ~Guard() {
      ::close(fd);
      c.kill_and_reap();
    }
  } guard{state, fds[0]};
  PipeSource source(fds[0], state, deadline);
  std::exception_ptr reader_error;
  bool late = false;
  try {
    parent(source);
    char extra = 0;
    if (source.read_some(&extra, 1) != 0) {
      throw ChildFailure(ChildFailure::Kind::Malformed, file,
                         who + " sent malformed data: bytes after the end of its output");
    }
  } catch (const DeadlinePassed&) {
    late = true;
  } catch (const InputError&) {
    reader_error = std::current_exception();
    try {
      source.drain();
    } catch (const DeadlinePassed&) {
      late = true;
    }
  }
  if (!late) late = !state.reap_until(deadline);
  if (late) state.kill_and_reap();
  if (late && !reader_error) {
    throw ChildFailure(
        ChildFailure::Kind::Timeout, file,
        who + " timed out after " + duration_text(limits.timeout_ms) + " and was killed");
  }
  if (!late) throw_if_failed(state, file, who);
  if (reader_error) std::rethrow_exception(reader_error);
}

}  // namespace texsim
