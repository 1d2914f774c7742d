#include "pipeline/texture/stages/address_stage.h"

namespace texsim {

void AddressStage::rows(StageReport& r, std::vector<BlockUse>& out) const {
  const uint64_t iso = r.fragments - aniso_fragments_;  // one probe each
  const uint64_t aniso_probes = probes_ - iso;
  r.taps = probes_ * taps_;
  const OpCounts ops = addr_.ops_setup(false) * iso + addr_.ops_setup(true) * aniso_fragments_ +
                       addr_.ops_per_item(false) * iso + addr_.ops_per_item(true) * aniso_probes;
  // Texels fetched: border taps read the sampler's colour, not memory.
  r.border_taps = border_taps_;
  r.add(out, addr_.name(), addr_.arithmetic(), addr_.timing(r.tech), ops, r.taps - border_taps_);
  out.back().border_taps = border_taps_;
}

}  // namespace texsim
