#pragma once
// The `object_space` material effect in `texsim run` (docs/derivations/object-space.md §7). Every
// material with the effect has its polygons drawn by the object-space pipeline (rotate →
// object-space raster → texture unit → inverse rotation and projection → splat and resolve),
// one pass per material with its own accumulation buffer, before the screen-space fragments.
// Visibility between materials: the frame's depth test at pixel centres over every primitive
// (the screen-space path's, which the reference shares) decides what each pixel shows; a pixel
// won by an object-space material takes that material's resolved colour instead of going
// through the screen-space texture unit. A scene without the effect builds nothing here.
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "pipeline/app/run.h"
#include "pipeline/raster/object_space_pipeline.h"
#include "pipeline/raster/primitive_raster.h"
#include "pipeline/report/object_space_report.h"
#include "pipeline/report/run_report.h"
#include "pipeline/scene/scene.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {

class ObjectSpaceFrame {
 public:
  ObjectSpaceFrame() = default;  // no object-space material: nothing built
  // Renders every object-space material of `scene` (`mats`: the run's materials, in the scene's
  // order). Throws InputError naming the file and key for an effect the variant cannot take
  // beside `object_space` (coords, footprint filters, lod, raster, relief, lighting) and for a
  // scene whose materials use the coordinate front end (`coords`).
  ObjectSpaceFrame(const Scene& scene, TextureSet& textures, const std::vector<MaterialSetup>& mats,
                   const PipelineSetup& setup);
  bool active() const { return !passes_.empty(); }
  bool drawn_by(int material) const {
    return material >= 0 && static_cast<size_t>(material) < pass_of_.size() &&
           pass_of_[static_cast<size_t>(material)] >= 0;
  }
  // The resolved colour of pixel (x, y) of object-space material `material`; counts the pixel
  // as shown, and as a hole shown when the material's buffer has no weight there.
  Rgba shade(int material, uint32_t x, uint32_t y);
  // Pixels shown by object-space materials.
  uint64_t pixels() const;
  // The report's section; `screen_cycles`: the screen-space pass's cycles.
  ObjectSpaceInfo info(uint64_t screen_cycles) const;

 private:
  struct Pass {
    int material = 0;
    std::string name;
    ObjectSpaceConfig config;
    ObjectSpaceResult result;
    uint64_t shown = 0, holes_shown = 0;
  };
  std::vector<Pass> passes_;
  std::vector<int> pass_of_;  // per material: index into passes_, -1 for screen space
  int width_ = 0;
};

// The run's object-space frame, for a run drawing the scene's own fragments; a run of a trace
// draws the trace's fragments screen-space and says so in `log` when a material has the effect.
ObjectSpaceFrame object_space_frame(const Scene& scene, bool scene_fragments, TextureSet& textures,
                                    const std::vector<MaterialSetup>& mats,
                                    const PipelineSetup& setup, std::ostream& log);

// After the screen-space pass: the report's section, and the summary's fragments (+ the pixels
// object space showed) and cycles (the frame's: the object-space passes, then the screen-space
// pass, whose texture unit and rasterisers of screen-space materials run as one pipeline, so
// the slower sets it, as in `texsim study objspace`). Nothing when inactive.
void finish_object_space(const ObjectSpaceFrame& os, uint64_t unit_cycles,
                         const std::vector<RasterCounters>& raster, RunSummary& sum, RunInfo& info);

}  // namespace texsim
