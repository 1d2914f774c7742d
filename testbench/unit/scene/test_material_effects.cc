// A scene's materials through the effect registry: exactly the blocks their effect tables
// name are built, unknown or misplaced effects are errors with file:line:column, and a
// `coords` table is read by its coordinate block's own Config::from_toml.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>

#include "blocks/base/input_error.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"
#include "pipeline/texture/effect_registry.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {
namespace {

std::vector<Scene> shipped_scenes() {
  std::vector<Scene> scenes{default_scene()};
  std::vector<std::string> paths;
  for (const auto& f :
       std::filesystem::directory_iterator(std::string(TEXSIM_SOURCE_DIR) + "/scenes"))
    if (f.path().extension() == ".toml") paths.push_back(f.path().string());
  std::sort(paths.begin(), paths.end());
  for (const auto& p : paths) scenes.push_back(load_scene(p));
  return scenes;
}

// The blocks a material's table asks for, as the texture unit reports them (prefixes).
std::set<std::string> needed(const SceneMaterial& m) {
  std::set<std::string> want;
  std::string footprint;
  for (const Effect& e : effect_registry()) {
    if (m.effects->contains(e.key) && !e.group.empty()) footprint = "filter." + std::string(e.key);
  }
  if (m.effects->contains("coords")) {
    want.insert("coords.");
    const toml::node* d = m.effects->at_path("coords.derivs").node();
    if (!d || d->value_or(std::string()) != "none") want.insert("derivs.");
  }
  // Relief and lighting: their blocks only when the material names them.
  if (m.effects->contains("relief")) want.insert("relief.");
  if (m.effects->contains("lighting")) {
    want.insert("lighting.blinn_phong");
    const toml::node* n = m.effects->at_path("lighting.normal").node();
    if (n && n->value_or(std::string()) != "flat") want.insert("lighting.normal_unit");
  }
  if (!footprint.empty()) {
    want.insert(footprint);
  } else {
    want.insert("lod");
    want.insert("filter.");
    want.insert("blend");
  }
  return want;
}

std::string prefix_of(const std::string& block) {
  for (const char* p :
       {"coords.", "derivs.", "filter.ewa", "filter.multi_probe", "filter.feline", "filter.spaf"}) {
    if (block.rfind(p, 0) == 0) return p;
  }
  if (block.rfind("filter.", 0) == 0) return "filter.";
  if (block.rfind("relief.", 0) == 0) return "relief.";
  return block;
}

TEST(MaterialEffects, EachShippedSceneBuildsExactlyTheBlocksItsMaterialsNeed) {
  for (const Scene& scene : shipped_scenes()) {
    const std::vector<MaterialSetup> mats = build_materials(scene);
    ASSERT_EQ(mats.size(), scene.materials.size()) << scene.path;
    TextureSet textures;  // stand-ins: the blocks do not depend on the texels
    for (size_t i = 0; i < scene.textures.size(); ++i)
      textures.add(load_texture("procedural:checker?size=64&cells=4", ""));
    const TextureUnit unit(textures, mats, PipelineSetup{}, scene.tech, false);
    for (size_t i = 0; i < mats.size(); ++i) {
      const SceneMaterial& sm = scene.materials[i];
      EXPECT_EQ(mats[i].coords != nullptr, sm.effects->contains("coords")) << sm.name;
      std::set<std::string> built;
      for (const BlockUse& b : unit.material_blocks(static_cast<int>(i)))
        built.insert(prefix_of(b.name));
      EXPECT_EQ(built, needed(sm)) << scene.path << ": material " << sm.name;
      // The rasteriser is the one the material names (edge without a `raster` table); it is
      // drawn by the fragment generator, never a block of the texture unit.
      const toml::node* r = sm.effects->at_path("raster.method").node();
      const std::string method = r ? r->value_or(std::string()) : "edge";
      EXPECT_EQ(mats[i].raster.block_name(), "raster." + method) << sm.name;
      EXPECT_EQ(built.count("raster.edge") + built.count("raster.rect_scan"), 0u);
    }
  }
}

TEST(MaterialEffects, DefaultSceneBuildsNoCoordinateUnitAndNoFootprintFilter) {
  for (const MaterialSetup& m : build_materials(default_scene())) {
    EXPECT_EQ(m.coords, nullptr) << m.name;
    EXPECT_EQ(m.footprint, nullptr) << m.name;
  }
}

std::string error_of(const std::string& text) {
  try {
    build_materials(parse_scene(text, "s.toml", ""));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const char* const kTexture = "[textures.t]\nsource = \"procedural:checker?size=64&cells=4\"\n";

TEST(MaterialEffects, UnknownOrMisplacedEffectsNameFileLineAndColumn) {
  const std::string unknown =
      error_of(std::string(kTexture) + "[materials.m]\ntexture = \"t\"\nfiltre = {}\n");
  EXPECT_NE(unknown.find("s.toml:5:1"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("materials.m: unknown key 'filtre' (known: texture, budget, sampler, "
                         "filter, lod, coords, raster, relief, lighting, object_space, lookup, "
                         "operation, ewa, multi_probe, feline, spaf)"),
            std::string::npos)
      << unknown;
  const std::string scalar =
      error_of(std::string(kTexture) + "[materials.m]\ntexture = \"t\"\nlod = 3\n");
  EXPECT_NE(scalar.find("s.toml:5:7"), std::string::npos) << scalar;
  EXPECT_NE(scalar.find("expected a table of effect settings"), std::string::npos) << scalar;
  const std::string two =
      error_of(std::string(kTexture) + "[materials.m]\ntexture = \"t\"\newa = {}\nspaf = {}\n");
  EXPECT_NE(two.find("s.toml:6:8"), std::string::npos) << two;
  EXPECT_NE(two.find("a material takes one footprint filter; it already has 'ewa'"),
            std::string::npos)
      << two;
}

TEST(MaterialEffects, EveryRegisteredEffectBuilds) {
  for (const Effect& e : effect_registry()) {
    // Relief needs its height map, lookup a layered texture; every other effect builds from
    // an empty table.
    const std::string table = e.key == "relief" ? "{ height_texture = 't' }" : "{}";
    const std::string texture =
        e.key == "lookup"
            ? "[textures.t]\ntype = \"2d_array\"\nlayers = [\"procedural:checker?size=8\"]\n"
            : kTexture;
    std::string text = texture;
    text += "[materials.m]\ntexture = \"t\"\n" + std::string(e.key) + " = " + table + "\n";
    EXPECT_EQ(error_of(text), "") << e.key;
  }
}

std::string coords_error(const std::string& coords) {
  return error_of(std::string(kTexture) + "[materials.m]\ntexture = \"t\"\ncoords = " + coords +
                  "\n");
}

TEST(MaterialEffects, CoordsTableIsReadByTheBlocksOwnConfig) {
  // A typo names the block that read the table, and where.
  const std::string typo = coords_error("{ method = 'heckbert', formt = 'float' }");
  EXPECT_NE(typo.find("s.toml:5:41"), std::string::npos) << typo;
  EXPECT_NE(typo.find("materials.m.coords[uv_heckbert_direct]: unknown key 'formt'"),
            std::string::npos)
      << typo;
  // The block's own keys: the k-lane adder's lanes (default 4), its range checked by the block.
  const std::string range = coords_error("{ method = 'incremental-k4', lanes = 0 }");
  EXPECT_NE(range.find("materials.m.coords[uv_incremental_adder].lanes"), std::string::npos)
      << range;
  const std::string fixed = coords_error("{ method = 'incremental-k4', form = 'sequential' }");
  EXPECT_NE(fixed.find("is set by method 'incremental-k4'"), std::string::npos) << fixed;
  auto lanes = [](const std::string& coords) {
    const Scene s = parse_scene(std::string(kTexture) + "[materials.m]\ntexture = \"t\"\n" +
                                    "filter = { mode = 'bilinear' }\ncoords = " + coords + "\n",
                                "s.toml", "");
    const MaterialSetup m = build_materials(s).front();
    return m.coords->stages(TechTable::defaults()).front().timing.lanes;
  };
  EXPECT_EQ(lanes("{ method = 'incremental-k4' }"), 4u);
  EXPECT_EQ(lanes("{ method = 'incremental-k4', lanes = 8 }"), 8u);
  EXPECT_EQ(lanes("{ method = 'incremental-bidir' }"), 2u);
}

}  // namespace
}  // namespace texsim
