// Layered textures in scenes (docs/scenes.md, docs/texture-types.md): `type` with `faces` or
// `layers`, the materials' `lookup` (a cube's direction per fragment, an array's layer), the
// bad keys' file:line:column messages, the procedural sky cube, the layered truth, and the
// shipped envmap scene rendered and replayed from its trace with the same figures.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <glm/geometric.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/texture/layered/cube_seam.h"
#include "pipeline/app/run.h"
#include "pipeline/geometry/direction_map.h"
#include "pipeline/raster/fragment_generator.h"
#include "pipeline/reference/layered_reference.h"
#include "pipeline/scene/layered_source.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"
#include "testbench/lib/error_of.h"
#include "testbench/lib/scene_report.h"
#include "testbench/lib/temp_dir.h"
#include "traces/trace_file.h"

namespace texsim {
namespace {

const std::string kHead = R"([output]
width = 32
height = 24
[camera]
position = [0.0, 2.0, 0.0]
look_at = [0.0, 0.0, -4.0]
)";

std::string faces(const std::string& kind, int n) {
  std::string s = "[";
  for (int k = 0; k < n; ++k) s += (k ? ", \"" : "\"") + kind + "\"";
  return s + "]";
}

std::string sky_faces(int size, int cells = 8) {
  std::string s = "[";
  for (int k = 0; k < 6; ++k)
    s += (k ? ", " : "") + std::string("\"procedural:sky?size=") + std::to_string(size) +
         "&face=" + std::to_string(k) + "&cells=" + std::to_string(cells) + "\"";
  return s + "]";
}

const std::string kPlane = R"(
[[planes]]
material = "m"
origin = [-4.0, 0.0, -1.0]
edge_u = [8.0, 0.0, 0.0]
edge_v = [0.0, 0.0, -8.0]
)";

Scene parse(const std::string& body) { return parse_scene(kHead + body, "s.toml", ""); }

// The message of the InputError parsing `body` throws ("" if none).
std::string error_of(const std::string& body) {
  return texsim::error_of([&] {
    const Scene s = parse(body);
    for (size_t i = 0; i < s.textures.size(); ++i) (void)load_scene_texture(s, i);
    (void)build_materials(s);
  });
}

TEST(SceneLayered, CubeFacesBecomeOneLayeredTexture) {
  const Scene s =
      parse("[textures.t]\ntype = \"cube\"\nfaces = " + sky_faces(16) +
            "\n[materials.m]\ntexture = \"t\"\nlookup = { direction = \"reflect\" }\n" + kPlane);
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[0].type, SceneTextureType::Cube);
  EXPECT_EQ(s.textures[0].source.rfind("layered:cube;procedural:sky?size=16&face=0&cells=8;", 0),
            0u);
  const Texture t = load_scene_texture(s, 0);
  EXPECT_EQ(t.shape().type, TextureType::Cube);
  EXPECT_EQ(t.shape().slices, 6);
  EXPECT_EQ(t.shape().mips, 5);  // 16, 8, 4, 2, 1 per face
  EXPECT_EQ(t.levels(), 30);
  EXPECT_EQ(t.width(0), 16);
  // Face 3 (−Y, the ground) is darker than face 2 (+Y, the sky) at its centre.
  const Rgba up = t.texel(t.slice_level(2, 0), 8, 8), down = t.texel(t.slice_level(3, 0), 8, 8);
  EXPECT_GT(up.b, down.b + 0.3f);
}

TEST(SceneLayered, ArraysAndCubeArraysHaveTheirSlices) {
  const std::string ck = "procedural:checker?size=16&cells=4";
  Scene s = parse("[textures.a]\ntype = \"2d_array\"\nlayers = " + faces(ck, 3) +
                  "\n[textures.c]\ntype = \"cube_array\"\nfaces = " + faces(ck, 12) + "\n");
  Texture a = load_scene_texture(s, 0), c = load_scene_texture(s, 1);
  EXPECT_EQ(a.shape().type, TextureType::Array);
  EXPECT_EQ(a.shape().slices, 3);
  EXPECT_EQ(c.shape().type, TextureType::Cube);
  EXPECT_EQ(c.shape().slices, 12);
  // A stored format converts every slice and keeps the shape.
  s = parse("[textures.a]\ntype = \"2d_array\"\nformat = \"rgba32f\"\nlayers = " + faces(ck, 2) +
            "\n");
  a = load_scene_texture(s, 0);
  EXPECT_EQ(a.shape().slices, 2);
  EXPECT_EQ(a.storage(), StorageFormat::Rgba32f);
}

