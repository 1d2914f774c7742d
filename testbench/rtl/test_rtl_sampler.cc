// Lockstep of the RTL sampler (rtl_model/rtl/texsim_sampler.v) over the shipped scenes'
// bilinear and trilinear materials: every fragment the scene's fragment generator gives such a
// material goes through the Verilated sampler (its texel reads answered from the texture's
// memory image) and through its C++ core FixedSampler: the eight texel word addresses on the
// cycle the C++ latencies put them, the levels, the level fraction and the RGBA8 colour bit for
// bit on the C++ latency, the op counters. The same fragments go through the texture unit's
// own float32 path (TextureUnit::process, TexelAddressGen's taps): levels, addresses and colours
// are compared and counted (docs/rtl/blocks.md says why they cannot all be equal).
// CI runs a sample per scene ($TEXSIM_RTL_SAMPLER_FRAGMENTS per scene; 0 = every fragment).
#include <Vtexsim_sampler.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "pipeline/raster/fragment_generator.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"
#include "pipeline/texture/texture_unit.h"
#include "rtl_model/params/rtl_params.h"
#include "rtl_model/verilator/sampler_driver.h"
#include "testbench/rtl/lockstep.h"

namespace texsim::rtl {
namespace {

using Model = Vtexsim_sampler;

uint64_t fragments_per_scene(uint64_t def) {
  const char* s = std::getenv("TEXSIM_RTL_SAMPLER_FRAGMENTS");  // NOLINT(concurrency-mt-unsafe)
  if (s == nullptr || *s == '\0') return def;
  const uint64_t n = std::strtoull(s, nullptr, 10);
  return n == 0 ? UINT64_MAX : n;
}

// What the run compared, per scene.
struct SceneCounts {
  std::string scene;
  uint64_t fragments = 0;     // through RTL and FixedSampler
  uint64_t mismatches = 0;    // RTL against FixedSampler (colours, levels, addresses, latency)
  uint64_t level_equal = 0;   // FixedSampler's levels and δ equal to TexelAddressGen's
  uint64_t addr_equal = 0;    // and its eight addresses equal to the taps' (levels equal)
  uint64_t colour_equal = 0;  // RGBA8 equal to the texture unit's colour rounded to 8 bits
  int colour_max_diff = 0;    // largest channel difference, in LSB of 8 bits
  // The texture unit with `filter.arithmetic = "fixed"`: its result (levels, delta, addresses,
  // RGBA8) equal to FixedSampler's, and its colour equal to that RGBA8.
  uint64_t fixed_equal = 0;
  std::string report;
};

// A negative control: `delta` added to word `word` of the expectation of transaction `at` on
// the colour board (stage 0) or the texel-read board (stage 1).
struct Perturb {
  int stage = -1;
  size_t word = 0;
  int64_t delta = 0;
  uint64_t at = 0;
  int latency = 0;  // added to the colour board's latency
};

class SamplerBench {
 public:
  explicit SamplerBench(const Perturb& p)
      : p_(p),
        colours_("texsim_sampler",
                 FixedSampler::latency(rtl_params::tech()) + static_cast<uint32_t>(p.latency)),
        reads_("texsim_sampler reads", FixedSampler::lod_latency(rtl_params::tech()) +
                                           FixedSampler::address_latency(rtl_params::tech())),
        d_("texsim_sampler") {}

  // Configures the sampler for one material and texture (pipeline empty).
  void configure(const FixedSampler& fs, const FixedSampler::TextureDesc& t, const OpCounts& ops,
                 std::vector<uint32_t> mem) {
    // The RTL counts the four kinds it has counters for.
    item_ops_ = OpCounts{};
    item_ops_.add = ops.add;
    item_ops_.mul = ops.mul;
    item_ops_.div = ops.div;
    item_ops_.cmp = ops.cmp;
    d_.configure(fs.config(), t, item_ops_);
    d_.set_memory(std::move(mem));
  }

