// Meshes: OBJ through tinyobjloader with texsim's own checks (errors name file and line),
// procedural boxes and grids, and the declared uv projections.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>

#include "blocks/base/input_error.h"
#include "pipeline/scene/mesh.h"
#include "pipeline/scene/obj_loader.h"
#include "testbench/lib/error_of.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

double area(const Mesh& m, const MeshTriangle& t) {
  return 0.5 * glm::length(glm::cross(m.positions[t.v[1]] - m.positions[t.v[0]],
                                      m.positions[t.v[2]] - m.positions[t.v[0]]));
}

TEST(ObjLoader, ReadsCoordinatesAndSplitsPolygonsIntoFans) {
  TempDir d("obj");
  std::ofstream(d.file("q.obj")) << "# a quad and a triangle\nv 0 0 0\nv 1 0 0\nv 1 1 0\n"
                                    "v 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                    "f 1/1 2/2 3/3 4/4\nf -4/1 -3/2 -1/4\n";
  const Mesh m = load_obj("q.obj", d.file(""), UvProjection::None);
  ASSERT_EQ(m.positions.size(), 4u);
  ASSERT_EQ(m.triangles.size(), 3u);
  EXPECT_TRUE(m.has_uvs);
  EXPECT_EQ(m.triangles[0].line, 10);
  EXPECT_EQ(m.triangles[1].line, 10);
  EXPECT_EQ(m.triangles[2].line, 11);
  EXPECT_EQ(m.triangles[1].v[2], 3);  // fan (1, 3, 4) in 0-based indices (0, 2, 3)
  EXPECT_EQ(m.triangles[1].uv[2], glm::dvec2(0, 1));
  EXPECT_EQ(m.triangles[2].v[2], 3);  // -1 = the last vertex
  EXPECT_DOUBLE_EQ(area(m, m.triangles[0]) + area(m, m.triangles[1]), 1.0);
}

TEST(ObjLoader, BadMeshesNameFileAndLine) {
  TempDir d("obj");
  const auto load = [&](const std::string& text, UvProjection p = UvProjection::Planar) {
    std::ofstream(d.file("m.obj")) << text;
    return error_of([&] { load_obj(d.file("m.obj"), "", p); });
  };
  const std::string f = d.file("m.obj");
  EXPECT_EQ(error_of([&] { load_obj(d.file("none.obj"), "", UvProjection::Planar); }),
            d.file("none.obj") + ": mesh file not found");
  // tinyobjloader reads "nan" as 0: texsim refuses it.
  EXPECT_EQ(load("v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n"),
            f + ":3: vertex coordinate 'nan' is not a finite number");
  EXPECT_EQ(load("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt inf 0\nf 1/1 2/1 3/1\n"),
            f + ":4: texture coordinate 'inf' is not a finite number");
  EXPECT_EQ(load("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n"),
            f + ":5: face refers to vertex 9 but the file has 3");
  EXPECT_EQ(load("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n"),
            f + ":4: face corner '0' is not a vertex index");
  EXPECT_EQ(load("v 0 0 0\nv 1 0 0\nf 1 2\n"), f + ":3: a face needs at least 3 corners");
  EXPECT_EQ(load("v 0 0 0\nv 1 0 0\nv 0 1\n"), f + ":3: vertex needs 3 numbers");
  EXPECT_EQ(load("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", UvProjection::None),
            f + ":4: face corner has no texture coordinate and the scene declares no uv "
                "projection (planar, box or spherical)");
  EXPECT_EQ(load("v 0 0 0\n"), f + ": mesh has no faces");
  EXPECT_EQ(error_of([&] { load_obj("/dev/null", "", UvProjection::Planar); }),
            "/dev/null: cannot read OBJ mesh: is a device, not a regular file");
}

