#pragma once
// The shading frame of a scene primitive, for the relief and lighting effects
// (docs/scenes.md#relief-and-lighting): the world directions in which the texture's u and v grow
// (tangent T, bitangent B, both unit, B made orthogonal to T), the unit normal N on the side the
// camera sees, the world length of one unit of u and of v, and the camera, so that the unit
// vector from a pixel's surface point towards the eye can be found for any pixel.
// Arithmetic: double.
#include <glm/vec3.hpp>

#include "blocks/geometry/camera.h"
#include "pipeline/scene/scene.h"

namespace texsim {

class SurfaceFrame {
 public:
  SurfaceFrame(const Scene& scene, const ScenePrimitive& prim);
  const glm::dvec3& tangent() const { return t_; }
  const glm::dvec3& bitangent() const { return b_; }
  const glm::dvec3& normal() const { return n_; }
  // World length of a unit step of u (and of v) on the plane.
  double u_length() const { return u_len_; }
  double v_length() const { return v_len_; }
  // Zero-area plane or texture map: no usable frame (the effects fall back to N = view).
  bool degenerate() const { return degenerate_; }
  // Unit world vector from the surface point seen at continuous pixel (x, y) towards the eye
  // (orthographic: the reverse view direction everywhere).
  glm::dvec3 view(double x, double y) const;
  // A world vector in the frame (x along T, y along B, z along N).
  glm::dvec3 to_tangent(const glm::dvec3& w) const;

 private:
  glm::dvec3 t_{1, 0, 0}, b_{0, 1, 0}, n_{0, 0, 1};
  double u_len_ = 1, v_len_ = 1;
  bool degenerate_ = false;
  // Camera: forward, right and down-the-screen unit vectors, focal length and centre.
  glm::dvec3 fwd_{0, 0, 1}, right_{1, 0, 0}, down_{0, 1, 0};
  double focal_ = 1, cx_ = 0, cy_ = 0;
  bool ortho_ = false;
};

}  // namespace texsim
