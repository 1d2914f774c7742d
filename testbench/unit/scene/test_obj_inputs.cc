// Hostile OBJ meshes and mesh memory: every line ending ends a line for texsim's checks and
// the OBJ library alike, every index and number is checked, faces of 256+ corners are refused
// (the library would truncate them), `mtllib` files are opened as inputs (no FIFO, device or
// directory), and a mesh over the memory limit is refused before it is allocated.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "blocks/base/input_error.h"
#include "pipeline/app/run_images.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/geometry/screen_extent.h"
#include "pipeline/scene/obj_loader.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/scene_memory.h"
#include "testbench/lib/error_of.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

class ObjInputs : public ::testing::Test {
 protected:
  std::string load(const std::string& text, UvProjection p = UvProjection::Planar) {
    std::ofstream(file(), std::ios::binary) << text;
    return error_of([&] { (void)load_obj(file(), "", p); });
  }
  Mesh mesh(const std::string& text) {
    std::ofstream(file(), std::ios::binary) << text;
    return load_obj(file(), "", UvProjection::Planar);
  }
  std::string file() const { return dir.file("m.obj"); }
  TempDir dir{"objin"};
};

const char* const kTri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

TEST_F(ObjInputs, CarriageReturnOnlyLinesAreCheckedLikeTheLibraryReadsThem) {
  // Crashed: texsim's check saw one line, the library four, and rendered vertex 4 of 3.
  EXPECT_EQ(load("v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 4\r"),
            file() + ":4: face refers to vertex 4 but the file has 3");
  // Read as 0 before: the check never saw the "nan" line on its own.
  EXPECT_EQ(load("v 0 0 0\rv nan 1 0\rv 0 1 0\rf 1 2 3\r"),
            file() + ":2: vertex coordinate 'nan' is not a finite number");
  EXPECT_EQ(load("v 0 0 0\r\nv 1 0 0\rv 0 1 inf\nf 1 2 3\r\n"),
            file() + ":3: vertex coordinate 'inf' is not a finite number");
}

TEST_F(ObjInputs, EveryLineEndingGivesTheSameMesh) {
  const Mesh a = mesh("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n");
  const Mesh b = mesh("v 0 0 0\r\nv 1 0 0\rv 1 1 0\nv 0 1 0\r\rf 1 2 3\r\nf 1 3 4");
  ASSERT_EQ(a.triangles.size(), 2u);
  ASSERT_EQ(b.triangles.size(), 2u);
  EXPECT_EQ(a.triangles[1].line, 6);
  EXPECT_EQ(b.triangles[1].line, 7);  // the empty line "\r\r" counts
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(a.positions[i], b.positions[i]);
}

TEST_F(ObjInputs, EveryIndexIsChecked) {
  const std::string t = kTri;
  // Just past the vertex list: rendered from memory that is not a vertex before.
  EXPECT_EQ(load(t + "f 1 2 4\n"), file() + ":4: face refers to vertex 4 but the file has 3");
  EXPECT_EQ(load(t + "f -1 -2 -4\n"),
            file() + ":4: face refers to vertex -4 but only 3 come before it");
  EXPECT_EQ(load(t + "vt 0 0\nvt 1 0\nf 1/1 2/2 3/3\n"),
            file() + ":6: face refers to texture coordinate 3 but the file has 2");
  EXPECT_EQ(load(t + "vt 0 0\nf 1/-2 2/1 3/1\n"),
            file() + ":5: face refers to texture coordinate -2 but only 1 come before it");
  EXPECT_EQ(load(t + "vn 0 0 1\nf 1//1 2//1 3//2\n"),
            file() + ":5: face refers to normal 2 but the file has 1");
  EXPECT_EQ(load(t + "f 1/ 2 3\n"), file() + ":4: face corner '1/' is not a valid index");
  EXPECT_EQ(load(t + "f 1 2 99999999999999999999\n"),
            file() + ":4: face corner '99999999999999999999' is not a vertex index");
  // A forward reference is fine when the file has the vertex.
  EXPECT_EQ(mesh("v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n").triangles.size(), 1u);
}

