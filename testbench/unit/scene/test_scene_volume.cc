// 3-D textures in scenes (docs/scenes.md, docs/texture-types.md): `type = "3d"` with `layers`
// (its z-slices) loads as a volume with its 3-D mip chain, the material's `lookup.r` gives each
// fragment r = a·u + b·v + c and its derivatives, and bad keys name file:line:column.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "blocks/base/input_error.h"
#include "pipeline/app/run.h"
#include "pipeline/raster/fragment_generator.h"
#include "pipeline/reference/layered_reference.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"
#include "pipeline/texture/effect_registry.h"
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

const std::string kPlane = R"(
[[planes]]
material = "m"
origin = [-4.0, 0.0, -1.0]
edge_u = [8.0, 0.0, 0.0]
edge_v = [0.0, 0.0, -8.0]
)";

std::string slices(int n, int size = 16) {
  std::string s = "[";
  for (int k = 0; k < n; ++k)
    s += (k ? ", " : "") + std::string("\"procedural:noise?size=") + std::to_string(size) +
         "&seed=" + std::to_string(k + 1) + "\"";
  return s + "]";
}

Scene parse(const std::string& body) { return parse_scene(kHead + body, "s.toml", ""); }

std::string error_of(const std::string& body) {
  return texsim::error_of([&] {
    const Scene s = parse(body);
    for (size_t i = 0; i < s.textures.size(); ++i) (void)load_scene_texture(s, i);
    (void)build_materials(s);
  });
}

TEST(SceneVolume, LayersBecomeAVolumeWithThreeDMips) {
  const Scene s = parse("[textures.t]\ntype = \"3d\"\nlayers = " + slices(4) + "\n");
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[0].type, SceneTextureType::Volume3D);
  EXPECT_EQ(s.textures[0].source.rfind("layered:3d;", 0), 0u);
  const Texture t = load_scene_texture(s, 0);
  EXPECT_EQ(t.shape().type, TextureType::Volume);
  EXPECT_EQ(t.shape().slices, 4);
  ASSERT_EQ(t.mips(), 5);  // 16x16x4 → 1x1x1
  EXPECT_EQ(t.volume_depth(1), 2);
  EXPECT_EQ(t.volume_depth(2), 1);
  EXPECT_EQ(t.levels(), 4 + 2 + 1 + 1 + 1);
}

TEST(SceneVolume, FragmentsCarryRFromTheirUv) {
  const Scene s =
      parse("[textures.t]\ntype = \"3d\"\nlayers = " + slices(4) +
            "\n[materials.m]\ntexture = \"t\"\nlookup = { r = [0.25, -0.5, 0.125] }\n" + kPlane);
  const std::vector<Fragment> fs = generate_fragments(s);
  ASSERT_GT(fs.size(), 100u);
  for (const Fragment& f : fs) {
    EXPECT_DOUBLE_EQ(f.w, 0.25 * f.u - 0.5 * f.v + 0.125);
    EXPECT_DOUBLE_EQ(f.dwdx, 0.25 * f.dudx - 0.5 * f.dvdx);
    EXPECT_DOUBLE_EQ(f.dwdy, 0.25 * f.dudy - 0.5 * f.dvdy);
  }
  // Without r: r = 0.
  const Scene z = parse("[textures.t]\ntype = \"3d\"\nlayers = " + slices(2) +
                        "\n[materials.m]\ntexture = \"t\"\n" + kPlane);
  for (const Fragment& f : generate_fragments(z)) EXPECT_EQ(f.w, 0.0);
}

TEST(SceneVolume, BadKeysNameFileLineAndColumn) {
  const std::string m = "\n[materials.m]\ntexture = \"t\"\n";
  const std::string vol = "[textures.t]\ntype = \"3d\"\nlayers = " + slices(2);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[textures.t]\ntype = \"3d\"\nfaces = " + slices(2), "has 'layers'"},
      {"[textures.t]\ntype = \"3d\"\nlayers = []", "no layers"},
      {vol + "\ncompress = { format = \"bc1_rgb\" }", "not compressed"},
      {vol + m + "lookup = { r = [1.0, 2.0] }", "[a, b, c]"},
      {vol + m + "lookup = { r = [1.0, \"x\", 0.0] }", "element 1"},
      {vol + m + "lookup = { r = [1.0, 0.0, inf] }", "element 2"},
      {vol + m + "lookup = { r = 0.5 }", "[a, b, c]"},
      {vol + m + "lookup = { direction = \"view\" }", "is not a cube"},
      {"[textures.t]\ntype = \"2d_array\"\nlayers = " + slices(2) + m +
           "lookup = { r = [0.0, 0.0, 0.5] }",
       "is not 3-D"},
      {vol + m + "filter = { mode = \"bilinear\", address = \"clamp\", address_w = \"wrap\" }",
       "together with 'address'"},
      {vol + m + "filter = { mode = \"bilinear\", address_w = \"warp\" }", "address_w"},
  };
  for (const auto& [body, what] : cases) {
    const std::string e = error_of(body);
    EXPECT_NE(e.find(what), std::string::npos) << body << "\n→ " << e;
    EXPECT_EQ(e.rfind("s.toml:", 0), 0u) << e;
    EXPECT_NE(e.find_first_of("0123456789", 7), std::string::npos) << e;
  }
  // Slices of different sizes fail when the texture loads.
  const std::string mixed =
      "[textures.t]\ntype = \"3d\"\nlayers = [\"procedural:noise?size=8\", "
      "\"procedural:noise?size=16\"]\n";
  EXPECT_NE(error_of(mixed).find("slice 0 is 8x8"), std::string::npos) << error_of(mixed);
}

