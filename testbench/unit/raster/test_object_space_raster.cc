// ObjectSpaceRaster and SplatResolve: grid and edge samples against a brute-force enumeration,
// affine texture coordinates against barycentric interpolation, the one LOD per polygon, the
// splat weights against the area formula, depth visibility and the resolve's normalisation.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <utility>

#include "blocks/raster/object_space_raster.h"
#include "blocks/raster/splat_resolve.h"

namespace texsim {
namespace {

bool inside_convex(const RotatedPolygon& p, double x, double y) {
  int pos = 0, neg = 0;
  const size_t n = p.xy.size();
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec2 a = p.xy[i], b = p.xy[(i + 1) % n];
    const double c = (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
    pos += c > 1e-12;
    neg += c < -1e-12;
  }
  return pos == 0 || neg == 0;
}

TEST(ObjectSpaceRaster, GridSamplesAreTheGridPointsInside) {
  const RotatedPolygon tri{{{0.13, 0.07}, {3.91, 0.52}, {1.2, 2.77}}, 5.0};
  const double h = 0.25;
  const ObjectSpaceRaster r;
  std::set<std::pair<long, long>> got;
  ObjectSpaceRasterStats st;
  OpCounts ops;
  PlaneUvMap m;
  r.rasterize(
      tri, h, m,
      [&](const PlaneSample& s) {
        got.insert({std::lround(s.x / h * 8), std::lround(s.y / h * 8)});
      },
      st, ops);
  uint64_t want = 0;
  for (long j = -4; j < 20; ++j) {
    for (long i = -4; i < 20; ++i) {
      if (!inside_convex(tri, static_cast<double>(i) * h, static_cast<double>(j) * h)) continue;
      ++want;
      EXPECT_TRUE(got.count({i * 8, j * 8})) << i << " " << j;
    }
  }
  EXPECT_EQ(st.grid_samples, want);
  // Edge samples: every edge cut into ceil(length / h) pieces, starting at its vertex.
  uint64_t edges = 0;
  for (size_t e = 0; e < 3; ++e) {
    const glm::dvec2 a = tri.xy[e], b = tri.xy[(e + 1) % 3];
    edges += static_cast<uint64_t>(std::ceil(std::hypot(b.x - a.x, b.y - a.y) / h));
  }
  EXPECT_EQ(st.edge_samples, edges);
  EXPECT_LE(static_cast<double>(st.grid_samples + st.edge_samples),
            ObjectSpaceRaster::sample_bound(tri, h));
}

TEST(ObjectSpaceRaster, AffineCoordinatesMatchBarycentricInterpolation) {
  const glm::dvec2 p[3] = {{0.5, -1.0}, {4.0, 0.2}, {1.0, 3.0}};
  const glm::dvec2 uv[3] = {{0.1, 0.2}, {0.9, 0.25}, {0.3, 1.7}};
  OpCounts ops;
  const PlaneUvMap m = ObjectSpaceRaster::uv_map(p, uv, ops);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0, 1);
  for (int t = 0; t < 100; ++t) {
    double a = u(rng), b = u(rng);
    if (a + b > 1) {
      a = 1 - a;
      b = 1 - b;
    }
    const glm::dvec2 q = p[0] + a * (p[1] - p[0]) + b * (p[2] - p[0]);
    const glm::dvec2 want = uv[0] + a * (uv[1] - uv[0]) + b * (uv[2] - uv[0]);
    EXPECT_NEAR(m.u0 + m.ux * q.x + m.uy * q.y, want.x, 1e-13);
    EXPECT_NEAR(m.v0 + m.vx * q.x + m.vy * q.y, want.y, 1e-13);
  }
}

TEST(ObjectSpaceRaster, OneLodFromTheStepInTexels) {
  PlaneUvMap m;
  m.ux = 0.5;  // half a texture per unit along x'
  m.vy = 0.25;
  OpCounts ops;
  // h = 1/64 unit: 256·0.5/64 = 2 texels along x', 1 along y': log2(2) = 1.
  EXPECT_NEAR(ObjectSpaceRaster::lod(m, 1.0 / 64, 256, 256, ops), 1.0, 1e-12);
}

TEST(ObjectSpaceRaster, StepFromTheLargestScreenScale) {
  OpCounts ops;
  // A vertex at Z = 2 on the axis and one at Z = 4 off it (q = 1): Jmax = f/2 · √2.
  const std::vector<glm::dvec3> v{{0, 0, 2}, {4, 0, 4}, {0, 1, 3}};
  const double j = ObjectSpaceRaster::max_screen_scale(v, 100, ops);
  EXPECT_NEAR(j, 50 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(ObjectSpaceRaster().step(j, ops), 0.75 / j, 1e-15);
  EXPECT_EQ(ObjectSpaceRaster::max_screen_scale({{0, 0, -1}, {1, 0, 2}}, 100, ops), 0);
  EXPECT_EQ(ObjectSpaceRaster().step(0, ops), 0);
}

TEST(SplatResolve, AreaWeightsOfTheFourNearestPixels) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-3, 10);
  for (int t = 0; t < 1000; ++t) {
    const double x = u(rng), y = u(rng);
    int i = 0, j = 0;
    double s[4];
    SplatResolve::weights(x, y, i, j, s);
    double sum = 0;
    for (int k = 0; k < 4; ++k) {
      // Independent: the tent (1 − |dx|)(1 − |dy|) of the pixel centre (px + ½, py + ½).
      const double cx = i + (k & 1) + 0.5, cy = j + (k >> 1) + 0.5;
      const double want = (1 - std::fabs(x - cx)) * (1 - std::fabs(y - cy));
      EXPECT_NEAR(s[k], want, 1e-12);
      EXPECT_GE(s[k], 0);
      sum += s[k];
    }
    EXPECT_NEAR(sum, 1, 1e-12);
  }
}

