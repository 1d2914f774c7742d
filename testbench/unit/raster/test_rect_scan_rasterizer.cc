// Rectangle-scan constant-depth rasteriser (seed 002) and its elements: the row pattern, the
// partition of the rectangle into rows, coverage equal to the edge-function rasteriser (top-left)
// for every orientation and row slope, the hazards (a diagonal crossing missed by an 8-connected
// outline, runs of hits, a row touching a vertex, |k| >> 1, B -> 0), shared edges, the seed's
// outline-inclusive convention measured, and cycles at both clocks with divisions = q.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <vector>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/base/tech_table.h"
#include "blocks/geometry/projective_map.h"
#include "blocks/raster/edge_rasterizer.h"
#include "blocks/raster/rect_scan/coordinate_counters.h"
#include "blocks/raster/rect_scan/line_stepper.h"
#include "blocks/raster/rect_scan/outline_comparator.h"
#include "blocks/raster/rect_scan/rect_scan_rasterizer.h"
#include "blocks/raster/rect_scan/row_start_counter.h"
#include "blocks/raster/rect_scan/seed_outline.h"
#include "blocks/raster/rect_scan/texturing_control.h"
#include "blocks/texture/coords/uv_constant_depth.h"

namespace texsim {
namespace {

constexpr int32_t kW = 64, kH = 48;
const Scissor kScreen{0, 0, kW, kH};

using PixelSet = std::set<std::pair<int32_t, int32_t>>;

PixelSet edge_pixels(const ScreenVertex v[3], const Scissor& sc = kScreen) {
  PixelSet p;
  for (const RowSpan& s : EdgeRasterizer().rasterize(v, sc)) {
    for (int32_t x = s.x0; x < s.x0 + s.n; ++x) p.insert({x, s.y});
  }
  return p;
}

RectScanRasterizer rect_scan(RectScanCoverage c = RectScanCoverage::TopLeft) {
  RectScanRasterizer::Config cfg;
  cfg.coverage = c;
  return RectScanRasterizer(cfg);
}

// Textured pixels as a set; fails on a pixel textured twice.
PixelSet scan_pixels(const RectScanResult& r) {
  PixelSet p;
  for (const auto& px : r.pixels) EXPECT_TRUE(p.insert(px).second) << "twice: " << px.first;
  return p;
}

TEST(LineStepper, StepsReproduceTheRowPattern) {
  const LineStepper ls;
  for (double k : {0.0, 0.3, -0.3, 0.5, -0.77, 1.0, -1.0, 1.0 / 3}) {
    const RowLine l = ls.line_for_slope(true, k);
    LineStepper li;
    li.start_row(l);
    int64_t d = 0;
    for (int64_t n = 1; n < 300; ++n) {
      d += li.step(l);
      ASSERT_EQ(d, l.offset(n)) << k << " " << n;
      ASSERT_LE(std::fabs(static_cast<double>(d) - l.slope() * static_cast<double>(n)), 0.5);
    }
    EXPECT_NEAR(l.slope(), k, 1.0 / 4096);
  }
}

TEST(LineStepper, MajorAxisFromTheDenominator) {
  const LineStepper ls;
  RowLine l = ls.line_for_denominator(0.2, 1.0);  // k = -0.2 along x
  EXPECT_TRUE(l.x_major);
  EXPECT_NEAR(l.slope(), -0.2, 1e-3);
  l = ls.line_for_denominator(100.0, 1.0);  // |k| = 100 along x: scan y, k = -0.01
  EXPECT_FALSE(l.x_major);
  EXPECT_NEAR(l.slope(), -0.01, 1e-3);
  l = ls.line_for_denominator(0.5, 0.0);  // B -> 0: vertical constant-depth lines, k = 0 along y
  EXPECT_FALSE(l.x_major);
  EXPECT_EQ(l.delta_minor, 0);
  l = ls.line_for_denominator(std::numeric_limits<double>::quiet_NaN(), 1);
  EXPECT_TRUE(l.x_major);
  EXPECT_EQ(l.delta_minor, 0);
}

TEST(RectScanElements, CountersAndComparator) {
  RowStartCounter rs;
  rs.load(3, -2);
  rs.next_row();
  EXPECT_EQ(rs.major0(), 3);
  EXPECT_EQ(rs.minor(), -1);
  CoordinateCounters cc(false);  // y-major: ЛЧу is the major counter
  cc.load(rs.major0(), rs.minor());
  cc.step(1);
  cc.step(0);
  EXPECT_EQ(cc.y(), 5);
  EXPECT_EQ(cc.x(), 0);
  OutlineComparator bp;
  bp.set_foreground(5);
  EXPECT_EQ(bp.compare(6), 4);
  EXPECT_EQ(bp.compare(2), 0);
  EXPECT_EQ(bp.hits(), 1u);
  for (const TimingSpec& t :
       {rs.timing(TechTable::defaults()), cc.timing(TechTable::defaults()),
        bp.timing(TechTable::defaults()), TexturingControl().timing(TechTable::defaults()),
        LineStepper().timing(TechTable::defaults())}) {
    EXPECT_EQ(t.ii, 1u);
    EXPECT_GE(t.latency, 1u);
  }
}

// Every pixel of the plane belongs to exactly one row: row(major, minor) = minor - d(n).
TEST(RectScanRasterizer, NeighbouringRowsTileThePlane) {
  const LineStepper ls;
  for (double k : {0.0, 0.37, -0.61, 1.0, -1.0}) {
    const RowLine l = ls.line_for_slope(true, k);
    std::map<std::pair<int, int>, int> count;
    for (int t = -40; t < 80; ++t) {
      for (int n = 0; n < 40; ++n) ++count[{n, t + static_cast<int>(l.offset(n))}];
    }
    for (int n = 0; n < 40; ++n) {
      for (int m = 0; m < 40; ++m) ASSERT_EQ((count[{n, m}]), 1) << k;
    }
  }
}

TEST(RectScanRasterizer, CoverageEqualsTheEdgeRasterizerForEveryOrientationAndSlope) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> ux(-6, kW + 6), uy(-6, kH + 6), uk(-1, 1);
  std::uniform_int_distribution<int> grid(-4, 70);
  const RectScanRasterizer r = rect_scan();
  uint64_t pixels = 0;
  for (int t = 0; t < 1500; ++t) {
    ScreenVertex v[3];
    for (auto& p : v) {
      p = t % 3 == 0 ? ScreenVertex{grid(rng) * 0.5, grid(rng) * 0.5}
                     : ScreenVertex{ux(rng), uy(rng)};
    }
    // Slopes of either axis, the axes themselves and the diagonals.
    const double k = t % 5 == 0 ? std::round(uk(rng)) : uk(rng);
    const RowLine line = r.line_for_slope(t % 2 == 0, k);
    const RectScanResult res = r.rasterize(v, line, kScreen);
    ASSERT_EQ(scan_pixels(res), edge_pixels(v)) << t << " k " << k;
    pixels += res.stats.pixels_textured;
    // q: rows with a textured pixel, one reciprocal each.
    std::set<int32_t> rows;
    for (const RectScanRun& run : res.runs) rows.insert(run.t);
    EXPECT_EQ(res.stats.rows_textured, rows.size());
  }
  EXPECT_GT(pixels, 100000u);
}

// The seed's 8-connected one-colour outline (SeedOutlineMemory, coverage = "outline_parity"),
// read back pixel by pixel over the screen.
PixelSet screen_outline_8(const ScreenVertex v[3]) {
  const EdgeRasterizer::Setup st = EdgeRasterizer().setup(v, kScreen);
  SeedOutlineMemory mem;
  mem.draw(st, RowLine{}, 0);
  PixelSet p;
  for (int32_t y = -1; y <= kH; ++y) {
    for (int32_t x = -1; x <= kW; ++x) {
      if (mem.read(x, y) != 0) p.insert({x, y});
    }
  }
  return p;
}

TEST(RectScanRasterizer, HazardDiagonalCrossingMissedByAnEightConnectedOutline) {
  // Left edge on the anti-diagonal x + y = 20, rows along the diagonal (k = 1): a row steps
  // (n, t+n) -> (n+1, t+n+1) while the outline steps (x, 20-x) -> (x+1, 19-x); rows with odd
  // t cross it between pixels.
  const ScreenVertex v[3] = {{20, 0}, {40, 20}, {0, 20}};
  const RectScanRasterizer r = rect_scan();
  const RowLine line = r.line_for_slope(true, 1.0);
  const RectScanResult res = r.rasterize(v, line, kScreen);
  EXPECT_EQ(scan_pixels(res), edge_pixels(v));
  const PixelSet outline = screen_outline_8(v);
  const PixelSet inside = edge_pixels(v);
  int missed = 0;
  for (int32_t t = -40; t <= 20; ++t) {
    int hits = 0;
    bool has_inside = false;
    for (int32_t n = 0; n <= 40; ++n) {
      const std::pair<int32_t, int32_t> px{n, t + static_cast<int32_t>(line.offset(n))};
      hits += outline.count(px) && px.first + px.second < 21;  // hits on the left edge only
      has_inside = has_inside || inside.count(px);
    }
    missed += has_inside && hits == 0;
  }
  EXPECT_GT(missed, 5) << "the 8-connected outline should miss the crossing on odd rows";
}

TEST(RectScanRasterizer, HazardRunsOfHitsAndRowsTouchingAVertex) {
  const RectScanRasterizer r = rect_scan();
  // An edge nearly parallel to the rows (slope 0.49 against k' = 0.5): the digital row zigzags
  // across it, several hits of one edge on one crossing (read back from the memory).
  const ScreenVertex shallow[3] = {{0, 0}, {63, 30.87}, {0, 47}};
  const RowLine line = r.line_for_slope(true, 0.5);
  const RectScanResult a = r.rasterize(shallow, line, kScreen);
  EXPECT_EQ(scan_pixels(a), edge_pixels(shallow));
  const EdgeRasterizer::Setup st = EdgeRasterizer().setup(shallow, kScreen);
  OutlineMemory mem(line, 0, 63, -40, 80);
  mem.draw(st);
  int most = 0;
  for (int32_t t = -40; t <= 47; ++t) {
    int hits = 0;
    for (int32_t n = 1; n <= 63; ++n) {
      const uint8_t w = mem.read(n, t + static_cast<int32_t>(line.offset(n)));
      for (int e = 0; e < 3; ++e) hits += (w >> e) & 1;
    }
    most = std::max(most, hits);
  }
  EXPECT_GE(most, 5);
  // Top vertex exactly on a pixel centre, alone on its row (k = 0): the edge rasteriser's rule
  // decides (both edges leave the vertex downwards: left edge inclusive, right edge exclusive).
  for (const ScreenVertex top :
       {ScreenVertex{20, 5}, ScreenVertex{20.5, 5}, ScreenVertex{20, 5.5}}) {
    const ScreenVertex v[3] = {top, {30, 25}, {10, 25}};
    const RectScanResult b = r.rasterize(v, r.line_for_slope(true, 0), kScreen);
    EXPECT_EQ(scan_pixels(b), edge_pixels(v));
    EXPECT_GT(b.stats.vertex_hits + (top.x == 20.5 ? 1u : 0u), 0u);
  }
  // A vertex touched by a sloped row only.
  const ScreenVertex v[3] = {{10, 10}, {30, 30}, {12, 30}};
  for (double k : {1.0, -1.0, 0.5}) {
    const RectScanResult c = r.rasterize(v, r.line_for_slope(true, k), kScreen);
    EXPECT_EQ(scan_pixels(c), edge_pixels(v)) << k;
  }
}

TEST(RectScanRasterizer, HazardSteepAndVerticalConstantDepthLines) {
  const RectScanRasterizer r = rect_scan();
  std::mt19937_64 rng(22);
  std::uniform_real_distribution<double> ux(0, kW), uy(0, kH);
  for (const auto& [g, h] :
       std::vector<std::pair<double, double>>{{100, 1}, {-250, 1}, {1, 0}, {-1, 1e-9}, {3, 2.99}}) {
    const RowLine line = r.line_for_denominator(g, h);
    EXPECT_LE(std::fabs(line.slope()), 1.0);
    EXPECT_EQ(line.x_major, !(std::fabs(g) > std::fabs(h)));
    for (int t = 0; t < 100; ++t) {
      const ScreenVertex v[3] = {{ux(rng), uy(rng)}, {ux(rng), uy(rng)}, {ux(rng), uy(rng)}};
      ASSERT_EQ(scan_pixels(r.rasterize(v, line, kScreen)), edge_pixels(v)) << g << " " << h;
    }
  }
}

TEST(RectScanRasterizer, RejectsAndClipsLikeTheEdgeRasterizer) {
  const RectScanRasterizer r = rect_scan();
  const RowLine line = r.line_for_slope(true, 0.4);
  const ScreenVertex bad[3] = {{std::numeric_limits<double>::quiet_NaN(), 1}, {5, 5}, {1, 9}};
  EXPECT_EQ(r.rasterize(bad, line, kScreen).reject, RasterReject::NotFinite);
  const ScreenVertex flat[3] = {{1, 1}, {5, 5}, {9, 9}};
  EXPECT_EQ(r.rasterize(flat, line, kScreen).reject, RasterReject::Degenerate);
  // Larger than the screen: rows bounded by the scissor, every pixel once.
  const ScreenVertex huge[3] = {{-3e5, -3e5}, {3e5, -1}, {-1, 3e5}};
  const RectScanResult res = r.rasterize(huge, line, kScreen);
  EXPECT_EQ(scan_pixels(res), edge_pixels(huge));
  EXPECT_EQ(res.stats.pixels_textured, static_cast<uint64_t>(kW * kH));
  EXPECT_LT(res.stats.rows_scanned, 200u);
}

// Triangles of one plane share the row line; fans and grids: every pixel once.
TEST(RectScanRasterizer, SharedEdgesNoHolesNoDuplicates) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> jitter(-0.45, 0.45), uk(-1, 1);
  const RectScanRasterizer r = rect_scan();
  for (int t = 0; t < 60; ++t) {
    const RowLine line = r.line_for_slope(t % 2 == 0, uk(rng));
    std::map<std::pair<int32_t, int32_t>, int> count;
    const auto add = [&](const ScreenVertex a, const ScreenVertex b, const ScreenVertex c) {
      const ScreenVertex tri[3] = {a, b, c};
      for (const auto& px : r.rasterize(tri, line, kScreen).pixels) ++count[px];
    };
    // A 6×4 grid over [4, 58] × [4, 44] (interior nodes jittered, cells convex).
    std::vector<ScreenVertex> node;
    for (int j = 0; j <= 4; ++j) {
      for (int i = 0; i <= 6; ++i) {
        const bool inner = i > 0 && i < 6 && j > 0 && j < 4;
        node.push_back({4 + 9.0 * i + (inner ? 4 * jitter(rng) : 0),
                        4 + 10.0 * j + (inner ? 4 * jitter(rng) : 0)});
      }
    }
    for (int j = 0; j < 4; ++j) {
      for (int i = 0; i < 6; ++i) {
        const ScreenVertex p00 = node[j * 7 + i], p10 = node[j * 7 + i + 1];
        const ScreenVertex p01 = node[(j + 1) * 7 + i], p11 = node[(j + 1) * 7 + i + 1];
        if (rng() & 1) {
          add(p00, p10, p11);
          add(p00, p11, p01);
        } else {
          add(p00, p10, p01);
          add(p10, p11, p01);
        }
      }
    }
    for (int32_t y = 0; y < kH; ++y) {
      for (int32_t x = 0; x < kW; ++x) {
        const bool in = x >= 4 && x < 58 && y >= 4 && y < 44;
        ASSERT_EQ((count[{x, y}]), in ? 1 : 0) << t << " " << x << "," << y;
      }
    }
  }
}

