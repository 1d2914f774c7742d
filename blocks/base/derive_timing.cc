#include "blocks/base/derive_timing.h"

#include <algorithm>
#include <cmath>

namespace texsim {

TimingSpec derive_timing(const TechTable& t, const OpCounts& ops, double path_cycles, Datapath dp,
                         uint32_t lanes, const OpCounts& extra_area_ops) {
  TimingSpec ts;
  ts.lanes = std::max<uint32_t>(1, lanes);
  if (dp == Datapath::Spatial) {
    ts.ii = 1;
    ts.latency = std::max<uint32_t>(1, static_cast<uint32_t>(std::ceil(path_cycles)));
    ts.area = t.area_of(ops) * ts.lanes + t.area_of(extra_area_ops);
  } else {
    uint64_t worst = 1;
    OpCounts units;
    for (int k = 0; k < kOpKinds; ++k) {
      const auto kind = static_cast<OpKind>(k);
      worst = std::max(worst, ops.get(kind));
      if (ops.get(kind) > 0 || extra_area_ops.get(kind) > 0) units.at(kind) = 1;
    }
    ts.ii = static_cast<uint32_t>(worst);
    ts.latency = std::max<uint32_t>(1, static_cast<uint32_t>(std::ceil(path_cycles)) + ts.ii - 1);
    ts.area = t.area_of(units) * ts.lanes;
  }
  return ts;
}

}  // namespace texsim
