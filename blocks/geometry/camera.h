#pragma once
// The pinhole camera of scenes, of the plane projection and of the coordinate front end.
// Pose in world space: at `position`, looking at `look_at`, `up` pointing up the screen. View
// space: the camera at the origin looking along +Z, X to the right and Y down the screen.
// Imaging: a width × height image with the principal point at its centre and a vertical field
// of view of 2·atan(tan_half_fov_y): a view-space point (X, Y, Z) appears at screen coordinates
// xs = cx + f·X/Z, ys = cy + f·Y/Z, f = focal_px(); pixel (i, j) has its centre at
// xs = i + 0.5, ys = j + 0.5. Nothing nearer than `near` (view depth) is seen.
// Orthographic: parallel view rays along the view direction; the image spans
// 2·ortho_half_height world units vertically (xs = cx + f·X, ys = cy + f·Y, f = height / 2 /
// ortho_half_height), and depth is still the view-space Z.
#include <glm/vec3.hpp>

namespace texsim {

struct Camera {
  glm::dvec3 position{0, 1, 0};
  glm::dvec3 look_at{0, 0, -10};
  glm::dvec3 up{0, 1, 0};
  long double tan_half_fov_y = 0.57735026918962576450914878050195746L;  // 60°
  double near = 0.01;
  int width = 320, height = 240;
  bool orthographic = false;
  long double ortho_half_height = 1;

  // Pixels per unit of X/Z (perspective) or per world unit (orthographic).
  long double focal_px() const {
    return height / 2.0L / (orthographic ? ortho_half_height : tan_half_fov_y);
  }
  long double cx() const { return width / 2.0L; }
  long double cy() const { return height / 2.0L; }
};

// A width × width camera with a 90° field of view (f = width / 2).
inline Camera square_camera(int width) {
  Camera c;
  c.width = c.height = width;
  c.tan_half_fov_y = 1;
  return c;
}

}  // namespace texsim
