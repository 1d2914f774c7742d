#pragma once
// One fragment record of a texture trace (traces/FORMAT.md). Coordinates are normalised
// texture coordinates (1.0 = one texture width) and their screen-space derivatives, in double
// so that reference traces carry the exact values; blocks convert to their own number formats.
#include <cstdint>

namespace texsim {

struct Fragment {
  uint32_t frame = 0;
  uint32_t prim = 0;  // primitive id
  uint32_t x = 0;     // pixel column
  uint32_t y = 0;     // pixel row
  uint32_t tex = 0;   // texture id (index into the trace's texture table)
  double u = 0, v = 0;
  double dudx = 0, dvdx = 0, dudy = 0, dvdy = 0;
  float lod_bias = 0;  // optional field; 0 when absent
  // Optional (trace version 2): the unit tangent-space vector towards the eye (x along +u, y
  // along +v, z out of the surface) that relief uses; all 0 when absent.
  float view_x = 0, view_y = 0, view_z = 0;
  bool has_view() const { return view_x != 0 || view_y != 0 || view_z != 0; }
};

}  // namespace texsim
