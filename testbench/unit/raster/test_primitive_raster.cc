// Primitives through each material's rasteriser: a jittered mesh grid (triangles sharing
// edges in every orientation) is covered with no holes and no duplicates by the edge-function
// and the rectangle-scan rasterisers alike, both give the same pixels, and the rectangle scan
// spends one division per textured row.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "blocks/base/input_error.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/raster/fragment_generator.h"
#include "pipeline/raster/primitive_raster.h"
#include "pipeline/scene/scene.h"
#include "pipeline/texture/effect_registry.h"

namespace texsim {
namespace {

// The view and the one material of both test scenes.
const char* const kView = R"([output]
width = 160
height = 120
[camera]
position = [0.3, 2.5, 4.0]
look_at = [0.0, 0.0, 0.0]
fov_y = 50.0
[textures.t]
source = "procedural:checker?size=64&cells=4"
[materials.m]
texture = "t"
)";

// A perspective view of a 12 x 9 grid of quads with jittered inner vertices.
Scene jittered_grid(unsigned seed) {
  const std::string text = std::string(kView) + R"([[meshes]]
material = "m"
source = "grid"
size = [4.0, 3.0]
cells = [12, 9]
)";
  Scene s = parse_scene(text, "grid.toml", "");
  // Jitter shared vertices consistently: move each distinct position once.
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> j(-0.1, 0.1);
  std::map<std::pair<long, long>, glm::dvec3> moved;
  auto key = [](const glm::dvec3& p) {
    return std::make_pair(std::lround(p.x * 1e6), std::lround(p.z * 1e6));
  };
  auto jitter = [&](const glm::dvec3& p) {
    auto [it, fresh] = moved.try_emplace(key(p), p);
    if (fresh && std::fabs(p.x) < 1.99 && std::fabs(p.z) < 1.49) {
      it->second += glm::dvec3(j(rng), 0.2 * j(rng), j(rng));
    }
    return it->second;
  };
  for (ScenePrimitive& p : s.primitives) {
    const glm::dvec3 a = jitter(p.origin), b = jitter(p.origin + p.edge_u),
                     c = jitter(p.origin + p.edge_v);
    p.origin = a;
    p.edge_u = b - a;
    p.edge_v = c - a;
  }
  return s;
}

std::map<std::pair<int, int>, int> coverage(const Scene& s, const RasterSetup& r,
                                            RasterCounters& c) {
  std::map<std::pair<int, int>, int> hits;
  for (const ScenePrimitive& p : s.primitives) {
    const PlaneProjection map(s, p);
    rasterize_primitive(map, r, s.tech, s.width, s.height, c,
                        [&](int32_t x, int32_t y, const CoordSample*) {
                          ++hits[{x, y}];
                        });
  }
  return hits;
}

TEST(PrimitiveRaster, MeshGridHasNoHolesNoDuplicatesWithEitherRasterizer) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const Scene s = jittered_grid(seed);
    RasterSetup edge, rect;
    rect.method = RasterSetup::Method::RectScan;
    RasterCounters ce, cr;
    const auto he = coverage(s, edge, ce);
    const auto hr = coverage(s, rect, cr);
    for (const auto& [px, n] : he) EXPECT_EQ(n, 1) << px.first << "," << px.second;
    for (const auto& [px, n] : hr) EXPECT_EQ(n, 1) << px.first << "," << px.second;
    EXPECT_EQ(he, hr) << "seed " << seed;
    // The grid is one flat sheet: its pixels in a row form one run (no hole inside it).
    std::map<int, std::pair<int, int>> rows;  // y -> (min x, count)
    for (const auto& [px, n] : he) {
      auto [it, fresh] = rows.try_emplace(px.second, px.first, 0);
      it->second.first = std::min(it->second.first, px.first);
      ++it->second.second;
    }
    for (const auto& [y, r] : rows) {
      EXPECT_TRUE(he.count({r.first + r.second - 1, y})) << "hole in row " << y;
    }
    EXPECT_EQ(ce.primitives, s.primitives.size());
    EXPECT_EQ(cr.pixels_covered, ce.pixels_covered);
    // One reciprocal per textured row, rows counted per triangle.
    EXPECT_GT(cr.divisions, 0u);
    EXPECT_LE(cr.divisions, cr.rows);
    EXPECT_GT(cr.fast_cycles + cr.memory_cycles, 0u);
    EXPECT_GT(he.size(), 5000u);
  }
}

// A floor seen in perspective, its material drawn by `raster` ("" for the default).
Scene floor_scene(const std::string& raster) {
  return parse_scene(std::string(kView) + raster + R"(
[[planes]]
material = "m"
origin = [-2.0, 0.0, 1.5]
edge_u = [4.0, 0.0, 0.0]
edge_v = [0.0, 0.0, -3.0]
)",
                     "floor.toml", "");
}

// A scene's fragments are the same whichever rasteriser a material takes; only the rectangle
// scan spends divisions.
TEST(PrimitiveRaster, RectScanMaterialGivesTheSameFragmentsAsEdge) {
  std::vector<RasterCounters> cr, ce;
  std::vector<Fragment> fr, fe;
  generate_fragments(
      floor_scene("raster = { method = \"rect_scan\" }"), 0,
      [&](const Fragment& f) { fr.push_back(f); }, &cr);
  generate_fragments(
      floor_scene(""), 0, [&](const Fragment& f) { fe.push_back(f); }, &ce);
  ASSERT_EQ(fr.size(), fe.size());
  for (size_t i = 0; i < fr.size(); ++i) {
    EXPECT_EQ(fr[i].x, fe[i].x);
    EXPECT_EQ(fr[i].y, fe[i].y);
  }
  EXPECT_GT(fr.size(), 5000u);
  EXPECT_GT(cr[0].divisions, 0u);
  EXPECT_EQ(ce[0].divisions, 0u);
}