// Random pairs sharing an edge, in both windings, with a common row line of either axis.
TEST(RectScanRasterizer, PairsSharingAnEdgeCoverItOnce) {
  int on_edge = 0;  // centres exactly on an open shared edge
  std::mt19937_64 rng(25);
  std::uniform_real_distribution<double> ux(0, kW), uy(0, kH), uk(-1, 1);
  std::uniform_int_distribution<int> gx(0, kW), gy(0, kH);
  const RectScanRasterizer r = rect_scan();
  for (int t = 0; t < 600; ++t) {
    const RowLine line = r.line_for_slope(t % 2 == 0, t % 7 == 0 ? std::round(uk(rng)) : uk(rng));
    ScreenVertex a{ux(rng), uy(rng)}, b{ux(rng), uy(rng)};
    if (t % 3 == 0) a = {double(gx(rng)), double(gy(rng))}, b = {double(gx(rng)), double(gy(rng))};
    const ScreenVertex c{ux(rng), uy(rng)}, d{ux(rng), uy(rng)};
    const double side_c = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    const double side_d = (b.x - a.x) * (d.y - a.y) - (b.y - a.y) * (d.x - a.x);
    if (!(side_c * side_d < 0)) continue;
    const ScreenVertex t1[3] = {a, b, c}, t2[3] = {t % 4 < 2 ? b : a, t % 4 < 2 ? a : b, d};
    const PixelSet s1 = scan_pixels(r.rasterize(t1, line, kScreen));
    const PixelSet s2 = scan_pixels(r.rasterize(t2, line, kScreen));
    for (const auto& p : s1) ASSERT_EQ(s2.count(p), 0u) << t;
    // Centres on the open shared edge: exactly one of the two.
    const auto st = EdgeRasterizer().setup(t1, kScreen);
    for (int32_t y = 0; y < kH; ++y) {
      for (int32_t x = 0; x < kW; ++x) {
        const int shared = st.perm[1] == 1 ? 2 : 1;  // a→b, or b→a after the set-up's swap
        if (!st.ok() || EdgeRasterizer::edge_value(st, shared, x, y) != 0) continue;
        const double along = ((x - a.x) * (b.x - a.x) + (y - a.y) * (b.y - a.y)) /
                             ((b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y));
        if (along > 1e-9 && along < 1 - 1e-9) {
          EXPECT_EQ(s1.count({x, y}) + s2.count({x, y}), 1u) << t << " " << x << "," << y;
          ++on_edge;
        }
      }
    }
  }
  EXPECT_GT(on_edge, 50);
}

