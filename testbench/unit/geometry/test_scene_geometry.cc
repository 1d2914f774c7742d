// Scene parsing and the exact plane projection: analytic derivatives against high-order
// central differences of the map, coverage and nearest-plane selection.
#include <gtest/gtest.h>

#include <cmath>

#include "blocks/base/input_error.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/raster/fragment_generator.h"
#include "pipeline/scene/scene.h"

namespace texsim {
namespace {

TEST(Scene, DefaultSceneParses) {
  const Scene s = default_scene();
  EXPECT_EQ(s.width, 320);
  EXPECT_EQ(s.primitives.size(), 3u);
  EXPECT_EQ(s.materials.size(), 3u);
  EXPECT_EQ(s.textures.size(), 3u);
}

TEST(Scene, ErrorsCarryLineAndColumn) {
  try {
    parse_scene("[camera]\nfov_y = 200.0\n", "s.toml", "");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("s.toml:2:9"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("fov_y"), std::string::npos) << e.what();
  }
  try {
    parse_scene("[[planes]]\nmaterial = 3\n", "s.toml", "");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("s.toml:2:12"), std::string::npos) << e.what();
  }
  try {
    parse_scene("[output]\nwidht = 3\n", "s.toml", "");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown key 'widht'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(
      parse_scene("[camera]\nlook_at = [0.0, 5.0, 0.0]\nposition = [0.0, 0.0, 0.0]\n", "s", ""),
      InputError);  // looking straight along 'up'
}

TEST(PlaneProjection, DerivativesMatchCentralDifferences) {
  const Scene s = default_scene();
  for (size_t p = 0; p < s.primitives.size(); ++p) {
    const PlaneProjection m(s, s.primitives[p]);
    for (double y : {130.5, 180.5, 239.5}) {
      for (double x : {0.5, 100.5, 319.5}) {
        const UvSample c = m.at(x, y);
        const double h = 1e-3;
        const auto d = [&](double dx, double dy, bool u) {
          const UvSample a = m.at(x + dx * h, y + dy * h), b = m.at(x - dx * h, y - dy * h);
          return ((u ? a.u : a.v) - (u ? b.u : b.v)) / (2 * h);
        };
        const double tol = 1e-6 * (1 + std::abs(c.dudx) + std::abs(c.dvdy));
        EXPECT_NEAR(c.dudx, d(1, 0, true), tol);
        EXPECT_NEAR(c.dvdx, d(1, 0, false), tol);
        EXPECT_NEAR(c.dudy, d(0, 1, true), tol);
        EXPECT_NEAR(c.dvdy, d(0, 1, false), tol);
      }
    }
  }
}

TEST(PlaneProjection, MapsPlaneCornersToTheirTextureCoordinates) {
  // A screen-parallel unit plane at distance 2 filling a known part of the view.
  const Scene s = parse_scene(
      "[output]\nwidth = 100\nheight = 100\n[camera]\nposition = [0.0, 0.0, 0.0]\n"
      "look_at = [0.0, 0.0, -1.0]\nfov_y = 90.0\n[textures.t]\nsource = \"procedural:checker\"\n"
      "[materials.m]\ntexture = \"t\"\n[[planes]]\nmaterial = \"m\"\norigin = [-1.0, 1.0, -2.0]\n"
      "edge_u = [2.0, 0.0, 0.0]\nedge_v = [0.0, -2.0, 0.0]\nuv_scale = [4.0, 4.0]\n",
      "s", "");
  const PlaneProjection m(s, s.primitives[0]);
  // At depth 2 with a 90° field of view the screen spans [-2, 2]: the plane covers the middle half.
  const UvSample a = m.at(25.0, 25.0), b = m.at(75.0, 75.0);
  EXPECT_NEAR(a.u, 0.0, 1e-12);
  EXPECT_NEAR(a.v, 0.0, 1e-12);
  EXPECT_NEAR(b.u, 4.0, 1e-12);
  EXPECT_NEAR(b.v, 4.0, 1e-12);
  EXPECT_NEAR(a.dudx, 4.0 / 50, 1e-12);  // affine for a screen-parallel plane
  EXPECT_NEAR(a.dvdy, 4.0 / 50, 1e-12);
  EXPECT_NEAR(a.depth, 2.0, 1e-12);
  const auto frags = generate_fragments(s);
  EXPECT_EQ(frags.size(), 50u * 50u);  // pixel centres 25.5 .. 74.5
}

TEST(FragmentGenerator, NearestPlaneWins) {
  const Scene s = default_scene();
  const auto frags = generate_fragments(s);
  std::vector<PlaneProjection> maps;
  for (const auto& p : s.primitives) maps.emplace_back(s, p);
  for (size_t i = 0; i < frags.size(); i += 97) {
    const Fragment& f = frags[i];
    const UvSample mine = maps[f.prim].at(f.x + 0.5, f.y + 0.5);
    ASSERT_TRUE(mine.inside);
    for (size_t p = 0; p < maps.size(); ++p) {
      const UvSample o = maps[p].at(f.x + 0.5, f.y + 0.5);
      if (o.inside) {
        EXPECT_GE(o.depth, mine.depth);
      }
    }
    EXPECT_TRUE(std::isfinite(f.u) && std::isfinite(f.dudx) && std::isfinite(f.dvdy));
  }
}

}  // namespace
}  // namespace texsim
