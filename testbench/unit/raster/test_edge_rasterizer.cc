// Edge-function rasteriser: top-left rule against a brute-force point-in-triangle test, shared
// edges covered exactly once (pairs, fans, grids), hard cases with defined outcomes,
// perspective-correct weights, and the measured coverage difference to closed triangles, the guard
// band.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <set>
#include <vector>

#include "blocks/base/tech_table.h"
#include "blocks/raster/edge_rasterizer.h"
#include "blocks/raster/guard_band_clipper.h"

namespace texsim {
namespace {

constexpr int32_t kW = 64, kH = 48;
const Scissor kScreen{0, 0, kW, kH};

size_t at(int32_t x, int32_t y) { return static_cast<size_t>(y) * kW + static_cast<size_t>(x); }

EdgeRasterizer with_bits(int bits) {
  EdgeRasterizer::Config c;
  c.subpixel_bits = bits;
  return EdgeRasterizer(c);
}

// Brute force in T on the snapped vertices (exact in double while coordinates stay below
// 2^20 units; long double for the huge cases): orientation, then the top-left rule.
template <class T>
bool reference_covers(const EdgeRasterizer::Setup& st, int32_t px, int32_t py) {
  const T s = std::ldexp(T{1}, -st.bits);
  T x[3], y[3];
  for (int i = 0; i < 3; ++i) {
    x[i] = static_cast<T>(st.vx[i]) * s;
    y[i] = static_cast<T>(st.vy[i]) * s;
  }
  for (int e = 0; e < 3; ++e) {
    const int a = (e + 1) % 3, b = (e + 2) % 3;
    const T dx = x[b] - x[a], dy = y[b] - y[a];
    const T ev = dx * (py - y[a]) - dy * (px - x[a]);
    const bool top_left = dy < 0 || (dy == 0 && dx > 0);
    if (ev < 0 || (ev == 0 && !top_left)) return false;
  }
  return true;
}

std::vector<int> coverage(const EdgeRasterizer& r, const ScreenVertex v[3], const Scissor& sc) {
  std::vector<int> c(static_cast<size_t>(sc.x1 - sc.x0) * static_cast<size_t>(sc.y1 - sc.y0), 0);
  for (const RowSpan& s : r.rasterize(v, sc)) {
    for (int32_t x = s.x0; x < s.x0 + s.n; ++x) {
      ++c[static_cast<size_t>(s.y - sc.y0) * static_cast<size_t>(sc.x1 - sc.x0) +
          static_cast<size_t>(x - sc.x0)];
    }
  }
  return c;
}

void add_coverage(const EdgeRasterizer& r, const ScreenVertex v[3], std::vector<int>& c) {
  const std::vector<int> one = coverage(r, v, kScreen);
  for (size_t i = 0; i < c.size(); ++i) c[i] += one[i];
}

TEST(EdgeRasterizer, MatchesBruteForceTopLeftInEveryOrientation) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> ux(-8, kW + 8), uy(-8, kH + 8);
  std::uniform_int_distribution<int> grid(-4, 70);
  for (int bits : {0, 4, 8}) {
    const EdgeRasterizer r = with_bits(bits);
    for (int t = 0; t < 600; ++t) {
      ScreenVertex v[3];
      for (auto& p : v) {
        // A third on integer or half-integer positions (many ties on pixel centres).
        p = t % 3 == 0 ? ScreenVertex{grid(rng) * 0.5, grid(rng) * 0.5, 1}
                       : ScreenVertex{ux(rng), uy(rng), 1};
      }
      const EdgeRasterizer::Setup st = r.setup(v, kScreen);
      if (!st.ok()) {
        EXPECT_EQ(st.reject, RasterReject::Degenerate);
        continue;
      }
      const std::vector<int> c = coverage(r, v, kScreen);
      for (int32_t y = 0; y < kH; ++y) {
        for (int32_t x = 0; x < kW; ++x) {
          ASSERT_EQ(c[at(x, y)], reference_covers<double>(st, x, y) ? 1 : 0)
              << "bits " << bits << " triangle " << t << " pixel " << x << "," << y;
        }
      }
    }
  }
}

TEST(EdgeRasterizer, SharedEdgesOfQuadsAreCoveredOnce) {
  int on_edge = 0;  // centres exactly on an open shared edge
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> ux(0, kW), uy(0, kH);
  std::uniform_int_distribution<int> gx(0, kW), gy(0, kH);
  const EdgeRasterizer r = with_bits(4);
  for (int t = 0; t < 400; ++t) {
    // Two triangles on either side of the shared edge a-b, in both windings.
    ScreenVertex a{ux(rng), uy(rng)}, b{ux(rng), uy(rng)}, c{ux(rng), uy(rng)}, d{ux(rng), uy(rng)};
    if (t % 2) a = {double(gx(rng)), double(gy(rng))}, b = {double(gx(rng)), double(gy(rng))};
    const ScreenVertex t1[3] = {a, b, c};
    const ScreenVertex t2[3] = {t % 4 < 2 ? b : a, t % 4 < 2 ? a : b, d};
    const auto s1 = r.setup(t1, kScreen), s2 = r.setup(t2, kScreen);
    if (!s1.ok() || !s2.ok()) continue;
    // c and d on opposite sides of a-b: the union has no hole along a-b.
    const auto side = [&](const ScreenVertex& p) {
      return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
    };
    if (!(side(c) * side(d) < 0)) continue;
    std::vector<int> cov(static_cast<size_t>(kW * kH), 0);
    add_coverage(r, t1, cov);
    add_coverage(r, t2, cov);
    for (int32_t y = 0; y < kH; ++y) {
      for (int32_t x = 0; x < kW; ++x) {
        const int n = cov[at(x, y)];
        ASSERT_LE(n, 1) << t;
        // A pixel centre exactly on the open shared edge is covered exactly once.
        // The shared edge a-b of t1 is oriented edge 2 (a→b), or edge 1 (b→a) when set-up
        // swapped b and c.
        const int shared = s1.perm[1] == 1 ? 2 : 1;
        const bool on1 = EdgeRasterizer::edge_value(s1, shared, x, y) == 0;
        const double along = ((x - a.x) * (b.x - a.x) + (y - a.y) * (b.y - a.y)) /
                             ((b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y));
        const bool strictly_between = along > 1e-9 && along < 1 - 1e-9;
        if (on1 && strictly_between) {
          EXPECT_EQ(n, 1);
          ++on_edge;
        }
      }
    }
  }
  EXPECT_GT(on_edge, 50);
}

TEST(EdgeRasterizer, FansAndGridsCoverEveryPixelOnce) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> jitter(-0.45, 0.45);
  const EdgeRasterizer r = with_bits(8);
  // Grids: a 6×4 lattice on [4, 58] × [4, 44] with jittered interior nodes, each cell cut along
  // a random diagonal (jitter small enough that every cell stays convex). The union is the
  // rectangle: pixels [4, 58) × [4, 44) once, others never.
  for (int t = 0; t < 40; ++t) {
    const int nx = 6, ny = 4;
    std::vector<ScreenVertex> node;
    for (int j = 0; j <= ny; ++j) {
      for (int i = 0; i <= nx; ++i) {
        const bool inner = i > 0 && i < nx && j > 0 && j < ny;
        node.push_back({4 + 9.0 * i + (inner ? 4 * jitter(rng) : 0),
                        4 + 10.0 * j + (inner ? 4 * jitter(rng) : 0)});
      }
    }
    std::vector<int> cov(static_cast<size_t>(kW * kH), 0);
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        const ScreenVertex p00 = node[j * (nx + 1) + i], p10 = node[j * (nx + 1) + i + 1];
        const ScreenVertex p01 = node[(j + 1) * (nx + 1) + i],
                           p11 = node[(j + 1) * (nx + 1) + i + 1];
        const bool diag = rng() & 1;
        const ScreenVertex a[3] = {p00, p10, diag ? p11 : p01}, b[3] = {diag ? p00 : p10, p11, p01};
        add_coverage(r, a, cov);
        add_coverage(r, b, cov);
      }
    }
    for (int32_t y = 0; y < kH; ++y) {
      for (int32_t x = 0; x < kW; ++x) {
        const bool in = x >= 4 && x < 58 && y >= 4 && y < 44;
        ASSERT_EQ(cov[at(x, y)], in ? 1 : 0) << t << " " << x << "," << y;
      }
    }
  }
  // Fans: a convex polygon on a circle around a centre. Pixels strictly inside: once; outside:
  // never; on the outline: at most once.
  for (int t = 0; t < 200; ++t) {
    const int n = 3 + t % 9;
    // Angles 2π(i + j)/n with |j| <= 0.2: every gap is below π, so the centre is inside.
    std::vector<double> ang(n);
    for (int i = 0; i < n; ++i) ang[i] = 6.283185307179586 * (i + 0.44 * jitter(rng)) / n;
    const ScreenVertex c{31.3 + jitter(rng), 23.7 + jitter(rng)};
    std::vector<ScreenVertex> rim;
    rim.reserve(ang.size());
    for (double a : ang) rim.push_back({32 + 20 * std::cos(a), 24 + 20 * std::sin(a)});
    std::vector<int> cov(static_cast<size_t>(kW * kH), 0);
    for (int i = 0; i < n; ++i) {
      const ScreenVertex tri[3] = {c, rim[i], rim[(i + 1) % n]};
      add_coverage(r, tri, cov);
    }
    for (int32_t y = 0; y < kH; ++y) {
      for (int32_t x = 0; x < kW; ++x) {
        const int k = cov[at(x, y)];
        ASSERT_LE(k, 1) << t;
        // Inside the polygon by more than a snapping step: must be covered.
        bool deep = true, outside = false;
        for (int i = 0; i < n; ++i) {
          const ScreenVertex &a = rim[i], &b = rim[(i + 1) % n];
          const double len = std::hypot(b.x - a.x, b.y - a.y);
          const double d = ((b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x)) / len;
          deep = deep && d > 0.01;
          outside = outside || d < -0.01;
        }
        if (deep) {
          EXPECT_EQ(k, 1) << t << " " << x << "," << y;
        }
        if (outside) {
          EXPECT_EQ(k, 0) << t << " " << x << "," << y;
        }
      }
    }
  }
}