// The truth's level-0 trilinear sample agrees with the unit's magnified sample (float texels),
// and reads r: a truth on slice 0 alone would not.
TEST(SceneVolume, TruthIsTrilinearInSpace) {
  std::vector<std::vector<float>> z(4, std::vector<float>(size_t{4} * 4 * 4, 0.0f));
  for (size_t k = 0; k < 4; ++k)
    for (size_t i = 0; i < z[k].size(); i += 4) z[k][i] = static_cast<float>(k) / 4;
  const Texture t = Texture::from_volume("v", 4, 4, z, TexelFormat::Rgba32f, true);
  const AddressMode clamp[3] = {AddressMode::Clamp, AddressMode::Clamp, AddressMode::Clamp};
  // r = 0.5: k0 = 1, k1 = 2 at ½ each.
  EXPECT_NEAR(reference_volume_trilinear(t, clamp, {}, 0.3, 0.3, 0.5).r, 1.5 / 4, 1e-12);
  const AddressMode border[3] = {AddressMode::Clamp, AddressMode::Clamp, AddressMode::Border};
  EXPECT_NEAR(reference_volume_trilinear(t, border, glm::dvec4(1), 0.3, 0.3, 1.0).r,
              0.5 * 3 / 4 + 0.5, 1e-12);
}

// The truth of an explicit LOD on a volume is the cube of its level's texels, of explicit
// gradients their 3-D parallelogram: on slices alternately 1 and 0, a magnified pixel's plain
// truth keeps its slice (1); LOD 1 (a cube of 2 texels) and gradients of 2 slices in r
// average them (½).
TEST(SceneVolume, OperationTruthsTakeTheThreeDFootprint) {
  std::vector<std::vector<float>> z(8);
  for (size_t k = 0; k < 8; ++k) z[k].assign(size_t{8} * 8 * 4, k % 2 == 0 ? 1.0f : 0.0f);
  const Texture t = Texture::from_volume("v", 8, 8, z, TexelFormat::Rgba32f, true);
  const AddressMode wrap[3] = {AddressMode::Wrap, AddressMode::Wrap, AddressMode::Wrap};
  const PixelIntegrator grid(TruthPixel::Box, TruthSampling{16});
  Fragment f;
  f.u = f.v = 0.5;
  f.w = 2.5 / 8;  // slice 2's centre
  f.dudx = f.dvdy = 0.01 / 8;
  f.op = static_cast<uint8_t>(SampleOp::kSampleLod);
  f.lod = 1;
  OperationSampler s;
  EXPECT_NEAR(reference_volume_trilinear(t, wrap, {}, f.u, f.v, f.w).r, 1.0, 1e-12);
  EXPECT_NEAR(ground_truth_volume_operation(t, wrap, {}, s, f, grid).r, 0.5, 1e-9);
  s.max_lod = 0;  // a cube of one texel: the tent's mean over ±½ slice, ¾
  EXPECT_NEAR(ground_truth_volume_operation(t, wrap, {}, s, f, grid).r, 0.75, 1e-9);
  s = {};
  f.op = static_cast<uint8_t>(SampleOp::kSampleGrad);
  f.dwdx = 2.0 / 8;  // two slices along x: ½ (a 2-D parallelogram, dw left out, would give 1)
  EXPECT_NEAR(ground_truth_volume_operation(t, wrap, {}, s, f, grid).r, 0.5, 1e-3);
}

// The shipped volume scene renders close to its truth with the 3-D path's row, and its trace
// (which carries r and its derivatives in w) replays it with the same figures.
TEST(SceneVolume, VolumeSceneRendersAndItsTraceReplaysIt) {
  TempDir dir("scene_volume");
  const nlohmann::json a = shipped_scene_report(dir, "volume", "", "scene");
  ASSERT_GT(a["fragments"].get<uint64_t>(), 1000u);
  // 29.8 dB at 96x72: the oblique floor minifies the volume anisotropically, which a 3-D
  // trilinear sample blurs (an isotropic λ from the longer axis).
  EXPECT_GT(a["accuracy"]["psnr_db"].get<double>(), 27.0) << a["accuracy"].dump();
  ASSERT_TRUE(a["blocks"].contains("volume.r_axis")) << a["blocks"].dump();
  const std::string trc = dir.file("vol.trc");
  ASSERT_EQ(generate_scene_trace(std::string(TEXSIM_SOURCE_DIR) + "/scenes/volume.toml", trc,
                                 {"output.width=96", "output.height=72"}),
            a["fragments"].get<uint64_t>());
  {
    TraceReader r(trc);
    std::vector<Fragment> fs;
    ASSERT_GT(r.next_chunk(fs), 0u);
    bool any_w = false;
    for (const Fragment& f : fs) any_w = any_w || (f.w != 0 && f.dwdx != 0);
    EXPECT_TRUE(any_w);
  }
  const nlohmann::json b = shipped_scene_report(dir, "volume", trc, "trace");
  for (const char* key : {"fragments", "cycles", "cache", "dram", "accuracy"})
    EXPECT_EQ(a[key], b[key]) << key;
  EXPECT_EQ(a["blocks"]["volume.r_axis"], b["blocks"]["volume.r_axis"]);
}