TEST(SceneLayered, BadKeysNameFileLineAndColumn) {
  const std::string ck = "procedural:checker?size=16&cells=4";
  const std::string m = "\n[materials.m]\ntexture = \"t\"\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[textures.t]\ntype = \"cube\"\nfaces = " + faces(ck, 5), "a cube has 6 faces, not 5"},
      {"[textures.t]\ntype = \"cube_array\"\nfaces = " + faces(ck, 8), "6 faces per cube"},
      {"[textures.t]\ntype = \"3d_array\"\nfaces = " + faces(ck, 6), "type"},
      {"[textures.t]\nsource = \"" + ck + "\"\nfaces = " + faces(ck, 6), "give 'type'"},
      {"[textures.t]\ntype = \"cube\"\nsource = \"" + ck + "\"\nfaces = " + faces(ck, 6),
       "from 'faces', not 'source'"},
      {"[textures.t]\ntype = \"cube\"\nlayers = " + faces(ck, 6), "has 'faces'"},
      {"[textures.t]\ntype = \"2d_array\"\nlayers = []", "no layers"},
      {"[textures.t]\ntype = \"2d_array\"\nlayers = [\"a;b\"]", "may not contain ';'"},
      {"[textures.t]\ntype = \"2d_array\"\nlayers = [\"procedural:sky?face=9\"]", "face"},
      {"[textures.t]\ntype = \"cube\"\nfaces = " + faces(ck, 6) +
           "\ncompress = { format = \"bc1_rgb\" }",
       "not compressed"},
      {"[textures.t]\ntype = \"cube\"\nfaces = " + faces(ck, 6) + m, "lookup = { direction"},
      {"[textures.t]\ntype = \"cube\"\nfaces = " + faces(ck, 6) + m +
           "lookup = { direction = \"sideways\" }",
       "direction"},
      {"[textures.t]\nsource = \"" + ck + "\"" + m + "lookup = { layer = 1 }", "is 2-D"},
      {"[textures.t]\ntype = \"2d_array\"\nlayers = " + faces(ck, 2) + m +
           "lookup = { direction = \"view\" }",
       "is not a cube"},
      {"[textures.t]\ntype = \"2d_array\"\nlayers = " + faces(ck, 2) + m +
           "lookup = { layer = 1, lyer = 2 }",
       "lyer"},
      {"[textures.t]\ntype = \"2d_array\"\nlayers = " + faces(ck, 2) + m +
           "lookup = { layer = 1e30 }",
       "layer"},
      {"[textures.t]\ntype = \"cube\"\nfaces = " + faces(ck, 6) + m +
           "lookup = { direction = \"view\" }\ncoords = { method = \"heckbert\" }",
       "not combined with coords"},
  };
  for (const auto& [body, what] : cases) {
    const std::string e = error_of(body);
    EXPECT_NE(e.find(what), std::string::npos) << body << "\n→ " << e;
    EXPECT_EQ(e.rfind("s.toml:", 0), 0u) << e;
    EXPECT_NE(e.find_first_of("0123456789", 7), std::string::npos) << e;
  }
  // Slices of different sizes, and a 1-D array of 2-D images, fail when the texture loads.
  const std::string mixed = "[textures.t]\ntype = \"2d_array\"\nlayers = [\"" + ck +
                            "\", \"procedural:checker?size=8\"]\n";
  EXPECT_NE(error_of(mixed).find("8x8, slice 0 is 16x16"), std::string::npos) << error_of(mixed);
  EXPECT_EQ(error_of(mixed).rfind("s.toml:9:10: textures.t.layers", 0), 0u) << error_of(mixed);
  EXPECT_NE(error_of("[textures.t]\ntype = \"1d_array\"\nlayers = " + faces(ck, 2))
                .find("one texel high"),
            std::string::npos);
}

