#include "blocks/base/temp_registry.h"

#include <unistd.h>

#include <array>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>

namespace texsim {

namespace {

constexpr size_t kSlots = 256;
constexpr size_t kPathMax = 4096;

// A slot is free (0), being written (1) or holds a path (2); the handler reads only slots in
// state 2, so it never sees a half-copied path.
struct Slot {
  std::atomic<int> state{0};
  std::array<char, kPathMax> path{};
};
std::array<Slot, kSlots> g_slots;

// Async-signal-safe: unlink, rmdir, signal and raise only.
extern "C" void remove_temps_and_die(int sig) {
  for (Slot& s : g_slots) {
    if (s.state.load() == 2) ::unlink(s.path.data());
  }
  for (Slot& s : g_slots) {
    if (s.state.load() == 2) ::rmdir(s.path.data());
  }
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

Slot* find(const std::string& path) {
  for (Slot& s : g_slots) {
    if (s.state.load() == 2 && path == s.path.data()) return &s;
  }
  return nullptr;
}

}  // namespace

void install_temp_cleanup() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction sa {};
    sa.sa_handler = remove_temps_and_die;
    sigemptyset(&sa.sa_mask);
    ::sigaction(sig, &sa, nullptr);
  }
}

void track_temp(const std::string& path) {
  if (path.size() >= kPathMax || find(path) != nullptr) return;
  for (Slot& s : g_slots) {
    int expected = 0;
    if (!s.state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(s.path.data(), path.c_str(), path.size() + 1);
    s.state.store(2);
    return;
  }
}

void untrack_temp(const std::string& path) {
  if (Slot* s = find(path)) s->state.store(0);
}

void remove_temp(const std::string& path) {
  untrack_temp(path);
  std::remove(path.c_str());
}

}  // namespace texsim