TEST_F(ObjInputs, NumbersAreFiniteDecimalAndBounded) {
  const std::string t = kTri;
  EXPECT_EQ(load("v 1e308 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
            file() + ":1: vertex coordinate '1e308' is beyond ±1e+12 (docs/cli.md#input-limits)");
  EXPECT_EQ(load("v -1e309 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
            file() + ":1: vertex coordinate '-1e309' is not a finite number");
  EXPECT_EQ(load("v 0x10 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
            file() + ":1: vertex coordinate '0x10' is not a finite number");
  EXPECT_EQ(load(t + "vt 1e7 0\nf 1/1 2/1 3/1\n"),
            file() + ":4: texture coordinate '1e7' is beyond ±1e+06 (docs/cli.md#input-limits)");
  EXPECT_EQ(load(t + "vn nan 0 1\nf 1 2 3\n"),
            file() + ":4: normal coordinate 'nan' is not a finite number");
  EXPECT_EQ(load("v 0 0 0\x0b\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
            file() + ":1: control character 0x0b (OBJ fields are separated by spaces and tabs)");
  EXPECT_EQ(load(std::string("v 0 0 0\nv 1 0\0 0\nv 0 1 0\nf 1 2 3\n", 33)),
            file() + ":2: control character 0x00 (OBJ fields are separated by spaces and tabs)");
}

// A polygon of `n` corners on the unit circle.
std::string polygon(int n) {
  std::ostringstream s;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    s << "v " << std::cos(a) << " " << std::sin(a) << " 0\n";
  }
  s << "f";
  for (int i = 1; i <= n; ++i) s << " " << i;
  s << "\n";
  return s.str();
}

TEST_F(ObjInputs, FacesOf256CornersAreRefusedNotTruncated) {
  // The library keeps the corner count in one byte: 256 corners read as 0, 300 as 44.
  EXPECT_EQ(load(polygon(256)), file() +
                                    ":257: a face has 256 corners; at most 255 (the OBJ "
                                    "library keeps a face's corner count in one byte)");
  EXPECT_NE(load(polygon(300)).find(":301: a face has 300 corners"), std::string::npos);
  const Mesh m = mesh(polygon(255));
  EXPECT_EQ(m.triangles.size(), 253u);
  for (const MeshTriangle& t : m.triangles) EXPECT_EQ(t.line, 256);
}

TEST_F(ObjInputs, MaterialLibrariesAreOpenedAsInputs) {
  const std::string t = kTri;
  // Missing: left out as before (texsim uses no OBJ material); a real one is read.
  EXPECT_EQ(load("mtllib none.mtl\n" + t + "f 1 2 3\n"), "");
  std::ofstream(dir.file("ok.mtl")) << "newmtl a\r\nKd 1 0 0\r\n";
  EXPECT_EQ(load("mtllib ok.mtl\nusemtl a\n" + t + "f 1 2 3\n"), "");
  std::filesystem::create_directory(dir.file("d.mtl"));
  EXPECT_NE(load("mtllib d.mtl\n" + t + "f 1 2 3\n").find(dir.file("d.mtl") + ": cannot read"),
            std::string::npos);
  ASSERT_EQ(::mkfifo(dir.file("f.mtl").c_str(), 0600), 0);  // blocked forever before
  EXPECT_NE(load("mtllib f.mtl\n" + t + "f 1 2 3\n").find("FIFO"), std::string::npos);
  EXPECT_NE(load("mtllib /dev/zero\n" + t + "f 1 2 3\n").find("/dev/zero: cannot read"),
            std::string::npos);
}

TEST_F(ObjInputs, OverTheMemoryLimitIsRefusedBeforeLoading) {
  std::ofstream(file()) << polygon(100);
  MeshBudget b;
  b.bytes_per_triangle = 1000;
  b.max_bytes = 50000;  // 98 triangles need more
  EXPECT_NE(error_of([&] {
              (void)load_obj(file(), "", UvProjection::Planar, b);
            }).find("over the memory limit"),
            std::string::npos);
  b.max_bytes = UINT64_MAX;
  b.max_triangles = 97;
  EXPECT_NE(error_of([&] {
              (void)load_obj(file(), "", UvProjection::Planar, b);
            }).find("98 triangles, more than the 97 allowed"),
            std::string::npos);
}

const char* const kScene = R"(
[output]
width = 96
height = 72
[camera]
position = [0.0, 1.0, 3.0]
look_at = [0.0, 0.0, 0.0]
[textures.t]
source = "procedural:checker?size=64&cells=4"
[materials.m]
texture = "t"
)";

TEST(SceneMeshMemory, AGridOverTheLimitIsRefusedBeforeItIsBuilt) {
  // Used 2 GB before --max-memory was checked.
  set_scene_memory_limit(uint64_t{256} << 20);
  const std::string text =
      std::string(kScene) +
      "[[meshes]]\nmaterial = \"m\"\nsource = \"grid\"\ncells = [1024, 1024]\n";
  const std::string e = error_of([&] { (void)parse_scene(text, "s.toml", ""); });
  set_scene_memory_limit(UINT64_MAX);
  EXPECT_NE(e.find("a grid of 1024 x 1024 cells would take an estimated"), std::string::npos) << e;
  EXPECT_NE(e.find("--max-memory"), std::string::npos) << e;
}

TEST(SceneMeshMemory, PlacedVerticesAreBounded) {
  TempDir d("objin");
  std::ofstream(d.file("big.obj")) << "v 1e12 0 0\nv 0 1e12 0\nv 0 0 1e12\nf 1 2 3\n";
  const std::string text = std::string(kScene) + "[[meshes]]\nmaterial = \"m\"\nsource = \"" +
                           d.file("big.obj") + "\"\nuv = \"planar\"\nscale = 1e4\n";
  EXPECT_NE(error_of([&] {
              (void)parse_scene(text, "s.toml", "");
            }).find("vertex 1 placed at a coordinate beyond ±1e15"),
            std::string::npos);
}

TEST(SceneMeshMemory, OverflowingProjectionsAndEstimatesStayBounded) {
  // Vertices at ±1e308 gave a screen extent of 2^31 pixels (NaN cast to int) and an estimate
  // of 4,294,960,240 GiB for a 96 x 72 image.
  Scene s = parse_scene(kScene, "s.toml", "");
  ScenePrimitive p;
  p.shape = ScenePrimitive::Shape::Triangle;
  p.origin = {-1e308, 0, -1};
  p.edge_u = {1.7e308, 1e308, 0};
  p.edge_v = {0, -1.7e308, 1e308};
  s.primitives.push_back(p);
  std::vector<PlaneProjection> maps;
  for (const ScenePrimitive& q : s.primitives) maps.emplace_back(s, q);
  const PixelRect r = scene_extent(s, maps);
  EXPECT_GE(r.x0, 0);
  EXPECT_GE(r.y0, 0);
  EXPECT_LE(r.x1, 96);
  EXPECT_LE(r.y1, 72);
  EXPECT_LE(RunImages::estimate_bytes(r, 2, 96, 72), uint64_t{1} << 20);
  EXPECT_EQ(RunImages::estimate_bytes({0, 0, INT_MAX, INT_MAX}, INT_MAX, INT_MAX, INT_MAX),
            UINT64_MAX);  // saturates instead of wrapping under the limit
}

}  // namespace
}  // namespace texsim
