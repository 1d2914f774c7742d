// WorkloadStats on tiny inputs whose figures are worked out by hand, and the reuse distances
// against a direct count.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <set>
#include <vector>

#include "pipeline/report/workload_feed.h"
#include "pipeline/report/workload_stats.h"

namespace texsim {
namespace {

using Sizes = std::vector<std::array<int, 2>>;

Fragment frag(uint32_t frame, uint32_t x, uint32_t y, double u, double v, double dudx,
              double dvdy) {
  Fragment f;
  f.frame = frame;
  f.x = x;
  f.y = y;
  f.u = u;
  f.v = v;
  f.dudx = dudx;
  f.dvdy = dvdy;
  return f;
}

TEST(WorkloadStats, PlacementFollowsTheTextureSet) {
  // Linear 8x8 RGBA8: levels of 256, 64, 16 and 4 bytes, each rounded up to 256 bytes; the
  // next texture starts on the next 4 KiB page.
  const auto t = place_workload_textures(Sizes{{8, 8}, {2, 2}}, TexelLayout::Linear);
  ASSERT_EQ(t.size(), 2u);
  ASSERT_EQ(t[0].levels.size(), 4u);
  EXPECT_EQ(t[0].levels[2].width, 2);
  EXPECT_EQ(t[0].levels[2].offset, 512u);
  EXPECT_EQ(t[0].address(0, 1, 1), 36u);
  EXPECT_EQ(t[1].base, 4096u);
  TextureSet set;
  set.add(Texture::from_rgba("a", 8, 8, std::vector<float>(size_t{8} * 8 * 4, 0.5f),
                             TexelFormat::Rgba8, true));
  set.place(TexelLayout::Tiled4x4);
  const WorkloadTexture w = workload_textures(set)[0];
  const auto p = place_workload_textures(Sizes{{8, 8}}, TexelLayout::Tiled4x4);
  for (int l = 0; l < 4; ++l) EXPECT_EQ(w.address(l, 1, 1), p[0].address(l, 1, 1)) << l;
}

TEST(WorkloadStats, TwoFramesByHand) {
  WorkloadStats s(place_workload_textures(Sizes{{8, 8}}, TexelLayout::Linear));
  // Frame 0, λ = 0 (one texel per pixel): footprints x 0-1 and 2-3, rows 0-1 (addresses 0, 4,
  // 32, 36 and 8, 12, 40, 44); then λ = -1 at x 6-7 (24, 28, 56, 60). Pixels (0,0), (1,0):
  // one quad; (2,0): another.
  s.add(frag(0, 0, 0, 1.0 / 8, 1.0 / 8, 1.0 / 8, 1.0 / 8), 0);
  s.add(frag(0, 1, 0, 3.0 / 8, 1.0 / 8, 1.0 / 8, 1.0 / 8), 0);
  s.add(frag(0, 2, 0, 7.0 / 8, 1.0 / 8, 1.0 / 16, 1.0 / 16), 0);
  // Frame 1: ρx = 4, ρy = 1: η = 4, λ = 2, level 2 (2x2, at 512): its four texels, one line.
  s.add(frag(1, 0, 0, 0.25, 0.25, 4.0 / 8, 1.0 / 8), 0);
  s.finish();
  ASSERT_EQ(s.frames().size(), 2u);
  const FrameWorkload& a = s.frames()[0];
  EXPECT_EQ(a.fragments, 3u);
  EXPECT_EQ(a.quads, 2u);
  EXPECT_EQ(a.textures, 1u);
  EXPECT_EQ(a.texels_level0, 12u);
  EXPECT_EQ(a.texels_lod, 12u);  // the magnified fragment reads level 0 too
  EXPECT_EQ(a.lines[0], 2u);     // 32-byte lines 0 and 1
  EXPECT_EQ(a.lines[1], 1u);
  EXPECT_EQ(a.lines[2], 1u);
  EXPECT_EQ(a.lod[8], 2u);  // [0, 0.5)
  EXPECT_EQ(a.lod[6], 1u);  // [-1, -0.5)
  EXPECT_EQ(a.magnified, 1u);
  EXPECT_EQ(a.minified, 2u);
  EXPECT_EQ(a.aniso[0], 3u);
  EXPECT_DOUBLE_EQ(a.footprint_texels, 2.25);
  EXPECT_EQ(a.line_uses, 3u);  // one 64-byte line per fragment
  EXPECT_EQ(a.first_uses, 1u);
  EXPECT_EQ(a.reuse[0], 2u);
  const FrameWorkload& b = s.frames()[1];
  EXPECT_EQ(b.frame, 1u);
  EXPECT_EQ(b.fragments, 1u);
  EXPECT_EQ(b.quads, 1u);
  EXPECT_EQ(b.texels_level0, 4u);
  EXPECT_EQ(b.texels_lod, 4u);
  EXPECT_EQ(b.lines[0], 1u);
  EXPECT_EQ(b.lod[12], 1u);  // [2, 2.5)
  EXPECT_EQ(b.aniso[2], 1u);
  EXPECT_DOUBLE_EQ(b.footprint_texels, 4.0);
  EXPECT_EQ(b.first_uses, 1u);
  const FrameWorkload t = s.total();
  EXPECT_EQ(t.fragments, 4u);
  EXPECT_EQ(t.magnified + t.minified, 4u);
}

TEST(WorkloadStats, HistogramEdges) {
  WorkloadStats s(place_workload_textures(Sizes{{16, 16}}, TexelLayout::Tiled4x4));
  Fragment f = frag(0, 0, 0, 0.5, 0.5, 0, 0);  // point footprint: λ = -inf
  s.add(f, 0);
  f.dudx = 1e6;  // λ ≈ 23.9: overflow; a line segment: η > 16
  s.add(f, 0);
  f.dudx = 1.0 / 16;
  f.dvdy = 23.0 / 16;  // η = 23: rounds to 32, ">16"
  s.add(f, 0);
  f.dvdy = 22.0 / 16;  // η = 22: rounds to 16
  s.add(f, 0);
  s.finish();
  const FrameWorkload& a = s.frames()[0];
  EXPECT_EQ(a.lod_under, 1u);
  EXPECT_EQ(a.lod_over, 1u);
  EXPECT_EQ(a.aniso[0], 1u);
  EXPECT_EQ(a.aniso[5], 2u);
  EXPECT_EQ(a.aniso[4], 1u);
  EXPECT_EQ(a.magnified, 1u);
}

TEST(ReuseDistance, ShortSequenceByHand) {
  // A B C A B B D A: distances 2 (B, C), 2 (C, A), 0, 2 (B, D).
  ReuseDistance r;
  for (uint64_t l : {1, 2, 3, 1, 2, 2, 4, 1}) r.use(l);
  EXPECT_EQ(r.uses, 8u);
  EXPECT_EQ(r.first_uses, 4u);
  EXPECT_EQ(r.hist[0], 1u);
  EXPECT_EQ(r.hist[2], 3u);  // [2, 4)
}

TEST(ReuseDistance, CyclesAcrossCompactions) {
  // 3000 lines three times over: every reuse sees the 2999 others, bin [2048, 4096).
  ReuseDistance r;
  for (int k = 0; k < 3; ++k)
    for (uint64_t l = 0; l < 3000; ++l) r.use(l * 7919);
  EXPECT_EQ(r.first_uses, 3000u);
  EXPECT_EQ(r.hist[12], 6000u);
}

TEST(ReuseDistance, MatchesADirectCount) {
  std::mt19937 rng(7);
  std::vector<uint64_t> seq(6000);
  for (auto& l : seq) l = rng() % (rng() % 2 ? 40 : 700);
  ReuseDistance r;
  std::array<uint64_t, ReuseDistance::kBins> want{};
  for (size_t i = 0; i < seq.size(); ++i) {
    r.use(seq[i]);
    std::set<uint64_t> between;
    for (size_t j = i; j-- > 0;) {
      if (seq[j] == seq[i]) {
        ++want[static_cast<size_t>(std::bit_width(between.size()))];
        break;
      }
      between.insert(seq[j]);
    }
  }
  EXPECT_EQ(r.hist, want);
  uint64_t reuses = 0;
  for (uint64_t n : r.hist) reuses += n;
  EXPECT_EQ(reuses, r.uses - r.first_uses);
}

// WorkloadFeed: the stats computed on the feed's thread are those of direct add() calls, over
// several frames and partial batches; a feed without a thread calls add() at once.
TEST(WorkloadFeed, ThreadGivesTheDirectFigures) {
  const auto textures = place_workload_textures(Sizes{{64, 32}, {16, 16}}, TexelLayout::Linear);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uv(-1.0, 2.0), d(1.0 / 256, 1.0 / 4);
  std::vector<std::pair<Fragment, uint32_t>> in;
  for (uint32_t i = 0; i < 10007; ++i) {
    Fragment f = frag(i / 3000, i % 64, (i / 64) % 32, uv(rng), uv(rng), d(rng), d(rng));
    in.emplace_back(f, i % 5 == 0 ? 1u : 0u);
  }
  WorkloadStats direct(textures), threaded(textures), inline_feed(textures);
  for (const auto& [f, t] : in) direct.add(f, t);
  direct.finish();
  {
    WorkloadFeed feed(threaded, true), at_once(inline_feed, false);
    for (const auto& [f, t] : in) {
      feed.add(f, t);
      at_once.add(f, t);
    }
    feed.finish();
    at_once.finish();
  }
  for (const WorkloadStats* s : {&threaded, &inline_feed}) {
    ASSERT_EQ(s->frames().size(), direct.frames().size());
    for (size_t k = 0; k < direct.frames().size(); ++k) {
      const FrameWorkload &a = direct.frames()[k], &b = s->frames()[k];
      EXPECT_EQ(a.fragments, b.fragments) << k;
      EXPECT_EQ(a.quads, b.quads) << k;
      EXPECT_EQ(a.texels_level0, b.texels_level0) << k;
      EXPECT_EQ(a.texels_lod, b.texels_lod) << k;
      EXPECT_EQ(a.lines, b.lines) << k;
      EXPECT_EQ(a.lod, b.lod) << k;
      EXPECT_EQ(a.aniso, b.aniso) << k;
      EXPECT_EQ(a.reuse, b.reuse) << k;
      EXPECT_EQ(a.footprint_texels, b.footprint_texels) << k;
    }
  }
}

// A feed destroyed before finish() (a run that failed) stops its thread without hanging.
TEST(WorkloadFeed, StopsWithoutFinish) {
  WorkloadStats s(place_workload_textures(Sizes{{8, 8}}, TexelLayout::Linear));
  WorkloadFeed feed(s, true);
  for (uint32_t i = 0; i < 20000; ++i) feed.add(frag(0, i % 8, 0, 0.1, 0.1, 0.1, 0.1), 0);
}

}  // namespace
}  // namespace texsim
