// The raster order (pipeline/raster/raster_order.*, `[raster]`): the walk visits every pixel of
// a rectangle exactly once in every order, on odd sizes and offsets; hand-computed orders of
// tiles, quads and lanes; the curves' indices; the table's errors; the fragment generator's
// orders and its per-material quads and helper lanes on a scene whose coverage is exact.
#include <gtest/gtest.h>

#include <algorithm>
#include <tuple>
#include <utility>
#include <vector>

#include "blocks/base/input_error.h"
#include "pipeline/raster/fragment_generator.h"
#include "pipeline/raster/raster_order.h"
#include "pipeline/scene/scene.h"
#include "pipeline/texture/quad_assembler.h"

namespace texsim {
namespace {

using Px = std::pair<int, int>;

RasterOrder tiled(int tile, CurveOrder tiles, CurveOrder quads) {
  RasterOrder o;
  o.kind = RasterOrder::Kind::Tiled;
  o.tile = tile;
  o.tile_order = tiles;
  o.quad_order = quads;
  return o;
}

std::vector<Px> walk(const RasterOrder& o, int w, int h, const PixelRect& r) {
  std::vector<Px> out;
  RasterWalk(o, w, h, r).for_each([&](int x, int y) { out.emplace_back(x, y); });
  return out;
}

std::vector<Px> walk(const RasterOrder& o, int w, int h) { return walk(o, w, h, {0, 0, w, h}); }

constexpr CurveOrder kCurves[] = {CurveOrder::Row, CurveOrder::Morton, CurveOrder::Hilbert};

// Every pixel of r once, none outside it.
void expect_each_pixel_once(const std::vector<Px>& got, const PixelRect& r, const char* what) {
  std::vector<int> seen(static_cast<size_t>(r.pixels()), 0);
  for (const auto& [x, y] : got) {
    ASSERT_TRUE(x >= r.x0 && y >= r.y0 && x < r.x1 && y < r.y1) << what << " " << x << "," << y;
    ++seen[static_cast<size_t>(y - r.y0) * static_cast<size_t>(r.x1 - r.x0) +
           static_cast<size_t>(x - r.x0)];
  }
  ASSERT_EQ(got.size(), r.pixels()) << what;
  for (const int n : seen) ASSERT_EQ(n, 1) << what;
}

TEST(RasterOrder, EveryPixelOnceOnOddSizesAndOffsets) {
  int walks = 0;
  for (const int w : {1, 2, 3, 5, 7, 9, 13, 17, 33}) {
    for (const int h : {1, 3, 4, 5, 11, 19}) {
      // The whole screen, and rectangles starting at odd pixels (cutting tiles and quads).
      const std::vector<PixelRect> rects = {
          {0, 0, w, h}, {w / 3, h / 2, w, h}, {1, 1, std::max(1, w - 1), std::max(1, h - 2)}};
      for (const PixelRect& r : rects) {
        if (r.empty()) continue;
        expect_each_pixel_once(walk(RasterOrder{}, w, h, r), r, "rows");
        for (const int tile : {4, 8, 16}) {
          for (const CurveOrder t : kCurves) {
            for (const CurveOrder q : kCurves) {
              expect_each_pixel_once(walk(tiled(tile, t, q), w, h, r), r, "tiled");
              ++walks;
            }
          }
        }
      }
    }
  }
  EXPECT_GT(walks, 1000);
  // The largest tile on a screen it cuts on both sides.
  const PixelRect big{3, 5, 301, 263};
  expect_each_pixel_once(walk(tiled(256, CurveOrder::Hilbert, CurveOrder::Hilbert), 301, 263, big),
                         big, "tile 256");
}

TEST(RasterOrder, RowsIsRowByRow) {
  EXPECT_EQ(walk(RasterOrder{}, 3, 2),
            (std::vector<Px>{{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}}));
  EXPECT_EQ(walk(RasterOrder{}, 9, 9, {7, 3, 9, 5}),
            (std::vector<Px>{{7, 3}, {8, 3}, {7, 4}, {8, 4}}));
}

TEST(RasterOrder, CurveIndicesByHand) {
  EXPECT_EQ(curve_index(CurveOrder::Row, 3, 2, 2), 11u);
  // Morton: x's bits in the even places.
  EXPECT_EQ(curve_index(CurveOrder::Morton, 1, 0, 2), 1u);
  EXPECT_EQ(curve_index(CurveOrder::Morton, 0, 1, 2), 2u);
  EXPECT_EQ(curve_index(CurveOrder::Morton, 2, 1, 2), 6u);
  EXPECT_EQ(curve_index(CurveOrder::Morton, 3, 3, 2), 15u);
  // Hilbert, 2 × 2: down, right, up.
  EXPECT_EQ(curve_index(CurveOrder::Hilbert, 0, 0, 1), 0u);
  EXPECT_EQ(curve_index(CurveOrder::Hilbert, 0, 1, 1), 1u);
  EXPECT_EQ(curve_index(CurveOrder::Hilbert, 1, 1, 1), 2u);
  EXPECT_EQ(curve_index(CurveOrder::Hilbert, 1, 0, 1), 3u);
  // Hilbert, 4 × 4: the cells in curve order.
  const std::vector<Px> h4 = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 2}, {0, 3}, {1, 3}, {1, 2},
                              {2, 2}, {2, 3}, {3, 3}, {3, 2}, {3, 1}, {2, 1}, {2, 0}, {3, 0}};
  for (uint32_t d = 0; d < h4.size(); ++d) {
    const auto [x, y] = h4[d];
    EXPECT_EQ(
        curve_index(CurveOrder::Hilbert, static_cast<uint32_t>(x), static_cast<uint32_t>(y), 2), d)
        << x << "," << y;
  }
  // Up to 32 × 32: a bijection onto 0..n²−1 whose consecutive cells are neighbours.
  for (int bits = 1; bits <= 5; ++bits) {
    const uint32_t n = 1u << bits;
    std::vector<Px> at(static_cast<size_t>(n) * n, {-1, -1});
    for (uint32_t y = 0; y < n; ++y) {
      for (uint32_t x = 0; x < n; ++x) {
        const uint32_t d = curve_index(CurveOrder::Hilbert, x, y, bits);
        ASSERT_LT(d, n * n);
        ASSERT_EQ(at[d].first, -1);
        at[d] = {static_cast<int>(x), static_cast<int>(y)};
      }
    }
    for (size_t d = 1; d < at.size(); ++d) {
      ASSERT_EQ(std::abs(at[d].first - at[d - 1].first) + std::abs(at[d].second - at[d - 1].second),
                1)
          << "bits " << bits << " d " << d;
    }
    EXPECT_EQ(at.back(), Px(static_cast<int>(n - 1), 0));
  }
}