TEST(RectScanRasterizer, ConfigFromToml) {
  const toml::table t = toml::parse(
      "subpixel_bits = 4\nslope_bits = 8\nfast_clock_mhz = 800\nmemory_clock_mhz = 200\n"
      "coverage = \"outline\"\n");
  const auto c = RectScanRasterizer::Config::from_toml(ConfigReader(t, "s.toml", "raster"));
  EXPECT_EQ(c.subpixel_bits, 4);
  EXPECT_EQ(c.slope_bits, 8);
  EXPECT_DOUBLE_EQ(c.memory_clock_mhz, 200);
  EXPECT_EQ(c.coverage, RectScanCoverage::Outline);
  for (const char* bad : {"fast_clock_mhz = 0\n", "memory_clock_mhz = -1\n", "slope_bits = 40\n",
                          "coverage = \"parity\"\n", "clock = 3\n", "subpixel_bits = 17\n"}) {
    const toml::table b = toml::parse(bad);
    EXPECT_THROW(RectScanRasterizer::Config::from_toml(ConfigReader(b, "s.toml", "raster")),
                 InputError)
        << bad;
    EXPECT_THROW(EdgeRasterizer::Config::from_toml(ConfigReader(b, "s.toml", "raster")), InputError)
        << bad;
  }
  EXPECT_NE(RectScanRasterizer(c).arithmetic().find("2^8"), std::string::npos);
}

