#include "pipeline/app/run_object_space.h"

#include <algorithm>
#include <string>

#include "blocks/base/config_reader.h"

namespace texsim {

namespace {

// The effects the object-space variant does not run beside it (it fetches trilinearly at one LOD
// per polygon with exact affine coordinates; `filter` gives the address modes).
constexpr const char* kExcluded[] = {"coords", "lod",    "raster", "relief",     "lighting",
                                     "ewa",    "feline", "spaf",   "multi_probe"};

void check_material(const Scene& scene, const SceneMaterial& m) {
  const ConfigReader r(*m.effects, scene.path, "materials." + m.name);
  for (const char* key : kExcluded) {
    if (m.effects->contains(key)) {
      r.fail(key, std::string("not with object_space (the object-space pipeline fetches "
                              "trilinearly at one LOD per polygon; only `filter` address modes "
                              "apply)"));
    }
  }
}

}  // namespace

ObjectSpaceFrame::ObjectSpaceFrame(const Scene& scene, TextureSet& textures,
                                   const std::vector<MaterialSetup>& mats,
                                   const PipelineSetup& setup)
    : width_(scene.width) {
  const SceneMaterial* with = nullptr;
  for (const SceneMaterial& m : scene.materials) {
    if (!m.object_space) continue;
    check_material(scene, m);
    with = &m;
  }
  if (with == nullptr) return;  // no material asks: nothing is built
  for (size_t i = 0; i < mats.size(); ++i) {
    if (mats[i].coords) {
      const ConfigReader r(*with->effects, scene.path, "materials." + with->name);
      r.fail("object_space", "not in a scene whose material '" + mats[i].name +
                                 "' uses `coords` (the coordinate front end draws every plane)");
    }
  }
  pass_of_.assign(scene.materials.size(), -1);
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    const SceneMaterial& m = scene.materials[i];
    // A material no primitive uses runs no pass (an unused effect costs nothing).
    if (!m.object_space ||
        std::none_of(scene.primitives.begin(), scene.primitives.end(),
                     [&](const ScenePrimitive& p) { return p.material == static_cast<int>(i); }))
      continue;
    pass_of_[i] = static_cast<int>(passes_.size());
    Pass p;
    p.material = static_cast<int>(i);
    p.name = m.name;
    p.config = *m.object_space;
    p.result = render_object_space(scene, textures, mats, setup, p.config, static_cast<int>(i));
    passes_.push_back(std::move(p));
  }
}

Rgba ObjectSpaceFrame::shade(int material, uint32_t x, uint32_t y) {
  Pass& p = passes_[static_cast<size_t>(pass_of_[static_cast<size_t>(material)])];
  const size_t at = static_cast<size_t>(y) * static_cast<size_t>(width_) + x;
  ++p.shown;
  if (!p.result.drawn[at]) ++p.holes_shown;
  return p.result.image[at];
}

uint64_t ObjectSpaceFrame::pixels() const {
  uint64_t n = 0;
  for (const Pass& p : passes_) n += p.shown;
  return n;
}

ObjectSpaceInfo ObjectSpaceFrame::info(uint64_t screen_cycles) const {
  ObjectSpaceInfo info;
  info.screen_cycles = screen_cycles;
  for (const Pass& p : passes_) {
    ObjectSpaceMaterialInfo m;
    m.material = p.name;
    m.config = p.config;
    m.result = p.result;
    m.result.image.clear();
    m.result.covered.clear();
    m.result.drawn.clear();
    m.pixels_shown = p.shown;
    m.holes_shown = p.holes_shown;
    info.materials.push_back(std::move(m));
  }
  return info;
}

ObjectSpaceFrame object_space_frame(const Scene& scene, bool scene_fragments, TextureSet& textures,
                                    const std::vector<MaterialSetup>& mats,
                                    const PipelineSetup& setup, std::ostream& log) {
  if (scene_fragments) return {scene, textures, mats, setup};
  for (const SceneMaterial& m : scene.materials) {
    if (m.object_space) {
      log << "texsim run: note: material '" << m.name
          << "': object_space ignored, the trace's fragments are drawn screen-space\n";
    }
  }
  return {};
}

void finish_object_space(const ObjectSpaceFrame& os, uint64_t unit_cycles,
                         const std::vector<RasterCounters>& raster, RunSummary& sum,
                         RunInfo& info) {
  if (!os.active()) return;
  uint64_t r = 0;
  for (size_t m = 0; m < raster.size(); ++m) {
    if (!os.drawn_by(static_cast<int>(m))) r += raster[m].cycles;
  }
  info.object_space = os.info(std::max(unit_cycles, r));
  sum.fragments += os.pixels();
  sum.cycles = info.object_space.frame_cycles();
}

}  // namespace texsim
