#include "blocks/lighting/blinn_phong_shader.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<BlinnPhongShader>);

namespace {

bool usable(const glm::vec3& a) {
  const float d = glm::dot(a, a);
  return std::isfinite(d) && d > 0;
}

glm::vec3 clamp01(const glm::vec3& c) {
  return {std::clamp(c.x, 0.0F, 1.0F), std::clamp(c.y, 0.0F, 1.0F), std::clamp(c.z, 0.0F, 1.0F)};
}

}  // namespace

BlinnPhongShader::Config BlinnPhongShader::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown(
      {"ambient", "diffuse", "specular", "shininess", "light_r", "light_g", "light_b", "datapath"});
  Config c;
  c.ambient = r.get_double("ambient", c.ambient);
  c.diffuse = r.get_double("diffuse", c.diffuse);
  c.specular = r.get_double("specular", c.specular);
  c.shininess = r.get_double("shininess", c.shininess);
  c.light_r = r.get_double("light_r", c.light_r);
  c.light_g = r.get_double("light_g", c.light_g);
  c.light_b = r.get_double("light_b", c.light_b);
  c.datapath = parse_datapath(r, c.datapath);
  for (const auto& [key, val] :
       {std::pair{"ambient", c.ambient}, std::pair{"diffuse", c.diffuse},
        std::pair{"specular", c.specular}, std::pair{"light_r", c.light_r},
        std::pair{"light_g", c.light_g}, std::pair{"light_b", c.light_b}}) {
    if (!(val >= 0 && val <= 16)) r.fail(key, "must be in [0, 16]");
  }
  if (!(c.shininess >= 1 && c.shininess <= 4096)) r.fail("shininess", "must be in [1, 4096]");
  return c;
}

BlinnPhongShader::Result BlinnPhongShader::shade(const glm::vec3& base, const glm::vec3& n,
                                                 const glm::vec3& l, const glm::vec3& v,
                                                 OpCounts& ops) const {
  ops += ops_per_item();
  Result res;
  const auto ka = static_cast<float>(cfg_.ambient), kd = static_cast<float>(cfg_.diffuse),
             ks = static_cast<float>(cfg_.specular);
  const glm::vec3 b =
      clamp01({std::isfinite(base.x) ? base.x : 0.0F, std::isfinite(base.y) ? base.y : 0.0F,
               std::isfinite(base.z) ? base.z : 0.0F});
  if (!usable(l) || !usable(v)) {
    res.fallback = true;
    res.rgb = clamp01(b * ka);
    return res;
  }
  glm::vec3 nn = n;
  if (!usable(n)) {
    res.fallback = true;
    nn = v;
  }
  const float ndl = glm::dot(nn, l);
  float spec = 0;
  if (ndl > 0) {
    const glm::vec3 hv = l + v;
    const float hl = std::sqrt(glm::dot(hv, hv));
    const float ndh = hl > 0 ? glm::dot(nn, hv) / hl : 0.0F;
    spec = ndh > 0 ? std::pow(ndh, static_cast<float>(cfg_.shininess)) : 0.0F;
  }
  const glm::vec3 light(static_cast<float>(cfg_.light_r), static_cast<float>(cfg_.light_g),
                        static_cast<float>(cfg_.light_b));
  res.rgb = clamp01(b * (ka + kd * std::max(ndl, 0.0F)) + light * (ks * spec));
  return res;
}

OpCounts BlinnPhongShader::ops_per_item() const {
  // n·l (3 mul, 2 add); h = l + v (3 add) and |h| (3 mul, 2 add, sqrt, rcp); n·h (3 mul,
  // 2 add, 1 mul by 1/|h|); the power (1 table read); ka + kd·max (1 mul, 1 add, 1 cmp);
  // colour·that (3 mul); ks·spec·light (1 + 3 mul); the sum (3 add); clamps (6 cmp); the
  // n·l > 0 and n·h > 0 tests (2 cmp).
  OpCounts o;
  o.mul = 3 + 3 + 3 + 1 + 1 + 3 + 4;
  o.add = 2 + 3 + 2 + 2 + 1 + 3;
  o.sqrt = 1;
  o.rcp = 1;
  o.lut = 1;
  o.cmp = 1 + 6 + 2;
  return o;
}

OpCounts BlinnPhongShader::critical_path() const {
  // h = l + v -> |h|² -> sqrt -> rcp -> n·h -> pow -> ks·spec·light -> sum -> clamp.
  OpCounts p;
  p.add = 1 + 2 + 1;
  p.mul = 1 + 1 + 2;
  p.sqrt = 1;
  p.rcp = 1;
  p.lut = 1;
  p.cmp = 1;
  return p;
}

TimingSpec BlinnPhongShader::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), critical_path(), cfg_.datapath);
}

}  // namespace texsim
