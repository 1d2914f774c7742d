#pragma once
// Row rasteriser of the rasterisation subsystem (ПРП): the pixels a screen triangle covers
// (centre inside, edges inclusive) as raster rows, in long double edge arithmetic.
#include <cstdint>
#include <vector>

#include "blocks/raster/raster_types.h"

namespace texsim {

// Pixels of the triangle (x[i], y[i]) covered within [0,w)×[0,h), as rows; none when the
// triangle is degenerate or not finite.
std::vector<RowSpan> rasterize_rows(const double x[3], const double y[3], int32_t w, int32_t h);

}  // namespace texsim
