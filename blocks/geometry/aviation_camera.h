#pragma once
// AviationCamera: the camera of the geometry subsystem (ПГП) given by its position and the
// aviation angles yaw ψ, pitch ϑ, roll γ (seed 003 §2.1–2.2; docs/rasterizers.md §3).
//
// Frames as in the seed: the ground (g) frame X, Y, Z with Y up and the ground plane Y = 0; the
// view (v) frame u, v, w with u the view axis through the screen centre and v, w parallel to
// the screen axes. A = Aψ·Aϑ·Aγ (rotations about Y, Z and X, eq. 2.17) takes v-components to
// g-components. The screen lies at distance u1 along u; its pixels are pixel_size wide. A pixel
// at pixel-index coordinates (xs, ys) (centre of pixel (i, j) at (i, j), i to the right, j
// down) sits at Ze = (xs + 1/2)·δ, Ye = (ys + 1/2)·δ from the screen's top-left corner, and its
// view vector is (u1, Ye0 - Ye, Ze - Ze0) in the v frame (eq. 2.34–2.35, Ye0, Ze0 the half
// sizes): v points up the screen, w to the right.
//
// The eye may sit off the vehicle's centre of gravity r0 = (x, y, z) by h, given in the v frame
// (eq. 2.16): r_h = r0 + A·h + λV (2.20–2.21); every ray and projection starts at eye().
#include <cstdint>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/geometry/projective_map.h"
#include "blocks/raster/raster_types.h"

namespace texsim {

class ConfigReader;

// A = Aψ·Aϑ·Aγ (eq. 2.17): yaw about Y, then pitch about Z, then roll about X, in degrees.
// Column j is the g-frame direction of v-axis j (u: the view axis, v: up, w: right).
glm::dmat3 aviation_rotation(double yaw_deg, double pitch_deg, double roll_deg);

class AviationCamera {
 public:
  struct Config {
    double x = 0, y = 100, z = 0;  // centre of gravity r0 = (X0, Y0, Z0), ground frame
    glm::dvec3 eye_offset{0.0};    // h = (h_u, h_v, h_w): the eye from r0, in the v frame
    double yaw_deg = 0, pitch_deg = -20, roll_deg = 0;
    double screen_distance = 256;  // u1, in the units of pixel_size
    double pixel_size = 1;         // δ (δy = δz)
    int width = 512, height = 512;
    double near = 1e-6;  // view depth below which a vertex is behind the eye
    static Config from_toml(const ConfigReader& r);
  };
  AviationCamera() : AviationCamera(Config{}) {}
  explicit AviationCamera(const Config& c);
  const Config& config() const { return cfg_; }

  // A = Aψ·Aϑ·Aγ, built with GLM; column j is the g-frame direction of v-axis j (u, v, w).
  const glm::dmat3& rotation() const { return a_; }
  // The eye (centre of projection) in the ground frame: r0 + A·h (eq. 2.16, 2.21).
  const glm::dvec3& eye() const { return eye_; }
  // The g-frame view vector of the pixel at (xs, ys): one matrix-vector multiply.
  glm::dvec3 view_vector(double xs, double ys) const;
  // The point of the ground plane Y = 0 seen at (xs, ys) (eq. 2.26–2.27): false when the ray
  // does not go down to it (horizon and sky: V_y >= 0 with the eye above the ground).
  bool ground_point(double xs, double ys, double& gx, double& gz) const;
  // The same as a projective map of pixel-index coordinates (eq. 2.39: a ratio of linear forms,
  // Heckbert's form): u = ground X, v = ground Z, q = V_y up to a factor.
  ProjectiveMap ground_map() const;
  // A g-frame point to the screen (pixel-index coordinates, w = view depth along u): false
  // when it is not in front of the eye (w < near).
  bool project(const glm::dvec3& p, ScreenVertex& out) const;

  // Item: one vertex (project): a matrix-vector multiply, one division, the screen mapping.
  OpCounts ops_per_item() const;
  OpCounts ground_point_ops() const;  // per pixel of the ground projection
  OpCounts setup_ops() const;  // sin/cos of the angles, A's products, the eye r0 + A·h (h ≠ 0)
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "geometry.aviation_camera"; }
  std::string arithmetic() const { return "double (GLM dmat3/dvec3)"; }

 private:
  Config cfg_;
  glm::dmat3 a_{1.0};
  glm::dvec3 eye_{0.0};
  double ye0_ = 0, ze0_ = 0;
};

}  // namespace texsim
