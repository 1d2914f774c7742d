// Primitives through each material's rasteriser: a jittered mesh grid (triangles sharing
// edges in every orientation) is covered with no holes and no duplicates by the edge-function
// and the rectangle-scan rasterisers alike, both give the same pixels, and the rectangle scan
// spends one division per textured row.
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "pipeline/geometry/plane_projection.h"
#include "pipeline/raster/fragment_generator.h"
#include "pipeline/raster/primitive_raster.h"
#include "pipeline/scene/scene.h"

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
    rasterize_primitive(map, r, s.tech, s.width, s.height, c, [&](int32_t x, int32_t y) {
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

}  // namespace
}  // namespace texsim
