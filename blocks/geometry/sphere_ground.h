#pragma once
// SphereGround: the spherical Earth as the ground of the flight camera's ray casting (seed 003
// §2.2, example 1, eq. 2.4–2.9; docs/derivations/terrain.md §8). The sphere of radius R touches
// the ground plane Y = 0 at the origin: its centre is (0, -R, 0), n = (0, -1, 0) points from the
// origin to the centre (r1 = R·n, d = 0). The ray r_h + λV (V any length, g frame) meets it at
// the smallest λ > 0.
//
// Forms:
//  - Stable: the quadratic λ²(V·V) + 2λ(o·V) + c = 0, o = r_h - r1, with the constant term
//    c = |o|² - R² computed as X_h² + Z_h² + Y_h(Y_h + 2R) (no difference of R-sized squares)
//    and the near root as c / (-b + √(b² - a·c)) (no cancellation between -b and the root);
//  - Textbook: the same quadratic with c = |o|² - R² and λ = (-b - √disc)/a as usually
//    printed: in float the two R² cancel (R = 6.371e6 m: ulp(R²) ≈ 4.4e6 m²);
//  - SeedIteration: eq. 2.8 read as a fixed point: λ = -(n·r_h - dc)/(n·V) with
//    dc = R(1 - cos α) of the current point (λ₀ from dc = 0, the flat ground), evaluated as
//    R·ρ²/(|q|(|q| + q_y)) (q = P - r1, ρ² = P_x² + P_z²), until λ changes by less than
//    `tolerance` (relative) or `max_iterations`. Its fixed points are the sphere's points and,
//    for a ray that misses, the spurious one where the ray crosses Y = -R (rejected).
#include <cmath>
#include <cstdint>
#include <glm/vec3.hpp>
#include <string>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"

namespace texsim {

class ConfigReader;

class SphereGround {
 public:
  enum class Form { Stable, Textbook, SeedIteration };
  struct Config {
    double radius = 6371000.0;  // R, in the scene's units (metres: the mean Earth radius)
    Form form = Form::Stable;
    int32_t max_iterations = 64;  // SeedIteration
    double tolerance = 1e-12;     // SeedIteration: stop when |Δλ| <= tolerance·λ
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };
  struct Hit {
    bool hit = false;
    double lambda = 0;       // ray parameter (in units of V)
    int32_t iterations = 0;  // SeedIteration: the evaluations of eq. 2.8
  };

  SphereGround() = default;
  explicit SphereGround(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // The nearest intersection with λ > 0 in the number format T (float, double, long double):
  // every operation rounds to T. No hit for a ray that misses or grazes outside the sphere,
  // goes up and away, starts inside or on it, or has non-finite inputs.
  template <class T>
  Hit intersect(const glm::dvec3& eye, const glm::dvec3& dir) const;

  // Item: one ray (one pixel), without the view vector (the camera's) and the point r_h + λV.
  OpCounts ops_per_item() const;  // SeedIteration: per iteration
  OpCounts critical_path() const;
  OpCounts setup_ops() const;  // per frame: the eye's terms
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "geometry.sphere_ground"; }
  std::string arithmetic() const { return "float/double/long double (the caller's T)"; }

 private:
  template <class T>
  Hit seed_iteration(T ex, T ey, T ez, T vx, T vy, T vz) const;
  Config cfg_{};
};

template <class T>
SphereGround::Hit SphereGround::intersect(const glm::dvec3& eye, const glm::dvec3& dir) const {
  Hit h;
  const T ex = static_cast<T>(eye.x), ey = static_cast<T>(eye.y), ez = static_cast<T>(eye.z);
  const T vx = static_cast<T>(dir.x), vy = static_cast<T>(dir.y), vz = static_cast<T>(dir.z);
  const T r = static_cast<T>(cfg_.radius);
  for (T v : {ex, ey, ez, vx, vy, vz, r}) {
    if (!std::isfinite(v)) return h;
  }
  if (cfg_.form == Form::SeedIteration) return seed_iteration<T>(ex, ey, ez, vx, vy, vz);
  const T oy = ey + r;  // o = r_h - r1, r1 = (0, -R, 0)
  const T a = vx * vx + vy * vy + vz * vz;
  const T b = ex * vx + oy * vy + ez * vz;  // o·V
  const T c = cfg_.form == Form::Stable ? ex * ex + ez * ez + ey * (ey + 2 * r)
                                        : ex * ex + oy * oy + ez * ez - r * r;
  if (!(c > 0) || !(b < 0) || !(a > 0)) return h;  // inside or on it; going away; V = 0
  const T disc = b * b - a * c;
  if (!(disc >= 0)) return h;  // misses
  const T root = std::sqrt(disc);
  h.lambda = static_cast<double>(cfg_.form == Form::Stable ? c / (root - b) : (-b - root) / a);
  h.hit = std::isfinite(h.lambda) && h.lambda > 0;
  return h;
}

template <class T>
SphereGround::Hit SphereGround::seed_iteration(T ex, T ey, T ez, T vx, T vy, T vz) const {
  Hit h;
  const T r = static_cast<T>(cfg_.radius);
  // n = (0, -1, 0): n·r_h = -Y_h, n·V = -V_y; eq. 2.8: λ = (Y_h + dc) / -V_y.
  if (!(vy < 0) || !(ey > 0)) return h;
  const T inv = static_cast<T>(1) / -vy;
  T lambda = ey * inv;  // dc = 0: the flat ground (eq. 2.14)
  T q = 0, qy = 0;      // |P - r1| and its Y component at the last point
  for (h.iterations = 1; h.iterations < cfg_.max_iterations; ++h.iterations) {
    const T px = ex + lambda * vx, py = ey + lambda * vy, pz = ez + lambda * vz;
    const T rho2 = px * px + pz * pz;
    qy = py + r;
    q = std::sqrt(rho2 + qy * qy);
    const T dc = r * rho2 / (q * (q + qy));  // R(1 - cos α), cos α = q_y/|q|
    const T next = (ey + dc) * inv;
    const bool done = std::fabs(next - lambda) <= static_cast<T>(cfg_.tolerance) * next;
    lambda = next;
    if (done || !std::isfinite(lambda)) break;
  }
  // Not converged: the ray grazes (the iteration crawls) or runs off. A ray that misses
  // converges too, to the spurious root of eq. 2.8 where it crosses the centre's plane
  // Y = -R (q_y = 0 also solves dc(P) = -P_y, with |q| > R): a hit needs |q| = R.
  if (h.iterations >= cfg_.max_iterations || !std::isfinite(lambda)) return h;
  if (!(qy > 0) || !(std::fabs(q - r) <= static_cast<T>(1e-6) * r)) return h;
  h.lambda = static_cast<double>(lambda);
  h.hit = h.lambda > 0;
  return h;
}

}  // namespace texsim
