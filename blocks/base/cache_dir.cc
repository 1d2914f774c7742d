#include "blocks/base/cache_dir.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "blocks/base/input_error.h"

namespace texsim {

namespace fs = std::filesystem;

namespace {

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::string(v) : std::string();
}

}  // namespace

std::string cache_root_from_env() {
  if (std::string d = env("TEXSIM_CACHE_DIR"); !d.empty()) return d;
  if (const std::string x = env("XDG_CACHE_HOME"); !x.empty() && x[0] == '/')
    return x + "/texsim";  // relative values are invalid (XDG base directory spec)
  if (const std::string h = env("HOME"); !h.empty()) return h + "/.cache/texsim";
  return "";
}

uint64_t parse_cache_max_bytes(const std::string& s, const std::string& variable) {
  size_t used = 0;
  uint64_t v = 0;
  try {
    v = std::stoull(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  int shift = 0;
  if (used > 0 && used + 1 == s.size()) {
    const char u = s.back();
    shift = u == 'K' || u == 'k' ? 10 : u == 'M' || u == 'm' ? 20 : u == 'G' || u == 'g' ? 30 : -1;
    if (shift >= 0) ++used;
  }
  if (used == 0 || used != s.size() || s[0] == '-' || shift < 0 || v > (~uint64_t{0} >> shift)) {
    throw InputError(variable + "=" + s,
                     "expected a size in bytes, optionally with a K, M or G suffix (e.g. 2G)");
  }
  return v << shift;
}

void evict_cache_entries(const std::string& dir, uint64_t max_bytes, const std::string& suffix) {
  struct Entry {
    fs::file_time_type mtime;
    uint64_t size;
    fs::path path;
  };
  std::vector<Entry> entries;
  uint64_t total = 0;
  std::error_code ec;
  const auto stale = fs::file_time_type::clock::now() - std::chrono::hours(24);
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code e1, e2;
    const fs::path& p = it->path();
    const uint64_t size = it->file_size(e1);
    const fs::file_time_type mtime = it->last_write_time(e2);
    if (e1 || e2) continue;  // vanished: another process evicted or renamed it
    const std::string name = p.filename().string();
    if (name.size() > suffix.size() && name.ends_with(suffix) && !name.starts_with(".")) {
      entries.push_back({mtime, size, p});
      total += size;
    } else if (name.starts_with(".") && name.find(".tmp.") != std::string::npos && mtime < stale) {
      fs::remove(p, e1);  // left by a process that died while writing
    }
  }
  if (total <= max_bytes) return;
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return a.mtime < b.mtime; });
  for (const Entry& e : entries) {
    if (total <= max_bytes) break;
    std::error_code e1;
    fs::remove(e.path, e1);  // gone already: someone else freed it
    total -= e.size;
  }
}

std::string cache_temp_path(const std::string& dir, const std::string& name) {
  static std::atomic<uint64_t> serial{0};
  return dir + "/." + name + ".tmp." + std::to_string(static_cast<long>(::getpid())) + "." +
         std::to_string(serial++);
}

}  // namespace texsim
