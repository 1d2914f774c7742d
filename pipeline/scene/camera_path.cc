#include "pipeline/scene/camera_path.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <string>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/geometry/aviation_camera.h"
#include "pipeline/scene/scene_values.h"

namespace texsim {

namespace {

constexpr int kMaxKeys = 4096;

// The view axis, up and right of a key as the columns of a rotation.
glm::dmat3 key_frame(const CameraKey& k) {
  const glm::dvec3 f = glm::normalize(k.look_at - k.position);
  const glm::dvec3 r = glm::normalize(glm::cross(f, k.up));
  return glm::dmat3(f, glm::cross(r, f), r);
}

CameraKey read_key(const toml::node& n, size_t i, const ConfigReader& cam) {
  const std::string name = "camera.path[" + std::to_string(i) + "]";
  if (!n.is_table()) cam.fail_at(n, "path: each key must be a table { t = ..., position = ... }");
  const ConfigReader r(*n.as_table(), cam.source(), name);
  r.reject_unknown({"t", "position", "look_at", "up", "yaw", "pitch", "roll"});
  CameraKey k;
  if (!r.table().contains("t")) r.fail("t", "each key needs its time t");
  k.t = r.get_double("t", 0);
  if (!std::isfinite(k.t)) r.fail("t", "must be finite");
  if (!r.table().contains("position")) r.fail("position", "each key needs a position");
  k.position = read_vec<3>(r, "position", k.position);
  const bool angles =
      r.table().contains("yaw") || r.table().contains("pitch") || r.table().contains("roll");
  if (angles) {
    for (const char* key : {"look_at", "up"}) {
      if (r.table().contains(key)) r.fail(key, "not together with yaw/pitch/roll");
    }
    const glm::dmat3 a = aviation_rotation(r.get_double("yaw", 0), r.get_double("pitch", 0),
                                           r.get_double("roll", 0));
    k.look_at = k.position + a[0];
    k.up = a[1];
  } else {
    if (!r.table().contains("look_at"))
      r.fail("look_at", "each key needs look_at (or yaw, pitch, roll)");
    k.look_at = read_vec<3>(r, "look_at", k.look_at);
    k.up = read_vec<3>(r, "up", k.up);
  }
  const glm::dvec3 f = k.look_at - k.position;
  const glm::dvec3 x = glm::cross(f, k.up);
  if (!(glm::dot(f, f) > 0 && glm::dot(x, x) > 0) || !std::isfinite(glm::dot(f, f)) ||
      !std::isfinite(glm::dot(x, x))) {
    r.fail(angles ? "yaw" : "look_at", "camera direction is zero or parallel to 'up'");
  }
  return k;
}

}  // namespace

std::vector<CameraKey> read_camera_path(const ConfigReader& cam) {
  std::vector<CameraKey> keys;
  const toml::node* n = cam.table().get("path");
  if (!n) return keys;
  const toml::array* arr = n->as_array();
  if (!arr || arr->empty())
    cam.fail("path",
             "expected an array of keys [{ t = 0, position = [...], look_at = [...] }, ...]");
  if (arr->size() > kMaxKeys) cam.fail("path", "more than 4096 keys");
  for (size_t i = 0; i < arr->size(); ++i) {
    keys.push_back(read_key(*arr->get(i), i, cam));
    if (i > 0 && !(keys[i].t > keys[i - 1].t))
      cam.fail_at(*arr->get(i),
                  "camera.path[" + std::to_string(i) + "].t: times must increase from key to key");
  }
  return keys;
}

Camera camera_at(const Camera& base, const std::vector<CameraKey>& path, double t) {
  Camera c = base;
  if (path.empty()) return c;
  size_t i = 0;
  while (i + 2 < path.size() && t > path[i + 1].t) ++i;
  const CameraKey& a = path[i];
  const CameraKey& b = path.size() > 1 ? path[i + 1] : a;
  const double s = b.t > a.t ? std::clamp((t - a.t) / (b.t - a.t), 0.0, 1.0) : 0.0;
  c.position = glm::mix(a.position, b.position, s);
  const glm::dquat q = glm::slerp(glm::quat_cast(key_frame(a)), glm::quat_cast(key_frame(b)), s);
  const glm::dmat3 m = glm::mat3_cast(q);
  const double dist =
      glm::mix(glm::length(a.look_at - a.position), glm::length(b.look_at - b.position), s);
  c.look_at = c.position + dist * m[0];
  c.up = m[1];
  return c;
}

double frame_time(const std::vector<CameraKey>& path, int frames, int k) {
  if (path.empty()) return 0;
  const double t0 = path.front().t, t1 = path.back().t;
  if (frames <= 1) return t0;
  return t0 + (t1 - t0) * static_cast<double>(k) / static_cast<double>(frames - 1);
}

}  // namespace texsim