// Neighbouring faces of the sky cube agree along their shared edges (the face axes are the
// selector's): across each of the 24 edges the texel beyond the edge is close to the one inside.
// Six ground sectors of 60°, so that no checker line runs along a face's edge (eight would:
// the side faces' edges are at 45° + k·90°).
TEST(SceneLayered, SkyFacesMeetAtTheirEdges) {
  const Scene s = parse("[textures.t]\ntype = \"cube\"\nfaces = " + sky_faces(32, 6) + "\n");
  const Texture t = load_scene_texture(s, 0);
  const int n = 32;
  int far = 0, total = 0;
  for (int face = 0; face < 6; ++face) {
    for (int i = 0; i < n; ++i) {
      const int xs[4][2] = {{-1, i}, {n, i}, {i, -1}, {i, n}};
      const int in[4][2] = {{0, i}, {n - 1, i}, {i, 0}, {i, n - 1}};
      for (int e = 0; e < 4; ++e) {
        std::array<CubeTexel, 3> out{};
        ASSERT_EQ(CubeSeam::resolve(face, xs[e][0], xs[e][1], n, out), 1);
        const Rgba a = t.texel(t.slice_level(face, 0), in[e][0], in[e][1]);
        const Rgba b = t.texel(t.slice_level(out[0].face, 0), out[0].x, out[0].y);
        far += glm::length(glm::vec3(a) - glm::vec3(b)) > 0.1f ? 1 : 0;
        ++total;
      }
    }
  }
  EXPECT_LT(far, total / 20) << far << " of " << total;  // the checker's lines cross some edges
}

// The fragment generator looks a cube up along the view ray ("view") or its reflection by the
// primitive ("reflect"), with exact constant derivatives; an array material's layer is set.
TEST(SceneLayered, FragmentsCarryTheDirectionAndTheLayer) {
  const std::string cube = "[textures.t]\ntype = \"cube\"\nfaces = " + sky_faces(8) + "\n";
  std::map<std::string, std::vector<Fragment>> by;
  for (const char* mode : {"view", "reflect"}) {
    std::string text = cube;
    text.append("[materials.m]\ntexture = \"t\"\nlookup = { direction = \"")
        .append(mode)
        .append("\" }\n")
        .append(kPlane);
    const Scene s = parse(text);
    by[mode] = generate_fragments(s);
    ASSERT_GT(by[mode].size(), 100u);
  }
  ASSERT_EQ(by["view"].size(), by["reflect"].size());
  size_t centre = 0;  // the fragment of pixel (16, 12), whose centre is next to the image's
  for (size_t i = 0; i < by["view"].size(); ++i)
    if (by["view"][i].x == 16 && by["view"][i].y == 12) centre = i;
  const Fragment& c = by["view"][centre];
  for (size_t i = 0; i < by["view"].size(); ++i) {
    const Fragment &v = by["view"][i], &r = by["reflect"][i];
    EXPECT_LT(v.v, 0);           // looking down at the floor
    EXPECT_DOUBLE_EQ(r.u, v.u);  // the floor (normal ±y) flips y only
    EXPECT_DOUBLE_EQ(r.v, -v.v);
    EXPECT_DOUBLE_EQ(r.w, v.w);
    EXPECT_DOUBLE_EQ(r.dvdy, -v.dvdy);
    EXPECT_DOUBLE_EQ(v.dudx, c.dudx);  // constant over the primitive
    EXPECT_DOUBLE_EQ(v.dwdy, c.dwdy);
  }
  // The derivatives are the direction's change from one pixel to the next.
  for (size_t i = 0; i + 1 < by["view"].size(); ++i) {
    const Fragment &a = by["view"][i], &b = by["view"][i + 1];
    if (b.y != a.y || b.x != a.x + 1) continue;
    EXPECT_NEAR(b.u - a.u, a.dudx, 1e-12);
    EXPECT_NEAR(b.w - a.w, a.dwdx, 1e-12);
  }
  // Pixel (16, 12)'s centre is half a pixel right of and below the image's centre: the ray
  // forward + ½/f·(right + down), f = 12 / tan 30° pixels (unit length along the view axis).
  const glm::dvec3 fwd = glm::normalize(glm::dvec3(0, -2, -4)), right{1, 0, 0};
  const glm::dvec3 down = glm::cross(fwd, right);
  const double focal = 12 / std::tan(M_PI / 6);
  const glm::dvec3 want = fwd + 0.5 / focal * (right + down);
  EXPECT_NEAR(c.u, want.x, 1e-9);
  EXPECT_NEAR(c.v, want.y, 1e-9);
  EXPECT_NEAR(c.w, want.z, 1e-9);
  // Arrays: the material's layer on every fragment, (u, v) from the plane.
  const Scene a =
      parse("[textures.t]\ntype = \"2d_array\"\nlayers = " + faces("procedural:checker?size=8", 3) +
            "\n[materials.m]\ntexture = \"t\"\nlookup = { layer = 2.5 }\n" + kPlane);
  const std::vector<Fragment> fa = generate_fragments(a);
  ASSERT_FALSE(fa.empty());
  for (const Fragment& f : fa) EXPECT_EQ(f.layer, 2.5f);
  EXPECT_GT(std::fabs(fa.back().u - fa.front().u), 0.1);
}

