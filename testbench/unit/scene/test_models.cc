// [[models]] through Assimp: a hand-written OBJ+MTL and glTF 2.0 in a scratch directory, their
// vertices and texture coordinates checked after placement; the file's diffuse texture made a
// texsim material; and bad inputs (missing file, not a model, too many triangles, over the
// memory limit) end in errors naming the file and the entry.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "blocks/base/input_error.h"
#include "blocks/geometry/aviation_camera.h"
#include "pipeline/scene/model_loader.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/scene_memory.h"
#include "testbench/lib/error_of.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

// Two triangles of a unit square with texture coordinates as OBJ writes them (v up).
const char* const kObj =
    "mtllib m.mtl\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "vt 0 0\nvt 1 0\nvt 1 0.75\nvt 0 0.75\n"
    "usemtl skin\n"
    "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
const char* const kMtl = "newmtl skin\nKd 1 1 1\nmap_Kd skin.ppm\n";

// One triangle with its buffer in a data URI: positions (0,0,0), (1,0,0), (0,1,0) and texture
// coordinates (0.25, 0.125), (0.75, 0.125), (0.25, 0.5) (glTF's: v down the image).
const char* const kGltf = R"({
 "asset": {"version": "2.0"},
 "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}}]}],
 "buffers": [{"byteLength": 60, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAACAPgAAAD4AAEA/AAAAPgAAgD4AAAA/"}],
 "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                 {"buffer": 0, "byteOffset": 36, "byteLength": 24}],
 "accessors": [
  {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
   "min": [0, 0, 0], "max": [1, 1, 0]},
  {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}]
})";

const char* const kHead = R"([output]
width = 32
height = 24
[textures.t]
source = "procedural:checker?size=16&cells=2"
[materials.m]
texture = "t"
)";

class Models : public ::testing::Test {
 protected:
  void SetUp() override {
    std::ofstream(dir.file("m.obj"), std::ios::binary) << kObj;
    std::ofstream(dir.file("m.mtl"), std::ios::binary) << kMtl;
    std::ofstream(dir.file("skin.ppm"), std::ios::binary) << "P3\n2 2\n255\n0 0 0 255 255 255\n"
                                                          << "255 255 255 0 0 0\n";
    std::ofstream(dir.file("t.gltf"), std::ios::binary) << kGltf;
  }
  // kGltf with its mesh in a material whose base colour is skin.ppm.
  static std::string textured_gltf() {
    std::string t = kGltf;
    t.replace(t.find("\"attributes\""), 0, "\"material\": 0, ");
    t.replace(t.rfind('}'), 0,
              ", \"images\": [{\"uri\": \"skin.ppm\"}], \"textures\": [{\"source\": 0}],\n"
              " \"materials\": [{\"name\": \"hide\", \"pbrMetallicRoughness\": "
              "{\"baseColorTexture\": {\"index\": 0}}}]\n");
    return t;
  }
  void TearDown() override { set_scene_memory_limit(UINT64_MAX); }
  Scene scene(const std::string& models) {
    return parse_scene(std::string(kHead) + models, "s.toml", dir.file(""));
  }
  std::string error(const std::string& models) {
    return error_of([&] { (void)scene(models); });
  }
  TempDir dir{"models"};
};

// The corner of primitive p at barycentric (a, b): its world position and texture coordinate.
glm::dvec3 corner(const ScenePrimitive& p, double a, double b) {
  return p.origin + a * p.edge_u + b * p.edge_v;
}
glm::dvec2 corner_uv(const ScenePrimitive& p, double a, double b) {
  return p.uv_origin + a * p.uv_edge_u + b * p.uv_edge_v;
}

void expect_near(const glm::dvec3& a, const glm::dvec3& b) {
  EXPECT_NEAR(a.x, b.x, 1e-6);
  EXPECT_NEAR(a.y, b.y, 1e-6);
  EXPECT_NEAR(a.z, b.z, 1e-6);
}

