// study filters measures on the texture unit itself: a method's cycles and cache misses are
// those of a TextureUnit built the way `texsim run` builds it (material_from_toml from a
// scene's material table) for the same fragments, and every hardware method's figures are the
// unit's for its material.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "blocks/base/tech_table.h"
#include "pipeline/raster/fragment_generator.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"
#include "pipeline/studies/study_filter_methods.h"
#include "pipeline/studies/study_filters.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {
namespace {

// A tilted plane (anisotropy about 8 at the centre) with one material: `effects` is the TOML
// of its effect tables.
Scene tilted_plane(const std::string& effects) {
  const std::string text =
      "[output]\nwidth = 32\nheight = 32\n"
      "[camera]\nposition = [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, -1.0]\nup = [0.0, 1.0, 0.0]\n"
      "fov_y = 20.0\n"
      "[textures.t]\nsource = \"procedural:checker?size=64&cells=8\"\n"
      "[materials.m]\ntexture = \"t\"\n" +
      effects +
      "[[planes]]\nmaterial = \"m\"\norigin = [-4.0, -1.0, -6.0]\n"
      "edge_u = [8.0, 0.0, 0.0]\nedge_v = [0.0, 2.0, -14.0]\nuv_scale = [4.0, 4.0]\n";
  return parse_scene(text, "test scene", "");
}

const StudyFilterMethod& method_named(const std::vector<StudyFilterMethod>& ms,
                                      const std::string& name) {
  for (const auto& m : ms) {
    if (m.name == name) return m;
  }
  throw std::runtime_error("no method " + name);
}

struct UnitFigures {
  uint64_t cycles = 0, misses = 0;
  std::vector<Rgba> colours;
};

UnitFigures run_unit(TextureSet& set, const MaterialSetup& m, const std::vector<Fragment>& frags) {
  TextureUnit unit(set, {m}, PipelineSetup{}, TechTable::defaults(), true);
  UnitFigures u;
  for (const Fragment& f : frags) u.colours.push_back(unit.process(f, 0));
  u.cycles = unit.cycles();
  u.misses = unit.cache().stats().misses;
  return u;
}

// The study's method and the scene's material of the same configuration cost the same.
void expect_study_matches_run(const std::string& method, const std::string& effects) {
  const Scene scene = tilted_plane(effects);
  const std::vector<Fragment> frags = generate_fragments(scene);
  ASSERT_GT(frags.size(), 200u);
  TextureSet set;
  set.add(load_texture(scene.textures[0].source, scene.base_dir));
  const MaterialSetup mat = material_from_toml("m", 0, *scene.materials[0].effects, "test scene");
  const UnitFigures run = run_unit(set, mat, frags);

  StudyFiltersOptions opt;
  opt.oiio = false;
  opt.mesa = false;
  const std::vector<StudyFilterMethod> methods = study_filter_methods(opt);
  const StudyFilterRun study =
      run_study_filter_method(method_named(methods, method), set, frags, TechTable::defaults());
  EXPECT_EQ(study.cycles, run.cycles) << method;
  EXPECT_EQ(study.misses, run.misses) << method;
  ASSERT_EQ(study.colours.size(), run.colours.size());
  for (size_t i = 0; i < frags.size(); ++i) EXPECT_EQ(study.colours[i], run.colours[i]) << i;
}

TEST(StudyFiltersOnUnit, TrilinearBaselineCostsWhatTexsimRunSimulates) {
  expect_study_matches_run("trilinear (isotropic)", "filter = { mode = \"trilinear\" }\n");
}

TEST(StudyFiltersOnUnit, VulkanProbesCostWhatTexsimRunSimulates) {
  expect_study_matches_run("trilinear aniso 16 (Vulkan probes)",
                           "filter = { mode = \"trilinear\" }\n"
                           "lod = { aniso = \"vulkan\", max_aniso = 16 }\n");
}

TEST(StudyFiltersOnUnit, EwaCostsWhatTexsimRunSimulates) {
  expect_study_matches_run("ewa lut256", "ewa = {}\n");
}

// Every hardware method of the study: its cycles are the unit's for its material.
TEST(StudyFiltersOnUnit, EveryMethodsCyclesAreTheUnits) {
  StudyFiltersOptions opt;
  opt.size = 24;
  opt.oiio = false;
  opt.mesa = false;
  TextureSet set;
  set.add(load_texture("procedural:noise?size=64&cells=8", ""));
  const std::vector<Fragment> frags = study_filter_fragments(8, opt, 64);
  ASSERT_GT(frags.size(), 100u);
  for (const StudyFilterMethod& m : study_filter_methods(opt)) {
    ASSERT_TRUE(m.hardware()) << m.name;
    const StudyFilterRun study = run_study_filter_method(m, set, frags, TechTable::defaults());
    const UnitFigures unit = run_unit(set, m.material, frags);
    EXPECT_GT(study.cycles, frags.size()) << m.name;
    EXPECT_EQ(study.cycles, unit.cycles) << m.name;
    EXPECT_EQ(study.misses, unit.misses) << m.name;
  }
}

}  // namespace
}  // namespace texsim