TEST(RasterOrder, TiledRowOrderByHand) {
  // 8 × 4, tiles of 4: the left tile's quads row by row, each quad's lanes in Vulkan's order,
  // then the right tile.
  const std::vector<Px> got = walk(tiled(4, CurveOrder::Row, CurveOrder::Row), 8, 4);
  const std::vector<Px> left = {{0, 0}, {1, 0}, {0, 1}, {1, 1}, {2, 0}, {3, 0}, {2, 1}, {3, 1},
                                {0, 2}, {1, 2}, {0, 3}, {1, 3}, {2, 2}, {3, 2}, {2, 3}, {3, 3}};
  ASSERT_EQ(got.size(), 32u);
  for (size_t i = 0; i < 16; ++i) {
    EXPECT_EQ(got[i], left[i]) << i;
    EXPECT_EQ(got[16 + i], Px(left[i].first + 4, left[i].second)) << i;
  }
  // 5 × 3: quads and tiles cut by the screen's edge give their pixels inside it only.
  EXPECT_EQ(walk(tiled(4, CurveOrder::Row, CurveOrder::Row), 5, 3), (std::vector<Px>{{0, 0},
                                                                                     {1, 0},
                                                                                     {0, 1},
                                                                                     {1, 1},
                                                                                     {2, 0},
                                                                                     {3, 0},
                                                                                     {2, 1},
                                                                                     {3, 1},
                                                                                     {0, 2},
                                                                                     {1, 2},
                                                                                     {2, 2},
                                                                                     {3, 2},
                                                                                     {4, 0},
                                                                                     {4, 1},
                                                                                     {4, 2}}));
}

// The tiles in the order a walk first enters them.
std::vector<Px> tiles_of(const std::vector<Px>& px, int tile) {
  std::vector<Px> t;
  for (const auto& [x, y] : px) {
    const Px c(x / tile, y / tile);
    if (t.empty() || t.back() != c) t.push_back(c);
  }
  return t;
}

