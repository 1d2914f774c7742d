#include "blocks/raster/rect_scan/coordinate_counters.h"

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<CoordinateCounters>);

CoordinateCounters::Config CoordinateCounters::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({});
  return {};
}

OpCounts CoordinateCounters::ops_per_item() const {
  OpCounts o;
  o.add = 2;
  return o;
}

TimingSpec CoordinateCounters::timing(const TechTable& t) const {
  OpCounts path;
  path.add = 1;
  return derive_timing(t, ops_per_item(), path, Datapath::Spatial);
}

}  // namespace texsim
