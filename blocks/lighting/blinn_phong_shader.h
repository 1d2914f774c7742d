#pragma once
// BlinnPhongShader: the per-fragment lighting of the lighting subsystem (ПРО;
// docs/derivations/lighting.md §1). The source names the subsystem, not its lighting model:
// Blinn-Phong is this project's choice. The filtered texture colour c (from ПНТ) is lit by one
// directional light:
//   out = c·(ka + kd·max(0, n·l)) + ks·light·max(0, n·h)^s,  h = (l + v)/|l + v|,
// with no specular term when n·l <= 0; each channel is clamped to [0, 1].
// A non-finite or zero normal is replaced by v (facing the viewer); a non-finite or zero light
// or view vector leaves the ambient term only. Both are flagged.
// Arithmetic: float; the power is one table read (a log/exp unit), exact to float rounding.
#include <glm/vec3.hpp>
#include <string>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"

namespace texsim {

class ConfigReader;

class BlinnPhongShader {
 public:
  struct Config {
    double ambient = 0.15, diffuse = 0.85, specular = 0.25, shininess = 32;
    double light_r = 1, light_g = 1, light_b = 1;  // the light's colour (specular)
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };
  struct Result {
    glm::vec3 rgb{0.0F};
    bool fallback = false;  // a non-finite or zero vector was replaced
  };

  BlinnPhongShader() = default;
  explicit BlinnPhongShader(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // n: unit normal; l: unit vector towards the light; v: unit vector towards the eye (all in
  // one frame); base: the filtered colour.
  Result shade(const glm::vec3& base, const glm::vec3& n, const glm::vec3& l, const glm::vec3& v,
               OpCounts& ops) const;

  // Item: one fragment.
  OpCounts ops_per_item() const;
  OpCounts critical_path() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "lighting.blinn_phong"; }
  std::string arithmetic() const { return "float"; }

 private:
  Config cfg_{};
};

}  // namespace texsim
