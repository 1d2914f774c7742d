#pragma once
// The object-space texturing pipeline (docs/derivations/object-space.md): every planar primitive
// of a scene is clipped to the view frustum in view space, rotated parallel to the screen
// (PolygonRotation), walked in its own plane on the hole-free grid (ObjectSpaceRaster: affine
// coordinates, one LOD per polygon), textured by the texture unit (trilinear mip-mapping through
// the texture cache and DRAM, so texels, misses and traffic are those of the real fetch path),
// rotated back and projected (SampleProjection) and splatted onto the four nearest pixels
// (SplatResolve) with per-sample depth visibility; the resolve normalises the buffer.
//
// Polygons whose depth varies by more than `band_ratio` (far / near) are cut into depth bands
// first, each a polygon of its own (its own step and LOD): one step for a whole floor running
// to the horizon would put thousands of samples in each of its far pixels.
//
// Cycles: the stages run as one pipeline, so a frame takes the slowest stage's cycles (the
// texture unit's clocked pipeline, or samples ÷ lanes of the rasteriser, projection and splat)
// plus per polygon the set-up latencies of rotation and projection (not overlapped: the
// polygon-count cost) plus the resolve of the whole frame (four pixels per cycle per lane: one
// from each bank of the accumulation buffer). Orthographic cameras: the projection has no
// division, the step is s / f everywhere (f pixels per world unit) and no depth bands are cut.
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/op_counts.h"
#include "blocks/geometry/polygon_rotation.h"
#include "blocks/geometry/sample_projection.h"
#include "blocks/raster/object_space_raster.h"
#include "blocks/raster/splat_resolve.h"
#include "pipeline/scene/object_space_config.h"
#include "pipeline/scene/scene.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {

struct ObjectSpaceResult {
  int width = 0, height = 0;
  std::vector<Rgba> image;       // width × height, background where nothing landed
  std::vector<uint8_t> covered;  // pixel centres inside some drawn polygon (for holes)
  std::vector<uint8_t> drawn;    // pixels with Σ S > 0 after the splats
  uint64_t primitives = 0;       // drawn (after culling, clipping and the edge-on test)
  uint64_t culled = 0, clipped_away = 0, edge_on = 0, degenerate = 0;
  uint64_t bands = 0;  // polygons walked (a primitive may give several bands)
  uint64_t samples = 0;
  ObjectSpaceRasterStats raster;
  SplatStats splat;
  ResolveStats resolve;
  double lod_sum = 0;  // Σ of the bands' LODs (mean = lod_sum / bands)
  // Cycles by stage and the frame's total.
  uint64_t texture_cycles = 0, raster_cycles = 0, projection_cycles = 0, splat_cycles = 0;
  uint64_t setup_cycles = 0, resolve_cycles = 0, cycles = 0;
  // Operations by block (texture: the texture unit's blocks, cache excluded).
  OpCounts rotation_ops, raster_ops, projection_ops, splat_ops, texture_ops;
  OpCounts total_ops() const {
    return rotation_ops + raster_ops + projection_ops + splat_ops + texture_ops;
  }
  std::vector<std::string> texture_blocks;  // the texture unit's blocks (cache excluded)
  uint64_t texels = 0;                      // texels the filter read (through the cache)
  TextureCache::Stats cache;
  uint64_t dram_bytes = 0;
  // Bytes of accumulation-buffer traffic (splat read-modify-writes and the resolve).
  uint64_t buffer_bytes() const {
    return splat.bytes_read + splat.bytes_written + resolve.bytes_read + resolve.bytes_written;
  }
};

// The materials of the object-space path: each scene material textured by trilinear mip-mapping
// with its own texture and address modes (footprint filters, coordinate units, relief and
// lighting left out).
std::vector<MaterialSetup> object_space_materials(const std::vector<MaterialSetup>& mats);

// Renders frame 0 of `scene` object-space. `textures` holds the scene's textures in its order.
// `material` >= 0: only the primitives of that material are drawn (-1: every primitive).
ObjectSpaceResult render_object_space(const Scene& scene, TextureSet& textures,
                                      const std::vector<MaterialSetup>& mats,
                                      const PipelineSetup& setup, const ObjectSpaceConfig& cfg,
                                      int material = -1);

}  // namespace texsim
