// Fragments per second of the texture unit on one core: functional-only vs timing mode, for
// bilinear and trilinear materials on a grazing checkerboard floor (fragments generated once,
// in memory, so the trace reader is not what is measured; see bench_trace_stream for that).
// Run: build/testbench/bench_texture_unit --benchmark_counters_tabular=true
// Wall-clock figures move with other load on the machine: compare binaries side by side in one
// session, or count instructions per fragment, which load does not change (one command):
//   valgrind --tool=callgrind --toggle-collect='texsim::TextureUnit::process(texsim::Fragment
//     const&, int, texsim::ItemCost const*)' build/testbench/bench_texture_unit
//     --benchmark_filter='BM_Bilinear_Timing$' --benchmark_min_time=0.000001
// (one iteration; the collected total divided by the `fragments` counter). The exact signature
// matters: a pattern such as 'process*' also matches functions called inside process() and
// switches collection off when they return. docs/performance.md has the figures.
#include <benchmark/benchmark.h>

#include "pipeline/texture/texture_unit.h"
#include "testbench/lib/bench_floor.h"

namespace texsim {
namespace {

BenchFloor& fixture() {
  static BenchFloor f = make_bench_floor(640, 480);
  return f;
}

void run(benchmark::State& state, FilterMode mode, bool timing) {
  BenchFloor& fx = fixture();
  MaterialSetup m;
  m.name = "floor";
  m.filter.filter = mode;
  PipelineSetup setup;
  uint64_t cycles = 0;
  float sink = 0;
  for (auto _ : state) {
    TextureUnit unit(fx.textures, {m}, setup, TechTable::defaults(), timing);
    for (const Fragment& f : fx.frags) sink += unit.process(f, 0).r;
    cycles = unit.cycles();
    benchmark::DoNotOptimize(sink);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(fx.frags.size()));
  state.counters["fragments"] = static_cast<double>(fx.frags.size());
  state.counters["sim_cycles_per_frag"] =
      static_cast<double>(cycles) / static_cast<double>(fx.frags.size());
}

void BM_Bilinear_Functional(benchmark::State& s) { run(s, FilterMode::Bilinear, false); }
void BM_Bilinear_Timing(benchmark::State& s) { run(s, FilterMode::Bilinear, true); }
void BM_Trilinear_Functional(benchmark::State& s) { run(s, FilterMode::Trilinear, false); }
void BM_Trilinear_Timing(benchmark::State& s) { run(s, FilterMode::Trilinear, true); }
BENCHMARK(BM_Bilinear_Functional)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Bilinear_Timing)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Trilinear_Functional)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Trilinear_Timing)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace texsim
