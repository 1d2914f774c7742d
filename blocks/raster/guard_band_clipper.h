#pragma once
// Guard-band clipper of the rasterisation subsystem (ПРП): the edge-function rasteriser takes
// snapped coordinates below 2^30 units of 2^-b pixel (EdgeRasterizer::kCoordBits), so a screen
// triangle reaching further (a plane running towards the eye projects to vertices millions of
// pixels away) is first clipped, in screen space, to a rectangle around the scissor well inside
// that range. Coverage inside the scissor is unchanged: the clip only cuts away pixels that no
// scissor test would keep. Arithmetic: long double for the intersections.
#include <cstdint>
#include <vector>

#include "blocks/raster/edge_rasterizer.h"
#include "blocks/raster/raster_types.h"

namespace texsim {

// Half the guard band of `subpixel_bits`, in pixels: the clip rectangle's reach from the
// scissor's corners (2^(kCoordBits − bits − 1)).
double guard_band_margin(int subpixel_bits);

// Sutherland–Hodgman clip of a convex polygon (pixel-index coordinates) to the scissor grown by
// `margin` pixels on each side. Fewer than 3 vertices out: nothing of it is near the scissor.
// A new vertex's w is interpolated linearly on the screen: right for coverage, not for
// perspective-correct attributes.
std::vector<ScreenVertex> clip_to_guard_band(const std::vector<ScreenVertex>& poly,
                                             const Scissor& sc, double margin);

// The polygon itself when every vertex lies within the guard band of `subpixel_bits` around the
// scissor (or one is not finite: the rasteriser rejects it), otherwise its clip to it.
std::vector<ScreenVertex> within_guard_band(const std::vector<ScreenVertex>& poly,
                                            const Scissor& sc, int subpixel_bits);

// The covered pixels of a convex polygon as one span per row (the union of its fan's
// triangles, each rasterised with the top-left rule, so no pixel twice and none missing on the
// fan's inner edges); clipped to the guard band first only when a vertex lies beyond it.
std::vector<RowSpan> rasterize_convex(const EdgeRasterizer& r,
                                      const std::vector<ScreenVertex>& poly, const Scissor& sc,
                                      EdgeRasterStats* stats = nullptr);

}  // namespace texsim
