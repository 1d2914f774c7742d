#pragma once
// VertexTransform: the per-vertex datapath of the geometry subsystem (ПГП): model-view-projection
// with GLM (one 4×4 matrix-vector multiply; the model transform is folded into the mesh's
// vertices when the scene is read), the perspective division, the viewport to pixel-index
// coordinates (centre of pixel i at x = i), and per triangle the back-face test on the sign of
// the screen-space area. Perspective (glm::perspective) or orthographic (glm::ortho) camera.
// Arithmetic: double (GLM dmat4/dvec4).
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <string>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/geometry/camera.h"
#include "blocks/raster/raster_types.h"

namespace texsim {

class ConfigReader;

class VertexTransform {
 public:
  struct Config {
    int lanes = 1;  // vertices transformed in parallel
    static Config from_toml(const ConfigReader& r);
  };
  explicit VertexTransform(const Camera& cam) : VertexTransform(cam, Config{}) {}
  VertexTransform(const Camera& cam, const Config& c);

  const glm::dmat4& mvp() const { return mvp_; }
  // Clip-space position: MVP · (p, 1).
  glm::dvec4 clip(const glm::dvec3& world) const { return mvp_ * glm::dvec4(world, 1.0); }
  // The screen vertex of a clip-space position (w: the view depth; orthographic: w = 1 and z
  // the view depth); false when it is nearer than the near plane (clip first) or not finite.
  bool to_screen(const glm::dvec4& clip, ScreenVertex& out) const;
  // Twice the signed area of a screen triangle: > 0 when it is counter-clockwise in the
  // world-space sense (clockwise on the screen with y down), i.e. its front faces the camera.
  static double front_area(const ScreenVertex v[3]);

  // Item: one vertex: 16 mul 12 add (matrix-vector), 1 rcp 2 mul (perspective division of x,
  // y), 2 mul 2 add (viewport), 1 cmp (near test).
  OpCounts ops_per_item() const;
  OpCounts triangle_ops() const;  // back-face test: 2 mul 5 add 1 cmp
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "geometry.vertex_transform"; }
  std::string arithmetic() const { return "double (GLM dmat4/dvec4)"; }

 private:
  Config cfg_;
  glm::dmat4 mvp_{1.0};
  bool orthographic_ = false;
  double near_ = 0, width_ = 0, height_ = 0;
};

}  // namespace texsim
