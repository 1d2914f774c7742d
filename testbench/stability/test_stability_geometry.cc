// Hard cases of the geometry and rasterisation subsystems, each with a defined outcome:
// degenerate (collinear) and sliver triangles, vertices behind the eye, triangles far larger
// than the screen, one-pixel triangles, edge-on planes, non-finite vertices.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "blocks/base/input_error.h"
#include "pipeline/geometry/geometry_unit.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/raster/fragment_generator.h"
#include "pipeline/scene/scene.h"

namespace texsim {
namespace {

// One triangle primitive in front of a camera at the origin looking down -Z (64 x 48 pixels).
Scene triangle_scene(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                     const std::string& raster = "") {
  Scene s = parse_scene(R"([output]
width = 64
height = 48
[camera]
position = [0.0, 0.0, 0.0]
look_at = [0.0, 0.0, -1.0]
fov_y = 60.0
near = 0.1
[textures.t]
source = "procedural:checker?size=64&cells=4"
[materials.m]
texture = "t"
)" + raster,
                        "hard.toml", "");
  ScenePrimitive p;
  p.shape = ScenePrimitive::Shape::Triangle;
  p.origin = a;
  p.edge_u = b - a;
  p.edge_v = c - a;
  s.primitives.push_back(p);
  return s;
}

struct Drawn {
  std::vector<Fragment> frags;
  GeometryCounters geometry;
  RasterCounters raster;
};

Drawn draw(const Scene& s) {
  Drawn d;
  std::vector<PlaneProjection> maps;
  for (const auto& p : s.primitives) maps.emplace_back(s, p);
  d.geometry = run_geometry(s, maps);
  std::vector<RasterCounters> rc;
  generate_fragments(
      s, 0, [&](const Fragment& f) { d.frags.push_back(f); }, &rc);
  d.raster = rc.at(0);
  for (const Fragment& f : d.frags) {
    EXPECT_TRUE(std::isfinite(f.u) && std::isfinite(f.v) && std::isfinite(f.dudx) &&
                std::isfinite(f.dvdy));
  }
  return d;
}

const std::string kRect = "raster = { method = \"rect_scan\" }\n";

TEST(GeometryStability, DegenerateTrianglesDrawNothing) {
  for (const std::string& r : {std::string(), kRect}) {
    const Drawn collinear = draw(triangle_scene({-1, 0, -3}, {0, 0, -3}, {2, 0, -3}, r));
    EXPECT_TRUE(collinear.frags.empty());
    EXPECT_EQ(collinear.geometry.degenerate, 1u);
    const Drawn point = draw(triangle_scene({0, 0, -3}, {0, 0, -3}, {0, 0, -3}, r));
    EXPECT_TRUE(point.frags.empty());
  }
}

TEST(GeometryStability, SliversAndOnePixelTrianglesStayInsideTheirBox) {
  for (const std::string& r : {std::string(), kRect}) {
    // A sliver 1e-4 units wide across the screen: a handful of pixels at most per row.
    const Drawn sliver = draw(triangle_scene({-1, -1, -3}, {1, 1, -3}, {1, 1.0001, -3}, r));
    EXPECT_LT(sliver.frags.size(), 48u * 2);
    // A triangle around one pixel centre: that pixel or none, never a neighbour's block.
    const double px = 2 * std::tan(M_PI / 6) * 3 / 48;  // one pixel at depth 3
    const Drawn tiny = draw(triangle_scene({0.1 * px, 0.1 * px, -3}, {0.9 * px, 0.2 * px, -3},
                                           {0.4 * px, 0.9 * px, -3}, r));
    EXPECT_LE(tiny.frags.size(), 1u);
  }
}

TEST(GeometryStability, VerticesBehindTheEyeAreClippedOrDropped) {
  // Wholly behind the eye: dropped by the geometry unit, nothing drawn.
  const Drawn behind = draw(triangle_scene({-1, -1, 3}, {1, -1, 3}, {0, 1, 3}));
  EXPECT_TRUE(behind.frags.empty());
  EXPECT_EQ(behind.geometry.behind_eye, 1u);
  // A floor triangle running from behind the eye to far ahead: clipped at the near plane, and
  // every drawn pixel lies on the floor in front of the eye.
  for (const std::string& r : {std::string(), kRect}) {
    const Scene s = triangle_scene({-50, -1, 20}, {50, -1, 20}, {0, -1, -200}, r);
    const Drawn d = draw(s);
    EXPECT_EQ(d.geometry.near_clipped, 1u);
    ASSERT_GT(d.frags.size(), 200u);
    const PlaneProjection map(s, s.primitives[0]);
    for (const Fragment& f : d.frags) EXPECT_GT(map.at(f.x + 0.5, f.y + 0.5).depth, 0.09);
  }
}

TEST(GeometryStability, TrianglesFarLargerThanTheScreenCoverItOnce) {
  for (const std::string& r : {std::string(), kRect}) {
    const Drawn d = draw(triangle_scene({-1e7, -1e7, -1}, {1e7, -1e7, -1}, {0, 1e7, -1}, r));
    EXPECT_EQ(d.frags.size(), 64u * 48u);
    std::set<std::pair<uint32_t, uint32_t>> px;
    for (const Fragment& f : d.frags) EXPECT_TRUE(px.insert({f.x, f.y}).second);
  }
}

TEST(GeometryStability, EdgeOnPlanesDrawNothing) {
  // The eye lies in the triangle's plane: it projects to a line.
  const Drawn d = draw(triangle_scene({-1, 0, -2}, {1, 0, -2}, {0, 0, -5}));
  EXPECT_TRUE(d.frags.empty());
  EXPECT_EQ(d.raster.pixels_covered, 0u);
}

TEST(GeometryStability, NonFiniteVerticesAreInputErrors) {
  const std::string head =
      "[textures.t]\nsource = \"procedural:checker\"\n[materials.m]\n"
      "texture = \"t\"\n[[planes]]\nmaterial = \"m\"\n";
  for (const char* v :
       {"origin = [nan, 0.0, 0.0]", "edge_u = [inf, 0.0, 0.0]", "edge_v = [0.0, -inf, 0.0]"}) {
    try {
      parse_scene(head + v + "\n", "nan.toml", "");
      ADD_FAILURE() << v;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("nan.toml:7"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace texsim
