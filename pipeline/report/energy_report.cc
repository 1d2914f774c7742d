#include "pipeline/report/energy_report.h"

namespace texsim {

EnergyBreakdown run_energy(const UnitArray& units, const EnergyTable& e) {
  EnergyBreakdown b;
  for (const BlockUse& u : units.blocks()) {
    const double pj = e.ops_pj(u.ops);
    b.blocks.emplace_back(u.name, pj);
    b.ops_pj += pj;
  }
  // L1: each texel delivered is one read of its 4 bytes; each fill one write of a line.
  const TextureCache::Config& c1 = units.l1_config();
  const TextureCache::Stats s1 = units.l1_totals();
  const auto texel_bytes = static_cast<uint32_t>(4);
  b.l1_pj = static_cast<double>(s1.texel_reads) * e.sram_access_pj(c1.size_bytes, texel_bytes) +
            static_cast<double>(s1.misses) * e.sram_access_pj(c1.size_bytes, c1.line_bytes);
  const MemorySystem& m = units.memory();
  // L2: each look-up reads an L1 line; each fill writes an L2 line.
  if (const L2Cache* l2 = m.l2()) {
    const L2Cache::Stats& s2 = l2->stats();
    const uint64_t fills = s2.misses + s2.prefetches_issued;
    b.l2_pj = static_cast<double>(s2.accesses) *
                  e.sram_access_pj(l2->config().size_bytes, c1.line_bytes) +
              static_cast<double>(fills) *
                  e.sram_access_pj(l2->config().size_bytes, l2->config().line_bytes);
  }
  // The flat DRAM has no rows: bytes only.
  const uint64_t activations = m.banked() ? m.banked()->stats().activations : 0;
  b.dram_pj = e.dram_pj(m.dram_totals().bytes, activations);
  return b;
}

}  // namespace texsim