TEST(EdgeRasterizer, HardCasesHaveDefinedOutcomes) {
  const EdgeRasterizer r = with_bits(8);
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const ScreenVertex collinear[3] = {{1, 1}, {5, 5}, {9, 9}};
  EXPECT_EQ(r.setup(collinear, kScreen).reject, RasterReject::Degenerate);
  const ScreenVertex coincident[3] = {{3, 3}, {3, 3}, {7, 1}};
  EXPECT_EQ(r.setup(coincident, kScreen).reject, RasterReject::Degenerate);
  // Collinear only after snapping (2^-10 off the line, grid 2^-8): degenerate, no pixels.
  const ScreenVertex almost[3] = {{1, 1}, {5, 5 + 1.0 / 1024}, {9, 9}};
  EXPECT_EQ(r.setup(almost, kScreen).reject, RasterReject::Degenerate);
  for (const ScreenVertex bad :
       {ScreenVertex{nan, 1}, ScreenVertex{1, inf}, ScreenVertex{1, 1, nan}}) {
    const ScreenVertex v[3] = {bad, {10, 1}, {1, 10}};
    EXPECT_EQ(r.setup(v, kScreen).reject, RasterReject::NotFinite);
    EXPECT_TRUE(r.rasterize(v, kScreen).empty());
  }
  const ScreenVertex behind[3] = {{1, 1, -1}, {10, 1}, {1, 10}};
  EXPECT_EQ(r.setup(behind, kScreen).reject, RasterReject::NonPositiveW);
  const ScreenVertex far[3] = {{-1e7, -1e7}, {1e7, 0}, {0, 1e7}};  // 1e7·256 > 2^30
  EXPECT_EQ(r.setup(far, kScreen).reject, RasterReject::OutOfRange);
  EXPECT_STRNE(reject_reason(RasterReject::OutOfRange), reject_reason(RasterReject::NotFinite));
  // Huge but inside the guard band (±4·10^6 pixels with 8 bits): clipped to the scissor, every
  // pixel of the screen covered, as the long double brute force says.
  const ScreenVertex huge[3] = {{-4e6, -4e6}, {4e6, -1}, {-1, 4e6}};
  const auto st = r.setup(huge, kScreen);
  ASSERT_TRUE(st.ok());
  const std::vector<int> c = coverage(r, huge, kScreen);
  for (int32_t y = 0; y < kH; ++y) {
    for (int32_t x = 0; x < kW; ++x) {
      ASSERT_EQ(c[at(x, y)], reference_covers<long double>(st, x, y) ? 1 : 0);
    }
  }
  EXPECT_EQ(c[0], 1);
  // One-pixel triangle around the centre of pixel (5, 7); a sliver covering no centre.
  const ScreenVertex one[3] = {{4.8, 6.8}, {5.3, 6.9}, {5.0, 7.4}};
  const auto rows = r.rasterize(one, kScreen);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].x0, 5);
  EXPECT_EQ(rows[0].y, 7);
  EXPECT_EQ(rows[0].n, 1);
  const ScreenVertex sliver[3] = {{0.2, 0.5}, {60.3, 0.6}, {30.1, 0.7}};
  EXPECT_TRUE(r.rasterize(sliver, kScreen).empty());
  // A sliver over a row of centres: top edge (horizontal, +x) keeps y = 3, bottom edge drops it.
  const ScreenVertex top[3] = {{0.5, 3}, {20.5, 3}, {10, 3.5}};
  const ScreenVertex bottom[3] = {{0.5, 3}, {10, 2.5}, {20.5, 3}};
  EXPECT_EQ(r.rasterize(top, kScreen).size(), 1u);
  EXPECT_TRUE(r.rasterize(bottom, kScreen).empty());
}

