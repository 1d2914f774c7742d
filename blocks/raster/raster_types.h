#pragma once
// Types shared by the rasterisers of the rasterisation subsystem (ПРП): screen vertices, the
// viewport scissor and the row spans they produce (docs/rasterizers.md).
#include <cstdint>

namespace texsim {

// Pixels x0 .. x0+n-1 of raster row y.
struct RowSpan {
  int32_t x0 = 0;
  int32_t y = 0;
  int32_t n = 0;
};

// A screen vertex in pixel-index coordinates (the centre of pixel i is at x = i, as
// project_to_pixel gives it) with the clip-space w of the vertex for perspective-correct
// attribute interpolation (w > 0 in front of the eye).
struct ScreenVertex {
  double x = 0, y = 0, w = 1;
};

// Viewport scissor: pixels [x0, x1) × [y0, y1).
struct Scissor {
  int32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

}  // namespace texsim
