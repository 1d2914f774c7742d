#include "blocks/base/derive_timing.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace texsim {

namespace {
// Cycles as a TimingSpec holds them. The technology table's ranges keep every path far below
// 2^32; a value outside is a defect, never silently wrapped.
uint32_t to_cycles(double c) {
  if (!(c >= 0 && c <= 4294967295.0))
    throw std::overflow_error("derive_timing: " + std::to_string(c) + " cycles out of range");
  return static_cast<uint32_t>(std::ceil(c));
}
}  // namespace

TimingSpec derive_timing(const TechTable& t, const OpCounts& ops, double path_cycles, Datapath dp,
                         uint32_t lanes, const OpCounts& extra_area_ops) {
  TimingSpec ts;
  ts.lanes = std::max<uint32_t>(1, lanes);
  if (dp == Datapath::Spatial) {
    ts.ii = 1;
    ts.latency = std::max<uint32_t>(1, to_cycles(path_cycles));
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
    ts.latency = std::max<uint32_t>(1, to_cycles(path_cycles + ts.ii - 1.0));
    ts.area = t.area_of(units) * ts.lanes;
  }
  return ts;
}

}  // namespace texsim