TEST(EdgeRasterizer, PerspectiveCorrectWeightsReproduceTheViewPoint) {
  // View-space vertices on a plane, projected with f = 40 around (32, 24); snapping-exact screen
  // positions are obtained by choosing the screen points and depths, then back-projecting.
  std::mt19937_64 rng(14);
  std::uniform_int_distribution<int> sx(0, 63 * 16), sy(0, 47 * 16);
  std::uniform_real_distribution<double> z(1, 20);
  const double f = 40, cx = 32, cy = 24;
  const EdgeRasterizer r = with_bits(4);
  int checked = 0;
  for (int t = 0; t < 200; ++t) {
    ScreenVertex v[3];
    double X[3], Y[3], Z[3];
    for (int i = 0; i < 3; ++i) {
      v[i] = {sx(rng) / 16.0, sy(rng) / 16.0, z(rng)};
      Z[i] = v[i].w;
      X[i] = (v[i].x - cx) * Z[i] / f;
      Y[i] = (v[i].y - cy) * Z[i] / f;
    }
    const auto st = r.setup(v, kScreen);
    if (!st.ok()) continue;
    r.scan(st, [&](int32_t x, int32_t y, const std::array<int64_t, 3>& e) {
      const auto w = EdgeRasterizer::perspective_weights(st, e);
      const double px = EdgeRasterizer::interpolate(w, X), py = EdgeRasterizer::interpolate(w, Y);
      const double pz = EdgeRasterizer::interpolate(w, Z);
      EXPECT_NEAR(f * px / pz + cx, x, 1e-9);
      EXPECT_NEAR(f * py / pz + cy, y, 1e-9);
      EXPECT_NEAR(w[0] + w[1] + w[2], 1.0, 1e-12);
      ++checked;
    });
  }
  EXPECT_GT(checked, 1000);
}

