#pragma once
// Effect `lookup` of a material that samples a layered texture (docs/scenes.md): where a cube
// is looked up (the fragment's direction: the view ray reflected by the surface, or the view
// ray itself, a sky box) and which array layer (or cube of a cube array) is read.
#include <cstdint>

#include "blocks/base/config_reader.h"

namespace texsim {

struct LayeredLookup {
  enum class Direction : uint8_t { None, Reflect, View };
  Direction direction = Direction::None;  // None: an array's (u, v) from the surface
  double layer = 0;  // the array coordinate a (rounded and clamped by the unit)
  // { direction = "reflect" | "view", layer = <number> }; errors name file:line:column.
  static LayeredLookup from_toml(const ConfigReader& r);
};

}  // namespace texsim
