#include "pipeline/texture/footprint_filter.h"

#include "blocks/texture/footprint/ewa_filter.h"
#include "blocks/texture/footprint/weight_map.h"

namespace texsim {

// The map's alpha defaults to the filter's.
std::unique_ptr<FootprintFilter> make_ewa_filter(const ConfigReader& effect) {
  const EwaFilter::Config cfg = EwaFilter::Config::from_toml(effect);
  std::shared_ptr<const WeightMap> map;
  if (cfg.weight == EwaFilter::Weight::Map) {
    const ConfigReader mr = effect.sub("weight_map");
    WeightMap::Config m = WeightMap::Config::from_toml(mr);
    if (!mr.table().contains("alpha")) m.alpha = cfg.alpha;
    map = std::make_shared<const WeightMap>(m);
  }
  return std::make_unique<FootprintFilterOf<EwaFilter>>(EwaFilter(cfg, map));
}

}  // namespace texsim