TEST_F(Models, ObjVerticesAndTextureCoordinatesArePlaced) {
  const Scene s = scene(
      "[[models]]\npath = \"m.obj\"\nmaterial = \"m\"\nposition = [10, 20, 30]\n"
      "rotation = [90, 0, 0]\nscale = 2\nuv_scale = [2, 4]\n");
  ASSERT_EQ(s.primitives.size(), 2u);
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_TRUE(s.meshes[0].model);
  EXPECT_EQ(s.meshes[0].vertices, 4u);  // shared corners joined
  const glm::dmat3 a = aviation_rotation(90, 0, 0);
  const glm::dvec3 pos(10, 20, 30);
  const ScenePrimitive& p = s.primitives[0];
  EXPECT_EQ(p.shape, ScenePrimitive::Shape::Triangle);
  EXPECT_EQ(p.material, 0);
  // Face 1 2 3: (0,0,0), (1,0,0), (1,1,0), each scaled by 2, rotated and moved.
  expect_near(corner(p, 0, 0), pos);
  expect_near(corner(p, 1, 0), pos + a * glm::dvec3(2, 0, 0));
  expect_near(corner(p, 0, 1), pos + a * glm::dvec3(2, 2, 0));
  // Yaw 90° turns +x to -z (aviation angles, the same as [[meshes]]).
  expect_near(a * glm::dvec3(1, 0, 0), glm::dvec3(0, 0, -1));
  // vt (u, v) becomes (u, 1 - v) (texsim's v runs down the image), times uv_scale.
  const glm::dvec2 uv0 = corner_uv(p, 0, 0), uv1 = corner_uv(p, 1, 0), uv2 = corner_uv(p, 0, 1);
  EXPECT_NEAR(uv0.x, 0, 1e-6);
  EXPECT_NEAR(uv0.y, 4, 1e-6);
  EXPECT_NEAR(uv1.x, 2, 1e-6);
  EXPECT_NEAR(uv1.y, 4, 1e-6);
  EXPECT_NEAR(uv2.x, 2, 1e-6);
  EXPECT_NEAR(uv2.y, 1, 1e-6);
}

TEST_F(Models, GltfKeepsItsTextureCoordinates) {
  const Model m = load_model("t.gltf", dir.file(""));
  ASSERT_EQ(m.mesh.triangles.size(), 1u);
  ASSERT_TRUE(m.mesh.has_uvs);
  const MeshTriangle& t = m.mesh.triangles[0];
  const glm::dvec3 want_p[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const glm::dvec2 want_uv[3] = {{0.25, 0.125}, {0.75, 0.125}, {0.25, 0.5}};
  for (int k = 0; k < 3; ++k) {
    expect_near(m.mesh.positions[static_cast<size_t>(t.v[k])], want_p[k]);
    EXPECT_NEAR(t.uv[k].x, want_uv[k].x, 1e-6);
    EXPECT_NEAR(t.uv[k].y, want_uv[k].y, 1e-6);
  }
}

TEST_F(Models, TheFilesDiffuseTextureBecomesAMaterial) {
  const Scene s =
      scene("[[models]]\npath = \"m.obj\"\neffects = { filter = { mode = \"bilinear\" } }\n");
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[1].name, "m.skin");
  ASSERT_EQ(s.textures.size(), 2u);
  EXPECT_EQ(std::filesystem::path(s.textures[1].source),
            std::filesystem::absolute(dir.file("skin.ppm")).lexically_normal());
  EXPECT_EQ(s.materials[1].texture, 1);
  ASSERT_NE(s.materials[1].effects, nullptr);
  EXPECT_TRUE(s.materials[1].effects->contains("filter"));
  for (const ScenePrimitive& p : s.primitives) EXPECT_EQ(p.material, 1);
}

