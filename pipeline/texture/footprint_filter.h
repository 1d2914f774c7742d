#pragma once
// A material's footprint filter block (EWA, multi-ellipse probes, Feline, SPAF) behind one
// interface, so the texture unit can instantiate whichever a scene names
// (docs/scenes.md: material effects `ewa`, `multi_probe`, `feline`, `spaf`).
#include <memory>
#include <string>
#include <vector>

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
  // The filter named by a material's table (`material` reads the material's own table), or
  // null when it names none. Two footprint filters in one material is an error.
  static std::unique_ptr<FootprintFilter> from_material(const ConfigReader& material);
  // Effect keys that select a footprint filter.
  static const std::vector<std::string_view>& effect_keys();

  virtual FilterOutput filter(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                              OpCounts& ops) const = 0;
  virtual uint32_t issue_cycles(const FilterStats& s) const = 0;
  virtual TimingSpec timing(const TechTable& tech) const = 0;
  virtual std::string name() const = 0;  // report name, e.g. "filter.ewa"
  virtual std::string arithmetic() const = 0;
  virtual AddressMode address_u() const = 0;
  virtual AddressMode address_v() const = 0;
};

}  // namespace texsim
