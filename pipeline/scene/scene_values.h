#pragma once
// Values of scene tables shared by the scene's readers (scene.cc, scene_meshes.cc): where a
// node is ("file:line:column") and vectors of finite numbers.
#include <toml++/toml.h>

#include <cmath>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <string_view>

#include "blocks/base/config_reader.h"

namespace texsim {

inline std::string source_at(const std::string& src, const toml::node& n) {
  const auto& b = n.source().begin;
  return src + ":" + std::to_string(b.line) + ":" + std::to_string(b.column);
}

// The array of N finite numbers (integers accepted) at `key`, or `def` when absent.
template <int N>
glm::vec<N, double> read_vec(const ConfigReader& r, std::string_view key, glm::vec<N, double> def) {
  const toml::node* n = r.table().get(key);
  if (!n) return def;
  const toml::array* a = n->as_array();
  if (!a || a->size() != N) r.fail(key, "expected an array of " + std::to_string(N) + " numbers");
  glm::vec<N, double> v;
  for (int i = 0; i < N; ++i) {
    const toml::node& e = *a->get(static_cast<size_t>(i));
    if (auto f = e.value_exact<double>())
      v[i] = *f;
    else if (auto k = e.value_exact<int64_t>())
      v[i] = static_cast<double>(*k);
    else
      r.fail_at(e, std::string(key) + ": element " + std::to_string(i) + " is not a number");
    if (!std::isfinite(v[i])) r.fail_at(e, std::string(key) + ": element must be finite");
  }
  return v;
}

}  // namespace texsim
