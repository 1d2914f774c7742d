// Fragments per second of texsim's functional texture unit beside Mesa's llvmpipe and softpipe
// (pipeline/reference/mesa_peer.h) filtering the same grazing checkerboard floor as
// bench_texture_unit (same camera, plane and 1024² texture with its mips), bilinear
// (GL_LINEAR_MIPMAP_NEAREST) and trilinear, one thread each. Mesa's figure is its draw time
// alone (texture uploaded, one warm-up draw, glFinish on both sides; manual timing), per
// texsim's fragment count of the view. scripts/bench-peers.sh runs it with llvmpipe on one
// thread (LP_NUM_THREADS=0) and prints the ratios; a driver that cannot start is reported as
// an error row with Mesa's reason.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <memory>
#include <vector>

#include "pipeline/reference/mesa_peer.h"
#include "pipeline/texture/texture_unit.h"
#include "testbench/lib/bench_floor.h"

namespace texsim {
namespace {

BenchFloor& fixture() {
  static BenchFloor f = make_bench_floor(640, 480);
  return f;
}

void set_counters(benchmark::State& state, size_t fragments) {
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(fragments));
  state.counters["fragments"] = static_cast<double>(fragments);
}

void texsim_run(benchmark::State& state, FilterMode mode) {
  BenchFloor& fx = fixture();
  MaterialSetup m;
  m.name = "floor";
  m.filter.filter = mode;
  float sink = 0;
  for (auto _ : state) {
    TextureUnit unit(fx.textures, {m}, PipelineSetup{}, TechTable::defaults(), false);
    // The batched datapath (SIMD across fragments), texsim's fastest functional path.
    std::vector<Rgba> out(LinearBatch::kMax);
    for (size_t i = 0; i < fx.frags.size(); i += LinearBatch::kMax) {
      const size_t n = std::min(LinearBatch::kMax, fx.frags.size() - i);
      unit.process_batch(fx.frags.data() + i, n, 0, out.data());
      sink += out[0].r;
    }
    benchmark::DoNotOptimize(sink);
  }
  set_counters(state, fx.frags.size());
}

// One peer per driver for the whole run (starting one costs up to ~60 ms).
const MesaPeer& peer(MesaDriver d) {
  static std::map<MesaDriver, std::unique_ptr<MesaPeer>> peers;
  auto& p = peers[d];
  if (!p) p = std::make_unique<MesaPeer>(d);
  return *p;
}

void mesa_run(benchmark::State& state, MesaDriver d, MesaFilter filter) {
  const MesaPeer& p = peer(d);
  if (!p.available()) {
    state.SkipWithError(p.why_not().c_str());
    return;
  }
  BenchFloor& fx = fixture();
  MesaView view = mesa_view(fx.scene, fx.textures, {AddressMode::Wrap});
  view.filter = filter;
  for (auto _ : state) state.SetIterationTime(p.time_draws(view, 1));
  set_counters(state, fx.frags.size());
  state.SetLabel(p.renderer());
}

void BM_Texsim_Bilinear(benchmark::State& s) { texsim_run(s, FilterMode::Bilinear); }
void BM_Texsim_Trilinear(benchmark::State& s) { texsim_run(s, FilterMode::Trilinear); }
void BM_Llvmpipe_Bilinear(benchmark::State& s) {
  mesa_run(s, MesaDriver::Llvmpipe, MesaFilter::Bilinear);
}
void BM_Llvmpipe_Trilinear(benchmark::State& s) {
  mesa_run(s, MesaDriver::Llvmpipe, MesaFilter::Trilinear);
}
void BM_Softpipe_Bilinear(benchmark::State& s) {
  mesa_run(s, MesaDriver::Softpipe, MesaFilter::Bilinear);
}
void BM_Softpipe_Trilinear(benchmark::State& s) {
  mesa_run(s, MesaDriver::Softpipe, MesaFilter::Trilinear);
}
BENCHMARK(BM_Texsim_Bilinear)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Texsim_Trilinear)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Llvmpipe_Bilinear)->Unit(benchmark::kMillisecond)->UseManualTime();
BENCHMARK(BM_Llvmpipe_Trilinear)->Unit(benchmark::kMillisecond)->UseManualTime();
BENCHMARK(BM_Softpipe_Bilinear)->Unit(benchmark::kMillisecond)->UseManualTime();
BENCHMARK(BM_Softpipe_Trilinear)->Unit(benchmark::kMillisecond)->UseManualTime();

}  // namespace
}  // namespace texsim
