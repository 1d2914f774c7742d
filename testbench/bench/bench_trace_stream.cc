// Streaming trace I/O (traces/FORMAT.md): read and write throughput in fragments/s, and the
// peak-RSS growth of reading a 10^5 vs a 10^7 fragment trace, which shows that the reader's
// memory does not depend on the trace length. Traces are written once per process into a
// temporary directory that is removed at exit (the 10^7 one is ~720 MB).
#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "traces/trace_file.h"

namespace {

namespace fs = std::filesystem;
using texsim::Fragment;
using texsim::TraceHeader;
using texsim::TraceReader;
using texsim::TraceWriter;

TraceHeader bench_header() {
  TraceHeader h;
  h.has_lod_bias = true;
  h.textures = {{0, "checker", "procedural:checker?size=512&cells=16", 512, 512},
                {1, "noise", "procedural:noise?size=256", 256, 256}};
  return h;
}

// A plausible fragment stream: 1920-wide scan lines, two textures, smooth coordinates.
Fragment bench_fragment(uint64_t i) {
  Fragment f;
  f.frame = static_cast<uint32_t>(i / 2000000);
  f.prim = static_cast<uint32_t>(i / 64);
  f.x = static_cast<uint32_t>(i % 1920);
  f.y = static_cast<uint32_t>((i / 1920) % 1080);
  f.tex = static_cast<uint32_t>((i / 64) % 2);
  f.u = static_cast<double>(f.x) / 1920.0;
  f.v = static_cast<double>(f.y) / 1080.0;
  f.dudx = 1.0 / 1920.0;
  f.dvdx = 1e-5 * static_cast<double>(i % 7);
  f.dudy = -1e-5 * static_cast<double>(i % 5);
  f.dvdy = 1.0 / 1080.0;
  f.lod_bias = static_cast<float>(i % 3) * 0.5f;
  return f;
}

// Owns the temporary traces; removes them when the process exits normally.
class TraceFiles {
 public:
  ~TraceFiles() {
    std::error_code ec;
    if (!dir_.empty()) fs::remove_all(dir_, ec);
  }
  const std::string& binary(uint64_t n) {
    auto it = files_.find(n);
    if (it != files_.end()) return it->second;
    const std::string path = (directory() / ("bench_" + std::to_string(n) + ".trc")).string();
    TraceWriter w(path, bench_header());
    for (uint64_t i = 0; i < n; ++i) w.write(bench_fragment(i));
    w.close();
    return files_.emplace(n, path).first->second;
  }
  fs::path directory() {
    if (dir_.empty()) {
      dir_ = fs::temp_directory_path() / ("texsim_bench_trace_" + std::to_string(::getpid()));
      fs::create_directories(dir_);
    }
    return dir_;
  }

 private:
  fs::path dir_;
  std::map<uint64_t, std::string> files_;
};

TraceFiles& files() {
  static TraceFiles f;
  return f;
}

// Reads the whole trace; returns a checksum so the decode cannot be optimised away.
double stream_all(const std::string& path, uint64_t* records) {
  TraceReader r(path);
  std::vector<Fragment> chunk;
  double sum = 0;
  uint64_t n = 0;
  while (size_t got = r.next_chunk(chunk)) {
    for (const Fragment& f : chunk) sum += f.u + f.dvdy + static_cast<double>(f.tex);
    n += got;
  }
  *records = n;
  return sum;
}

long maxrss_kb() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_maxrss;  // kilobytes on Linux
}

long current_rss_kb() {
  long pages_total = 0, pages_resident = 0;
  if (std::FILE* f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%ld %ld", &pages_total, &pages_resident) != 2) pages_resident = 0;
    std::fclose(f);
  }
  return pages_resident * (sysconf(_SC_PAGESIZE) / 1024);
}

void BM_TraceStreamRead(benchmark::State& state) {
  const auto n = static_cast<uint64_t>(state.range(0));
  const std::string& path = files().binary(n);
  uint64_t records = 0;
  for (auto _ : state) benchmark::DoNotOptimize(stream_all(path, &records));
  if (records != n) state.SkipWithError("record count mismatch");
  state.SetItemsProcessed(static_cast<int64_t>(n) * state.iterations());
  state.SetBytesProcessed(static_cast<int64_t>(fs::file_size(path)) * state.iterations());
}
BENCHMARK(BM_TraceStreamRead)->Arg(1000000)->Unit(benchmark::kMillisecond);

void BM_TraceStreamWrite(benchmark::State& state) {
  const auto n = static_cast<uint64_t>(state.range(0));
  const std::string path = (files().directory() / "bench_write.trc").string();
  for (auto _ : state) {
    TraceWriter w(path, bench_header());
    for (uint64_t i = 0; i < n; ++i) w.write(bench_fragment(i));
    w.close();
  }
  state.SetItemsProcessed(static_cast<int64_t>(n) * state.iterations());
  state.SetBytesProcessed(static_cast<int64_t>(fs::file_size(path)) * state.iterations());
  fs::remove(path);
}
BENCHMARK(BM_TraceStreamWrite)->Arg(1000000)->Unit(benchmark::kMillisecond);

// Peak-RSS growth of streaming a whole trace. Each read runs in a fresh child process: the
// peak RSS is a high-water mark, so measuring in this process would carry the writing of the
// trace and earlier runs. A child's high-water mark starts at its RSS at fork().
void BM_TraceStreamRss(benchmark::State& state) {
  const auto n = static_cast<uint64_t>(state.range(0));
  const std::string& path = files().binary(n);
  long growth_kb = -1, rss_before_kb = -1, rss_after_kb = -1;
  for (auto _ : state) {
    int fds[2];
    if (pipe(fds) != 0) {
      state.SkipWithError("pipe failed");
      return;
    }
    std::fflush(nullptr);
    const pid_t pid = fork();
    if (pid == 0) {
      close(fds[0]);
      long out[4] = {maxrss_kb(), 0, 0, 0};
      uint64_t records = 0;
      benchmark::DoNotOptimize(stream_all(path, &records));
      out[1] = maxrss_kb();
      out[2] = current_rss_kb();
      out[3] = static_cast<long>(records);
      const bool ok = write(fds[1], out, sizeof out) == static_cast<ssize_t>(sizeof out);
      _exit(ok ? 0 : 1);  // no static destructors: they would delete the parent's traces
    }
    close(fds[1]);
    long in[4] = {0, 0, 0, 0};
    const bool got = read(fds[0], in, sizeof in) == static_cast<ssize_t>(sizeof in);
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    if (!got || !WIFEXITED(status) || WEXITSTATUS(status) != 0 || in[3] != static_cast<long>(n)) {
      state.SkipWithError("child reader failed");
      return;
    }
    growth_kb = in[1] - in[0];
    rss_before_kb = in[0];
    rss_after_kb = in[2];
  }
  state.counters["fragments"] = static_cast<double>(n);
  state.counters["trace_MB"] = static_cast<double>(fs::file_size(path)) / 1e6;
  state.counters["maxrss_growth_kB"] = static_cast<double>(growth_kb);
  state.counters["maxrss_before_kB"] = static_cast<double>(rss_before_kb);
  state.counters["rss_after_kB"] = static_cast<double>(rss_after_kb);
  state.SetItemsProcessed(static_cast<int64_t>(n) * state.iterations());
}
BENCHMARK(BM_TraceStreamRss)
    ->Arg(100000)
    ->Arg(10000000)
    ->Iterations(1)
    ->UseRealTime()  // the work happens in the child: CPU time of this process means nothing
    ->Unit(benchmark::kMillisecond);

}  // namespace