TEST(RasterOrder, TileAndQuadCurvesByHand) {
  // Morton over a 3 × 3 tile grid (its curve spans 4 × 4; the missing tiles are skipped).
  EXPECT_EQ(
      tiles_of(walk(tiled(4, CurveOrder::Morton, CurveOrder::Row), 12, 12), 4),
      (std::vector<Px>{{0, 0}, {1, 0}, {0, 1}, {1, 1}, {2, 0}, {2, 1}, {0, 2}, {1, 2}, {2, 2}}));
  // Hilbert over 2 × 2 tiles.
  EXPECT_EQ(tiles_of(walk(tiled(4, CurveOrder::Hilbert, CurveOrder::Row), 8, 8), 4),
            (std::vector<Px>{{0, 0}, {0, 1}, {1, 1}, {1, 0}}));
  // A rectangle inside the screen keeps the screen's tile order (tiles it misses skipped).
  EXPECT_EQ(tiles_of(walk(tiled(4, CurveOrder::Hilbert, CurveOrder::Row), 8, 8, {3, 1, 7, 6}), 4),
            (std::vector<Px>{{0, 0}, {0, 1}, {1, 1}, {1, 0}}));
  EXPECT_EQ(tiles_of(walk(tiled(4, CurveOrder::Hilbert, CurveOrder::Row), 8, 8, {4, 0, 8, 8}), 4),
            (std::vector<Px>{{1, 1}, {1, 0}}));
  // Quads of an 8 × 8 tile in Hilbert order: the 4 × 4 curve; Morton: Z inside Z.
  const std::vector<Px> h = walk(tiled(8, CurveOrder::Row, CurveOrder::Hilbert), 8, 8);
  const std::vector<Px> m = walk(tiled(8, CurveOrder::Row, CurveOrder::Morton), 8, 8);
  std::vector<Px> hq, mq;
  for (size_t i = 0; i < h.size(); i += 4) {
    hq.emplace_back(h[i].first / 2, h[i].second / 2);
    mq.emplace_back(m[i].first / 2, m[i].second / 2);
    // Each quad's four lanes together, in Vulkan's order.
    for (size_t l = 0; l < 4; ++l) {
      EXPECT_EQ(h[i + l],
                Px(h[i].first + static_cast<int>(l & 1), h[i].second + static_cast<int>(l >> 1)));
    }
  }
  EXPECT_EQ(hq, (std::vector<Px>{{0, 0},
                                 {1, 0},
                                 {1, 1},
                                 {0, 1},
                                 {0, 2},
                                 {0, 3},
                                 {1, 3},
                                 {1, 2},
                                 {2, 2},
                                 {2, 3},
                                 {3, 3},
                                 {3, 2},
                                 {3, 1},
                                 {2, 1},
                                 {2, 0},
                                 {3, 0}}));
  EXPECT_EQ(mq, (std::vector<Px>{{0, 0},
                                 {1, 0},
                                 {0, 1},
                                 {1, 1},
                                 {2, 0},
                                 {3, 0},
                                 {2, 1},
                                 {3, 1},
                                 {0, 2},
                                 {1, 2},
                                 {0, 3},
                                 {1, 3},
                                 {2, 2},
                                 {3, 2},
                                 {2, 3},
                                 {3, 3}}));
}