// The closed triangle (long double, no snapping) includes pixel centres on every edge, the
// convention of the row rasteriser this block replaced; this block includes them on top and
// left edges only. Measured over random triangles of every orientation.
std::vector<int> closed_coverage(const double x[3], const double y[3]) {
  std::vector<int> c(static_cast<size_t>(kW * kH), 0);
  const long double area = (static_cast<long double>(x[1]) - x[0]) * (y[2] - y[0]) -
                           (static_cast<long double>(x[2]) - x[0]) * (y[1] - y[0]);
  if (area == 0) return c;
  for (int32_t py = 0; py < kH; ++py) {
    for (int32_t px = 0; px < kW; ++px) {
      bool in = true;
      for (int e = 0; e < 3; ++e) {
        const long double ax = x[e], ay = y[e], bx = x[(e + 1) % 3], by = y[(e + 1) % 3];
        const long double ev = (bx - ax) * (py - ay) - (by - ay) * (px - ax);
        in = in && (area > 0 ? ev >= 0 : ev <= 0);
      }
      c[at(px, py)] = in ? 1 : 0;
    }
  }
  return c;
}

TEST(EdgeRasterizer, CoverageDifferenceToClosedTriangles) {
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<double> ux(-4, kW + 4), uy(-4, kH + 4);
  std::uniform_int_distribution<int> gx(-4, kW + 4), gy(-4, kH + 4);
  const EdgeRasterizer r = with_bits(8);
  for (int mode = 0; mode < 3; ++mode) {
    uint64_t both = 0, row_only = 0, edge_only = 0;
    for (int t = 0; t < 3000; ++t) {
      ScreenVertex v[3];
      for (auto& p : v) {
        if (mode == 0) p = {ux(rng), uy(rng)};  // any double
        if (mode == 1) p = {std::round(ux(rng) * 256) / 256, std::round(uy(rng) * 256) / 256};
        if (mode == 2) p = {double(gx(rng)), double(gy(rng))};  // integers
      }
      const double x[3] = {v[0].x, v[1].x, v[2].x}, y[3] = {v[0].y, v[1].y, v[2].y};
      const std::vector<int> rc = closed_coverage(x, y);
      const std::vector<int> ec = coverage(r, v, kScreen);
      for (size_t i = 0; i < rc.size(); ++i) {
        both += rc[i] && ec[i];
        row_only += rc[i] && !ec[i];
        edge_only += !rc[i] && ec[i];
      }
    }
    const char* names[3] = {"random doubles", "on the 1/256 grid", "integer vertices"};
    std::printf(
        "coverage vs closed triangles (%s): common %llu, closed only %llu (%.4f%%), edge only "
        "%llu (%.4f%%)\n",
        names[mode], static_cast<unsigned long long>(both),
        static_cast<unsigned long long>(row_only),
        100.0 * static_cast<double>(row_only) / static_cast<double>(both),
        static_cast<unsigned long long>(edge_only),
        100.0 * static_cast<double>(edge_only) / static_cast<double>(both));
    // On the snapping grid the only difference is the bottom/right edge pixels: edge ⊆ row.
    if (mode > 0) {
      EXPECT_EQ(edge_only, 0u) << names[mode];
    }
    if (mode == 2) {
      EXPECT_GT(row_only, 0u);
    }
  }
}

