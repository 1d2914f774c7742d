// C++ block models against their Verilated RTL on the same vectors (docs/rtl/blocks.md):
// Cpp/<block> runs the functional core, Rtl/<block> clocks the Verilated block one input per
// cycle (no tracing, no scoreboard). After the runs the speed ratio per block is printed. The
// sampler runs the bunny scene's fragments: FixedSampler, the texture unit's own float path
// (Cpp/texture_unit), and the Verilated sampler built single-threaded and with --threads 2.
#include <Vbilinear_lerp.h>
#include <Vrect_scan_stepper.h>
#include <Vtexsim_sampler.h>
#include <Vtexsim_sampler_mt.h>
#include <Vuv_incremental.h>
#include <Vvd_p1.h>
#include <Vvd_p2.h>
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "blocks/raster/rect_scan/coordinate_counters.h"
#include "blocks/raster/rect_scan/row_start_counter.h"
#include "blocks/texture/sampler/fixed_sampler.h"
#include "pipeline/raster/fragment_generator.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"
#include "pipeline/texture/texture_unit.h"
#include "rtl_model/params/rtl_params.h"
#include "rtl_model/verilator/rtl_harness.h"
#include "rtl_model/verilator/sampler_driver.h"

namespace texsim::rtl {
namespace {

constexpr size_t kBatch = 4096;  // vectors per benchmark iteration

std::vector<uint32_t> random_words(uint64_t seed, uint32_t mask) {
  std::mt19937_64 rng(seed);
  std::vector<uint32_t> v(kBatch);
  for (auto& x : v) x = static_cast<uint32_t>(rng()) & mask;
  return v;
}

using VdFmt = rtl_params::VdFormat;

template <class Core>
void cpp_vd(benchmark::State& state) {
  const std::vector<uint32_t> d = random_words(1, 0xffff);
  const Core core;
  for (auto _ : state) {
    int64_t sum = 0;
    for (uint32_t x : d) sum += core.template eval<VdFmt>(VdFmt::In::from_raw(x)).raw();
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kBatch));
}

template <class Model>
void rtl_vd(benchmark::State& state, const char* name) {
  const std::vector<uint32_t> d = random_words(1, 0xffff);
  RtlHarness<Model> h(name);
  h.reset();
  Model& top = h.top();
  top.in_valid = 1;
  for (auto _ : state) {
    int64_t sum = 0;
    for (uint32_t x : d) {
      top.d = static_cast<uint16_t>(x);
      h.step();
      sum += top.v;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kBatch));
}

void cpp_lerp(benchmark::State& state) {
  const BilinearLerp core(rtl_params::kLerp);
  const std::vector<uint32_t> t = random_words(2, 0xffffffff), f = random_words(3, 0xffff);
  for (auto _ : state) {
    uint64_t sum = 0;
    for (size_t i = 0; i + 3 < kBatch; ++i) {
      sum += core.lerp({t[i], t[i + 1], t[i + 2], t[i + 3]}, f[i] & 0xff, f[i] >> 8);
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * (kBatch - 3)));
}

void rtl_lerp(benchmark::State& state) {
  const std::vector<uint32_t> t = random_words(2, 0xffffffff), f = random_words(3, 0xffff);
  RtlHarness<Vbilinear_lerp> h("bilinear_lerp");
  h.reset();
  Vbilinear_lerp& top = h.top();
  top.in_valid = 1;
  for (auto _ : state) {
    uint64_t sum = 0;
    for (size_t i = 0; i + 3 < kBatch; ++i) {
      top.t00 = t[i];
      top.t10 = t[i + 1];
      top.t01 = t[i + 2];
      top.t11 = t[i + 3];
      top.fx = static_cast<uint8_t>(f[i] & 0xff);
      top.fy = static_cast<uint8_t>(f[i] >> 8);
      h.step();
      sum += top.out;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * (kBatch - 3)));
}

// One row of 64 pixels of a fixed map, as both sides compute it.
constexpr int32_t kRowPixels = 64;
constexpr std::array<int64_t, 9> kMap = {21845,   -9362, 2621440, 13107, 7281,
                                         -196608, 37,    -11,     65536};

void cpp_uv(benchmark::State& state) {
  using T = rtl_params::UvFixed;
  const UvIncrementalAdder core(rtl_params::uv_config());
  MapCoeffs<T> m;
  T* dst[9] = {&m.A, &m.B, &m.C, &m.D, &m.E, &m.F, &m.G, &m.H, &m.I};
  for (size_t j = 0; j < 9; ++j) *dst[j] = T::from_raw(kMap[j]);
  m.ok = true;
  std::vector<CoordSample> out(kRowPixels);
  int32_t y = 0;
  for (auto _ : state) {
    core.eval_row(m, RowSpan{17, y++ & 1023, kRowPixels}, out.data());
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * kRowPixels);
}

void rtl_uv(benchmark::State& state) {
  RtlHarness<Vuv_incremental> h("uv_incremental");
  h.reset();
  Vuv_incremental& top = h.top();
  uint32_t* ports[9] = {&top.ca, &top.cb, &top.cc, &top.cd, &top.ce,
                        &top.cf, &top.cg, &top.ch, &top.ci};
  for (size_t j = 0; j < 9; ++j) *ports[j] = static_cast<uint32_t>(kMap[j]);
  top.x0 = 17;
  top.n = kRowPixels;
  int32_t y = 0;
  for (auto _ : state) {
    while (!top.in_ready) h.step();
    top.y = static_cast<uint16_t>(y++ & 1023);
    top.in_valid = 1;
    h.step();
    top.in_valid = 0;
    benchmark::DoNotOptimize(top.out_u[0]);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * kRowPixels);
}

// A 33 × 9 rectangle along a line of slope 0.3, scanned by the C++ elements and by the RTL.
constexpr int32_t kScanCols = 33, kScanRows = 9;

void cpp_rect_scan(benchmark::State& state) {
  RowLine line;
  line.delta_major = int64_t{1} << rtl_params::kRectScanLine.slope_bits;
  line.delta_minor = line.delta_major * 3 / 10;
  for (auto _ : state) {
    LineStepper li(rtl_params::kRectScanLine);
    RowStartCounter start;
    CoordinateCounters counters(true);
    int64_t sum = 0;
    start.load(0, 0);
    for (; start.minor() < kScanRows; start.next_row()) {
      counters.load(start.major0(), start.minor());
      li.start_row(line);
      for (;;) {
        sum += counters.x() ^ counters.y();
        if (counters.major() >= kScanCols - 1) break;
        counters.step(li.step(line));
      }
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * kScanCols * kScanRows);
}

void rtl_rect_scan(benchmark::State& state) {
  RtlHarness<Vrect_scan_stepper> h("rect_scan_stepper");
  h.reset();
  Vrect_scan_stepper& top = h.top();
  top.x_major = 1;
  top.delta_minor = static_cast<uint16_t>((1 << rtl_params::kRectScanLine.slope_bits) * 3 / 10);
  top.major1 = kScanCols - 1;
  top.t_hi = kScanRows - 1;
  for (auto _ : state) {
    int64_t sum = 0;
    top.in_valid = 1;
    h.step();
    top.in_valid = 0;
    while (!top.in_ready) {
      h.step();
      sum += top.out_x ^ top.out_y;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * kScanCols * kScanRows);
}

// ---- The sampler: bunny's trilinear material, every fragment, in the generator's order ----
struct SamplerWork {
  Scene scene;
  std::vector<MaterialSetup> mats;
  TextureSet set;
  std::unique_ptr<TextureUnit> unit;
  std::vector<Fragment> frags;
  std::vector<FixedSampler::Input> in;
  std::vector<uint32_t> mem;
  FixedSampler::TextureDesc desc;
  FixedSampler::Config cfg;
};

const SamplerWork& sampler_work() {
  static const SamplerWork w = [] {
    SamplerWork s;
    s.scene = load_scene(std::string(TEXSIM_SOURCE_DIR) + "/scenes/bunny.toml");
    s.mats = build_materials(s.scene);
    for (size_t i = 0; i < s.scene.textures.size(); ++i) s.set.add(load_scene_texture(s.scene, i));
    s.unit = std::make_unique<TextureUnit>(s.set, s.mats, PipelineSetup{}, s.scene.tech, false);
    s.frags = generate_fragments(s.scene, 0);
    s.in.reserve(s.frags.size());
    for (const Fragment& f : s.frags) s.in.push_back(FixedSampler::to_input(f));
    const Texture& tex = s.unit->texture_of(0);
    s.mem = FixedSampler::memory_image(tex);
    s.desc = FixedSampler::describe(tex);
    s.cfg = FixedSampler::config_of(s.mats[0].filter, s.mats[0].lod);
    return s;
  }();
  return w;
}

void cpp_sampler(benchmark::State& state) {
  const SamplerWork& w = sampler_work();
  const FixedSampler fs(w.cfg);
  for (auto _ : state) {
    uint64_t sum = 0;
    for (const FixedSampler::Input& in : w.in) sum += fs.sample(in, w.desc, w.mem).rgba;
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * w.in.size()));
}

// The texture unit's own functional path (float32), fragment by fragment.
void cpp_texture_unit(benchmark::State& state) {
  const SamplerWork& w = sampler_work();
  for (auto _ : state) {
    float sum = 0;
    for (const Fragment& f : w.frags) sum += w.unit->process(f, 0).r;
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * w.frags.size()));
}

// The same through the unit's batched SIMD datapath (TextureUnit::process_batch).
void cpp_texture_unit_batch(benchmark::State& state) {
  const SamplerWork& w = sampler_work();
  std::vector<Rgba> out(w.frags.size());
  for (auto _ : state) {
    w.unit->process_batch(w.frags.data(), w.frags.size(), 0, out.data());
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * w.frags.size()));
}