  void issue(const FixedSampler::Input& in, const FixedSampler::Result& r) {
    OutWords col{r.rgba, r.level_hi, r.level_lo, r.delta};
    OutWords rd{};
    for (size_t k = 0; k < 8; ++k) rd[k] = r.addr[k];
    if (issued_ == p_.at && p_.stage == 0) col[p_.word] += p_.delta;
    if (issued_ == p_.at && p_.stage == 1) rd[p_.word] += p_.delta;
    ops_ += item_ops_;
    const std::string text = "fragment " + std::to_string(issued_);
    colours_.expect(text, d_.cycle(), col, ops_);
    reads_.expect(text, d_.cycle(), rd, {});
    d_.input(in);
    clock();
    d_.no_input();
    ++issued_;
  }

  // Runs until every fragment retired, and one cycle more: the counters take the last
  // retirement's cfg_*_n at that edge, so the configuration may change only after it.
  void drain() {
    for (int i = 0; i < 256 && colours_.pending() > 0; ++i) clock();
    clock();
  }
  uint64_t finish() {
    drain();
    colours_.finish();
    reads_.finish();
    return colours_.mismatches() + reads_.mismatches();
  }
  std::string report() const { return colours_.report() + reads_.report(); }
  uint64_t compared() const { return colours_.compared(); }

 private:
  void clock() {
    d_.clock();
    Model& top = d_.top();
    if (top.rd_valid) {
      OutWords rd{};
      for (size_t k = 0; k < 8; ++k) rd[k] = top.rd_addr[k];
      reads_.observe(d_.cycle(), rd, {});
    }
    if (top.out_valid) {
      colours_.observe(d_.cycle(),
                       {top.out_rgba, top.out_level_hi, top.out_level_lo, top.out_delta},
                       d_.harness().ops());
    }
  }

