#include "blocks/lighting/normal_unit.h"

#include <cmath>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<NormalUnit>);

namespace {

// |v| and the division: 3 mul, 2 add, sqrt, rcp, 3 mul, and the zero/NaN check.
OpCounts normalise_ops() {
  OpCounts o;
  o.mul = 6;
  o.add = 2;
  o.sqrt = 1;
  o.rcp = 1;
  o.cmp = 1;
  return o;
}

}  // namespace

NormalUnit::Config NormalUnit::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"source", "bump_scale", "datapath"});
  Config c;
  c.source =
      static_cast<Source>(r.get_choice("source", 0, {"normal_map", "height_map", "terrain"}));
  c.bump_scale = r.get_double("bump_scale", c.bump_scale);
  c.datapath = parse_datapath(r, c.datapath);
  if (!(std::fabs(c.bump_scale) <= 1e6)) r.fail("bump_scale", "must be finite, |s| <= 1e6");
  return c;
}

NormalUnit::Result NormalUnit::normalise(const glm::vec3& v, const glm::vec3& up) {
  const float len2 = v.x * v.x + v.y * v.y + v.z * v.z;
  if (!(len2 > 0) || !std::isfinite(len2)) return {up, true};
  return {v * (1.0F / std::sqrt(len2)), false};
}

NormalUnit::Result NormalUnit::from_map(const glm::vec3& rgb, OpCounts& ops) const {
  OpCounts o = normalise_ops();
  o.mul += 3;  // 2c
  o.add += 3;  // - 1
  ops += o;
  return normalise(rgb * 2.0F - 1.0F, {0, 0, 1});
}

NormalUnit::Result NormalUnit::from_height(const ReliefHeightMap& hm, int32_t x, int32_t y,
                                           OpCounts& ops) const {
  OpCounts o = normalise_ops();
  o.mem += 4;
  o.add += 2;
  o.mul += 2;  // (h+ - h-)·(s/2)
  ops += o;
  if (hm.width <= 0 || hm.height <= 0) return {{0, 0, 1}, true};
  const float s = static_cast<float>(cfg_.bump_scale) * 0.5F;
  const float dx = (hm.texel(x + 1, y) - hm.texel(x - 1, y)) * s;
  const float dy = (hm.texel(x, y + 1) - hm.texel(x, y - 1)) * s;
  return normalise({-dx, -dy, 1.0F}, {0, 0, 1});
}

NormalUnit::Result NormalUnit::from_terrain(double dydx, double dydz, OpCounts& ops) const {
  ops += normalise_ops();
  return normalise({static_cast<float>(-dydx), 1.0F, static_cast<float>(-dydz)}, {0, 1, 0});
}

OpCounts NormalUnit::ops_per_item() const {
  OpCounts o = normalise_ops();
  switch (cfg_.source) {
    case Source::NormalMap:
      o.mul += 3;
      o.add += 3;
      break;
    case Source::HeightMap:
      o.mem += 4;
      o.add += 2;
      o.mul += 2;
      break;
    case Source::Terrain:
      break;
  }
  return o;
}

OpCounts NormalUnit::critical_path() const {
  OpCounts p;
  p.mul = 2;
  p.add = 2;
  p.sqrt = 1;
  p.rcp = 1;
  if (cfg_.source == Source::HeightMap) p.mem = 1;
  return p;
}

TimingSpec NormalUnit::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), critical_path(), cfg_.datapath);
}

}  // namespace texsim
