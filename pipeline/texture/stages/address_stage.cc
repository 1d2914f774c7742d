#include "pipeline/texture/stages/address_stage.h"

#include "blocks/base/derive_timing.h"

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
  if (cube_fragments_ > 0) {
    // Face selection per cube fragment, the edge unit per tap it moved to another face.
    const OpCounts cube = CubeFaceSelect::ops_per_item() * cube_fragments_ +
                          LayeredAddressGen::ops_per_edge_tap() * edge_taps_;
    r.add(out, CubeFaceSelect::name(), CubeFaceSelect::arithmetic(), CubeFaceSelect::timing(r.tech),
          cube);
  }
  if (array_fragments_ > 0) {
    OpCounts layer;  // round half even, clamp to [0, d − 1]
    layer.add = 1;
    layer.cmp = 2;
    r.add(out, "array.layer_select", "float32 to integer",
          derive_timing(r.tech, layer, layer, Datapath::Spatial), layer * array_fragments_);
  }
  if (volume_fragments_ > 0) {
    // Per level: r·d − ½ (a multiply-add), its floor and fraction, the two addressed k's
    // (two compares); λ's third derivative term (two multiply-adds) once per fragment.
    OpCounts r_axis;
    r_axis.mul = 4;
    r_axis.add = 6;
    r_axis.cmp = 4;
    r.add(out, "volume.r_axis", "float32", derive_timing(r.tech, r_axis, r_axis, Datapath::Spatial),
          r_axis * volume_fragments_);
  }
}

}  // namespace texsim