TEST(SplatResolve, NormalisesAndCountsTrafficAndHoles) {
  const SplatResolve sr;
  SplatBuffer b(4, 3);
  SplatStats st;
  OpCounts ops;
  // Two samples of different colours at the same depth on pixel (1, 1)'s centre and between
  // pixels: the resolved pixel is their weighted mean.
  sr.splat(b, 1.5, 1.5, 2.0, 0.01, Rgba(1, 0, 0, 1), st, ops);
  sr.splat(b, 2.0, 1.5, 2.0, 0.01, Rgba(0, 1, 0, 1), st, ops);
  std::vector<uint8_t> covered(12, 0);
  covered[b.index(1, 1)] = covered[b.index(2, 1)] = covered[b.index(3, 2)] = 1;
  std::vector<Rgba> out;
  const ResolveStats rs = sr.resolve(b, covered, Rgba(0, 0, 0, 0), out, ops);
  EXPECT_NEAR(out[b.index(1, 1)].r, 1.0 / 1.5, 1e-6);
  EXPECT_NEAR(out[b.index(1, 1)].g, 0.5 / 1.5, 1e-6);
  EXPECT_NEAR(out[b.index(2, 1)].g, 1.0, 1e-6);
  EXPECT_EQ(rs.expected, 3u);
  EXPECT_EQ(rs.holes, 1u);  // (3, 2): covered, no weight
  EXPECT_EQ(out[b.index(3, 2)], Rgba(0, 0, 0, 0));
  for (const Rgba& c : out) EXPECT_FALSE(std::isnan(c.r));
  // Sample 1 has one target of weight 1 and three of weight 0 (still written); sample 2 two
  // of ½ and two of 0.
  EXPECT_EQ(st.targets, 8u);
  EXPECT_EQ(st.bytes_read, 8 * SplatResolve::kEntryBytes);
  EXPECT_EQ(st.bytes_written, 8 * SplatResolve::kEntryBytes);
  EXPECT_EQ(rs.bytes_read, 12 * SplatResolve::kEntryBytes);
  EXPECT_EQ(rs.bytes_written, 12 * SplatResolve::kOutputBytes);
}

TEST(SplatResolve, DepthVisibilityPerSample) {
  const SplatResolve sr;
  SplatBuffer b(2, 2);
  SplatStats st;
  OpCounts ops;
  sr.splat(b, 1.0, 1.0, 5.0, 0.1, Rgba(1, 0, 0, 1), st, ops);   // far surface
  sr.splat(b, 1.0, 1.0, 2.0, 0.1, Rgba(0, 1, 0, 1), st, ops);   // nearer: restarts the pixels
  sr.splat(b, 1.0, 1.0, 9.0, 0.1, Rgba(0, 0, 1, 1), st, ops);   // behind: dropped
  sr.splat(b, 1.0, 1.0, 2.05, 0.1, Rgba(0, 1, 0, 1), st, ops);  // same surface: accumulates
  EXPECT_EQ(st.depth_resets, 4u);
  EXPECT_EQ(st.depth_dropped, 4u);
  std::vector<Rgba> out;
  (void)sr.resolve(b, {}, Rgba(0), out, ops);
  for (const Rgba& c : out) EXPECT_EQ(c, Rgba(0, 1, 0, 1));
  EXPECT_NEAR(b.weight[0], 0.5, 1e-12);
}

TEST(SplatResolve, OffscreenTargetsAreNotAccessed) {
  const SplatResolve sr;
  SplatBuffer b(2, 2);
  SplatStats st;
  OpCounts ops;
  sr.splat(b, 0.2, 0.2, 1, 0, Rgba(1), st, ops);  // three targets left of or above the image
  EXPECT_EQ(st.offscreen, 3u);
  sr.splat(b, std::nan(""), 0, 1, 0, Rgba(1), st, ops);
  sr.splat(b, 1e300, 0, 1, 0, Rgba(1), st, ops);
  EXPECT_EQ(st.offscreen, 11u);
  EXPECT_EQ(st.targets, 1u);
}

}  // namespace
}  // namespace texsim
