#pragma once
// Cube map face selector: the major axis of a direction (u, v, w) = (rx, ry, rz), the face's
// coordinates (s, t) and their screen derivatives (Vulkan "Cube Map Face Selection", "Cube Map
// Coordinate Transformation", "Cube Map Derivative Transformation"; docs/texture-types.md §1).
// Arithmetic: float32. Ties: Vulkan leaves the face of a direction whose largest magnitudes are
// equal to the implementation, provided the choice is deterministic; the selector takes Z over
// Y over X (the rule Direct3D fixes), so an edge or corner direction always gives one face.
#include <array>
#include <cstdint>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"

namespace texsim {

// Faces in Vulkan's layer order.
enum class CubeFace : uint8_t { PosX, NegX, PosY, NegY, PosZ, NegZ };
inline constexpr int kCubeFaces = 6;

// A face's axes as integer vectors: the major axis m (the outward normal), and the axes whose
// components are sc and tc (Vulkan's table): s = ½·sc/|rc| + ½, t = ½·tc/|rc| + ½.
struct CubeFaceAxes {
  std::array<int, 3> m, s, t;
};
const CubeFaceAxes& cube_face_axes(int face);

struct CubeFaceCoord {
  int face = 0;
  float s = 0.5f, t = 0.5f;  // in [0, 1]
  float rc = 0;              // |rc|, the major component's magnitude (0: a zero direction)
  float sc = 0, tc = 0;      // the signed components along the face's s and t axes
};
struct CubeFaceDerivs {
  float dsdx = 0, dtdx = 0, dsdy = 0, dtdy = 0;
};

class CubeFaceSelect {
 public:
  // Non-finite components are taken as 0; a zero direction selects +Z (the tie rule on
  // (0, 0, +0)) at the face's centre. The sign of a ±0 major component is its sign bit.
  static CubeFaceCoord select(float rx, float ry, float rz);
  // The derivatives of (s, t) from those of the direction along screen x and y:
  // ∂s/∂x = ½·(∂sc/∂x − (sc/|rc|)·∂|rc|/∂x)/|rc|, likewise t and y, with ∂|rc| = sign(rc)·∂rc.
  // Zero for a zero direction; non-finite inputs are taken as 0.
  static CubeFaceDerivs derivatives(const CubeFaceCoord& c, const float ddx[3], const float ddy[3]);
  // Operations of one fragment (selection, coordinates and four derivatives).
  static OpCounts ops_per_item();
  // Latency of the path |r| compare → select → 1/|rc| → × → ± (one fragment per cycle).
  static TimingSpec timing(const TechTable& tech);
  static std::string name() { return "cube.face_select"; }
  static std::string arithmetic() { return "float32"; }
};

}  // namespace texsim
