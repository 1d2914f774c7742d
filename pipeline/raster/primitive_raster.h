#pragma once
// Draws one scene primitive through its material's rasteriser (the rasterisation subsystem ПРП,
// docs/rasterizers.md): the primitive's near-clipped screen polygon, brought within the guard
// band, is split into a fan of triangles, each rasterised by the edge-function rasteriser or the
// rectangle-scan rasteriser; the covered pixels are handed on with the rasteriser's counters.
#include <cstdint>
#include <functional>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/texture/coords/coord_types.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/texture/effect_registry.h"

namespace texsim {

struct RasterCounters {
  uint64_t primitives = 0;  // primitives drawn (culled ones never reach the rasteriser)
  uint64_t triangles = 0, rejected = 0;
  uint64_t rows = 0;            // rows entered (edge: bounding-box rows; rect_scan: rectangle rows)
  uint64_t pixels_visited = 0;  // pixels stepped through
  uint64_t pixels_covered = 0;  // pixels handed on (before the depth test)
  // Rectangle scan only: reciprocals (= q rows with a textured pixel) and its two clocks.
  uint64_t divisions = 0;
  uint64_t fast_cycles = 0, memory_cycles = 0;
  // Edge: one visited pixel per issue slot at the pipeline clock.
  uint64_t cycles = 0;
  double time_ns = 0;  // rectangle scan: both clocks; edge: cycles at the tech table's clock
  // After the depth test (the fragment generator): 2×2 quads anchored at even x, y in which a
  // primitive of the material kept at least one pixel (one quad per primitive and square), and
  // their uncovered lanes, which a GPU runs as helper lanes for the quad's derivatives.
  uint64_t quads = 0, helper_lanes = 0;
  OpCounts ops;
  // Rectangle scan with raster.coords = "constant_depth": the constant-depth coordinate block
  // on the scan's rows (coords.constant_depth): pixels it gave (u, v), pixels whose line it
  // rejected (q below its limit: they keep the exact coordinates), and its operations
  // (triangle set-up with the slope's division, one reciprocal per textured row, 2 adds a pixel).
  uint64_t coord_pixels = 0, coord_rejected = 0;
  OpCounts coord_ops;
  // Rectangle scan with coverage = "outline_parity": the parity rule's hazards.
  ParityHazards hazards;
  RasterCounters& operator+=(const RasterCounters& o);
};

// A covered pixel; `uv`: its normalised texture coordinates from the rasteriser's own
// coordinate block (rect_scan with constant-depth coordinates), null otherwise (exact ones).
using RasterVisit = std::function<void(int32_t x, int32_t y, const CoordSample* uv)>;

// Calls visit for every pixel of [0,w)×[0,h) the rasteriser covers (a pixel once per fan
// triangle that covers it: the fan's triangles share edges, so once in all), in the
// rasteriser's order, and adds its counters to `c`. A culled primitive draws nothing.
void rasterize_primitive(const PlaneProjection& map, const RasterSetup& r, const TechTable& tech,
                         int width, int height, RasterCounters& c, const RasterVisit& visit);

}  // namespace texsim