// The seed's convention (outline included) against top-left: the extra pixels, and the pixels
// two triangles sharing an edge both texture. Random triangles of every orientation and slope.
TEST(RectScanRasterizer, SeedOutlineConventionMeasured) {
  std::mt19937_64 rng(24);
  std::uniform_real_distribution<double> ux(0, kW), uy(0, kH), uk(-1, 1);
  const RectScanRasterizer seed = rect_scan(RectScanCoverage::Outline);
  uint64_t top_left = 0, extra = 0, dup = 0, shared_tl = 0;
  for (int t = 0; t < 2000; ++t) {
    const RowLine line = seed.line_for_slope(t % 2 == 0, uk(rng));
    const ScreenVertex a{ux(rng), uy(rng)}, b{ux(rng), uy(rng)}, c{ux(rng), uy(rng)},
        d{ux(rng), uy(rng)};
    const ScreenVertex t1[3] = {a, b, c}, t2[3] = {b, a, d};
    const PixelSet e1 = edge_pixels(t1), e2 = edge_pixels(t2);
    const PixelSet s1 = scan_pixels(seed.rasterize(t1, line, kScreen));
    const PixelSet s2 = scan_pixels(seed.rasterize(t2, line, kScreen));
    for (const auto& p : e1) ASSERT_TRUE(s1.count(p));  // a superset of top-left
    top_left += e1.size();
    extra += s1.size() - e1.size();
    const double side_c = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    const double side_d = (b.x - a.x) * (d.y - a.y) - (b.y - a.y) * (d.x - a.x);
    if (side_c * side_d < 0) {
      for (const auto& p : s1) dup += s2.count(p);
      for (const auto& p : e1) shared_tl += e2.count(p);
    }
  }
  EXPECT_EQ(shared_tl, 0u);
  EXPECT_GT(dup, 0u);
  std::printf(
      "seed outline convention vs top-left: %llu top-left pixels, %llu extra (%.2f%%); "
      "pixels textured by both triangles of a shared edge: %llu (top-left: %llu)\n",
      static_cast<unsigned long long>(top_left), static_cast<unsigned long long>(extra),
      100.0 * static_cast<double>(extra) / static_cast<double>(top_left),
      static_cast<unsigned long long>(dup), static_cast<unsigned long long>(shared_tl));
}

