// The geometry subsystem (ПГП) of scene runs: the GLM vertex transform against the exact
// projection, cameras given by aviation angles against the seed's ground projection (2.39),
// orthographic cameras, back-face culling, meshes in scenes and their errors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <random>
#include <set>

#include "blocks/base/input_error.h"
#include "blocks/geometry/aviation_camera.h"
#include "blocks/geometry/vertex_transform.h"
#include "pipeline/geometry/geometry_unit.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/raster/fragment_generator.h"
#include "pipeline/scene/scene.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

const char* kHead = R"([output]
width = 200
height = 150
[textures.t]
source = "procedural:checker?size=64&cells=4"
[materials.m]
texture = "t"
)";

std::string error_of(const std::string& text, const std::string& dir = "") {
  try {
    parse_scene(text, "s.toml", dir);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The GLM datapath (double) puts every corner where the exact long-double projection does.
TEST(VertexTransform, MatchesTheExactProjectionForBothCameras) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-3, 3);
  for (const char* cam : {"fov_y = 50.0", "projection = \"orthographic\"\nheight = 6.0"}) {
    const std::string text = std::string(kHead) + "[camera]\nposition = [0.5, 2.0, 6.0]\n" +
                             "look_at = [0.0, 0.0, 0.0]\n" + cam + "\n";
    Scene s = parse_scene(text, "s.toml", "");
    const VertexTransform vt(s.camera);
    int checked = 0;
    for (int t = 0; t < 200; ++t) {
      ScenePrimitive p;
      p.shape = ScenePrimitive::Shape::Triangle;
      p.origin = {u(rng), u(rng), u(rng)};
      p.edge_u = {u(rng), u(rng), u(rng)};
      p.edge_v = {u(rng), u(rng), u(rng)};
      const PlaneProjection exact(s, p);
      const std::vector<glm::dvec2> poly = exact.screen_polygon();
      if (poly.size() != 3) continue;  // clipped by the near plane
      const glm::dvec3 c[3] = {p.origin, p.origin + p.edge_u, p.origin + p.edge_v};
      for (int k = 0; k < 3; ++k) {
        ScreenVertex v;
        ASSERT_TRUE(vt.to_screen(vt.clip(c[k]), v));
        EXPECT_NEAR(v.x, poly[static_cast<size_t>(k)].x, 1e-7) << cam;
        EXPECT_NEAR(v.y, poly[static_cast<size_t>(k)].y, 1e-7) << cam;
      }
      ++checked;
    }
    EXPECT_GT(checked, 100) << cam;
  }
}

// A scene camera given by aviation angles sees the ground where the seed's explicit
// ground-plane projection (eq. 2.26–2.27, AviationCamera::ground_point) puts it.
TEST(SceneCamera, AviationAnglesReproduceTheSeedsGroundProjection) {
  const double fov = 50, yaw = 30, pitch = -12, roll = 8;
  const std::string text = std::string(kHead) +
                           "[camera]\nposition = [3.0, 60.0, -7.0]\nyaw = 30.0\npitch = -12.0\n"
                           "roll = 8.0\nfov_y = 50.0\n[[planes]]\nmaterial = \"m\"\n"
                           "origin = [0.0, 0.0, 0.0]\nedge_u = [1.0, 0.0, 0.0]\n"
                           "edge_v = [0.0, 0.0, 1.0]\n";
  const Scene s = parse_scene(text, "s.toml", "");
  AviationCamera::Config ac;
  ac.x = 3;
  ac.y = 60;
  ac.z = -7;
  ac.yaw_deg = yaw;
  ac.pitch_deg = pitch;
  ac.roll_deg = roll;
  ac.width = 200;
  ac.height = 150;
  ac.screen_distance = 75 / std::tan(fov * M_PI / 360);
  const AviationCamera seed(ac);
  const PlaneProjection proj(s, s.primitives[0]);
  int hits = 0;
  for (int j = 0; j < 150; j += 7) {
    for (int i = 0; i < 200; i += 9) {
      double gx = 0, gz = 0;
      if (!seed.ground_point(i, j, gx, gz)) continue;
      const UvSample t = proj.at(i + 0.5, j + 0.5);
      EXPECT_NEAR(t.u, gx, 1e-9 * (1 + std::fabs(gx))) << i << "," << j;
      EXPECT_NEAR(t.v, gz, 1e-9 * (1 + std::fabs(gz))) << i << "," << j;
      ++hits;
    }
  }
  EXPECT_GT(hits, 200);
  // Angles and look_at are two ways to say one thing: not both.
  EXPECT_NE(error_of(std::string(kHead) + "[camera]\nyaw = 3.0\nlook_at = [0.0, 0.0, 1.0]\n")
                .find("not together with yaw/pitch/roll"),
            std::string::npos);
}

