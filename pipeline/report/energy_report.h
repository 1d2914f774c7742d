#pragma once
// Energy of a timed run from the technology's energy table ([tech.energy]): the blocks'
// operations, the SRAM accesses of each cache level and the DRAM's bytes and row activations
// (docs/timing-model.md#energy says what each access is charged).
#include <string>
#include <utility>
#include <vector>

#include "blocks/base/energy_table.h"
#include "pipeline/texture/unit_array.h"

namespace texsim {

struct EnergyBreakdown {
  std::vector<std::pair<std::string, double>> blocks;  // pJ of each block's operations
  double ops_pj = 0;                                   // Σ blocks
  double l1_pj = 0;                                    // texel reads and line fills of every L1
  double l2_pj = 0;    // look-ups and fills of the L2 (0 without one)
  double dram_pj = 0;  // bytes moved and rows activated
  double total_pj() const { return ops_pj + l1_pj + l2_pj + dram_pj; }
};

EnergyBreakdown run_energy(const UnitArray& units, const EnergyTable& e);

}  // namespace texsim
