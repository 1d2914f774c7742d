#pragma once
// The one derivation of a block's TimingSpec from its operators and critical path
// (docs/timing-model.md): every block's timing() goes through derive_timing, so a change of
// the technology table moves every block alike.
#include <cstdint>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"

namespace texsim {

// TimingSpec of `lanes` copies of a datapath with `ops` operators (per item) whose longest
// dependent chain takes `path_cycles`; `extra_area_ops` adds operators that exist once beside
// the lanes (e.g. a row set-up unit) to the area. Latency is at least one cycle.
TimingSpec derive_timing(const TechTable& t, const OpCounts& ops, double path_cycles, Datapath dp,
                         uint32_t lanes = 1, const OpCounts& extra_area_ops = {});
// The same with the critical path given as the operations along it.
inline TimingSpec derive_timing(const TechTable& t, const OpCounts& ops,
                                const OpCounts& critical_path, Datapath dp, uint32_t lanes = 1,
                                const OpCounts& extra_area_ops = {}) {
  return derive_timing(t, ops, t.path_latency(critical_path), dp, lanes, extra_area_ops);
}

}  // namespace texsim