// The seed's literal datapath (coverage = "outline_parity"): one-colour outline and parity.
// What it should texture is the inside (top-left) and the outline it drew; every pixel where it
// does otherwise is counted and its row put down to a cause.
TEST(RectScanRasterizer, OutlineParityDiffersOnlyAtItsCountedHazards) {
  std::mt19937_64 rng(28);
  std::uniform_real_distribution<double> ux(0, kW), uy(0, kH), uk(-1, 1);
  const RectScanRasterizer parity = rect_scan(RectScanCoverage::OutlineParity);
  uint64_t pixels = 0, differ = 0, clean = 0;
  ParityHazards all;
  for (int t = 0; t < 2000; ++t) {
    const RowLine line = parity.line_for_slope(t % 2 == 0, uk(rng));
    const ScreenVertex v[3] = {{ux(rng), uy(rng)}, {ux(rng), uy(rng)}, {ux(rng), uy(rng)}};
    // The inside and the outline pixels within the scanned box (the scan visits no other).
    PixelSet meant = edge_pixels(v);
    const EdgeRasterizer::Setup st = EdgeRasterizer().setup(v, kScreen);
    for (const auto& px : screen_outline_8(v)) {
      if (px.first >= st.x0 && px.second >= st.y0 && px.first <= st.x1 && px.second <= st.y1)
        meant.insert(px);
    }
    const RectScanResult r = parity.rasterize(v, line, kScreen);
    const PixelSet p = scan_pixels(r);
    uint64_t extra = 0, missed = 0;
    for (const auto& px : p) extra += !meant.count(px);
    for (const auto& px : meant) missed += !p.count(px);
    const ParityHazards& h = r.stats.hazards;
    ASSERT_EQ(h.extra_pixels, extra) << t;
    ASSERT_EQ(h.missed_pixels, missed) << t;
    ASSERT_EQ(h.rows() > 0, extra + missed > 0) << t;
    pixels += meant.size();
    differ += extra + missed;
    clean += extra + missed == 0;
    all += h;
  }
  EXPECT_GT(clean, 0u);
  EXPECT_GT(all.vertex_rows, 0u);
  EXPECT_GT(all.run_rows + all.touching_rows, 0u);
  EXPECT_GT(all.missed_crossing_rows, 0u);
  std::printf(
      "outline parity vs inside + outline over 2000 triangles: %llu pixels, %llu extra, "
      "%llu missed (%.2f%% differ); triangles without a hazard %llu; hazard rows: vertex %llu, "
      "touching edges %llu, runs along an edge %llu, crossing without a hit %llu\n",
      static_cast<unsigned long long>(pixels), static_cast<unsigned long long>(all.extra_pixels),
      static_cast<unsigned long long>(all.missed_pixels),
      100.0 * static_cast<double>(differ) / static_cast<double>(pixels),
      static_cast<unsigned long long>(clean), static_cast<unsigned long long>(all.vertex_rows),
      static_cast<unsigned long long>(all.touching_rows),
      static_cast<unsigned long long>(all.run_rows),
      static_cast<unsigned long long>(all.missed_crossing_rows));
}

