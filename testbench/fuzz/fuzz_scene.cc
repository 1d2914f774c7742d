// libFuzzer harness: scene TOML text through everything `texsim run` builds from it: the scene
// parser, the materials' effects, the [pipeline] setup, the clocked texture unit, the planes'
// projective maps, and a small render through the front end or the reference generator with
// the ground truth of each pixel. Bad input must end in InputError; a broken timing invariant
// (std::logic_error) is a finding like any other exception.
//
// To keep each input fast, and the harness off the disk: texture files are replaced by a small
// procedural stand-in (layered textures by small slices of their type), procedural textures larger
// than kMaxTextureSize are too (their spec is still parsed and checked), the image is scaled down
// to at most kMaxSide pixels per side and the ground truth takes at most 2x2 samples per pixel.
#include <algorithm>
#include <cstdio>
#include <vector>

#include "pipeline/geometry/plane_projection.h"
#include "pipeline/raster/fragment_generator.h"
#include "pipeline/raster/scene_front_end.h"
#include "pipeline/reference/ground_truth.h"
#include "pipeline/reference/layered_reference.h"
#include "pipeline/scene/layered_source.h"
#include "pipeline/scene/procedural_texture.h"
#include "pipeline/scene/scene.h"
#include "pipeline/texture/effect_registry.h"
#include "pipeline/texture/texture_unit.h"
#include "testbench/fuzz/fuzz_input.h"

namespace {

using namespace texsim;

constexpr int kMaxTextureSize = 64;
constexpr int kMaxSide = 24;

// A layered texture's stand-in: its type and at most two cubes or four layers of 8 × 8 (one
// texel high for a 1-D array) procedural slices.
Texture layered_stand_in(const SceneTexture& t) {
  const LayeredSource ls = parse_layered_source(t.source, t.where);
  const bool cube = ls.type == SceneTextureType::Cube || ls.type == SceneTextureType::CubeArray;
  const size_t n = std::min(ls.slices.size(), size_t{cube ? 12u : 4u});
  const int h = ls.type == SceneTextureType::Array1D ? 1 : 8;
  std::vector<std::vector<float>> slices(n);
  for (size_t k = 0; k < n; ++k) {
    slices[k].assign(size_t{8} * static_cast<size_t>(h) * 4, 1.0f);
    for (size_t i = 0; i < slices[k].size(); i += 4) slices[k][i] = static_cast<float>(k % 7) / 6;
  }
  if (ls.type == SceneTextureType::Volume3D)
    return Texture::from_volume(t.name, 8, h, slices, TexelFormat::Rgba8, true);
  return Texture::from_slices(t.name, cube ? TextureType::Cube : TextureType::Array, 8, h, slices,
                              TexelFormat::Rgba8, true);
}

TextureSet scene_textures(const Scene& scene) {
  TextureSet set;
  for (const SceneTexture& t : scene.textures) {
    if (is_layered_source(t.source)) {
      set.add(layered_stand_in(t));
      continue;
    }
    const bool small = is_procedural_source(t.source) &&
                       parse_procedural_source(t.source, t.where).size <= kMaxTextureSize;
    set.add(
        make_procedural_texture(small ? t.source : "procedural:checker?size=32&cells=4", t.where));
  }
  return set;
}

// The same view at most kMaxSide pixels per side.
void shrink_image(Scene& scene) {
  const int side = std::max(scene.width, scene.height);
  if (side <= kMaxSide) return;
  scene.width = std::max(1, scene.width * kMaxSide / side);
  scene.height = std::max(1, scene.height * kMaxSide / side);
  scene.camera.width = scene.width;
  scene.camera.height = scene.height;
}

void run_scene(const std::string& text) {
  Scene scene = parse_scene(text, "fuzz.toml", "");
  shrink_image(scene);
  TextureSet textures = scene_textures(scene);
  std::vector<MaterialSetup> mats = build_materials(scene);
  if (mats.empty()) {  // as `texsim run` does: one default material
    mats.emplace_back();
    mats.back().name = "default";
    mats.back().filter.filter = FilterMode::Trilinear;
  }
  static const toml::table kNoPipeline;
  const PipelineSetup setup =
      PipelineSetup::from_toml(scene.pipeline ? *scene.pipeline : kNoPipeline, scene.path);
  TextureUnit unit(textures, mats, setup, scene.tech, true);
  std::vector<PlaneProjection> maps;
  for (const ScenePrimitive& p : scene.primitives) maps.emplace_back(scene, p);
  // At most 2×2 fixed samples, or the adaptive grid when the scene asks for it.
  const PixelIntegrator integrate(
      TruthPixel::Box, {scene.reference_samples > 0 ? std::min(scene.reference_samples, 2) : 0});
  auto truth = [&](const Fragment& f, int material) {
    const MaterialSetup& m = mats[static_cast<size_t>(material)];
    const Texture& tex = textures[static_cast<int>(f.tex)];
    if (tex.shape().type == TextureType::Cube) {
      (void)ground_truth_cube(tex, reference_layer(f.layer, tex.shape().slices / 6), true,
                              m.address_u(), m.address_v(), glm::dvec4(0), DirectionMap::of(f),
                              static_cast<int>(f.x), static_cast<int>(f.y), integrate);
      return;
    }
    (void)ground_truth_exact(textures[static_cast<int>(f.tex)], m.address_u(), m.address_v(),
                             maps[f.prim], static_cast<int>(f.x), static_cast<int>(f.y), integrate);
  };
  if (unit.front_stages() > 0) {
    draw_scene_front_end(scene, maps, unit,
                         [&](const Fragment& f, int material, const Rgba*) { truth(f, material); });
  } else {
    generate_fragments(scene, 0, [&](const Fragment& f) {
      const int material = scene.primitives[f.prim].material;
      (void)unit.process(f, material);
      truth(f, material);
    });
  }
  unit.check_timing_invariants();
  (void)unit.blocks();
  for (int m = 0; m < unit.material_count(); ++m) (void)unit.material_blocks(m);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  texsim::fuzz::expect_clean([&] { run_scene(text); });
  return 0;
}
