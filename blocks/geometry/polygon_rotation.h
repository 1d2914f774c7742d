#pragma once
// PolygonRotation: the rotation block of object-space texturing (docs/derivations/object-space.md
// §1): the polygon's unit normal, the sines and cosines of the two rotations that turn it
// parallel to the screen (about x by α, then about y by β) without trigonometric calls, the
// rotated vertices (x', y' for every vertex, z' for one: all are equal after the rotation) and
// the inverse rotation. Camera view space (X right, Y down, Z forward); the normal is oriented
// so that Nz >= 0 before the rotation (the plane is the same either way), so a polygon already
// parallel to the screen gets the identity and no rotation exceeds 90° about x.
//   d = √(Ny² + Nz²)   (the seed prints a minus: erratum)
//   cos α = Nz/d, sin α = Ny/d;  cos β = d, sin β = Nx
//   x' = x cos β − z cos α sin β − y sin α sin β,  y' = y cos α − z sin α,
//   z' = x sin β + (y sin α + z cos α) cos β
// Fallbacks: zero normal (collinear vertices): Degenerate, no rotation; d = 0 (Ny = Nz = 0, the
// seed's formulas divide by d): α = 0 (cos α = 1, sin α = 0), β = ±90°; already parallel (Nx =
// Ny = 0): the exact identity. Arithmetic: double.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"

namespace texsim {

class ConfigReader;

enum class RotationCase : uint8_t {
  General,     // d > 0 and not parallel: the seed's formulas
  Identity,    // already parallel to the screen (Nx = Ny = 0)
  DZero,       // Ny = Nz = 0: α = 0, β = ±90°
  Degenerate,  // zero normal: no plane, nothing to rotate
};
const char* rotation_case_name(RotationCase c);

struct Rotation {
  double cos_a = 1, sin_a = 0, cos_b = 1, sin_b = 0;
  glm::dvec3 normal{0, 0, 1};  // unit, oriented Nz >= 0
  RotationCase kind = RotationCase::Identity;
  bool flipped = false;  // the winding's normal had Nz < 0 (faces the eye from in front)
};

// A polygon after the rotation: its vertices in the plane z' = z (one depth for all).
struct RotatedPolygon {
  std::vector<glm::dvec2> xy;
  double z = 0;
};

class PolygonRotation {
 public:
  struct Config {
    int lanes = 1;  // vertices rotated in parallel
    static Config from_toml(const ConfigReader& r);
  };
  PolygonRotation() = default;
  explicit PolygonRotation(const Config& c) : cfg_(c) {}

  // Unit normal (B − A) × (C − A) / |…| of three vertices (zero vector if they are collinear):
  // 6 mul 3 add (cross) + 6 add (edges) + 3 mul 2 add (length²) + 1 sqrt 1 rcp 3 mul.
  static glm::dvec3 unit_normal(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                                OpCounts& ops);
  // Sines and cosines from a unit normal: 2 mul 1 add 1 sqrt (d), 1 rcp 2 mul, 3 cmp.
  static Rotation setup(glm::dvec3 n, OpCounts& ops);
  // Rotated x', y' of a point (the item of this block): 6 mul 3 add.
  static glm::dvec2 rotate_xy(const Rotation& r, const glm::dvec3& p, OpCounts& ops);
  // z' of one point: 3 mul 2 add.
  static double rotate_z(const Rotation& r, const glm::dvec3& p, OpCounts& ops);
  // Every vertex (x', y') and z' of vertex 0 only.
  static RotatedPolygon rotate_polygon(const Rotation& r, const std::vector<glm::dvec3>& v,
                                       OpCounts& ops);
  // The inverse rotation R⁻¹ = R_x⁻¹ R_y⁻¹ of a point (x', y', z'): 8 mul 4 add.
  static glm::dvec3 inverse(const Rotation& r, const glm::dvec3& p, OpCounts& ops);

  // Item: one vertex rotated (x', y').
  OpCounts ops_per_item() const;
  // Per polygon: normal, sines and cosines, z' of one vertex.
  OpCounts polygon_ops() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "geometry.polygon_rotation"; }
  std::string arithmetic() const { return "double"; }

 private:
  Config cfg_{};
};

}  // namespace texsim