std::string error_of(const std::string& raster_table) {
  try {
    parse_scene("[output]\nwidth = 8\n" + raster_table, "s.toml", "");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(RasterOrder, TableDefaultsValuesAndErrors) {
  const Scene d = default_scene();
  EXPECT_EQ(d.raster.kind, RasterOrder::Kind::Rows);
  EXPECT_EQ(d.raster.tile, 16);
  EXPECT_EQ(d.raster.tile_order, CurveOrder::Row);
  EXPECT_EQ(d.raster.quad_order, CurveOrder::Row);
  const Scene s = default_scene({"raster.order=tiled", "raster.tile=32",
                                 "raster.tile_order=hilbert", "raster.quad_order=morton"});
  EXPECT_EQ(s.raster.kind, RasterOrder::Kind::Tiled);
  EXPECT_EQ(s.raster.tile, 32);
  EXPECT_EQ(s.raster.tile_order, CurveOrder::Hilbert);
  EXPECT_EQ(s.raster.quad_order, CurveOrder::Morton);
  EXPECT_EQ(error_of("[raster]\norder = \"tiled\"\ntile = 12\n"),
            "s.toml:5:8: scene.raster.tile: must be a power of two (4, 8, ..., 256)");
  EXPECT_EQ(error_of("[raster]\ntile = 2\n"),
            "s.toml:4:8: scene.raster.tile: value 2 out of range [4, 256]");
  EXPECT_EQ(error_of("[raster]\ntile = 512\n"),
            "s.toml:4:8: scene.raster.tile: value 512 out of range [4, 256]");
  EXPECT_EQ(
      error_of("[raster]\norder = \"zigzag\"\n"),
      "s.toml:4:9: scene.raster.order: unknown value 'zigzag' (expected one of: rows, tiled)");
  EXPECT_EQ(error_of("[raster]\nquad_order = \"peano\"\n"),
            "s.toml:4:14: scene.raster.quad_order: unknown value 'peano' (expected one of: row, "
            "morton, hilbert)");
  EXPECT_EQ(error_of("[raster]\ntile_order = 3\n"),
            "s.toml:4:14: scene.raster.tile_order: expected one of: row, morton, hilbert");
  EXPECT_EQ(error_of("[raster]\ntiles = 8\n"),
            "s.toml:4:9: scene.raster: unknown key 'tiles' (known: order, tile, tile_order, "
            "quad_order)");
  try {
    parse_scene("raster = 3\n", "s.toml", "");
    ADD_FAILURE() << "raster = 3 accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "s.toml:1:10: scene.raster: expected a table");
  }
}

// Two planes side by side seen by an orthographic camera at one world unit per pixel, their
// edges on pixel boundaries (so coverage is exact): material a covers x in [1, 5), material b
// x in [5, 8), both y in [1, 4), on a 16 × 8 screen.
Scene two_planes(const std::string& raster) {
  return parse_scene(R"([output]
width = 16
height = 8
[camera]
position = [0.0, 0.0, 10.0]
look_at = [0.0, 0.0, 0.0]
projection = "orthographic"
height = 8.0
[textures.t]
source = "procedural:checker?size=16&cells=2"
[materials.a]
texture = "t"
[materials.b]
texture = "t"
[[planes]]
material = "a"
origin = [-7.0, 0.0, 0.0]
edge_u = [4.0, 0.0, 0.0]
edge_v = [0.0, 3.0, 0.0]
[[planes]]
material = "b"
origin = [-3.0, 0.0, 0.0]
edge_u = [3.0, 0.0, 0.0]
edge_v = [0.0, 3.0, 0.0]
)" + raster,
                     "two.toml", "");
}

std::vector<Fragment> frags(const Scene& s, std::vector<RasterCounters>* rc = nullptr) {
  std::vector<Fragment> out;
  generate_fragments(
      s, 0, [&](const Fragment& f) { out.push_back(f); }, rc);
  return out;
}

std::vector<std::tuple<int, int, uint32_t>> pixels(const std::vector<Fragment>& f) {
  std::vector<std::tuple<int, int, uint32_t>> p;
  p.reserve(f.size());
  for (const Fragment& g : f) p.emplace_back(g.x, g.y, g.prim);
  return p;
}

TEST(RasterOrder, GeneratorRowsAndTiledByHand) {
  std::vector<RasterCounters> rc;
  const std::vector<Fragment> rows = frags(two_planes(""), &rc);
  // Rows: top to bottom, left to right.
  std::vector<std::tuple<int, int, uint32_t>> want;
  for (int y = 1; y < 4; ++y) {
    for (int x = 1; x < 8; ++x) want.emplace_back(x, y, x < 5 ? 0u : 1u);
  }
  EXPECT_EQ(pixels(rows), want);
  // Quads (squares at even x, y; one per primitive per square), hand-counted:
  // a: (0,0) 1 lane, (1,0) 2, (2,0) 1, (0,1) 2, (1,1) 4, (2,1) 2 → 6 quads, 12 pixels;
  // b: (2,0) 1, (3,0) 2, (2,1) 2, (3,1) 4 → 4 quads, 9 pixels.
  ASSERT_EQ(rc.size(), 2u);
  EXPECT_EQ(rc[0].quads, 6u);
  EXPECT_EQ(rc[0].helper_lanes, 24u - 12u);
  EXPECT_EQ(rc[1].quads, 4u);
  EXPECT_EQ(rc[1].helper_lanes, 16u - 9u);
  // Tiled (tiles of 4, rows of tiles, rows of quads): in the square both planes share, a's
  // lanes first, then b's.
  std::vector<RasterCounters> tc;
  const std::vector<Fragment> t = frags(two_planes("[raster]\norder = \"tiled\"\ntile = 4\n"), &tc);
  const std::vector<std::tuple<int, int, uint32_t>> tiled_want = {
      {1, 1, 0}, {2, 1, 0}, {3, 1, 0}, {1, 2, 0}, {1, 3, 0}, {2, 2, 0}, {3, 2, 0},
      {2, 3, 0}, {3, 3, 0}, {4, 1, 0}, {5, 1, 1}, {6, 1, 1}, {7, 1, 1}, {4, 2, 0},
      {4, 3, 0}, {5, 2, 1}, {5, 3, 1}, {6, 2, 1}, {7, 2, 1}, {6, 3, 1}, {7, 3, 1}};
  EXPECT_EQ(pixels(t), tiled_want);
  // The same counters whatever the order.
  ASSERT_EQ(tc.size(), 2u);
  for (size_t m = 0; m < 2; ++m) {
    EXPECT_EQ(tc[m].quads, rc[m].quads);
    EXPECT_EQ(tc[m].helper_lanes, rc[m].helper_lanes);
    EXPECT_EQ(tc[m].pixels_covered, rc[m].pixels_covered);
  }
  // The quads a trace's reader recovers: the tiled stream holds exactly the counted quads; the
  // row stream splits every square into its rows (15 quads: 5 per row).
  QuadAssembler qt, qr;
  for (const Fragment& f : t) qt.push(f);
  qt.flush();
  for (const Fragment& f : rows) qr.push(f);
  qr.flush();
  EXPECT_EQ(qt.counts().quads, 10u);
  EXPECT_EQ(qt.counts().helper_lanes, 19u);
  EXPECT_EQ(qr.counts().quads, 15u);
  EXPECT_EQ(qr.counts().helper_lanes, 60u - 21u);
}

// A perspective scene of several materials: every tiled order emits the row order's
// fragments (the same records, reordered), with the same counters; the tiled stream's quads are
// the counted ones.
TEST(RasterOrder, TiledOrdersPermuteTheRowOrdersFragments) {
  const Scene base = default_scene({"output.width=101", "output.height=67"});
  std::vector<RasterCounters> rc;
  const std::vector<Fragment> rows = frags(base, &rc);
  ASSERT_GT(rows.size(), 3000u);
  const auto key = [](const Fragment& f) { return std::make_pair(f.y, f.x); };
  for (const int tile : {4, 16, 64}) {
    for (const CurveOrder t : kCurves) {
      for (const CurveOrder q : kCurves) {
        Scene s = base;
        s.raster = tiled(tile, t, q);
        std::vector<RasterCounters> tc;
        std::vector<Fragment> got = frags(s, &tc);
        QuadAssembler qa;
        for (const Fragment& f : got) qa.push(f);
        qa.flush();
        uint64_t quads = 0, helpers = 0;
        for (size_t m = 0; m < tc.size(); ++m) {
          EXPECT_EQ(tc[m].quads, rc[m].quads);
          EXPECT_EQ(tc[m].helper_lanes, rc[m].helper_lanes);
          quads += tc[m].quads;
          helpers += tc[m].helper_lanes;
        }
        EXPECT_EQ(qa.counts().quads, quads);
        EXPECT_EQ(qa.counts().helper_lanes, helpers);
        std::sort(got.begin(), got.end(),
                  [&](const Fragment& a, const Fragment& b) { return key(a) < key(b); });
        ASSERT_EQ(got.size(), rows.size());
        for (size_t i = 0; i < rows.size(); ++i) {
          ASSERT_EQ(key(got[i]), key(rows[i]));
          ASSERT_EQ(got[i].prim, rows[i].prim);
          ASSERT_EQ(got[i].u, rows[i].u);
          ASSERT_EQ(got[i].v, rows[i].v);
          ASSERT_EQ(got[i].dudx, rows[i].dudx);
          ASSERT_EQ(got[i].dvdy, rows[i].dvdy);
        }
      }
    }
  }
  // Rows stay sorted by (y, x): today's order.
  EXPECT_TRUE(std::is_sorted(rows.begin(), rows.end(), [&](const Fragment& a, const Fragment& b) {
    return key(a) < key(b);
  }));
}

}  // namespace
}  // namespace texsim
