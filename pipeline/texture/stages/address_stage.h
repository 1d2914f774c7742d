#pragma once
// A material's texel address generator (its `filter` table: nearest, bilinear, trilinear,
// anisotropic probes), in the address slot: one probe per issue cycle. Operations depend only
// on the probes N of each fragment, so it counts fragments with N > 1 and probes, and its row
// multiplies the per-fragment and per-probe counts: exact, and two increments per fragment.
#include <cstdint>

#include "blocks/texture/layered/layered_address_gen.h"
#include "blocks/texture/sampler/texel_address_gen.h"
#include "pipeline/texture/stages/unit_stage.h"

namespace texsim {

class AddressStage final : public UnitStage {
 public:
  explicit AddressStage(const TexelAddressGen::Config& c)
      : addr_(c), taps_(static_cast<uint32_t>(addr_.taps_per_probe())) {}
  void declare(SlotPlan& plan, const TechTable& tech) const override {
    plan.occupy(Slot::Address, addr_.timing(tech).latency);
  }
  // Sets r.taps, which the blend after it blends.
  void rows(StageReport& r, std::vector<BlockUse>& out) const override;

  const TexelAddressGen& gen() const { return addr_; }
  FilterMode filter() const { return addr_.config().filter; }
  uint32_t taps_per_probe() const { return taps_; }
  void count(uint32_t probes) {
    aniso_fragments_ += probes > 1;
    probes_ += probes;
  }
  void count_border(int taps) { border_taps_ += static_cast<uint64_t>(taps); }
  uint64_t probes() const { return probes_; }
  uint64_t border_taps() const { return border_taps_; }
  // A layered texture's fragment (LayeredAddressGen): a cube fragment through the face
  // selector, with `edge_taps` taps the edge unit resolved on a neighbouring face; an array
  // fragment through the layer selector.
  void count_cube(int edge_taps) {
    ++cube_fragments_;
    edge_taps_ += static_cast<uint64_t>(edge_taps);
  }
  void count_array() { ++array_fragments_; }
  // A 3-D texture's fragment: the r axis's scale, floor and address mode beside u and v's.
  void count_volume() { ++volume_fragments_; }
  LayeredAddressGen layered() const {
    return LayeredAddressGen(addr_, addr_.config().seamless_cube);
  }
  // count(1) n times.
  void count_single_probes(uint64_t n) { probes_ += n; }

 private:
  TexelAddressGen addr_;
  uint32_t taps_;
  uint64_t aniso_fragments_ = 0;  // fragments with N > 1
  uint64_t probes_ = 0;           // Σ N over all fragments
  uint64_t border_taps_ = 0;      // taps that read the border colour (CLAMP_TO_BORDER)
  uint64_t cube_fragments_ = 0, edge_taps_ = 0, array_fragments_ = 0, volume_fragments_ = 0;
};

}  // namespace texsim