// Each hazard on a triangle made for it.
TEST(RectScanRasterizer, OutlineParityHazardsByCause) {
  const RectScanRasterizer parity = rect_scan(RectScanCoverage::OutlineParity);
  // 45° rows against a -45° edge: crossings between two outline pixels on odd rows.
  const ScreenVertex diag[3] = {{20, 0}, {40, 20}, {0, 20}};
  const RectScanResult a = parity.rasterize(diag, parity.line_for_slope(true, 1.0), kScreen);
  EXPECT_GT(a.stats.hazards.missed_crossing_rows + a.stats.hazards.vertex_rows, 0u);
  EXPECT_GT(a.stats.hazards.extra_pixels + a.stats.hazards.missed_pixels, 0u);
  // Rows of slope 0.3 along a top edge of slope 0.24: the row zigzags along its outline, runs
  // of hits that are no crossing.
  const ScreenVertex along[3] = {{2.3, 2.2}, {30.6, 9.1}, {8.2, 30.7}};
  const RectScanResult b = parity.rasterize(along, parity.line_for_slope(true, 0.3), kScreen);
  EXPECT_GT(b.stats.hazards.run_rows, 0u);
  // A horizontal edge on the first row of horizontal rows: its run holds the end vertices, so
  // it counts two and the row is right.
  const ScreenVertex flat[3] = {{4, 10}, {40, 10}, {20, 30}};
  const RectScanResult f = parity.rasterize(flat, parity.line_for_slope(true, 0.0), kScreen);
  EXPECT_EQ(f.stats.hazards.run_rows + f.stats.hazards.vertex_rows, 0u);
  // A sliver whose two long edges touch: one run for two crossings.
  const ScreenVertex sliver[3] = {{2, 20}, {60, 23}, {60, 24.5}};
  const RectScanResult c = parity.rasterize(sliver, parity.line_for_slope(true, 0.0), kScreen);
  EXPECT_GT(c.stats.hazards.rows(), 0u);
  EXPECT_GT(c.stats.hazards.touching_rows + c.stats.hazards.vertex_rows, 0u);
}

