// Lookups per second of each anisotropic filter method against OpenImageIO's TextureSystem on
// the same queries (one run, one core), functional only and in timing mode (the filter's
// fetched texels through the texture cache and the clocked pipeline).
// Queries: a plane at 8:1 anisotropy (centre), photo texture crate-base.png, 128×128 pixels.
// Run: build/testbench/bench_filters --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <sstream>
#include <vector>

#include "blocks/texture/footprint/ewa_filter.h"
#include "blocks/texture/footprint/feline_filter.h"
#include "blocks/texture/footprint/multi_probe_filter.h"
#include "blocks/texture/footprint/spaf_filter.h"
#include "blocks/texture/footprint/weight_map.h"
#include "blocks/texture/memory/dram_model.h"
#include "blocks/texture/memory/texture_cache.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/kernel/clocked_pipeline.h"
#include "pipeline/reference/oiio_peer.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"

namespace texsim {
namespace {

std::string scene_text(double aniso) {
  // The study's view geometry (pipeline/studies/study_filters.cc): tilt acos(1/N), fov 20°.
  const double D = 10, th = std::acos(1.0 / aniso), cs = std::cos(th), sn = std::sin(th);
  const double su = 0.8 * D, sv = 1.5 * D,
               pixel = 2 * D * std::tan(10 * 3.14159265358979 / 180) / 128;
  const double texel = pixel / 1.5;
  std::ostringstream s;
  s.precision(17);
  s << "[output]\nwidth = 128\nheight = 128\n[camera]\nposition = [0.0, 0.0, 0.0]\nlook_at = [0.0, "
       "0.0, -1.0]\n"
    << "fov_y = 20.0\n[textures.t]\nsource = \"x\"\n[materials.m]\ntexture = "
       "\"t\"\n[[planes]]\nmaterial = \"m\"\n"
    << "origin = [" << -su / 2 << ", " << -0.5 * D * cs << ", " << -D + 0.5 * D * sn << "]\n"
    << "edge_u = [" << su << ", 0.0, 0.0]\nedge_v = [0.0, " << sv * cs << ", " << -sv * sn << "]\n"
    << "uv_scale = [" << su / (texel * 512) << ", " << sv / (texel * 512) << "]\n";
  return s.str();
}

struct Fixture {
  Texture tex = load_texture("/usr/share/glmark2/textures/crate-base.png", "");
  std::vector<Fragment> frags;
  Fixture() {
    tex.place(0, TexelLayout::Tiled4x4);
    const Scene scene = parse_scene(scene_text(8), "bench", "");
    const PlaneProjection proj(scene, scene.primitives[0]);
    for (int y = 0; y < 128; ++y) {
      for (int x = 0; x < 128; ++x) {
        const UvSample s = proj.at(x + 0.5, y + 0.5);
        if (!s.inside) continue;
        frags.push_back(s.fragment(static_cast<uint32_t>(x), static_cast<uint32_t>(y)));
      }
    }
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

// Timing mode: the fetched texels' cache lines through the cache (+DRAM) and a 3-stage
// pipeline (filter, cache, blend), as study filters does.
struct Timing {
  TextureCache cache;
  DramModel dram;
  ClockedPipeline pipe;
  std::vector<uint64_t> lines;
  Timing()
      : pipe({{"filter", TimingSpec{40, 1, 1, 0}, 4, 0},
              {"cache", TimingSpec{4, 1, 1, 0}, 4, 32},
              {"blend", TimingSpec{6, 1, 1, 0}, 4, 0}}) {}
  void issue(const Texture& tex, const std::vector<TexelRef>& fetched, uint32_t filter_cycles) {
    lines.clear();
    for (const TexelRef& t : fetched)
      lines.push_back(cache.line_of(tex.address(t.level, t.x, t.y)));
    std::sort(lines.begin(), lines.end());
    lines.erase(std::unique(lines.begin(), lines.end()), lines.end());
    const auto n = static_cast<uint32_t>(fetched.size());
    ItemCost cost[4];  // the kernel's unrolled 4-stage path is instantiated too
    cost[0].extra_ii = filter_cycles - 1;
    cost[1].extra_ii = n ? (n + 3) / 4 - 1 : 0;
    cost[2].extra_ii = n ? (n + 7) / 8 - 1 : 0;
    pipe.issue_with(0, [&](int s, uint64_t start) {
      if (s == 1) {
        uint64_t ready = start + 4;
        for (uint64_t l : lines) {
          if (!cache.access(l * 64)) ready = std::max(ready, dram.read(start, 64));
        }
        cost[1].extra_latency = static_cast<uint32_t>(ready - (start + 4));
      }
      return cost[s];
    });
  }
};

template <class Block>
void run_block(benchmark::State& state, const Block& b, bool timing) {
  Fixture& fx = fixture();
  std::vector<TexelRef> fetched;
  fetched.reserve(4096);
  float sink = 0;
  uint64_t texels = 0, cycles = 0;
  for (auto _ : state) {
    std::unique_ptr<Timing> t;
    if (timing) t = std::make_unique<Timing>();
    for (const Fragment& f : fx.frags) {
      fetched.clear();
      OpCounts ops;
      const FilterOutput o = b.filter(fx.tex, f, timing ? &fetched : nullptr, ops);
      sink += o.colour.r;
      texels += o.stats.texels;
      if (t) t->issue(fx.tex, fetched, b.issue_cycles(o.stats));
    }
    if (t) cycles = t->pipe.cycles();
  }
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(fx.frags.size()));
  state.counters["lookups/s"] = benchmark::Counter(
      static_cast<double>(state.iterations() * fx.frags.size()), benchmark::Counter::kIsRate);
  state.counters["texels/lookup"] =
      static_cast<double>(texels) / static_cast<double>(state.iterations() * fx.frags.size());
  if (timing)
    state.counters["cycles/frag"] =
        static_cast<double>(cycles) / static_cast<double>(fx.frags.size());
}

void BM_Ewa(benchmark::State& state, EwaFilter::Config c, bool timing) {
  run_block(state, EwaFilter(c), timing);
}

EwaFilter::Config ewa_cfg(EwaFilter::Weight w, NumberFormat a = NumberFormat::Float) {
  EwaFilter::Config c;
  c.weight = w;
  c.arith = a;
  return c;
}

void BM_EwaMap(benchmark::State& state, WeightMap::Kind k, bool timing) {
  EwaFilter::Config c;
  c.weight = EwaFilter::Weight::Map;
  WeightMap::Config m;
  m.kind = k;
  m.size = 64;
  m.function = WeightMap::Function::Pow8;
  run_block(state, EwaFilter(c, std::make_shared<const WeightMap>(m)), timing);
}

void BM_MultiProbe(benchmark::State& state, NumberFormat a, bool timing) {
  MultiProbeFilter::Config c;
  c.arith = a;
  run_block(state, MultiProbeFilter(c), timing);
}
void BM_Feline(benchmark::State& state, NumberFormat a, bool timing) {
  FelineFilter::Config c;
  c.arith = a;
  run_block(state, FelineFilter(c), timing);
}
void BM_Spaf(benchmark::State& state, SpafFilter::Config c, bool timing) {
  run_block(state, SpafFilter(c), timing);
}

// V(d) P2 cut-off in u0.16 (the RTL format): SPAF coverage or EWA edge weighting.
SubtexelCutoff::Config vd_p2_fx16() {
  SubtexelCutoff::Config v;
  v.evaluator = VdEvaluatorKind::P2;
  v.format = NumberFormat::Fx16;
  return v;
}
SpafFilter::Config spaf_cfg(SpafFilter::Coverage cov, NumberFormat a = NumberFormat::Float) {
  SpafFilter::Config c;
  c.coverage = cov;
  c.arith = a;
  if (cov == SpafFilter::Coverage::Vd) c.vd = vd_p2_fx16();
  return c;
}
EwaFilter::Config ewa_edge_cfg() {
  EwaFilter::Config c = ewa_cfg(EwaFilter::Weight::Lut);
  c.edge = EwaFilter::Edge::Vd;
  c.vd = vd_p2_fx16();
  return c;
}

void BM_Oiio(benchmark::State& state) {
  Fixture& fx = fixture();
  OiioPeer::Config pc;
  pc.max_aniso = 16;
  const OiioPeer peer(fx.tex, pc);
  float sink = 0;
  for (const Fragment& f : fx.frags) sink += peer.lookup(f).r;  // warm the tile cache
  for (auto _ : state) {
    for (const Fragment& f : fx.frags) sink += peer.lookup(f).r;
  }
  benchmark::DoNotOptimize(sink);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(fx.frags.size()));
  state.counters["lookups/s"] = benchmark::Counter(
      static_cast<double>(state.iterations() * fx.frags.size()), benchmark::Counter::kIsRate);
}

BENCHMARK(BM_Oiio)->Name("oiio_texturesystem_aniso16")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ewa, ewa_lut_float, ewa_cfg(EwaFilter::Weight::Lut), false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ewa, ewa_lut_fixed, ewa_cfg(EwaFilter::Weight::Lut, NumberFormat::S18_30),
                  false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ewa, ewa_exp_double, ewa_cfg(EwaFilter::Weight::Exp, NumberFormat::Double),
                  false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ewa, ewa_pow8_float, ewa_cfg(EwaFilter::Weight::Pow8), false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EwaMap, ewa_map_quarter, WeightMap::Kind::Quarter, false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EwaMap, ewa_map_radial_r2, WeightMap::Kind::RadialR2, false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ewa, ewa_edge_vd_p2_fx16, ewa_edge_cfg(), false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MultiProbe, multi_probe, NumberFormat::Float, false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MultiProbe, multi_probe_fixed, NumberFormat::S16_24HalfUp, false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Feline, feline, NumberFormat::Float, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Feline, feline_fixed, NumberFormat::S16_24HalfUp, false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Spaf, spaf, spaf_cfg(SpafFilter::Coverage::Mask), false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Spaf, spaf_fixed,
                  spaf_cfg(SpafFilter::Coverage::Mask, NumberFormat::S20_28HalfUp), false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Spaf, spaf_vd_p2_fx16, spaf_cfg(SpafFilter::Coverage::Vd), false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ewa, ewa_lut_float_timing, ewa_cfg(EwaFilter::Weight::Lut), true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EwaMap, ewa_map_quarter_timing, WeightMap::Kind::Quarter, true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Ewa, ewa_edge_vd_p2_fx16_timing, ewa_edge_cfg(), true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MultiProbe, multi_probe_timing, NumberFormat::Float, true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Feline, feline_timing, NumberFormat::Float, true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Spaf, spaf_timing, spaf_cfg(SpafFilter::Coverage::Mask), true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Spaf, spaf_vd_p2_fx16_timing, spaf_cfg(SpafFilter::Coverage::Vd), true)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace texsim
