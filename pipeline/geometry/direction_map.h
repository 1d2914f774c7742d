#pragma once
// The direction a cube-mapped primitive is looked up at, per pixel: the camera's view ray
// through the pixel (not normalised: forward + offsets along the image's right and down axes),
// or that ray reflected by the primitive's plane. Both are affine in the pixel coordinates,
// so the direction's screen derivatives are exact and constant over the primitive; the unit
// and the ground truth read the same map.
#include <glm/vec3.hpp>

#include "blocks/base/fragment.h"
#include "blocks/geometry/camera.h"
#include "pipeline/scene/scene.h"

namespace texsim {

struct DirectionMap {
  // direction(x, y) = origin + x·ddx + y·ddy at continuous pixel coordinates (centres at +0.5).
  glm::dvec3 origin{0, 0, 1}, ddx{0}, ddy{0};
  // The view ray through each pixel; with `reflect`, reflected by the primitive's plane.
  static DirectionMap make(const Camera& c, const ScenePrimitive& p, bool reflect);
  glm::dvec3 at(double x, double y) const { return origin + x * ddx + y * ddy; }
  // The map a fragment's direction and derivatives span (exact for a fragment apply() made:
  // the map is affine); what the truth integrates a cube fragment over.
  static DirectionMap of(const Fragment& f);
  // Sets the fragment's (u, v, w) to the direction at its pixel centre and the derivatives.
  void apply(Fragment& f) const;
};

}  // namespace texsim
