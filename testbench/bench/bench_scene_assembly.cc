// Effect-driven assembly costs nothing per fragment: a bilinear-only scene's texture unit built
// by the scene builder (build_materials through the effect registry) against one built by hand
// from a MaterialSetup with only the bilinear path, on the same fragments, side by side.
// Run: build/testbench/bench_scene_assembly --benchmark_repetitions=5
//        --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true
// The ratio of the two medians is the builder's overhead (expected ≈ 1.0).
#include <benchmark/benchmark.h>

#include "pipeline/texture/effect_registry.h"
#include "pipeline/texture/texture_unit.h"
#include "testbench/lib/bench_floor.h"

namespace texsim {
namespace {

BenchFloor& fixture() {
  static BenchFloor f = make_bench_floor(480, 360, "filter = { mode = \"bilinear\" }\n");
  return f;
}

void run(benchmark::State& state, const std::vector<MaterialSetup>& mats) {
  BenchFloor& fx = fixture();
  float sink = 0;
  uint64_t cycles = 0;
  for (auto _ : state) {
    TextureUnit unit(fx.textures, mats, PipelineSetup{}, fx.scene.tech, true);
    for (const Fragment& f : fx.frags) sink += unit.process(f, 0).r;
    cycles = unit.cycles();
    benchmark::DoNotOptimize(sink);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(fx.frags.size()));
  state.counters["sim_cycles"] = static_cast<double>(cycles);  // equal for both: same pipeline
}

void BM_SceneBuilder(benchmark::State& s) { run(s, build_materials(fixture().scene)); }

void BM_HandBuilt(benchmark::State& s) {
  MaterialSetup m;
  m.name = "floor";
  m.filter.filter = FilterMode::Bilinear;
  run(s, {m});
}

BENCHMARK(BM_SceneBuilder)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_HandBuilt)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace texsim