// `eye_offset` (eq. 2.16): the scene camera's eye is position + A·h, h in the vehicle's frame,
// and sees the ground where AviationCamera with the same h puts it; absent, nothing changes.
TEST(SceneCamera, EyeOffsetMovesTheEyeByTheRotatedOffset) {
  const std::string cam =
      "[camera]\nposition = [3.0, 60.0, -7.0]\nyaw = 30.0\npitch = -12.0\n"
      "roll = 8.0\nfov_y = 50.0\n";
  const std::string plane =
      "[[planes]]\nmaterial = \"m\"\norigin = [0.0, 0.0, 0.0]\n"
      "edge_u = [1.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, 1.0]\n";
  const Scene s = parse_scene(std::string(kHead) + cam + "eye_offset = [4.0, -1.5, 2.5]\n" + plane,
                              "s.toml", "");
  const Scene s0 = parse_scene(std::string(kHead) + cam + plane, "s.toml", "");
  const Scene sz =
      parse_scene(std::string(kHead) + cam + "eye_offset = [0, 0, 0]\n" + plane, "s.toml", "");
  EXPECT_EQ(s0.camera.position, sz.camera.position);
  EXPECT_EQ(s0.camera.look_at, sz.camera.look_at);
  AviationCamera::Config ac;
  ac.x = 3;
  ac.y = 60;
  ac.z = -7;
  ac.yaw_deg = 30;
  ac.pitch_deg = -12;
  ac.roll_deg = 8;
  ac.eye_offset = {4.0, -1.5, 2.5};
  ac.width = 200;
  ac.height = 150;
  ac.screen_distance = 75 / std::tan(50 * M_PI / 360);
  const AviationCamera seed(ac);
  const glm::dvec3 d = s.camera.position - s0.camera.position;
  EXPECT_NEAR(glm::length(d), glm::length(ac.eye_offset), 1e-12);
  EXPECT_NEAR(glm::distance(s.camera.position, seed.eye()), 0, 1e-12);
  const PlaneProjection proj(s, s.primitives[0]);
  int hits = 0;
  for (int j = 0; j < 150; j += 7) {
    for (int i = 0; i < 200; i += 9) {
      double gx = 0, gz = 0;
      if (!seed.ground_point(i, j, gx, gz)) continue;
      const UvSample t = proj.at(i + 0.5, j + 0.5);
      EXPECT_NEAR(t.u, gx, 1e-9 * (1 + std::fabs(gx))) << i << "," << j;
      EXPECT_NEAR(t.v, gz, 1e-9 * (1 + std::fabs(gz))) << i << "," << j;
      ++hits;
    }
  }
  EXPECT_GT(hits, 200);
  EXPECT_NE(error_of(std::string(kHead) +
                     "[camera]\nlook_at = [0.0, 0.0, 1.0]\neye_offset = [1.0, 0.0, 0.0]\n")
                .find("needs yaw/pitch/roll"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(kHead) + "[camera]\nyaw = 1.0\neye_offset = [1.0, 0.0]\n")
                .find("expected an array of 3 numbers"),
            std::string::npos);
}

TEST(SceneCamera, OrthographicMapsAreAffineAndKeysBelongToOneProjection) {
  const std::string text = std::string(kHead) +
                           "[camera]\nposition = [0.0, 3.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\n"
                           "projection = \"orthographic\"\nheight = 4.0\n[[planes]]\n"
                           "material = \"m\"\norigin = [-1.0, 0.0, 1.0]\n"
                           "edge_u = [2.0, 0.0, 0.0]\nedge_v = [0.0, 0.0, -2.0]\n";
  const Scene s = parse_scene(text, "s.toml", "");
  const PlaneProjection proj(s, s.primitives[0]);
  EXPECT_EQ(proj.G, 0);
  EXPECT_EQ(proj.H, 0);
  // Equal screen steps give equal texture steps anywhere on the plane.
  const UvSample a = proj.at(50, 50), b = proj.at(60, 50), c = proj.at(150, 100),
                 d = proj.at(160, 100);
  EXPECT_NEAR(b.u - a.u, d.u - c.u, 1e-12);
  EXPECT_NEAR(b.v - a.v, d.v - c.v, 1e-12);
  EXPECT_FALSE(generate_fragments(s).empty());
  EXPECT_NE(error_of(std::string(kHead) + "[camera]\nprojection = \"orthographic\"\nfov_y = 3.0\n")
                .find("perspective only"),
            std::string::npos);
  EXPECT_NE(error_of(std::string(kHead) + "[camera]\nheight = 3.0\n").find("orthographic only"),
            std::string::npos);
}

