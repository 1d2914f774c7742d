#pragma once
// The memory limit of the scene's inputs that a run builds before its own estimate can be
// made (mesh faces and their projections, DEM height fields): `texsim run` sets it from
// --max-memory before it loads the scene, so a mesh or DEM over the limit is refused before
// it is allocated. Unlimited unless set. Saturating arithmetic for the estimates.
#include <cstdint>

namespace texsim {

void set_scene_memory_limit(uint64_t bytes);
uint64_t scene_memory_limit();

inline uint64_t sat_mul(uint64_t a, uint64_t b) {
  uint64_t r = 0;
  return __builtin_mul_overflow(a, b, &r) ? UINT64_MAX : r;
}
inline uint64_t sat_add(uint64_t a, uint64_t b) { return a > UINT64_MAX - b ? UINT64_MAX : a + b; }

}  // namespace texsim