  Perturb p_;
  Scoreboard colours_, reads_;
  SamplerDriver<Model> d_;
  OpCounts ops_, item_ops_;
  uint64_t issued_ = 0;
};

// Whether material m of the unit is one the RTL sampler covers at its build parameters.
bool covered(const MaterialSetup& m, const Texture& tex) {
  if (m.footprint || m.relief || m.lighting || m.coords) return false;
  if (!FixedSampler::covers(m.filter, m.lod, nullptr)) return false;
  const TexelAddressGen::Config d;
  if (m.filter.sub_texel_bits != d.sub_texel_bits || m.filter.mipmap_bits != d.mipmap_bits)
    return false;
  return tex.format() == TexelFormat::Rgba8 && tex.storage() == StorageFormat::Rgba8Unorm &&
         !tex.compressed() && tex.shape().type == TextureType::Tex2D &&
         tex.levels() <= FixedSampler::kMaxLevels;
}

uint8_t to8(float x) {
  const float c = std::clamp(x, 0.0f, 1.0f) * 255.0f;
  return static_cast<uint8_t>(std::lrint(c));
}

// The texture unit's own path for one fragment: its taps' levels and word addresses, and its
// colour rounded to RGBA8; compared with FixedSampler's result into `n`.
void compare_with_unit(const MaterialSetup& m, const Texture& tex, const Fragment& f, Rgba colour,
                       const FixedSampler::Result& r, SceneCounts& n) {
  const LodUnit lod(m.lod);
  const TexelAddressGen gen(m.filter);
  FilterTaps taps;
  const LodResult lr = lod.eval(f, tex.width(0), tex.height(0));
  gen.taps(tex, f.u, f.v, lr, taps);
  const TexelAddressGen::LevelSelect sel = gen.select_levels(lr.lambda, tex.levels());
  const auto delta = static_cast<uint32_t>(std::lrint(sel.delta * 256.0f));
  const bool tri = m.filter.filter == FilterMode::Trilinear;
  if (sel.d_hi == r.level_hi && sel.d_lo == r.level_lo && (!tri || delta == r.delta)) {
    ++n.level_equal;
    bool same = true;
    for (int k = 0; k < taps.count && k < 8; ++k) {
      const TexelTap& t = taps.tap[static_cast<size_t>(k)];
      const uint64_t a = (tex.address(t.level, t.x, t.y) - tex.base()) / 4;
      same = same && a == r.addr[static_cast<size_t>(k)];
    }
    n.addr_equal += same ? 1 : 0;
  }
  const uint8_t want[4] = {to8(colour.r), to8(colour.g), to8(colour.b), to8(colour.a)};
  int worst = 0;
  for (int c = 0; c < 4; ++c)
    worst = std::max(worst, std::abs(static_cast<int>((r.rgba >> (8 * c)) & 255) - want[c]));
  n.colour_equal += worst == 0 ? 1 : 0;
  n.colour_max_diff = std::max(n.colour_max_diff, worst);
}

SceneCounts run_scene(const std::string& name, uint64_t most, TexelLayout layout,
                      const Perturb& p = {}) {
  SceneCounts n;
  n.scene = name;
  const Scene scene = load_scene(std::string(TEXSIM_SOURCE_DIR) + "/scenes/" + name + ".toml");
  const std::vector<MaterialSetup> mats = build_materials(scene);
  TextureSet set;
  for (size_t i = 0; i < scene.textures.size(); ++i) set.add(load_scene_texture(scene, i));
  PipelineSetup setup;
  setup.layout = layout;
  TextureUnit unit(set, mats, setup, scene.tech, false);
  // The same materials with fixed arithmetic where it covers them: the unit the RTL must equal.
  std::vector<MaterialSetup> fixed_mats = mats;
  for (size_t m = 0; m < mats.size(); ++m)
    fixed_mats[m].filter.fixed_arithmetic = covered(mats[m], unit.texture_of(static_cast<int>(m)));
  TextureUnit fixed_unit(set, fixed_mats, setup, scene.tech, false);
  // The covered materials' fragments, per material, in the generator's order.
  std::vector<std::vector<Fragment>> by_mat(mats.size());
  std::vector<bool> ok(mats.size());
  for (size_t m = 0; m < mats.size(); ++m)
    ok[m] = covered(mats[m], unit.texture_of(static_cast<int>(m)));
  uint64_t taken = 0;
  generate_fragments(scene, 0, [&](const Fragment& f) {
    const auto m = static_cast<size_t>(scene.primitives[f.prim].material);
    if (taken >= most || !ok[m] || f.op != 0 || f.lod_bias != 0.0f) return;
    by_mat[m].push_back(f);
    ++taken;
  });
  SamplerBench bench(p);
  for (size_t m = 0; m < mats.size(); ++m) {
    if (by_mat[m].empty()) continue;
    const Texture& tex = unit.texture_of(static_cast<int>(m));
    const FixedSampler fs(FixedSampler::config_of(mats[m].filter, mats[m].lod));
    const FixedSampler::TextureDesc desc = FixedSampler::describe(tex);
    std::vector<uint32_t> mem = FixedSampler::memory_image(tex);
    bench.drain();
    bench.configure(fs, desc, fs.ops_per_item(mats[m].filter, mats[m].lod), mem);
    for (const Fragment& f : by_mat[m]) {
      const FixedSampler::Input in = FixedSampler::to_input(f);
      const FixedSampler::Result r = fs.sample(in, desc, mem);
      // The RTL's expectation is the fixed-arithmetic texture unit's own result.
      const Rgba fc = fixed_unit.process(f, static_cast<int>(m));
      const FixedSampler::Result& u = fixed_unit.last_fixed();
      const uint32_t fc8 = uint32_t{to8(fc.r)} | uint32_t{to8(fc.g)} << 8 |
                           uint32_t{to8(fc.b)} << 16 | uint32_t{to8(fc.a)} << 24;
      n.fixed_equal += u.rgba == r.rgba && u.level_hi == r.level_hi && u.level_lo == r.level_lo &&
                       u.delta == r.delta && u.addr == r.addr && fc8 == u.rgba;
      bench.issue(in, u);
      compare_with_unit(mats[m], tex, f, unit.process(f, static_cast<int>(m)), r, n);
    }
  }
  n.mismatches = bench.finish();
  n.fragments = bench.compared();
  n.report = bench.report();
  std::cout << "texsim_sampler " << name << ": " << n.fragments << " fragments, " << n.mismatches
            << " mismatches against the texture unit with fixed arithmetic (equal to FixedSampler: "
            << n.fixed_equal << "); against its float32 path: levels equal " << n.level_equal
            << ", addresses equal " << n.addr_equal << ", RGBA8 equal " << n.colour_equal
            << ", largest difference " << n.colour_max_diff << " LSB\n"
            << n.report;
  return n;
}

// Every shipped scene; those without a covered material give no fragments (the run says so).
const char* const kScenes[] = {
    "border",         "bunny",       "camera_path",       "coords",
    "cube",           "flight",      "footprint_filters", "models",
    "object_space",   "photo",       "photo_compressed",  "photo_etc2_bc7",
    "photo_srgb",     "relief_wall", "subtexel_cutoff",   "terrain_dem",
    "terrain_flyover"};

TEST(RtlLockstep, SamplerMatchesCppOnShippedScenes) {
  const uint64_t most = fragments_per_scene(1500);
  uint64_t total = 0;
  int i = 0;
  for (const char* s : kScenes) {
    // The layouts take turns, so a run covers linear, tiled and Morton addresses.
    const auto layout = static_cast<TexelLayout>(i++ % 3);
    const SceneCounts n = run_scene(s, most, layout);
    EXPECT_EQ(n.mismatches, 0u) << s << "\n" << n.report;
    EXPECT_EQ(n.fixed_equal, n.fragments) << s;
    // Against the float32 texture unit: levels within the rounding of λ (measured: at most
    // 1 in 1000 fragments differ), addresses equal where the levels are, colours within 1 LSB.
    EXPECT_GE(n.level_equal * 1000, n.fragments * 998) << s;
    EXPECT_EQ(n.addr_equal, n.level_equal) << s;
    EXPECT_LE(n.colour_max_diff, 1) << s;
    total += n.fragments;
  }
  EXPECT_GT(total, 0u);
}

// Random fragments on textures of power-of-two and other sizes (1x1 up to 300x17, every
// level), every covered address mode, both filters, the three layouts, texel offsets and LOD
// bias and limits: the RTL against FixedSampler bit for bit, and FixedSampler's addresses against
// TexelAddressGen's wherever their levels agree.
TEST(RtlLockstep, SamplerMatchesCppOnRandomFragmentsAndSizes) {
  std::mt19937_64 rng(2901);
  const int sizes[][2] = {{37, 23}, {64, 64}, {300, 17}, {1, 1}, {5, 128}, {256, 3}};
  const AddressMode modes[] = {AddressMode::Wrap, AddressMode::Clamp, AddressMode::Mirror,
                               AddressMode::MirrorClamp};
  std::uniform_real_distribution<double> coord(-3.0, 3.0), lg(-12.0, 2.0), unit(-1.0, 1.0);
  SamplerBench bench({});
  uint64_t fragments = 0, level_equal = 0, addr_equal = 0;
  int config = 0;
  for (const auto& sz : sizes) {
    std::vector<float> rgba(static_cast<size_t>(sz[0]) * static_cast<size_t>(sz[1]) * 4);
    for (float& c : rgba) c = static_cast<float>(rng() % 256) / 255.0f;
    for (int k = 0; k < 6; ++k, ++config) {
      Texture tex = Texture::from_rgba("t", sz[0], sz[1], rgba, TexelFormat::Rgba8, true);
      tex.place(0, static_cast<TexelLayout>(config % 3));
      TexelAddressGen::Config a;
      a.filter = k % 2 == 0 ? FilterMode::Trilinear : FilterMode::Bilinear;
      a.address_u = modes[static_cast<size_t>(config) % 4];
      a.address_v = modes[static_cast<size_t>(config + 1 + k / 2) % 4];
      a.offset_u = static_cast<int>(rng() % 16) - 8;
      a.offset_v = static_cast<int>(rng() % 16) - 8;
      LodUnit::Config l;
      l.lod_bias = static_cast<float>(unit(rng));
      l.min_lod = k == 3 ? 0.75f : 0.0f;
      l.max_lod = k == 5 ? 2.5f : 1000.0f;
      const FixedSampler fs(FixedSampler::config_of(a, l));
      const FixedSampler::TextureDesc desc = FixedSampler::describe(tex);
      const std::vector<uint32_t> mem = FixedSampler::memory_image(tex);
      bench.drain();
      bench.configure(fs, desc, fs.ops_per_item(a, l), mem);
      const LodUnit lod(l);
      const TexelAddressGen gen(a);
      for (int i = 0; i < 700; ++i) {
        Fragment f;
        f.u = coord(rng);
        f.v = coord(rng);
        const double s = std::exp2(lg(rng));
        f.dudx = s * unit(rng);
        f.dvdx = s * unit(rng);
        f.dudy = s * unit(rng);
        f.dvdy = s * unit(rng);
        const FixedSampler::Result r = fs.sample(FixedSampler::to_input(f), desc, mem);
        bench.issue(FixedSampler::to_input(f), r);
        ++fragments;
        FilterTaps taps;
        const LodResult lr = lod.eval(f, tex.width(0), tex.height(0));
        gen.taps(tex, f.u, f.v, lr, taps);
        const TexelAddressGen::LevelSelect sel = gen.select_levels(lr.lambda, tex.levels());
        if (sel.d_hi != r.level_hi || sel.d_lo != r.level_lo) continue;
        ++level_equal;
        bool same = true;
        for (int t = 0; t < taps.count && t < 8; ++t) {
          const TexelTap& tp = taps.tap[static_cast<size_t>(t)];
          same = same && (tex.address(tp.level, tp.x, tp.y) - tex.base()) / 4 ==
                             r.addr[static_cast<size_t>(t)];
        }
        addr_equal += same ? 1 : 0;
      }
    }
  }
  const uint64_t mismatches = bench.finish();
  std::cout << "texsim_sampler random: " << fragments << " fragments on " << config
            << " textures and samplers, " << mismatches
            << " mismatches against FixedSampler; levels equal to the texture unit's "
            << level_equal << ", addresses equal " << addr_equal << "\n"
            << bench.report();
  EXPECT_EQ(mismatches, 0u) << bench.report();
  EXPECT_EQ(bench.compared(), fragments);
  EXPECT_EQ(addr_equal, level_equal);
  EXPECT_GE(level_equal * 100, fragments * 99);
}

// Negative controls, one per stage: one LSB of the level fraction (LOD), of one texel address
// (address generation), of the colour (read and blend), and a latency one cycle off.
TEST(RtlLockstep, SamplerScoreboardCatchesOneLsbPerStage) {
  const SceneCounts lod =
      run_scene("footprint_filters", 400, TexelLayout::Linear, {0, 3, 1, 123, 0});
  EXPECT_EQ(lod.mismatches, 1u) << lod.report;
  EXPECT_NE(lod.report.find("fragment 123)"), std::string::npos) << lod.report;
  const SceneCounts addr =
      run_scene("footprint_filters", 400, TexelLayout::Tiled4x4, {1, 5, 1, 200, 0});
  EXPECT_EQ(addr.mismatches, 1u) << addr.report;
  EXPECT_NE(addr.report.find("fragment 200)"), std::string::npos) << addr.report;
  const SceneCounts col =
      run_scene("footprint_filters", 400, TexelLayout::Morton, {0, 0, 1, 321, 0});
  EXPECT_EQ(col.mismatches, 1u) << col.report;
  const SceneCounts lat =
      run_scene("footprint_filters", 100, TexelLayout::Linear, {-1, 0, 0, 0, 1});
  EXPECT_EQ(lat.mismatches, lat.fragments) << lat.report;
}

}  // namespace
}  // namespace texsim::rtl