// A closed box seen from a corner: three faces (six triangles) face away and are culled; the
// image is the same with culling off (the depth test hides them), at fewer rasterised pixels.
TEST(GeometryUnit, BackFaceCullingDropsTheHiddenHalfOfABox) {
  const std::string text = std::string(kHead) +
                           "[camera]\nposition = [2.2, 1.7, 2.6]\nlook_at = [0.0, 0.0, 0.0]\n"
                           "[[meshes]]\nmaterial = \"m\"\nsource = \"box\"\ncull = \"back\"\n";
  const Scene culled = parse_scene(text, "s.toml", "");
  const Scene all = parse_scene(text, "s.toml", "", {"meshes.0.cull=\"none\""});
  std::vector<PlaneProjection> maps;
  for (const auto& p : culled.primitives) maps.emplace_back(culled, p);
  const GeometryCounters g = run_geometry(culled, maps);
  EXPECT_EQ(g.primitives, 12u);
  EXPECT_EQ(g.vertices, 8u);  // the box's distinct corners, once each
  EXPECT_EQ(g.culled_back, 6u);
  EXPECT_EQ(g.cull_disagreements, 0u);
  EXPECT_EQ(g.ops.rcp, 8u);
  std::vector<RasterCounters> rc, ra;
  std::vector<Fragment> fc, fa;
  generate_fragments(
      culled, 0, [&](const Fragment& f) { fc.push_back(f); }, &rc);
  generate_fragments(
      all, 0, [&](const Fragment& f) { fa.push_back(f); }, &ra);
  ASSERT_EQ(fc.size(), fa.size());
  for (size_t i = 0; i < fc.size(); ++i) {
    EXPECT_EQ(fc[i].x, fa[i].x);
    EXPECT_EQ(fc[i].prim, fa[i].prim);
  }
  EXPECT_EQ(rc[0].primitives, 6u);
  EXPECT_EQ(ra[0].primitives, 12u);
  EXPECT_LT(rc[0].pixels_covered, ra[0].pixels_covered);
}

TEST(SceneMeshes, PlacementUvAndErrorsNameFileAndLine) {
  const TempDir dir("meshes");
  const std::string dir_path = std::filesystem::path(dir.file("x")).parent_path().string();
  const std::string obj = dir.file("tri.obj");
  std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const std::string base = std::string(kHead) + "[[meshes]]\nmaterial = \"m\"\n";
  // No texture coordinates in the file and none declared: an error naming the file and line.
  const std::string no_uv = error_of(base + "source = \"tri.obj\"\n", dir_path);
  EXPECT_NE(no_uv.find("tri.obj:4"), std::string::npos) << no_uv;
  const Scene s = parse_scene(base +
                                  "source = \"tri.obj\"\nuv = \"planar\"\nposition = [1.0, "
                                  "2.0, 3.0]\nscale = 2.0\nrotation = [90.0, 0.0, 0.0]\n",
                              "s.toml", dir_path);
  ASSERT_EQ(s.primitives.size(), 1u);
  const ScenePrimitive& p = s.primitives[0];
  EXPECT_EQ(p.shape, ScenePrimitive::Shape::Triangle);
  EXPECT_NEAR(p.origin.x, 1, 1e-12);
  EXPECT_NEAR(p.origin.z, 3, 1e-12);
  // Yaw 90° about Y takes +X to -Z; scale 2.
  EXPECT_NEAR(p.edge_u.z, -2, 1e-12);
  EXPECT_NEAR(p.edge_u.x, 0, 1e-12);
  EXPECT_NEAR(p.edge_v.y, 2, 1e-12);
  EXPECT_EQ(s.meshes[0].uv, "planar");
  EXPECT_NE(
      error_of(base + "source = \"missing.obj\"\nuv = \"box\"\n", dir_path).find("missing.obj"),
      std::string::npos);
  EXPECT_NE(error_of(base + "source = \"box\"\ncells = [2, 2]\n").find("grid only"),
            std::string::npos);
  EXPECT_NE(error_of(base + "source = \"grid\"\nscale = -1.0\n").find("scale"), std::string::npos);
  EXPECT_NE(error_of(base + "source = \"box\"\ncul = \"back\"\n").find("unknown key 'cul'"),
            std::string::npos);
  std::ofstream(dir.file("nan.obj")) << "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n";
  const std::string nan = error_of(base + "source = \"nan.obj\"\nuv = \"planar\"\n", dir_path);
  EXPECT_NE(nan.find("nan.obj:2"), std::string::npos) << nan;
}

}  // namespace
}  // namespace texsim