TEST(ObjLoader, BunnyWithoutCoordinatesNeedsAProjection) {
  const std::string bunny = "/usr/share/glmark2/models/bunny.obj";
  EXPECT_NE(error_of([&] {
              load_obj(bunny, "", UvProjection::None);
            }).find("no texture coordinate and the scene declares no uv projection"),
            std::string::npos);
  const Mesh m = load_obj(bunny, "", UvProjection::Spherical);
  EXPECT_EQ(m.positions.size(), 34835u);
  EXPECT_EQ(m.triangles.size(), 69666u);
  for (const MeshTriangle& t : m.triangles) {
    for (const glm::dvec2& uv : t.uv) {
      ASSERT_TRUE(uv.x >= 0 && uv.x < 2 && uv.y >= 0 && uv.y <= 1) << uv.x << " " << uv.y;
    }
    // Continuous across the seam: a triangle across it would span almost the whole longitude
    // (near the poles small triangles legitimately span up to 0.62 of it).
    const double lo = std::min({t.uv[0].x, t.uv[1].x, t.uv[2].x});
    const double hi = std::max({t.uv[0].x, t.uv[1].x, t.uv[2].x});
    ASSERT_LE(hi - lo, 0.75);
  }
}

TEST(ProceduralMesh, BoxIsClosedAndWoundOutward) {
  const Mesh m = make_box({2, 4, 6});
  ASSERT_EQ(m.triangles.size(), 12u);
  double total = 0;
  for (const MeshTriangle& t : m.triangles) {
    total += area(m, t);
    const glm::dvec3 a = m.positions[t.v[0]], b = m.positions[t.v[1]], c = m.positions[t.v[2]];
    // Outward: the normal points away from the centre.
    EXPECT_GT(glm::dot(glm::cross(b - a, c - a), (a + b + c) / 3.0), 0);
  }
  EXPECT_DOUBLE_EQ(total, 2 * (2 * 4 + 4 * 6 + 2 * 6));
}

TEST(ProceduralMesh, GridFacesUpAndSpansTheTexture) {
  const Mesh m = make_grid(4, 3, {8, 6});
  ASSERT_EQ(m.triangles.size(), 24u);
  double total = 0;
  glm::dvec2 lo(1e9), hi(-1e9);
  for (const MeshTriangle& t : m.triangles) {
    total += area(m, t);
    const glm::dvec3 a = m.positions[t.v[0]], b = m.positions[t.v[1]], c = m.positions[t.v[2]];
    EXPECT_GT(glm::cross(b - a, c - a).y, 0);
    for (const glm::dvec2& uv : t.uv) {
      lo = glm::min(lo, uv);
      hi = glm::max(hi, uv);
    }
  }
  EXPECT_DOUBLE_EQ(total, 48);
  EXPECT_EQ(lo, glm::dvec2(0, 0));
  EXPECT_EQ(hi, glm::dvec2(1, 1));
}

TEST(UvProjection, PlanarAndBoxMatchTheirFormulas) {
  Mesh m = make_box({2, 4, 6});
  project_uvs(m, UvProjection::Planar);  // largest extents: z (6) then y (4) → u = y, v = z
  for (const MeshTriangle& t : m.triangles) {
    for (int k = 0; k < 3; ++k) {
      const glm::dvec3 p = m.positions[t.v[k]];
      EXPECT_DOUBLE_EQ(t.uv[k].x, (p.y + 2) / 4);
      EXPECT_DOUBLE_EQ(t.uv[k].y, (p.z + 3) / 6);
    }
  }
  project_uvs(m, UvProjection::Box);
  for (const MeshTriangle& t : m.triangles) {
    // Each face maps onto the whole texture: its corners take only the values 0 and 1.
    for (const glm::dvec2& uv : t.uv) {
      EXPECT_TRUE(uv.x == 0 || uv.x == 1);
      EXPECT_TRUE(uv.y == 0 || uv.y == 1);
    }
    EXPECT_GT(std::abs((t.uv[1].x - t.uv[0].x) * (t.uv[2].y - t.uv[0].y) -
                       (t.uv[2].x - t.uv[0].x) * (t.uv[1].y - t.uv[0].y)),
              0.5);  // not degenerate in texture space
  }
}

}  // namespace
}  // namespace texsim
