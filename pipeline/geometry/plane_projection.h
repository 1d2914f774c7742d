#pragma once
// Exact screen→texture map of a scene primitive (a parallelogram or a triangle)
// (docs/architecture.md#reference-generator): the plane's ProjectiveMap u = (A x + B y + C) / (G x
// + H y + I), v = (D x + E y + F) / (G x + H y
// + I) for continuous pixel coordinates (x, y) (pixel centres at +0.5) and the plane's texture
// coordinates (uv scale and offset included), evaluated in long double.
#include <glm/vec2.hpp>
#include <vector>

#include "blocks/base/fragment.h"
#include "blocks/geometry/projective_map.h"
#include "pipeline/scene/scene.h"

namespace texsim {

struct UvSample {
  double u = 0, v = 0;
  double dudx = 0, dvdx = 0, dudy = 0, dvdy = 0;  // analytic derivatives at (x, y)
  double depth = 0;                               // distance along the view direction
  bool inside = false;  // on the plane's parallelogram, in front of the near plane

  // A fragment of pixel (x, y) with these coordinates and derivatives.
  Fragment fragment(uint32_t x, uint32_t y) const {
    Fragment f;
    f.x = x;
    f.y = y;
    f.u = u;
    f.v = v;
    f.dudx = dudx;
    f.dvdx = dvdx;
    f.dudy = dudy;
    f.dvdy = dvdy;
    return f;
  }
};

// The map (its coefficients A..I are the ProjectiveMap's), and where on it the plane lies.
class PlaneProjection : public ProjectiveMap {
 public:
  PlaneProjection(const Scene& scene, const ScenePrimitive& plane);
  // The camera sees the side edge_v × edge_u points to (the primitive's back).
  bool back_facing() const { return back_facing_; }
  // Zero area (parallel or zero edges): no pixel is on it.
  bool degenerate() const { return degenerate_; }
  // Not drawn: degenerate, or back-facing with back-face culling on.
  bool culled() const { return degenerate_ || (cull_back_ && back_facing_); }
  // Evaluates the map at continuous pixel coordinates (x, y).
  UvSample at(double x, double y) const;

  // The plane's parallelogram clipped to the near plane and projected to pixel-index
  // coordinates (centre of pixel i at x = i, the coordinate blocks' convention); empty when
  // nothing of it is in front of the near plane.
  std::vector<glm::dvec2> screen_polygon() const;
  // The same map as a ProjectiveMap in pixel-index coordinates and texels of a tw x th
  // texture, with q = G x + H y + I > 0 in front of the camera.
  ProjectiveMap texel_map(int tw, int th) const;

 private:
  // Plane parameters a, b (each in [0,1] on the parallelogram) share the denominator.
  long double a_[3], b_[3];   // numerators of a and b: k0 x + k1 y + k2
  long double depth_num_[3];  // depth = (d0 x + d1 y + d2) / (G x + H y + I)
  double near_;
  // Camera frame and the plane's corners, for screen_polygon().
  long double cam_[3], right_[3], up_[3], fwd_[3];
  long double tan_half_, aspect_;
  int width_, height_;
  bool orthographic_ = false, triangle_ = false, degenerate_ = false, back_facing_ = false;
  bool cull_back_ = false;
  long double corner_[4][3];  // a triangle uses the first three
};

// The primitive's exact fragments over the pixels [0, width) × [0, height), row by row: every
// pixel whose centre it covers, with (u, v) and the analytic derivatives there (no depth test).
std::vector<Fragment> pixel_fragments(const PlaneProjection& proj, int width, int height);

}  // namespace texsim
