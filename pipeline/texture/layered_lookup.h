#pragma once
// Effect `lookup` of a material that samples a layered texture (docs/scenes.md): where a cube
// is looked up (the fragment's direction: the view ray reflected by the surface, or the view
// ray itself, a sky box) and which array layer (or cube of a cube array) is read.
#include <cstdint>

#include "blocks/base/config_reader.h"
#include "blocks/base/fragment.h"

namespace texsim {

struct LayeredLookup {
  enum class Direction : uint8_t { None, Reflect, View };
  Direction direction = Direction::None;  // None: an array's (u, v) from the surface
  double layer = 0;  // the array coordinate a (rounded and clamped by the unit)
  // A 3-D texture's r: a·u + b·v + c of the surface's (u, v) (a plane slicing the volume), its
  // derivatives a·∂u + b·∂v. has_r false: r = 0.
  bool has_r = false;
  double r[3] = {0, 0, 0};
  // { direction = "reflect" | "view", layer = <number>, r = [a, b, c] }; errors name
  // file:line:column.
  static LayeredLookup from_toml(const ConfigReader& r);
  // Sets f.w, f.dwdx, f.dwdy from f's (u, v) and their derivatives (with has_r).
  void apply_r(Fragment& f) const;
};

}  // namespace texsim
