#pragma once
// Exact screen→texture map of a scene plane (docs/architecture.md#reference-generator):
// u = (A x + B y + C) / (G x + H y + I), v = (D x + E y + F) / (G x + H y + I) for continuous
// pixel coordinates (x, y) (pixel centres at +0.5), evaluated in long double.
#include "pipeline/scene.h"

namespace texsim {

struct UvSample {
  double u = 0, v = 0;
  double dudx = 0, dvdx = 0, dudy = 0, dvdy = 0;  // analytic derivatives at (x, y)
  double depth = 0;       // distance along the view direction
  bool inside = false;    // on the plane's parallelogram, in front of the near plane
};

class PlaneProjection {
 public:
  PlaneProjection(const Scene& scene, const ScenePlane& plane);
  // Evaluates the map at continuous pixel coordinates (x, y).
  UvSample at(double x, double y) const;
  // Heckbert coefficients A..I of u and v (including the plane's uv scale and offset).
  long double A, B, C, D, E, F, G, H, I;

 private:
  // Plane parameters a, b (each in [0,1] on the parallelogram) share the denominator.
  long double a_[3], b_[3];  // numerators of a and b: k0 x + k1 y + k2
  long double depth_num_;    // depth = depth_num_ / (G x + H y + I)
  double near_;
};

}  // namespace texsim