// The truth's cube lookup: the face by the major axis (ties Z over Y over X), bilinear on the
// face, taps beyond an edge from the neighbour when seamless, clamped to the face when not.
TEST(SceneLayered, CubeTruthSamplesTheFacesTheUnitSelects) {
  const int n = 4;
  std::vector<std::vector<float>> fs(6);
  for (int k = 0; k < 6; ++k) {
    fs[static_cast<size_t>(k)].assign(static_cast<size_t>(n) * n * 4, 1.0f);
    for (int i = 0; i < n * n; ++i)
      fs[static_cast<size_t>(k)][static_cast<size_t>(i) * 4] = static_cast<float>(k) / 5;
  }
  const Texture t =
      Texture::from_slices("c", TextureType::Cube, n, n, fs, TexelFormat::Rgba32f, true);
  const auto red = [&](glm::dvec3 r, bool seamless) {
    return reference_cube_bilinear(t, 0, r, seamless, AddressMode::Clamp, AddressMode::Clamp).r;
  };
  const glm::dvec3 dirs[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(red(dirs[k], true), k / 5.0, 1e-7) << k;
  EXPECT_EQ(reference_cube_face({1, 1, 0}).face, 2);   // +Y over +X
  EXPECT_EQ(reference_cube_face({1, 1, -1}).face, 5);  // −Z over both
  EXPECT_EQ(reference_cube_face({0, 0, -0.0}).face, 5);
  EXPECT_EQ(reference_cube_face({NAN, INFINITY, 0}).face, 4);
  // Near the +X/+Z edge, inside +X: seamless mixes +Z's texels in, per face stays on +X.
  const glm::dvec3 edge{1, 0, 0.95};
  EXPECT_EQ(reference_cube_face(edge).face, 0);
  EXPECT_GT(red(edge, true), 0.0);
  EXPECT_LT(red(edge, true), 0.8);
  EXPECT_DOUBLE_EQ(red(edge, false), 0.0);
  // Seamless and per-face filtering differ there.
  EXPECT_NE(red(edge, true), red(edge, false));
  EXPECT_EQ(reference_layer(2.5, 4), 2);  // round to nearest even
  EXPECT_EQ(reference_layer(3.5, 8), 4);
  EXPECT_EQ(reference_layer(-7, 4), 0);
  EXPECT_EQ(reference_layer(1e30, 4), 3);
  EXPECT_EQ(reference_layer(NAN, 4), 0);
}

// The shipped envmap scene renders close to its truth, counts its face selections, and
// replaying its trace (which carries each fragment's direction) gives the same figures.
TEST(SceneLayered, EnvmapSceneRendersAndItsTraceReplaysIt) {
  TempDir dir("layered_envmap");
  const nlohmann::json a = shipped_scene_report(dir, "envmap", "", "scene");
  EXPECT_EQ(a["fragments"].get<uint64_t>(), 96u * 72u);
  EXPECT_GT(a["accuracy"]["psnr_db"].get<double>(), 40.0) << a["accuracy"].dump();
  ASSERT_TRUE(a["blocks"].contains("cube.face_select")) << a["blocks"].dump();
  // The face selector issues in the address slot ahead of each fragment's one probe (no
  // anisotropy here): two address-slot cycles per fragment.
  EXPECT_EQ(a["stages"]["address"]["busy"].get<uint64_t>(), 2u * 96u * 72u);
  const std::string trc = dir.file("env.trc");
  ASSERT_EQ(generate_scene_trace(std::string(TEXSIM_SOURCE_DIR) + "/scenes/envmap.toml", trc,
                                 {"output.width=96", "output.height=72"}),
            96u * 72u);
  {
    TraceReader r(trc);
    EXPECT_EQ(r.header().version, 4u);
    std::vector<Fragment> fs;
    ASSERT_GT(r.next_chunk(fs), 0u);
    bool any_w = false;
    for (const Fragment& f : fs) any_w = any_w || f.w != 0;
    EXPECT_TRUE(any_w);
  }
  const nlohmann::json b = shipped_scene_report(dir, "envmap", trc, "trace");
  for (const char* key : {"fragments", "cycles", "cache", "dram", "accuracy"})
    EXPECT_EQ(a[key], b[key]) << key;
  EXPECT_EQ(a["blocks"]["cube.face_select"], b["blocks"]["cube.face_select"]);
}

// The shipped arrays scene (a 2-D, a 1-D and a cube array, a layer per primitive, layers
// beyond the array clamped) renders close to its truth, and its trace (each fragment's layer in the
// version-4 field) replays it with the same figures.
TEST(SceneLayered, ArraysSceneRendersAndItsTraceReplaysIt) {
  TempDir dir("layered_arrays");
  const nlohmann::json a = shipped_scene_report(dir, "arrays", "", "scene");
  ASSERT_GT(a["fragments"].get<uint64_t>(), 1000u);
  ASSERT_TRUE(a["blocks"].contains("array.layer_select")) << a["blocks"].dump();
  ASSERT_TRUE(a["blocks"].contains("cube.face_select")) << a["blocks"].dump();
  for (const char* m :
       {"floor", "layer1", "layer_half", "layer_over", "strip1", "strip_under", "cube0", "cube1"}) {
    ASSERT_TRUE(a["materials"].contains(m)) << m;
    EXPECT_GT(a["materials"][m]["fragments"].get<uint64_t>(), 50u) << m;
    // A wrong layer (unrounded, unclamped, or another's) would read another image: ~10 dB.
    EXPECT_GT(a["materials"][m]["accuracy"]["psnr_db"].get<double>(), 20.0) << m;
  }
  const std::string trc = dir.file("arrays.trc");
  ASSERT_EQ(generate_scene_trace(std::string(TEXSIM_SOURCE_DIR) + "/scenes/arrays.toml", trc,
                                 {"output.width=96", "output.height=72"}),
            a["fragments"].get<uint64_t>());
  {
    TraceReader r(trc);
    EXPECT_EQ(r.header().version, 4u);
    std::vector<Fragment> fs;
    ASSERT_GT(r.next_chunk(fs), 0u);
    bool any_layer = false;
    for (const Fragment& f : fs) any_layer = any_layer || f.layer != 0;
    EXPECT_TRUE(any_layer);
  }
  const nlohmann::json b = shipped_scene_report(dir, "arrays", trc, "trace");
  for (const char* key : {"fragments", "cycles", "cache", "dram", "accuracy", "materials"})
    EXPECT_EQ(a[key], b[key]) << key;
  EXPECT_EQ(a["blocks"]["array.layer_select"], b["blocks"]["array.layer_select"]);
  EXPECT_EQ(a["blocks"]["cube.face_select"], b["blocks"]["cube.face_select"]);
}

}  // namespace
}  // namespace texsim