TEST_F(Models, TheGltfBaseColourTextureBecomesAMaterial) {
  std::ofstream(dir.file("tex.gltf"), std::ios::binary) << textured_gltf();
  const Scene s = scene("[[models]]\npath = \"tex.gltf\"\n");
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[1].name, "tex.hide");
  EXPECT_EQ(std::filesystem::path(s.textures[1].source),
            std::filesystem::absolute(dir.file("skin.ppm")).lexically_normal());
  ASSERT_EQ(s.primitives.size(), 1u);
  EXPECT_EQ(s.primitives[0].material, 1);
}

TEST(ShippedModels, CatAndHorseFromGlmark2Data) {
  const Scene s = load_scene(std::string(TEXSIM_SOURCE_DIR) + "/scenes/models.toml");
  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_EQ(s.meshes[0].count, 14348u);  // cat.3ds's triangles
  EXPECT_EQ(s.meshes[1].count, 7172u);   // horse.3ds's
  EXPECT_EQ(s.primitives.size(), 1u + 14348u + 7172u);
  EXPECT_EQ(s.meshes[1].uv, "file");
}

TEST_F(Models, BadInputsNameTheFileAndTheEntry) {
  EXPECT_EQ(error("[[models]]\npath = \"none.obj\"\nmaterial = \"m\"\n"),
            "s.toml:8:1: models[0].path: " + dir.file("none.obj") +
                ": cannot open model file: no such file");
  std::ofstream(dir.file("junk.3ds"), std::ios::binary) << "this is not a model\n";
  const std::string junk = error("[[models]]\npath = \"junk.3ds\"\nmaterial = \"m\"\n");
  EXPECT_NE(junk.find("s.toml:8:1: models[0].path: " + dir.file("junk.3ds") + ": not a model"),
            std::string::npos)
      << junk;
  EXPECT_NE(error("[[models]]\npath = \".\"\nmaterial = \"m\"\n").find("directory"),
            std::string::npos);
  EXPECT_EQ(error("[[models]]\npath = \"m.obj\"\nmaterial = \"nope\"\n"),
            "s.toml:10:12: unknown material 'nope'");
  EXPECT_NE(error("[[models]]\npath = \"m.obj\"\nmaterial = \"m\"\nsize = 2\n").find("size"),
            std::string::npos);
  std::ofstream(dir.file("bare.obj"), std::ios::binary) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  EXPECT_NE(error("[[models]]\npath = \"bare.obj\"\nmaterial = \"m\"\n")
                .find("models[0].uv: the model has no texture coordinates"),
            std::string::npos);
  EXPECT_NE(error("[[models]]\npath = \"bare.obj\"\nuv = \"planar\"\n")
                .find("the file's material 'DefaultMaterial' has no diffuse texture file"),
            std::string::npos);
}

TEST_F(Models, AFileTheModelNamesIsOpenedAsAnInput) {
  // An MTL that is a FIFO with no writer: refused at once, never waited on.
  ASSERT_EQ(::mkfifo(dir.file("f.mtl").c_str(), 0600), 0);
  std::ofstream(dir.file("f.obj"), std::ios::binary)
      << "mtllib f.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n";
  const std::string e = error_of([&] { (void)load_model(dir.file("f.obj"), ""); });
  EXPECT_NE(e.find(dir.file("f.mtl")), std::string::npos) << e;
  EXPECT_NE(e.find("FIFO"), std::string::npos) << e;
}

TEST_F(Models, TooManyTrianglesOrTooMuchMemoryIsRefused) {
  MeshBudget b;
  b.max_triangles = 1;
  EXPECT_EQ(
      error_of([&] { (void)load_model(dir.file("m.obj"), "", b); }),
      dir.file("m.obj") + ": 2 triangles, over the limit of 1 (with the scene's faces before it)");
  set_scene_memory_limit(1000);
  EXPECT_NE(error("[[models]]\npath = \"m.obj\"\nmaterial = \"m\"\n").find("over the memory limit"),
            std::string::npos);
}

}  // namespace
}  // namespace texsim
