#pragma once
// Energy per operation, per SRAM access and per DRAM byte and row activation, in picojoules
// (docs/timing-model.md#energy). Read from the `energy` subtable of a scene's [tech] table.
//
// Defaults: M. Horowitz, "Computing's energy problem (and what we can do about it)", ISSCC
// 2014, 45 nm at 0.9 V: 32-bit float add 0.9 pJ, float multiply 3.7 pJ, 32-bit integer add
// 0.1 pJ; a 64-bit SRAM read 10 pJ (8 KB), 20 pJ (32 KB), 100 pJ (1 MB); DRAM 1.3-2.6 nJ per
// 64-bit access. What the paper does not give is an assumption, stated where it is set
// (energy_table.cc) and in the docs. All arithmetic is double.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/op_counts.h"

namespace toml {
inline namespace v3 {
class table;
}
}  // namespace toml

namespace texsim {

struct EnergyTable {
  static constexpr double kMaxPj = 1e6;  // any one figure a scene may set (1 uJ)

  // One SRAM capacity class: an access of sram_access_bytes to an array of capacity_bytes.
  struct SramClass {
    uint64_t capacity_bytes = 0;
    double pj = 0;
  };

  std::array<double, kOpKinds> op_pj{};  // per operation of each OpKind
  std::vector<SramClass> sram;           // by increasing capacity, at least one
  uint32_t sram_access_bytes = 8;        // the access width the sram figures are for
  double dram_byte_pj = 0;               // per byte moved
  double dram_activation_pj = 0;         // per row activation

  static EnergyTable defaults();
  // Defaults overridden by `tech`'s `energy` subtable (keys op.<kind>, sram, sram_access_bytes,
  // dram_byte_pj, dram_activation_pj); `tech` is the scene's [tech] table. Throws InputError
  // naming source:line:column and the key on a bad value.
  static EnergyTable from_toml(const toml::table& tech, const std::string& source);

  // Σ count × pJ over the kinds.
  double ops_pj(const OpCounts& ops) const;
  // One access of `access_bytes` to an SRAM of `capacity_bytes`: the class figure,
  // interpolated linearly in log2(capacity) between neighbouring classes and held constant
  // outside them, scaled linearly by access_bytes / sram_access_bytes.
  double sram_access_pj(uint64_t capacity_bytes, uint32_t access_bytes) const;
  double dram_pj(uint64_t bytes, uint64_t activations) const;
};

}  // namespace texsim
