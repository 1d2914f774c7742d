#pragma once
// One fragment record of a texture trace (traces/FORMAT.md). Coordinates are normalised
// texture coordinates (1.0 = one texture width) and their screen-space derivatives, in double
// so that reference traces carry the exact values; blocks convert to their own number formats.
#include <cstdint>

namespace texsim {

struct Fragment {
  // Fields ordered so that the record packs into 128 bytes with no padding before the
  // doubles (two host cache lines); the trace format's field order is its own.
  uint32_t frame = 0;
  uint32_t prim = 0;   // primitive id
  uint32_t x = 0;      // pixel column
  uint32_t y = 0;      // pixel row
  uint32_t tex = 0;    // texture id (index into the trace's texture table)
  float lod_bias = 0;  // optional field; 0 when absent
  double u = 0, v = 0;
  double dudx = 0, dvdx = 0, dudy = 0, dvdy = 0;
  // Optional (trace version 2): the unit tangent-space vector towards the eye (x along +u, y
  // along +v, z out of the surface) that relief uses; all 0 when absent.
  float view_x = 0, view_y = 0, view_z = 0;
  bool has_view() const { return view_x != 0 || view_y != 0 || view_z != 0; }
  // Optional (trace version 4); the defaults leave an implicit-LOD 2-D sample unchanged.
  float layer = 0;                   // array layer, rounded and clamped by the unit
  double w = 0, dwdx = 0, dwdy = 0;  // third coordinate: 3-D r, or a cube direction's z
  float lod = 0;                     // explicit LOD for SampleOp::kSampleLod
  float compare_ref = 0;             // depth-comparison reference
  uint8_t op = 0;                    // SampleOp (blocks/base/sample_op.h)
  uint8_t gather_component = 0;      // 0..3 = r, g, b, a for SampleOp::kGather
  uint16_t sampler = 0;              // sampler-table index; 0 = the material's own sampler
  int8_t offset_u = 0, offset_v = 0, offset_w = 0;  // constant texel offsets
};
static_assert(sizeof(Fragment) == 128, "Fragment packs into two 64-byte lines");

}  // namespace texsim