template <class Model>
void rtl_sampler(benchmark::State& state, const char* name) {
  const SamplerWork& w = sampler_work();
  SamplerDriver<Model> d(name);
  d.configure(w.cfg, w.desc);
  d.set_memory(w.mem);
  Model& top = d.top();
  for (auto _ : state) {
    uint64_t sum = 0;
    for (const FixedSampler::Input& in : w.in) {
      d.input(in);
      d.clock();
      sum += top.out_rgba;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * w.in.size()));
}
void rtl_sampler_1(benchmark::State& s) { rtl_sampler<Vtexsim_sampler>(s, "texsim_sampler"); }
// The same design verilated with --threads 2.
void rtl_sampler_2(benchmark::State& s) { rtl_sampler<Vtexsim_sampler_mt>(s, "texsim_sampler_mt"); }

BENCHMARK(cpp_vd<VdEvaluatorP2>)->Name("Cpp/vd_p2");
void rtl_vd_p2(benchmark::State& state) { rtl_vd<Vvd_p2>(state, "vd_p2"); }
void rtl_vd_p1(benchmark::State& state) { rtl_vd<Vvd_p1>(state, "vd_p1"); }

BENCHMARK(rtl_vd_p2)->Name("Rtl/vd_p2");
BENCHMARK(cpp_vd<VdEvaluatorP1>)->Name("Cpp/vd_p1");
BENCHMARK(rtl_vd_p1)->Name("Rtl/vd_p1");
BENCHMARK(cpp_lerp)->Name("Cpp/bilinear_lerp");
BENCHMARK(rtl_lerp)->Name("Rtl/bilinear_lerp");
BENCHMARK(cpp_uv)->Name("Cpp/uv_incremental");
BENCHMARK(rtl_uv)->Name("Rtl/uv_incremental");
BENCHMARK(cpp_rect_scan)->Name("Cpp/rect_scan_stepper");
BENCHMARK(rtl_rect_scan)->Name("Rtl/rect_scan_stepper");
BENCHMARK(cpp_sampler)->Name("Cpp/texsim_sampler");
BENCHMARK(cpp_texture_unit)->Name("Cpp/texture_unit");
BENCHMARK(cpp_texture_unit_batch)->Name("Cpp/texture_unit_batch");
BENCHMARK(rtl_sampler_1)->Name("Rtl/texsim_sampler");
BENCHMARK(rtl_sampler_2)->Name("Rtl/texsim_sampler_threads2");