// The rectangle scan drives the constant-depth coordinate block: each fragment's (u, v) is the
// block's value on its digital row, off the exact one by the row's offset from the exact
// constant-depth line (at most about half a pixel, a quarter on average) times the map's
// derivative across the rows; the derivatives stay exact. `coords = "exact"` gives the exact
// fragments of the edge rasteriser's run.
// The floor seen with the camera rolled by `up_x` (0: level, constant-depth lines horizontal).
Scene rolled_floor(const std::string& raster, double up_x) {
  Scene s = floor_scene(raster);
  s.camera.up = glm::dvec3(up_x, 1.0, 0.0);
  return s;
}

TEST(PrimitiveRaster, RectScanDrivesTheConstantDepthCoordinates) {
  std::vector<RasterCounters> cr, cx;
  std::vector<Fragment> fr, fe, fx, level_r, level_e;
  const Scene rect = rolled_floor("raster = { method = \"rect_scan\" }", 0.4);
  generate_fragments(
      rect, 0, [&](const Fragment& f) { fr.push_back(f); }, &cr);
  generate_fragments(rolled_floor("", 0.4), 0, [&](const Fragment& f) { fe.push_back(f); });
  generate_fragments(
      rolled_floor("raster = { method = \"rect_scan\", coords = \"exact\" }", 0.4), 0,
      [&](const Fragment& f) { fx.push_back(f); }, &cx);
  // A level camera: the constant-depth lines are the pixel rows, and the digital rows exact.
  generate_fragments(floor_scene("raster = { method = \"rect_scan\" }"), 0,
                     [&](const Fragment& f) { level_r.push_back(f); });
  generate_fragments(floor_scene(""), 0, [&](const Fragment& f) { level_e.push_back(f); });
  ASSERT_EQ(level_r.size(), level_e.size());
  for (size_t i = 0; i < level_r.size(); ++i) {
    EXPECT_NEAR(level_r[i].u, level_e[i].u, 1e-9);
    EXPECT_NEAR(level_r[i].v, level_e[i].v, 1e-9);
  }
  ASSERT_EQ(fr.size(), fe.size());
  ASSERT_EQ(fx.size(), fe.size());
  const ProjectiveMap m = PlaneProjection(rect, rect.primitives[0]).texel_map(1, 1);
  const bool x_major = !(std::fabs(m.G) > std::fabs(m.H));
  EXPECT_GT(std::fabs(m.G), 0.05 * std::fabs(m.H)) << "the rolled view's rows should slope";
  double sum = 0, most = 0;
  size_t moved = 0;
  for (size_t i = 0; i < fr.size(); ++i) {
    ASSERT_EQ(fr[i].x, fe[i].x);
    ASSERT_EQ(fr[i].y, fe[i].y);
    EXPECT_EQ(fx[i].u, fe[i].u);
    EXPECT_EQ(fx[i].v, fe[i].v);
    EXPECT_EQ(fr[i].dudx, fe[i].dudx);
    EXPECT_EQ(fr[i].dvdy, fe[i].dvdy);
    const double across = x_major ? std::max(std::fabs(fe[i].dudy), std::fabs(fe[i].dvdy))
                                  : std::max(std::fabs(fe[i].dudx), std::fabs(fe[i].dvdx));
    const double err = std::max(std::fabs(fr[i].u - fe[i].u), std::fabs(fr[i].v - fe[i].v));
    moved += err > 1e-9;
    const double px = err / across;
    sum += px;
    most = std::max(most, px);
  }
  const double mean = sum / static_cast<double>(fr.size());
  EXPECT_GT(moved, fr.size() / 2) << "the digital rows should move most coordinates";
  EXPECT_GT(mean, 0.15);
  EXPECT_LT(mean, 0.35);
  EXPECT_LT(most, 0.8);
  // Ledger of the block: one reciprocal per textured row, the slope's division per triangle,
  // 2 adds per pixel; none with exact coordinates.
  EXPECT_EQ(cr[0].coord_pixels + cr[0].coord_rejected, cr[0].pixels_covered);
  EXPECT_EQ(cr[0].coord_rejected, 0u);
  EXPECT_EQ(cr[0].coord_ops.rcp, cr[0].divisions);
  EXPECT_EQ(cr[0].coord_ops.div, cr[0].triangles - cr[0].rejected);
  EXPECT_GE(cr[0].coord_ops.add, 2 * cr[0].coord_pixels);
  EXPECT_EQ(cx[0].coord_ops.total(), 0u);
  EXPECT_EQ(cx[0].coord_pixels, 0u);
  EXPECT_EQ(cx[0].divisions, cr[0].divisions);
}

// raster.coords: a choice for rect_scan only, refused with its place in the file.
TEST(PrimitiveRaster, RasterCoordsKeyIsValidated) {
  const auto message = [](const std::string& raster) {
    try {
      (void)build_materials(floor_scene(raster));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string bad = message("raster = { method = \"rect_scan\", coords = \"heckbert\" }");
  EXPECT_NE(bad.find("floor.toml:"), std::string::npos) << bad;
  EXPECT_NE(bad.find("coords"), std::string::npos) << bad;
  EXPECT_NE(bad.find("constant_depth"), std::string::npos) << bad;
  const std::string edge = message("raster = { method = \"edge\", coords = \"exact\" }");
  EXPECT_NE(edge.find("floor.toml:"), std::string::npos) << edge;
  EXPECT_NE(edge.find("coords"), std::string::npos) << edge;
  EXPECT_EQ(message("raster = { method = \"rect_scan\", coords = \"exact\" }"), "");
}

}  // namespace
}  // namespace texsim