// An explicit LOD on a volume material (`operation`): the image moves with it (an ignored
// operation would give the plain scene's), the report carries the operation's row, and the
// scene's trace (its records' op and lod) replays the same figures.
TEST(SceneVolume, ExplicitLodOnAVolumeMaterialRendersAndReplays) {
  TempDir dir("scene_volume_ops");
  std::ifstream in(std::string(TEXSIM_SOURCE_DIR) + "/scenes/volume.toml");
  std::ostringstream text;
  text << in.rdbuf();
  std::string scene = text.str();
  const std::string lookup = "lookup = { r = [0.25, 0.75, 0.0] }";
  const size_t at = scene.find(lookup);
  ASSERT_NE(at, std::string::npos);
  scene.insert(at + lookup.size(), "\noperation = { op = \"lod\", lod = 1.0 }");
  const std::string path = dir.file("volume_lod.toml");
  std::ofstream(path) << scene;
  // 48 × 36: the operation's truth integrates a cube per fragment.
  const std::vector<std::string> size = {"output.width=48", "output.height=36"};
  const auto run = [&](const std::string& out, const std::string& trace,
                       const std::string& scene_path) {
    RunOptions opt;
    opt.scene = scene_path;
    opt.trace = trace;
    opt.threads = 1;
    opt.truth_cache = false;
    opt.out = dir.file(out);
    opt.overrides = size;
    std::ostringstream log;
    run_simulation(opt, log);
    std::ifstream r(opt.out + "/report.json");
    return nlohmann::json::parse(r);
  };
  const nlohmann::json a = run("scene", "", path);
  const nlohmann::json plain =
      run("plain", "", std::string(TEXSIM_SOURCE_DIR) + "/scenes/volume.toml");
  const nlohmann::json& row = a["materials"]["slice"]["operations"]["lod"];
  ASSERT_TRUE(row.is_object()) << a["materials"].dump();
  EXPECT_EQ(row["fragments"], a["fragments"]);
  EXPECT_EQ(row["taps_per_fragment"].get<double>(), 16.0);  // trilinear 3-D: 2 levels × 8
  EXPECT_NE(a["accuracy"]["psnr_db"], plain["accuracy"]["psnr_db"]);
  const std::string trc = dir.file("vol_lod.trc");
  ASSERT_EQ(generate_scene_trace(path, trc, size), a["fragments"].get<uint64_t>());
  const nlohmann::json b = run("trace", trc, path);
  for (const char* key : {"fragments", "cycles", "cache", "accuracy"})
    EXPECT_EQ(a[key], b[key]) << key;
  EXPECT_EQ(b["materials"]["slice"]["operations"]["lod"], row);
}

// 3-D fragments on four units behind a shared L2 (the two-step timing of several units):
// the image, its accuracy and the r axis's operations are one unit's.
TEST(SceneVolume, FourUnitsWithAnL2GiveOneUnitsImage) {
  TempDir dir("scene_volume_units");
  const auto run = [&](const std::string& out, const std::vector<std::string>& extra) {
    RunOptions opt;
    opt.scene = std::string(TEXSIM_SOURCE_DIR) + "/scenes/volume.toml";
    opt.threads = 1;
    opt.truth_cache = false;
    opt.out = dir.file(out);
    opt.overrides = {"output.width=96", "output.height=72"};
    opt.overrides.insert(opt.overrides.end(), extra.begin(), extra.end());
    std::ostringstream log;
    run_simulation(opt, log);
    std::ifstream in(opt.out + "/report.json");
    return nlohmann::json::parse(in);
  };
  const nlohmann::json one = run("one", {});
  const nlohmann::json four = run("four", {"pipeline.units=4", "pipeline.l2.size_bytes=524288"});
  EXPECT_EQ(one["fragments"], four["fragments"]);
  EXPECT_EQ(one["accuracy"], four["accuracy"]);
  // The same operations (the area is per unit: four times one's).
  EXPECT_EQ(one["blocks"]["volume.r_axis"]["ops"], four["blocks"]["volume.r_axis"]["ops"]);
  ASSERT_TRUE(four.contains("l2")) << four.dump();
  EXPECT_GT(four["l2"]["accesses"].get<uint64_t>(), 0u);
  const auto slurp = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  };
  const std::string image = slurp(dir.file("one") + "/image.png");
  EXPECT_FALSE(image.empty());
  EXPECT_EQ(image, slurp(dir.file("four") + "/image.png"));
}

}  // namespace
}  // namespace texsim
