// Relief and lighting as material effects: a material without them builds no relief or
// lighting block and no stage, and its colours do not change when another material of the
// scene uses them; flat lighting and parallax over flat height maps give their closed forms;
// unknown texture names
// are errors naming the key.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <set>

#include "blocks/base/input_error.h"
#include "pipeline/geometry/surface_frame.h"
#include "pipeline/reference/surface_reference.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"
#include "pipeline/texture/effect_registry.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {
namespace {

const char* const kScene = R"(
[output]
width = 64
height = 48
[camera]
position = [0.0, 1.0, 0.0]
look_at = [0.0, 1.0, -10.0]
[textures.t]
source = "procedural:checker?size=64&cells=4"
[textures.h]
source = "procedural:noise?size=64"
[materials.a_plain]
texture = "t"
[materials.b_lit]
texture = "t"
relief = { method = "steep", height_texture = "h", scale = 4.0 }
lighting = { normal = "height_map", normal_texture = "h" }
[[planes]]
material = "a_plain"
origin = [-1.0, 0.0, -1.0]
edge_u = [2.0, 0.0, 0.0]
edge_v = [0.0, 0.0, -8.0]
[[planes]]
material = "b_lit"
origin = [-1.0, 0.0, -1.0]
edge_u = [0.0, 0.0, -8.0]
edge_v = [0.0, 2.0, 0.0]
)";

TextureSet scene_textures(const Scene& s) {
  TextureSet set;
  for (size_t i = 0; i < s.textures.size(); ++i) set.add(load_scene_texture(s, i));
  return set;
}

std::vector<Fragment> fragments_of(const Scene& s, uint32_t prim) {
  const PlaneProjection map(s, s.primitives[prim]);
  std::vector<Fragment> out;
  for (int y = 0; y < s.height; ++y) {
    for (int x = 0; x < s.width; ++x) {
      const UvSample u = map.at(x + 0.5, y + 0.5);
      if (!u.inside) continue;
      Fragment f = u.fragment(static_cast<uint32_t>(x), static_cast<uint32_t>(y));
      f.prim = prim;
      out.push_back(f);
    }
  }
  return out;
}

TEST(SurfaceEffects, AnUnusedEffectCostsNothingAndChangesNothing) {
  const Scene s = parse_scene(kScene, "s.toml", "");
  TextureSet tex = scene_textures(s);
  const std::vector<MaterialSetup> mats = build_materials(s);
  ASSERT_FALSE(mats[0].relief || mats[0].lighting);
  ASSERT_TRUE(mats[1].relief && mats[1].lighting);
  std::vector<SurfaceFrame> frames;
  for (const auto& p : s.primitives) frames.emplace_back(s, p);
  TextureUnit both(tex, mats, PipelineSetup{}, s.tech, false);
  both.set_surfaces(frames);
  TextureUnit plain(tex, {mats[0]}, PipelineSetup{}, s.tech, true);
  TextureUnit plain_f(tex, {mats[0]}, PipelineSetup{}, s.tech, false);
  for (const BlockUse& b : plain.material_blocks(0)) {
    EXPECT_NE(b.name.rfind("relief.", 0), 0u) << b.name;
    EXPECT_NE(b.name.rfind("lighting.", 0), 0u) << b.name;
  }
  for (int st = 0; st < plain.pipeline()->stage_count(); ++st) {
    EXPECT_NE(plain.pipeline()->config(st).name, "relief");
    EXPECT_NE(plain.pipeline()->config(st).name, "lighting");
  }
  const std::vector<Fragment> frags = fragments_of(s, 0);
  ASSERT_GT(frags.size(), 100u);
  for (const Fragment& f : frags) {
    const Rgba a = both.process(f, 0), b = plain_f.process(f, 0);
    ASSERT_EQ(a, b) << f.x << "," << f.y;
  }
  // The lit material reports its blocks and relief steps.
  for (const Fragment& f : fragments_of(s, 1)) (void)both.process(f, 1);
  std::set<std::string> names;
  for (const BlockUse& b : both.material_blocks(1)) names.insert(b.name);
  EXPECT_TRUE(names.count("relief.parallax_iterative"));
  EXPECT_TRUE(names.count("lighting.normal_unit"));
  EXPECT_TRUE(names.count("lighting.blinn_phong"));
  EXPECT_GT(both.material_relief_steps(1), both.material_fragments(1));
}