TEST(EdgeRasterizer, BlockContract) {
  const EdgeRasterizer r;
  EXPECT_EQ(r.name(), "raster.edge");
  EXPECT_NE(r.arithmetic().find("int64"), std::string::npos);
  const TimingSpec ts = r.timing(TechTable::defaults());
  EXPECT_EQ(ts.ii, 1u);
  EXPECT_GE(ts.latency, 1u);
  EXPECT_EQ(r.ops_per_item().add, 3u);
  EdgeRasterStats s;
  const ScreenVertex v[3] = {{1, 1}, {20, 2}, {5, 15}};
  (void)r.rasterize(v, kScreen, &s);
  EXPECT_EQ(s.triangles, 1u);
  EXPECT_GT(s.pixels_visited, s.pixels_covered);
  EXPECT_GT(s.pixels_covered, 100u);
}

// A triangle reaching far beyond the guard band (a plane running towards the eye) is clipped
// in screen space first: its coverage on the screen is the closed triangle's minus at most the
// pixels on its bottom/right edges, and a convex polygon's fan covers each pixel once.
TEST(GuardBandClipper, FarVerticesAreClippedWithoutChangingScreenCoverage) {
  const EdgeRasterizer r = with_bits(8);
  const double x[3] = {-3.0e9, 50.5, 20.25}, y[3] = {10.3, 1.2e9, -7.7};
  const std::vector<ScreenVertex> tri = {{x[0], y[0], 1}, {x[1], y[1], 1}, {x[2], y[2], 1}};
  ASSERT_FALSE(r.setup(tri.data(), kScreen).ok());  // beyond ±2^30 units: refused unclipped
  std::vector<int> ec(static_cast<size_t>(kW * kH), 0);
  for (const RowSpan& s : rasterize_convex(r, tri, kScreen)) {
    for (int32_t i = s.x0; i < s.x0 + s.n; ++i) ++ec[at(i, s.y)];
  }
  const std::vector<int> cc = closed_coverage(x, y);
  uint64_t n = 0, closed_only = 0;
  for (size_t i = 0; i < ec.size(); ++i) {
    EXPECT_LE(ec[i], 1) << i;
    EXPECT_LE(ec[i], cc[i]) << i;  // nothing outside the triangle
    n += static_cast<uint64_t>(ec[i]);
    closed_only += static_cast<uint64_t>(cc[i] - ec[i]);
  }
  EXPECT_GT(n, 500u);
  EXPECT_LE(closed_only, static_cast<uint64_t>(kW + kH));  // one edge's pixels at most
  // A hexagon: its fan's pixels once each, the union equal to the closed polygon's interior.
  std::vector<ScreenVertex> hex;
  for (int k = 0; k < 6; ++k) {
    const double a = k * 3.14159265358979 / 3 + 0.1;
    hex.push_back({31.3 + 40 * std::cos(a), 23.7 + 30 * std::sin(a), 1});
  }
  std::vector<int> hc(static_cast<size_t>(kW * kH), 0);
  std::set<int32_t> rows;
  for (const RowSpan& s : rasterize_convex(r, hex, kScreen)) {
    EXPECT_TRUE(rows.insert(s.y).second) << "one span per row";
    for (int32_t i = s.x0; i < s.x0 + s.n; ++i) ++hc[at(i, s.y)];
  }
  for (int v : hc) EXPECT_LE(v, 1);
  EXPECT_GT(rows.size(), 40u);
}

}  // namespace
}  // namespace texsim
