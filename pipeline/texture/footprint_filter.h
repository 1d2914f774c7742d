#pragma once
// A material's footprint filter block (EWA, multi-ellipse probes, Feline, SPAF) behind one
// interface, so the texture unit can instantiate whichever a scene names
// (docs/scenes.md: material effects `ewa`, `multi_probe`, `feline`, `spaf`; the effect
// registry, effect_registry.h, maps each key to its factory below).
#include <memory>
#include <string>
#include <vector>

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"
#include "blocks/base/fragment.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/footprint/footprint_types.h"
#include "blocks/texture/memory/texture_memory.h"

namespace texsim {

class FootprintFilter {
 public:
  virtual ~FootprintFilter() = default;

  virtual FilterOutput filter(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                              OpCounts& ops) const = 0;
  virtual uint32_t issue_cycles(const FilterStats& s) const = 0;
  virtual TimingSpec timing(const TechTable& tech) const = 0;
  virtual std::string name() const = 0;  // report name, e.g. "filter.ewa"
  virtual std::string arithmetic() const = 0;
  virtual AddressMode address_u() const = 0;
  virtual AddressMode address_v() const = 0;
};

template <Block B>
class FootprintFilterOf final : public FootprintFilter {
 public:
  explicit FootprintFilterOf(B block) : block_(std::move(block)) {}
  FilterOutput filter(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                      OpCounts& ops) const override {
    return block_.filter(tex, f, fetched, ops);
  }
  uint32_t issue_cycles(const FilterStats& s) const override { return block_.issue_cycles(s); }
  TimingSpec timing(const TechTable& tech) const override { return block_.timing(tech); }
  std::string name() const override { return block_.name(); }
  std::string arithmetic() const override { return block_.arithmetic(); }
  AddressMode address_u() const override { return block_.config().address_u; }
  AddressMode address_v() const override { return block_.config().address_v; }

 private:
  B block_;
};

// The block configured by its effect table (`effect`, read by B::Config::from_toml).
template <Block B>
std::unique_ptr<FootprintFilter> make_footprint_filter(const ConfigReader& effect) {
  return std::make_unique<FootprintFilterOf<B>>(B(B::Config::from_toml(effect)));
}

// EWA, with the weight map its `weight_map` table describes when weight = "map".
std::unique_ptr<FootprintFilter> make_ewa_filter(const ConfigReader& effect);

}  // namespace texsim
