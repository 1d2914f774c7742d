#pragma once
// PlaneGround: the piecewise-planar ground of the flight camera's ray casting (seed 003 §2.2,
// example 2, eq. 2.10–2.12; docs/derivations/terrain.md §8). Each element is a plane n·r = d
// (n a unit normal, g frame) bounded to the rectangle [x0, x1] × [z0, z1] of the ground's
// X, Z; the ray r_h + λV meets it at λ = -(n·r_h - d)/(n·V) = F/G (eq. 2.11, 2.15). The surface's
// point is the hit with the smallest λ > 0 over the elements whose hit lies in their rectangle.
// F depends only on the eye (once per frame and element); per pixel each element costs G = n·V,
// one division and the rectangle test. No element list: the one unbounded plane Y = 0 (2.14).
#include <cmath>
#include <cstdint>
#include <glm/vec3.hpp>
#include <limits>
#include <string>
#include <vector>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"

namespace texsim {

class ConfigReader;

class PlaneGround {
 public:
  struct Element {
    glm::dvec3 n{0, 1, 0};  // unit normal (normalised by from_toml)
    double d = 0;           // n·r = d
    double x0 = -std::numeric_limits<double>::infinity(),
           x1 = std::numeric_limits<double>::infinity();
    double z0 = -std::numeric_limits<double>::infinity(),
           z1 = std::numeric_limits<double>::infinity();
  };
  struct Config {
    std::vector<Element> elements{Element{}};
    Datapath datapath = Datapath::Spatial;
    // `elements = [{ normal = [nx, ny, nz], d = ..., x = [x0, x1], z = [z0, z1] }, ...]`.
    static Config from_toml(const ConfigReader& r);
  };
  struct Hit {
    bool hit = false;
    double lambda = 0;
    int32_t element = -1;
  };

  PlaneGround() = default;
  explicit PlaneGround(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // The nearest element hit with λ > 0 in the number format T (every operation rounds to T).
  // A ray parallel to a plane (G = 0), starting on it (F = 0) or with non-finite inputs misses
  // that element.
  template <class T>
  Hit intersect(const glm::dvec3& eye, const glm::dvec3& dir) const;

  // Item: one ray against one element (G, λ = F/G, the point's X, Z, the rectangle test, the
  // nearest-hit select).
  OpCounts ops_per_item() const;
  OpCounts critical_path() const;
  OpCounts setup_ops() const;  // per frame and element: F = d - n·r_h
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "geometry.plane_ground"; }
  std::string arithmetic() const { return "float/double/long double (the caller's T)"; }

 private:
  Config cfg_{};
};

template <class T>
PlaneGround::Hit PlaneGround::intersect(const glm::dvec3& eye, const glm::dvec3& dir) const {
  Hit h;
  const T ex = static_cast<T>(eye.x), ey = static_cast<T>(eye.y), ez = static_cast<T>(eye.z);
  const T vx = static_cast<T>(dir.x), vy = static_cast<T>(dir.y), vz = static_cast<T>(dir.z);
  for (T v : {ex, ey, ez, vx, vy, vz}) {
    if (!std::isfinite(v)) return h;
  }
  T best = std::numeric_limits<T>::infinity();
  for (size_t i = 0; i < cfg_.elements.size(); ++i) {
    const Element& e = cfg_.elements[i];
    const T nx = static_cast<T>(e.n.x), ny = static_cast<T>(e.n.y), nz = static_cast<T>(e.n.z);
    const T f = static_cast<T>(e.d) - (nx * ex + ny * ey + nz * ez);  // F = -(n·r_h - d)
    const T g = nx * vx + ny * vy + nz * vz;                          // G = n·V
    const T lambda = f / g;  // eq. 2.11; G = 0 gives ±inf or NaN, rejected below
    if (!(lambda > 0) || !std::isfinite(lambda) || !(lambda < best)) continue;
    const T px = ex + lambda * vx, pz = ez + lambda * vz;
    if (!(px >= static_cast<T>(e.x0) && px <= static_cast<T>(e.x1) && pz >= static_cast<T>(e.z0) &&
          pz <= static_cast<T>(e.z1))) {
      continue;
    }
    best = lambda;
    h = {true, static_cast<double>(lambda), static_cast<int32_t>(i)};
  }
  return h;
}

}  // namespace texsim
