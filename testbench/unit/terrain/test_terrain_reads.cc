// The terrain marcher's height reads, logged for the texture cache: an evaluation logs exactly
// the nodes it reads (clamped at the edge), a ray across known cells logs exactly their nodes,
// and logging changes none of the marcher's or the relief effect's results.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <set>
#include <utility>
#include <vector>

#include "blocks/texture/relief/terrain_ray_marcher.h"
#include "pipeline/texture/surface_effects.h"

namespace texsim {
namespace {

TerrainGrid bumpy_grid(int32_t w, int32_t d) {
  TerrainGrid g(w, d);
  for (int32_t j = 0; j < d; ++j) {
    for (int32_t i = 0; i < w; ++i) g.at(i, j) = static_cast<float>((i * 7 + j * 3) % 11) / 4.0F;
  }
  return g;
}

TEST(TerrainReads, AnEvaluationLogsTheNodesItReads) {
  const TerrainGrid g = bumpy_grid(8, 8);
  const TerrainHeightEvaluator e;
  OpCounts ops;
  std::vector<TerrainNode> reads;
  e.height(g, 2.3, 4.6, ops, &reads);
  EXPECT_EQ(reads, (std::vector<TerrainNode>{{2, 4}, {2, 5}, {3, 4}, {3, 5}}));
  // Beyond the edge the grid clamps, and so does the log: x = -0.5 reads column 0 twice.
  reads.clear();
  e.height(g, -0.5, 7.2, ops, &reads);
  EXPECT_EQ(reads, (std::vector<TerrainNode>{{0, 7}, {0, 7}, {0, 7}, {0, 7}}));
  // A non-finite position reads the node (0, 0).
  reads.clear();
  e.height(g, NAN, 1.0, ops, &reads);
  EXPECT_EQ(reads, (std::vector<TerrainNode>{{0, 0}}));
  // Variant 1 (support 3/2): the 3 × 3 nodes around x̂ = ⌊x + 1/2⌋.
  TerrainHeightEvaluator::Config c;
  c.basis.deformation = Deformation::Widened;
  const TerrainHeightEvaluator w(c);
  reads.clear();
  w.height(g, 2.7, 4.2, ops, &reads);
  std::vector<TerrainNode> want;
  for (int32_t a = 2; a <= 4; ++a) {
    for (int32_t b = 3; b <= 5; ++b) want.push_back({a, b});
  }
  EXPECT_EQ(reads, want);
}

TEST(TerrainReads, ARayAcrossKnownCellsLogsExactlyTheirNodes) {
  // Flat at 0 for x < 5, a plateau at 2 from node 5: a level ray at y = 1 along z = 2.5 from
  // x = 0.3 steps through cells 0..4 and hits where the cosine surface crosses 1 (x = 4.5).
  TerrainGrid g(8, 8, 0.0F);
  for (int32_t j = 0; j < 8; ++j) {
    for (int32_t i = 5; i < 8; ++i) g.at(i, j) = 2.0F;
  }
  const TerrainRayMarcher m;
  OpCounts ops;
  std::vector<ReliefRead> reads;
  const auto r = m.march_ray(g, m.top_bound(g), {0.3, 1.0, 2.5}, {1, 0, 0}, ops, &reads);
  ASSERT_TRUE(r.hit);
  EXPECT_NEAR(r.point.x, 4.5, 1e-3);
  EXPECT_EQ(r.steps, 18u);  // x = 0.3, 0.55, ..., 4.55
  EXPECT_EQ(r.refinements, 10u);
  ASSERT_EQ(reads.size(), size_t{4} * r.evaluations);
  EXPECT_EQ(reads.size(), r.fetches);
  std::set<std::pair<int32_t, int32_t>> got, want;
  for (size_t k = 0; k < reads.size(); ++k) {
    EXPECT_EQ(reads[k].z, ReliefRead::kHeightRead);
    got.insert({reads[k].x, reads[k].y});
    // Each evaluation reads one cell's corners: (i, j), (i, j + 1), (i + 1, j), (i + 1, j + 1).
    const ReliefRead& c = reads[k - k % 4];
    EXPECT_EQ(reads[k].x, c.x + static_cast<int32_t>(k % 4 / 2)) << k;
    EXPECT_EQ(reads[k].y, c.y + static_cast<int32_t>(k % 2)) << k;
  }
  for (int32_t i = 0; i <= 5; ++i) want.insert({{i, 2}, {i, 3}});
  EXPECT_EQ(got, want);
  // The first evaluation is at the eye (cell 0), the last one of the bisection in cell 4.
  EXPECT_EQ(reads.front().x, 0);
  EXPECT_EQ(reads[reads.size() - 4].x, 4);
}

TEST(TerrainReads, LoggingChangesNoResultOfTheMarcher) {
  const TerrainGrid g = bumpy_grid(24, 20);
  for (const auto def : {Deformation::None, Deformation::Widened, Deformation::Blended}) {
    TerrainRayMarcher::Config c;
    c.evaluator.basis.deformation = def;
    const TerrainRayMarcher m(c);
    const double top = m.top_bound(g);
    for (int k = 0; k < 40; ++k) {
      const glm::dvec3 eye(1.0 + 0.5 * k, 4.0, 2.0 + 0.3 * k);
      const glm::dvec3 dir(std::cos(0.4 * k), -0.2 - 0.05 * (k % 7), std::sin(0.4 * k));
      OpCounts plain_ops, logged_ops;
      std::vector<ReliefRead> reads;
      const auto a = m.march_ray(g, top, eye, dir, plain_ops);
      const auto b = m.march_ray(g, top, eye, dir, logged_ops, &reads);
      EXPECT_EQ(a.hit, b.hit);
      EXPECT_EQ(a.capped, b.capped);
      EXPECT_EQ(a.t, b.t);
      EXPECT_EQ(a.point, b.point);
      EXPECT_EQ(a.steps, b.steps);
      EXPECT_EQ(a.refinements, b.refinements);
      EXPECT_EQ(a.evaluations, b.evaluations);
      EXPECT_EQ(a.fetches, b.fetches);
      EXPECT_EQ(plain_ops, logged_ops);
      EXPECT_EQ(reads.size(), b.fetches);
      for (const ReliefRead& rd : reads) {
        EXPECT_TRUE(rd.x >= 0 && rd.x < g.nx && rd.y >= 0 && rd.y < g.nz);
      }
    }
  }
}

TEST(TerrainReads, TheReliefEffectLogsTheMarchersReadsAndKeepsItsShift) {
  const int w = 16, h = 16;
  std::vector<float> rgba(size_t{w} * h * 4, 1.0F);
  for (size_t y = 0; y < size_t{h}; ++y) {
    for (size_t x = 0; x < size_t{w}; ++x)
      rgba[(y * w + x) * 4] = static_cast<float>((x * 5 + y * 3) % 9) / 8.0F;
  }
  const Texture height = Texture::from_rgba("h", w, h, rgba, TexelFormat::Rgba32f, false);
  ReliefSetup rs;
  rs.method = ReliefSetup::Method::Terrain;
  rs.height_texture = "h";
  rs.scale = 4;
  const ReliefEffect e(rs, height);
  int logged = 0;
  for (int k = 0; k < 30; ++k) {
    const glm::dvec3 v = glm::normalize(glm::dvec3(std::cos(0.7 * k), std::sin(0.7 * k), 0.6));
    OpCounts plain_ops, logged_ops;
    std::vector<ReliefRead> reads;
    const double u = 0.1 + 0.027 * k, vv = 0.9 - 0.025 * k;
    const ReliefEffect::Shift a = e.shift(u, vv, v, 1.0, 1.0, plain_ops);
    const ReliefEffect::Shift b = e.shift(u, vv, v, 1.0, 1.0, logged_ops, &reads);
    EXPECT_EQ(a.u, b.u);
    EXPECT_EQ(a.v, b.v);
    EXPECT_EQ(a.steps, b.steps);
    EXPECT_EQ(a.fetches, b.fetches);
    EXPECT_EQ(plain_ops, logged_ops);
    EXPECT_EQ(reads.size(), b.fetches);
    for (const ReliefRead& rd : reads) {
      EXPECT_EQ(rd.z, ReliefRead::kHeightRead);
      EXPECT_TRUE(rd.x >= 0 && rd.x < w && rd.y >= 0 && rd.y < h);
    }
    logged += static_cast<int>(reads.size());
  }
  EXPECT_GT(logged, 0);
}

}  // namespace
}  // namespace texsim