// Console output as usual, plus the time per item of every run for the ratio table.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  RatioReporter() : ConsoleReporter(OO_Tabular) {}
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      const auto it = r.counters.find("items_per_second");
      if (it != r.counters.end() && it->second.value > 0)
        rate_[r.benchmark_name()] = it->second.value;
    }
    ConsoleReporter::ReportRuns(runs);
  }
  void print_ratios() const {
    std::printf("\nC++ model vs Verilated RTL, same vectors (items/s):\n");
    for (const auto& [name, cpp] : rate_) {
      if (name.rfind("Cpp/", 0) != 0) continue;
      const auto rtl = rate_.find("Rtl/" + name.substr(4));
      if (rtl == rate_.end()) continue;
      std::printf("  %-18s C++ %10.3g  RTL %10.3g  ratio %6.1fx\n", name.substr(4).c_str(), cpp,
                  rtl->second, cpp / rtl->second);
    }
    // The texture unit's float path and the two-thread model against the sampler RTL.
    const auto rtl = rate_.find("Rtl/texsim_sampler");
    for (const char* other :
         {"Cpp/texture_unit", "Cpp/texture_unit_batch", "Rtl/texsim_sampler_threads2"}) {
      const auto it = rate_.find(other);
      if (rtl == rate_.end() || it == rate_.end()) continue;
      std::printf("  %-27s %10.3g  against Rtl/texsim_sampler %10.3g: %6.2fx\n", other, it->second,
                  rtl->second, it->second / rtl->second);
    }
  }

 private:
  std::map<std::string, double> rate_;
};

}  // namespace
}  // namespace texsim::rtl

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  texsim::rtl::RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.print_ratios();
  benchmark::Shutdown();
  return 0;
}
