// TextureUnit::process_batch against process, fragment by fragment: the same colours (bit for
// bit), fragment counts, cycles, per-stage counters, cache and DRAM figures and block operation
// counts, for bilinear and trilinear materials in every texel layout, functional and timed,
// with batch sizes that split and with fragments the batch leaves to the scalar path (hard
// inputs, anisotropic probes, a second texture it does not serve).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "blocks/base/sample_op.h"
#include "testbench/lib/bench_floor.h"

namespace texsim {
namespace {

BenchFloor& floor_fixture() {
  static BenchFloor fixture = [] {
    BenchFloor b = make_bench_floor(200, 150);
    // A second texture the batch does not serve (RGBA32F), for every third run of 500.
    std::vector<float> px(size_t{64} * 64 * 4);
    for (size_t i = 0; i < px.size(); ++i) px[i] = static_cast<float>(i % 251) / 251.0f;
    b.textures.add(Texture::from_rgba("f32", 64, 64, px, TexelFormat::Rgba32f, true));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (size_t i = 0; i < b.frags.size(); ++i) {
      Fragment& f = b.frags[i];
      if ((i / 500) % 3 == 1) f.tex = 1;
      if (i % 97 == 5) f.dudx = nan;  // non-finite derivative: λ from the fallback
      if (i % 89 == 7) f.u = 3e7;     // beyond the batch's int32 fixed point
      if (i % 83 == 11) f.lod_bias = std::numeric_limits<float>::infinity();
    }
    return b;
  }();
  return fixture;
}

struct Figures {
  std::vector<Rgba> colours;
  uint64_t fragments = 0, cycles = 0;
  TextureCache::Stats cache;
  DramModel::Stats dram;
  std::vector<StageStats> stages;
  std::vector<BlockUse> blocks;
  std::vector<FrameStats> frames;
};

Figures run(const MaterialSetup& m, TexelLayout layout, bool timing, size_t batch,
            const PipelineSetup& base = {}) {
  BenchFloor& fx = floor_fixture();
  PipelineSetup setup = base;
  setup.layout = layout;
  TextureUnit unit(fx.textures, {m}, setup, TechTable::defaults(), timing);
  Figures out;
  out.colours.resize(fx.frags.size());
  if (batch == 0) {
    for (size_t i = 0; i < fx.frags.size(); ++i) out.colours[i] = unit.process(fx.frags[i], 0);
  } else {
    for (size_t i = 0; i < fx.frags.size(); i += batch) {
      const size_t n = std::min(batch, fx.frags.size() - i);
      unit.process_batch(fx.frags.data() + i, n, 0, out.colours.data() + i);
    }
  }
  out.fragments = unit.fragments();
  out.cycles = unit.cycles();
  out.cache = unit.cache().stats();
  out.dram = unit.memory().dram_totals();
  if (unit.pipeline()) {
    for (int s = 0; s < unit.pipeline()->stage_count(); ++s)
      out.stages.push_back(unit.pipeline()->stats(s));
  }
  out.blocks = unit.blocks();
  out.frames = unit.frames();
  return out;
}

void expect_same(const Figures& a, const Figures& b) {
  ASSERT_EQ(a.colours.size(), b.colours.size());
  size_t differ = 0;
  for (size_t i = 0; i < a.colours.size(); ++i)
    for (int c = 0; c < 4; ++c)
      differ +=
          std::bit_cast<uint32_t>(a.colours[i][c]) != std::bit_cast<uint32_t>(b.colours[i][c]);
  EXPECT_EQ(differ, 0u);
  EXPECT_EQ(a.fragments, b.fragments);
  EXPECT_EQ(a.cycles, b.cycles);
  EXPECT_EQ(a.cache.accesses, b.cache.accesses);
  EXPECT_EQ(a.cache.hits, b.cache.hits);
  EXPECT_EQ(a.cache.misses, b.cache.misses);
  EXPECT_EQ(a.cache.texel_reads, b.cache.texel_reads);
  EXPECT_EQ(a.dram.requests, b.dram.requests);
  EXPECT_EQ(a.dram.busy_cycles, b.dram.busy_cycles);
  ASSERT_EQ(a.stages.size(), b.stages.size());
  for (size_t s = 0; s < a.stages.size(); ++s) {
    EXPECT_EQ(a.stages[s].items, b.stages[s].items);
    EXPECT_EQ(a.stages[s].busy, b.stages[s].busy);
    EXPECT_EQ(a.stages[s].stall_starved, b.stages[s].stall_starved);
    EXPECT_EQ(a.stages[s].stall_blocked, b.stages[s].stall_blocked);
    EXPECT_EQ(a.stages[s].stall_full, b.stages[s].stall_full);
  }
  ASSERT_EQ(a.blocks.size(), b.blocks.size());
  for (size_t k = 0; k < a.blocks.size(); ++k) {
    EXPECT_EQ(a.blocks[k].name, b.blocks[k].name);
    EXPECT_TRUE(a.blocks[k].ops == b.blocks[k].ops) << a.blocks[k].name;
    EXPECT_EQ(a.blocks[k].texels, b.blocks[k].texels);
  }
  ASSERT_EQ(a.frames.size(), b.frames.size());
  for (size_t k = 0; k < a.frames.size(); ++k) {
    EXPECT_EQ(a.frames[k].frame, b.frames[k].frame);
    EXPECT_EQ(a.frames[k].fragments, b.frames[k].fragments);
    EXPECT_EQ(a.frames[k].cycles, b.frames[k].cycles);
  }
}

TEST(UnitBatch, SameFiguresAsOneByOne) {
  for (FilterMode filter : {FilterMode::Bilinear, FilterMode::Trilinear}) {
    for (TexelLayout layout : {TexelLayout::Linear, TexelLayout::Tiled4x4, TexelLayout::Morton}) {
      for (bool timing : {false, true}) {
        MaterialSetup m;
        m.name = "floor";
        m.filter.filter = filter;
        SCOPED_TRACE(std::string(to_string(filter)) + " " + to_string(layout) +
                     (timing ? " timed" : " functional"));
        const Figures one = run(m, layout, timing, 0);
        if (timing) {
          EXPECT_GT(one.cache.accesses, 0u);  // the timed runs use the cache
        }
        for (size_t batch : {size_t{7}, LinearBatch::kMax, size_t{1000}})
          expect_same(one, run(m, layout, timing, batch));
      }
    }
  }
}

// The timed batch looks a run's lines up before it clocks the run: a small cache (many misses,
// hits on other ways than the most recent, evictions) and frames that change inside a batch
// must still give the one-by-one figures, each frame's cycles included.
TEST(UnitBatch, SmallCacheAndFramesInsideABatch) {
  std::vector<Fragment> saved = floor_fixture().frags;
  for (size_t i = 0; i < floor_fixture().frags.size(); ++i)
    floor_fixture().frags[i].frame = static_cast<uint32_t>(i / 300);
  for (uint32_t ways : {1u, 2u}) {
    PipelineSetup setup;
    setup.cache.size_bytes = 1024;
    setup.cache.ways = ways;
    for (FilterMode filter : {FilterMode::Bilinear, FilterMode::Trilinear}) {
      for (bool timing : {false, true}) {
        MaterialSetup m;
        m.name = "floor";
        m.filter.filter = filter;
        SCOPED_TRACE(std::string(to_string(filter)) + " ways " + std::to_string(ways) +
                     (timing ? " timed" : " functional"));
        const Figures one = run(m, TexelLayout::Linear, timing, 0, setup);
        if (timing) {
          EXPECT_GT(one.cache.misses, one.cache.accesses / 50);  // the cache is under pressure
        }
        EXPECT_GT(one.frames.size(), 10u);
        for (size_t batch : {size_t{7}, LinearBatch::kMax})
          expect_same(one, run(m, TexelLayout::Linear, timing, batch, setup));
      }
    }
  }
  floor_fixture().frags = std::move(saved);
}

// An R8 or RG8 texture keeps the 8-bit store but takes 1 or 2 bytes a texel in memory: the
// batch, whose lines assume 4, must leave it to the scalar path (same cache figures).
TEST(UnitBatch, NarrowTexelsTakeTheirOwnBytes) {
  for (const StorageFormat f : {StorageFormat::R8Unorm, StorageFormat::Rg8Unorm}) {
    BenchFloor b = make_bench_floor(120, 90);
    b.textures[0] = b.textures[0].converted(f);
    MaterialSetup m;
    m.name = "floor";
    m.filter.filter = FilterMode::Trilinear;
    auto figures = [&](size_t batch) {
      PipelineSetup setup;
      TextureUnit unit(b.textures, {m}, setup, TechTable::defaults(), true);
      std::vector<Rgba> out(b.frags.size());
      if (batch == 0) {
        for (size_t i = 0; i < b.frags.size(); ++i) out[i] = unit.process(b.frags[i], 0);
      } else {
        for (size_t i = 0; i < b.frags.size(); i += batch)
          unit.process_batch(b.frags.data() + i, std::min(batch, b.frags.size() - i), 0,
                             out.data() + i);
      }
      return std::make_pair(unit.cache().stats().fill_bytes, unit.cycles());
    };
    const auto one = figures(0);
    EXPECT_EQ(figures(LinearBatch::kMax), one) << to_string(f);
    // A narrower texel fills fewer bytes than RGBA8's on the same floor.
    BenchFloor rgba = make_bench_floor(120, 90);
    PipelineSetup setup;
    TextureUnit unit(rgba.textures, {m}, setup, TechTable::defaults(), true);
    for (const Fragment& fr : rgba.frags) (void)unit.process(fr, 0);
    EXPECT_LT(one.first, unit.cache().stats().fill_bytes) << to_string(f);
  }
}

TEST(UnitBatch, AnisotropicMaterialMixesBatchAndScalarFragments) {
  MaterialSetup m;
  m.name = "floor";
  m.filter.filter = FilterMode::Trilinear;
  m.lod.aniso = AnisoMode::Vulkan;
  m.lod.max_aniso = 8;
  expect_same(run(m, TexelLayout::Tiled4x4, true, 0), run(m, TexelLayout::Tiled4x4, true, 256));
}

// Border and mirror-clamp addressing and texel offsets: the batch leaves them to the one-by-one
// path, so every figure (and the border-tap count) is the same either way; the floor's
// coordinates run far outside [0, 1], so border taps are many and fetch nothing.
TEST(UnitBatch, BorderMirrorClampAndOffsetsTakeTheOneByOnePath) {
  struct Case {
    AddressMode u, v;
    int ou, ov;
  };
  for (const Case c : {Case{AddressMode::Border, AddressMode::Border, 0, 0},
                       Case{AddressMode::MirrorClamp, AddressMode::Wrap, 0, 0},
                       Case{AddressMode::Wrap, AddressMode::Wrap, 3, -8}}) {
    MaterialSetup m;
    m.name = "floor";
    m.filter.filter = FilterMode::Trilinear;
    m.filter.address_u = c.u;
    m.filter.address_v = c.v;
    m.filter.border = Rgba(0.0f, 0.0f, 0.0f, 1.0f);
    m.filter.offset_u = c.ou;
    m.filter.offset_v = c.ov;
    SCOPED_TRACE(std::string(to_string(c.u)) + "/" + to_string(c.v));
    const Figures one = run(m, TexelLayout::Tiled4x4, true, 0);
    const Figures batched = run(m, TexelLayout::Tiled4x4, true, LinearBatch::kMax);
    expect_same(one, batched);
    uint64_t border = 0, texels = 0;
    for (const BlockUse& b : batched.blocks) {
      border += b.border_taps;
      if (b.name.rfind("filter.", 0) == 0) texels += b.texels;
    }
    EXPECT_EQ(border > 0, c.u == AddressMode::Border) << border;
    EXPECT_EQ(batched.cache.texel_reads, texels);
  }
}

// Explicit LOD and explicit gradients (Fragment::op) take the one-by-one path: the same figures
// either way, and the explicit LOD changes the colours the implicit sample gave.
TEST(UnitBatch, ExplicitLodAndGradientsTakeTheOneByOnePath) {
  BenchFloor& fx = floor_fixture();
  const std::vector<Fragment> plain = fx.frags;
  for (size_t i = 0; i < fx.frags.size(); ++i) {
    Fragment& f = fx.frags[i];
    if (i % 5 == 1) {
      f.op = static_cast<uint8_t>(SampleOp::kSampleLod);
      f.lod = 3.5f;
    } else if (i % 7 == 2) {
      f.op = static_cast<uint8_t>(SampleOp::kSampleGrad);
      f.lod_bias = 4.0f;  // the shader's Bias: not with explicit gradients
    }
  }
  MaterialSetup m;
  m.name = "floor";
  m.filter.filter = FilterMode::Trilinear;
  const Figures one = run(m, TexelLayout::Tiled4x4, true, 0);
  const Figures batched = run(m, TexelLayout::Tiled4x4, true, LinearBatch::kMax);
  fx.frags = plain;
  expect_same(one, batched);
  const Figures implicit = run(m, TexelLayout::Tiled4x4, true, LinearBatch::kMax);
  size_t lod_changed = 0, grad_changed = 0;
  for (size_t i = 0; i < plain.size(); ++i) {
    const bool same = std::bit_cast<uint32_t>(one.colours[i][0]) ==
                      std::bit_cast<uint32_t>(implicit.colours[i][0]);
    if (i % 5 == 1) lod_changed += !same;
    if (i % 5 != 1 && i % 7 == 2) grad_changed += !same;
  }
  EXPECT_GT(lod_changed, plain.size() / 20);
  // A gradient fragment differs only where the fixture gave it a bias.
  EXPECT_LT(grad_changed, plain.size() / 50);
}

TEST(UnitBatch, AnUnloadedTextureFailsAtItsFragment) {
  BenchFloor& fx = floor_fixture();
  std::vector<Fragment> frags(fx.frags.begin(), fx.frags.begin() + 40);
  frags[25].tex = 9;
  MaterialSetup m;
  m.name = "floor";
  m.filter.filter = FilterMode::Bilinear;
  TextureUnit one(fx.textures, {m}, PipelineSetup{}, TechTable::defaults(), true);
  TextureUnit batched(fx.textures, {m}, PipelineSetup{}, TechTable::defaults(), true);
  for (size_t i = 0; i < 25; ++i) one.process(frags[i], 0);
  EXPECT_THROW(one.process(frags[25], 0), std::out_of_range);
  std::vector<Rgba> out(frags.size());
  EXPECT_THROW(batched.process_batch(frags.data(), frags.size(), 0, out.data()), std::out_of_range);
  // The fragments before it went through, as one by one.
  EXPECT_EQ(batched.fragments(), one.fragments());
  EXPECT_EQ(batched.cycles(), one.cycles());
}

}  // namespace
}  // namespace texsim
