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
#include "pipeline/texture/unit_array.h"
#include "testbench/lib/bench_floor.h"

namespace texsim {
namespace {

BenchFloor& fixture() {
  static BenchFloor f = make_bench_floor(640, 480);
  return f;
}

// `batched`: fragments go in batches of LinearBatch::kMax through process_batch (the SIMD
// datapath), else one by one through process.
void run(benchmark::State& state, FilterMode mode, bool timing, bool batched = false) {
  BenchFloor& fx = fixture();
  MaterialSetup m;
  m.name = "floor";
  m.filter.filter = mode;
  PipelineSetup setup;
  uint64_t cycles = 0;
  float sink = 0;
  for (auto _ : state) {
    TextureUnit unit(fx.textures, {m}, setup, TechTable::defaults(), timing);
    if (batched) {
      std::vector<Rgba> out(LinearBatch::kMax);
      for (size_t i = 0; i < fx.frags.size(); i += LinearBatch::kMax) {
        const size_t n = std::min(LinearBatch::kMax, fx.frags.size() - i);
        unit.process_batch(fx.frags.data() + i, n, 0, out.data());
        sink += out[0].r;
      }
    } else {
      for (const Fragment& f : fx.frags) sink += unit.process(f, 0).r;
    }
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
void BM_Bilinear_Functional_Batch(benchmark::State& s) {
  run(s, FilterMode::Bilinear, false, true);
}
void BM_Bilinear_Timing_Batch(benchmark::State& s) { run(s, FilterMode::Bilinear, true, true); }
void BM_Trilinear_Functional_Batch(benchmark::State& s) {
  run(s, FilterMode::Trilinear, false, true);
}
void BM_Trilinear_Timing_Batch(benchmark::State& s) { run(s, FilterMode::Trilinear, true, true); }
// Several units on one global clock (UnitArray, the scheduler in cycle order), trilinear,
// timed, one by one: the simulator's cost per fragment as the unit count grows (argument: units;
// 1 is the plain unit UnitArray wraps). `shared`: an L2 over banked DRAM behind the L1s.
// `ordered`: every fragment committed in the global cycle order (a commit observer turns off
// the early commit of fragments that hit their L1), the scheduler before that change.
void run_units(benchmark::State& state, bool shared, bool ordered = false) {
  BenchFloor& fx = fixture();
  MaterialSetup m;
  m.name = "floor";
  m.filter.filter = FilterMode::Trilinear;
  PipelineSetup setup;
  setup.units = static_cast<uint32_t>(state.range(0));
  if (shared) {
    setup.has_l2 = true;
    setup.dram_kind = PipelineSetup::DramKind::Banked;
  }
  uint64_t cycles = 0;
  float sink = 0;
  const UnitArray::Record record = [&](const Fragment&, const Fragment&, int, const Rgba* c,
                                       uint64_t) { sink += c->r; };
  for (auto _ : state) {
    UnitArray units(fx.textures, {m}, setup, TechTable::defaults(), true);
    units.set_record(record);
    if (ordered) units.set_commit_observer([](int, const ClockedPipeline&) {});
    uint64_t i = 0;
    for (const Fragment& f : fx.frags) {
      if (units.several()) {
        units.add(f, f, f, 0, i++);
      } else {
        sink += units.unit(0).process(f, 0).r;
      }
    }
    units.finish();
    cycles = units.cycles();
    benchmark::DoNotOptimize(sink);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(fx.frags.size()));
  state.counters["sim_cycles_per_frag"] =
      static_cast<double>(cycles) / static_cast<double>(fx.frags.size());
}
void BM_Units_FlatDram(benchmark::State& s) { run_units(s, false); }
void BM_Units_L2_BankedDram(benchmark::State& s) { run_units(s, true); }
void BM_Units_FlatDram_Ordered(benchmark::State& s) { run_units(s, false, true); }
BENCHMARK(BM_Units_FlatDram)->Arg(1)->Arg(2)->Arg(4)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Units_L2_BankedDram)->Arg(1)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Units_FlatDram_Ordered)->Arg(2)->Arg(16)->Unit(benchmark::kMillisecond);

BENCHMARK(BM_Bilinear_Functional)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Bilinear_Timing)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Trilinear_Functional)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Trilinear_Timing)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Bilinear_Functional_Batch)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Bilinear_Timing_Batch)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Trilinear_Functional_Batch)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Trilinear_Timing_Batch)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace texsim
