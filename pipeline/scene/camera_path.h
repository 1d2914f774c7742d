#pragma once
// Camera paths ([camera] path, docs/scenes.md): keyframes of position and orientation (a
// look-at point and up, or aviation angles) at increasing times t; with [output] frames = N the
// scene is rendered N times, frame k at t_k = t_first + k/(N-1)·(t_last - t_first). Between two
// keys the position and the distance to the look-at point are linear in t and the orientation
// (the view axis and up, as a rotation) is slerped, so the camera turns at a constant rate and
// never through a degenerate frame.
#include <glm/vec3.hpp>
#include <vector>

#include "blocks/geometry/camera.h"

namespace texsim {

class ConfigReader;

struct CameraKey {
  double t = 0;
  glm::dvec3 position{0}, look_at{0, 0, -1}, up{0, 1, 0};
};

// Reads `path` of the [camera] table `cam` (an array of inline tables); throws InputError
// naming file:line:column of a bad key. Empty when the table has no path.
std::vector<CameraKey> read_camera_path(const ConfigReader& cam);

// `base` (its imaging: field of view, size, near) posed at time t of the path (clamped to its
// first and last keys).
Camera camera_at(const Camera& base, const std::vector<CameraKey>& path, double t);

// The time of frame k of `frames` along the path.
double frame_time(const std::vector<CameraKey>& path, int frames, int k);

}  // namespace texsim