TEST(RectScanRasterizer, CyclesAtBothClocksAndDivisions) {
  const RectScanRasterizer r;
  struct Case {
    const char* name;
    ScreenVertex v[3];
    double k;
    bool x_major;
  };
  const Case cases[] = {
      {"right triangle 40x40, k=0", {{2, 2}, {42, 2}, {2, 42}}, 0.0, true},
      {"same, k=0.5", {{2, 2}, {42, 2}, {2, 42}}, 0.5, true},
      {"same, k=-0.5", {{2, 2}, {42, 2}, {2, 42}}, -0.5, true},
      {"thin sliver, k=0.3", {{1, 1}, {62, 30}, {60, 33}}, 0.3, true},
      {"floor-like, k=0.1 y-major", {{5, 40}, {60, 44}, {30, 10}}, 0.1, false},
  };
  for (const Case& c : cases) {
    const RectScanResult res = r.rasterize(c.v, r.line_for_slope(c.x_major, c.k), kScreen);
    const RectScanStats& s = res.stats;
    EXPECT_EQ(s.pixels_visited, s.pixels_textured + s.background_pixels);
    EXPECT_EQ(s.memory_cycles, s.pixels_textured);
    EXPECT_EQ(s.fast_cycles, s.background_pixels + s.rows_scanned);
    EXPECT_LE(s.rows_textured, s.rows_scanned);
    EXPECT_EQ(s.steps, s.pixels_visited - s.rows_scanned);  // the first pixel of a row is loaded
    EXPECT_EQ(s.memory_reads, s.steps);
    EXPECT_LE(s.minor_steps, s.steps);
    std::printf(
        "%-28s rows %3llu (q = divisions %3llu) visited %4llu textured %4llu  fast-clock "
        "cycles %4llu  memory-clock cycles %4llu (+%llu outline writes)  %.0f ns\n",
        c.name, static_cast<unsigned long long>(s.rows_scanned),
        static_cast<unsigned long long>(s.rows_textured),
        static_cast<unsigned long long>(s.pixels_visited),
        static_cast<unsigned long long>(s.pixels_textured),
        static_cast<unsigned long long>(s.fast_cycles),
        static_cast<unsigned long long>(s.memory_cycles),
        static_cast<unsigned long long>(s.prep_cycles), s.time_ns);
  }
  EXPECT_EQ(r.name(), "raster.rect_scan");
  EXPECT_GE(r.timing(TechTable::defaults()).latency, 1u);
  EXPECT_EQ(r.ops_per_item().mem, 1u);
}

