#include "blocks/lighting/terrain_normal_unit.h"

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/base/derive_timing.h"

namespace texsim {

static_assert(Block<TerrainNormalUnit>);

namespace {

NormalUnit::Config terrain_source(Datapath dp) {
  NormalUnit::Config c;
  c.source = NormalUnit::Source::Terrain;
  c.datapath = dp;
  return c;
}

}  // namespace

TerrainNormalUnit::Config TerrainNormalUnit::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"method", "epsilon", "datapath", "function", "deformation", "blend_shift"});
  Config c;
  c.method = static_cast<Method>(r.get_choice("method", 0, {"gradient", "central_difference"}));
  c.epsilon = r.get_double("epsilon", c.epsilon);
  if (!(c.epsilon > 0 && c.epsilon <= 1)) r.fail("epsilon", "must be in (0, 1] grid units");
  c.datapath = parse_datapath(r, c.datapath);
  c.evaluator = TerrainHeightEvaluator::Config::from_toml(
      r.for_block("terrain.height_evaluator", {"method", "epsilon"}));
  c.evaluator.datapath = c.datapath;
  return c;
}

TerrainNormalUnit::TerrainNormalUnit(const Config& c)
    : cfg_(c), eval_(c.evaluator), normalise_(terrain_source(c.datapath)) {}

TerrainNormalUnit::Result TerrainNormalUnit::normal(const TerrainGrid& g, double x, double z,
                                                    OpCounts& ops) const {
  double gx = 0, gz = 0;
  if (cfg_.method == Method::Gradient) {
    const TerrainHeightEvaluator::Sample s = eval_.sample(g, x, z, ops);
    gx = s.dydx;
    gz = s.dydz;
  } else {
    const double e = cfg_.epsilon, k = 1 / (2 * e);
    gx = (eval_.height(g, x + e, z, ops) - eval_.height(g, x - e, z, ops)) * k;
    gz = (eval_.height(g, x, z + e, ops) - eval_.height(g, x, z - e, ops)) * k;
  }
  ops += difference_ops();
  const NormalUnit::Result r = normalise_.from_terrain(gx, gz, ops);
  return {r.n, r.fallback};
}

OpCounts TerrainNormalUnit::difference_ops() const {
  OpCounts o;
  if (cfg_.method == Method::CentralDifference) {
    o.add = 4 + 2;  // x ± ε, z ± ε; the two differences
    o.mul = 2;      // × 1/(2ε)
  }
  return o;
}

OpCounts TerrainNormalUnit::ops_per_item() const {
  OpCounts o = cfg_.method == Method::Gradient ? eval_.ops_per_item() + eval_.gradient_ops()
                                               : eval_.ops_per_item() * 4;
  return o + difference_ops() + normalise_.ops_per_item();
}

OpCounts TerrainNormalUnit::critical_path() const {
  // The evaluations run side by side: one evaluation, then (gradient) f' times the bracket,
  // or (central difference) the offset before and the difference and scale after; then the
  // normaliser.
  OpCounts p = eval_.critical_path();
  if (cfg_.method == Method::Gradient) {
    p.mul += 1;
  } else {
    p.add += 2;
    p.mul += 1;
  }
  return p + normalise_.critical_path();
}

TimingSpec TerrainNormalUnit::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), critical_path(), cfg_.datapath);
}

}  // namespace texsim