TEST(SurfaceEffects, TimedUnitHasReliefAndLightingStagesOnlyWhenUsed) {
  const Scene s = parse_scene(kScene, "s.toml", "");
  TextureSet tex = scene_textures(s);
  const TextureUnit unit(tex, build_materials(s), PipelineSetup{}, s.tech, true);
  std::vector<std::string> names;
  names.reserve(static_cast<size_t>(unit.pipeline()->stage_count()));
  for (int st = 0; st < unit.pipeline()->stage_count(); ++st)
    names.push_back(unit.pipeline()->config(st).name);
  EXPECT_EQ(names,
            (std::vector<std::string>{"relief", "lod", "address", "cache", "blend", "lighting"}));
}

TEST(SurfaceEffects, FlatLightingIsTheClosedForm) {
  LightingSetup ls;
  ls.shader.ambient = 0.1;
  ls.shader.diffuse = 0.7;
  ls.shader.specular = 0.2;
  const LightingEffect e(ls, nullptr);
  OpCounts no, so;
  // Light and eye on the normal: c·(ka + kd) + ks.
  const Rgba c = e.shade({0.5F, 0.25F, 1.0F, 0.5F}, 0.3, 0.3, {0, 0, 1}, {0, 0, 1}, no, so);
  EXPECT_NEAR(c.r, 0.5 * 0.8 + 0.2, 1e-6);
  EXPECT_NEAR(c.g, 0.25 * 0.8 + 0.2, 1e-6);
  EXPECT_NEAR(c.b, 1.0, 1e-6);  // clamped
  EXPECT_EQ(c.a, 0.5F);
  EXPECT_EQ(no.total(), 0u);  // flat normals: no normal unit
  EXPECT_GT(so.total(), 0u);
  // Light behind the surface: ambient only.
  const Rgba d = e.shade({0.5F, 0.5F, 0.5F, 1.0F}, 0, 0, {0, 0, 1}, {0, 0, -1}, no, so);
  EXPECT_NEAR(d.r, 0.05, 1e-6);
}

Texture flat_height(float h) {
  return Texture::from_rgba("h", 32, 32, std::vector<float>(size_t{32} * 32 * 4, h),
                            TexelFormat::Rgba32f, false);
}

TEST(SurfaceEffects, ParallaxOverFlatHeightsShiftsByTheClosedForm) {
  ReliefSetup rs;
  rs.height_texture = "h";
  rs.scale = 4;
  rs.parallax.depth_texels = 4;
  const glm::dvec3 v = glm::normalize(glm::dvec3(1, 0, 1));  // 45° towards +u
  for (const auto method : {ReliefSetup::Method::Parallax, ReliefSetup::Method::Steep}) {
    rs.method = method;
    rs.parallax.method = method == ReliefSetup::Method::Parallax
                             ? ParallaxMapper::Method::Offset
                             : ParallaxMapper::Method::Iterative;
    OpCounts ops;
    // Height 1: the surface is the polygon, no shift.
    const ReliefEffect top(rs, flat_height(1.0F));
    const ReliefEffect::Shift a = top.shift(0.5, 0.5, v, 1.0, 1.0, ops);
    EXPECT_NEAR(a.u, 0.5, 1e-9);
    EXPECT_NEAR(a.v, 0.5, 1e-9);
    // Height 0, steep: the ray descends 4 texels, moving 4 texels towards −u (away from the eye).
    if (method == ReliefSetup::Method::Steep) {
      const ReliefEffect bottom(rs, flat_height(0.0F));
      const ReliefEffect::Shift b = bottom.shift(0.5, 0.5, v, 1.0, 1.0, ops);
      EXPECT_NEAR(b.u, 0.5 - 4.0 / 32, 1e-6);
      EXPECT_NEAR(b.v, 0.5, 1e-9);
      EXPECT_GT(b.steps, 1u);
      EXPECT_EQ(b.fetches % 4, 0u);
    }
  }
}

TEST(SurfaceEffects, UnknownTextureNameNamesTheKey) {
  const std::string text = std::string(kScene) + "";
  std::string bad = text;
  bad.replace(bad.find("height_texture = \"h\""), 20, "height_texture = \"x\"");
  try {
    build_materials(parse_scene(bad, "s.toml", ""));
    FAIL() << "accepted an unknown texture";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("relief.height_texture"), std::string::npos) << w;
    EXPECT_NE(w.find("no texture named 'x'"), std::string::npos) << w;
  }
}

TEST(SurfaceEffects, ProcessWithoutPlanesIsRefused) {
  const Scene s = parse_scene(kScene, "s.toml", "");
  TextureSet tex = scene_textures(s);
  TextureUnit unit(tex, build_materials(s), PipelineSetup{}, s.tech, false);
  Fragment f;
  EXPECT_THROW((void)unit.process(f, 1), std::invalid_argument);
}

}  // namespace
}  // namespace texsim