// The rows drive the constant-depth coordinate block: one reciprocal per run of a row, values
// on the row's exact line written to the digital row's pixels. The error of that offset against
// exact Heckbert at the pixel centres is measured (a plane tilted 70° seen at 512×512).
TEST(RectScanRasterizer, DrivesTheConstantDepthCoordinateBlock) {
  for (double az : {30.0, 100.0}) {
    PlaneView pv;
    pv.tilt_deg = 70;
    pv.azimuth_deg = az;
    pv.u_offset = pv.v_offset = 512;
    const long double cx[1] = {255.5L}, cy[1] = {255.5L};
    const ProjectiveMap m = ProjectiveMap::from_plane_view(pv).normalised(cx, cy, 1);
    const RectScanRasterizer r;
    const RowLine line = r.line_for_denominator(static_cast<double>(m.G), static_cast<double>(m.H));
    const UvConstantDepth block;
    EXPECT_EQ(line.x_major, block.x_major(m));
    const MapCoeffs<double> mc = to_coeffs<double>(m);
    const auto st = block.setup_triangle(mc);
    ASSERT_TRUE(st.ok);
    const ScreenVertex v[3] = {{20, 20}, {500, 60}, {200, 490}};
    const RectScanResult res = r.rasterize(v, line, Scissor{0, 0, 512, 512});
    double worst = 0, sum = 0, worst_px = 0;
    uint64_t n = 0;
    std::vector<CoordSample> out;
    for (const RectScanRun& run : res.runs) {
      out.resize(static_cast<size_t>(run.n));
      block.eval_row(mc, st, UvConstantDepth::SlopedSpan{run.major0, run.h, run.n}, out.data());
      for (int32_t i = 0; i < run.n; ++i) {
        const int32_t major = run.major0 + i;
        const auto minor = static_cast<int32_t>(run.t + line.offset(major - res.major_start));
        const long double x = line.x_major ? major : minor, y = line.x_major ? minor : major;
        if (m.den(x, y) < 1.0L / 64) continue;  // near the horizon: not this check's concern
        ASSERT_TRUE(out[static_cast<size_t>(i)].valid);
        const double err =
            std::max(std::fabs(out[static_cast<size_t>(i)].u - static_cast<double>(m.u(x, y))),
                     std::fabs(out[static_cast<size_t>(i)].v - static_cast<double>(m.v(x, y))));
        // In pixels of minor offset: the digital row is within 1/2 pixel of the exact line
        // (plus the slope's quantisation along the row).
        const DerivsL dl = analytic_derivs(m, x, y);
        const double per_px =
            static_cast<double>(line.x_major ? std::max(std::fabs(dl.uy), std::fabs(dl.vy))
                                             : std::max(std::fabs(dl.ux), std::fabs(dl.vx)));
        worst_px = std::max(worst_px, err / per_px);
        worst = std::max(worst, err);
        sum += err;
        ++n;
      }
    }
    EXPECT_GT(n, res.stats.pixels_textured / 2);
    EXPECT_LE(res.stats.rows_textured, res.runs.size());
    EXPECT_LT(worst_px, 0.75);  // 1/2 pixel, slope quantisation, curvature near the horizon
    std::printf(
        "constant-depth rows, azimuth %.0f: %llu pixels, q = %llu rows (%zu runs = "
        "reciprocals) vs %llu Heckbert divisions; error vs Heckbert at centres: max %.3f, "
        "mean %.3f texels; max %.3f pixels of minor offset\n",
        az, static_cast<unsigned long long>(n),
        static_cast<unsigned long long>(res.stats.rows_textured), res.runs.size(),
        static_cast<unsigned long long>(n), worst, sum / static_cast<double>(n), worst_px);
  }
}

}  // namespace
}  // namespace texsim
