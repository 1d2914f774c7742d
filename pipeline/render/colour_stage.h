#pragma once
// The fixed-function colour stage of a replayed OpenGL frame (traces/DRAWS.md): texture
// environment, alpha test and blending. It sits after the texture unit and is not part of it:
// texsim models no cost for it (no cycles, operations or area); it exists so that a replayed
// frame can be compared with the application's own image. Arithmetic: float32 on [0, 1]
// (OpenGL's fixed-function equations, each result clamped to [0, 1]); the framebuffer is RGBA8,
// written rounded to nearest.
#include <cmath>
#include <cstdint>
#include <string>

#include "blocks/texture/memory/texture_memory.h"
#include "traces/draw_trace.h"

namespace texsim {

namespace gl {
inline constexpr uint32_t kModulate = 0x2100, kDecal = 0x2101, kBlend = 0x0BE2, kReplace = 0x1E01,
                          kAdd = 0x0104, kCombine = 0x8570;
inline constexpr uint32_t kNever = 0x0200, kLess = 0x0201, kEqual = 0x0202, kLequal = 0x0203,
                          kGreater = 0x0204, kNotequal = 0x0205, kGequal = 0x0206, kAlways = 0x0207;
inline constexpr uint32_t kFront = 0x0404, kBack = 0x0405, kFrontAndBack = 0x0408;
inline constexpr uint32_t kCw = 0x0900, kCcw = 0x0901;
}  // namespace gl

// The part of a draw's state the colour stage cannot reproduce, or "" when it can. A draw with
// such state is left out of the frame and counted under this reason (never guessed):
// texture environment BLEND (its constant colour is not in the trace) and COMBINE.
std::string colour_stage_unsupported(const Draw& d);

// Texture environment of one unit: the colour before it (`in`: the vertex colour for unit 0,
// the previous unit's result for unit 1) and the texel `tex` (OpenGL 1.3 table 3.23 for an
// RGBA texture: MODULATE, REPLACE, DECAL, ADD).
Rgba texture_env(uint32_t mode, const Rgba& in, const Rgba& tex);

// OpenGL comparison `func` (NEVER .. ALWAYS) of a against b: alpha and depth tests.
template <class T>
bool gl_compare(uint32_t func, T a, T b) {
  switch (func) {
    case gl::kNever:
      return false;
    case gl::kLess:
      return a < b;
    case gl::kEqual:
      return a == b;
    case gl::kLequal:
      return a <= b;
    case gl::kGreater:
      return a > b;
    case gl::kNotequal:
      return a != b;
    case gl::kGequal:
      return a >= b;
    default:
      return true;  // ALWAYS (the reader accepts no other value)
  }
}

// Source colour `src` blended over the framebuffer's `dst` with factors sf, df (OpenGL blend
// factor enums), clamped to [0, 1].
Rgba blend(uint32_t sf, uint32_t df, const Rgba& src, const Rgba& dst);

// A [0, 1] channel as RGBA8: round to nearest (clamped first).
inline uint8_t to_unorm8(float c) {
  const float k = c <= 0 ? 0 : (c >= 1 ? 1 : c);
  // floor of the float sum, not lround(x): the two differ where the sum rounds up to a whole.
  return static_cast<uint8_t>(std::floor(k * 255.0f + 0.5f));
}

}  // namespace texsim
