#include "blocks/raster/rect_scan/row_start_counter.h"

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<RowStartCounter>);

RowStartCounter::Config RowStartCounter::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({});
  return {};
}

OpCounts RowStartCounter::ops_per_item() const {
  OpCounts o;
  o.add = 1;
  return o;
}

TimingSpec RowStartCounter::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), ops_per_item(), Datapath::Spatial);
}

}  // namespace texsim
