#pragma once
// Seamless cube filtering's edge unit: a texel one step outside a face, taken from the
// neighbouring face (Vulkan "Cube Map Edge Handling"; docs/texture-types.md §2). Across an edge
// the texel is the neighbour's texel that touches the edge at the same place along it; beyond a
// corner (outside both edges) the spec leaves the texel to the implementation, and this unit
// returns the three texels that meet at the cube's corner, to be averaged. The mapping is a
// fold of the integer texel-centre vector over the cube's edge, exact in integers: it equals a
// table of 24 (face, edge) → (face, orientation) entries in hardware.
#include <array>
#include <cstdint>

namespace texsim {

struct CubeTexel {
  int face = 0;
  int x = 0, y = 0;
};

class CubeSeam {
 public:
  // Texel (x, y) of `face` on a level of n × n texels, x and y in [−1, n]: writes the texel(s) it
  // stands for to `out` and returns their number (1 inside the face or across an edge, 3 at a
  // corner). Coordinates further out are clamped to that range first.
  static int resolve(int face, int x, int y, int n, std::array<CubeTexel, 3>& out);
  // The neighbouring face across the edge of `face` in direction (dx, dy) (one of ±1, 0).
  static int neighbour(int face, int dx, int dy);
};

}  // namespace texsim
