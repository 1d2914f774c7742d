#pragma once
// SPAF, sub-texel precision anisotropic filter (Shin, Lee & Kim; seed 004 eq. 18–22): the
// footprint quadrilateral's four edge functions E = (u − u0)·deu + (v − v0)·dev with
// (deu, dev) = (ΔV, −ΔU)/(|ΔU| + |ΔV|); a texel with every |E| ≥ ½ is fully in or out,
// otherwise sub-texel masks from a table indexed by (slope, E) are ANDed and counted; the
// coverage multiplies a Gaussian weight (docs/anisotropic-filters.md §6).
// Arithmetic: float32 set-up, edge functions and Q; masks of side² ≤ 64 bits; float32 blend.
#include <cstdint>
#include <vector>

#include "blocks/config_reader.h"
#include "blocks/ewa_filter.h"
#include "blocks/op_counts.h"
#include "blocks/tech_table.h"
#include "blocks/texture_memory.h"
#include "blocks/timing_spec.h"
#include "traces/fragment.h"

namespace texsim {

class SpafFilter {
 public:
  struct Config {
    int mask_side = 4;          // sub-texels per side: masks of mask_side² bits (≤ 8)
    int slope_steps = 32;       // table rows over the edge normal's direction
    int offset_steps = 16;      // table columns over E ∈ (−½, ½)
    double half_px = 1.0;       // quadrilateral = centre ± half_px·(J_x ± J_y) (the Gaussian's support square)
    bool gaussian = true;       // weight = coverage·exp(−α·Q) (else coverage only: an area filter)
    double alpha = 2.0;         // Q = the R = 1 px ellipse's quadratic form (EWA's pixel model)
    int texel_budget = 64;      // bounding-box texels: the finest level whose box fits (8×8)
    int lanes = 4;              // texels per cycle
    AddressMode address_u = AddressMode::Wrap;
    AddressMode address_v = AddressMode::Wrap;
    // Keys: mask_side, slope_steps, offset_steps, half_px, gaussian, alpha, texel_budget,
    // lanes, address_u, address_v.
    static Config from_toml(const ConfigReader& r);
  };

  SpafFilter() : SpafFilter(Config{}) {}
  explicit SpafFilter(const Config& c);
  const Config& config() const { return cfg_; }

  // The sub-texel mask of a texel cut by an edge whose normalised normal is (deu, dev)
  // (|deu| + |dev| = 1) at value E ∈ (−½, ½) at the texel centre: the table's entry.
  uint64_t mask(double deu, double dev, double e) const;
  // The exact mask (every sub-texel centre tested), for the table's error measurement.
  uint64_t exact_mask(double deu, double dev, double e) const;
  int mask_bits() const { return cfg_.mask_side * cfg_.mask_side; }

  FilterOutput filter(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                      OpCounts& ops) const;

  uint32_t issue_cycles(const FilterStats& s) const;
  OpCounts setup_ops() const;
  OpCounts per_visit_ops() const;   // four edge steps and the in/out tests, Q step
  OpCounts per_partial_edge_ops() const;  // table index and read for an edge with |E| < ½
  OpCounts per_inside_ops() const;  // AND, popcount, weight, address, read, MAC
  TimingSpec timing(const TechTable& tech) const;
  uint64_t table_bytes() const;

 private:
  int slope_index(double deu, double dev) const;
  Config cfg_;
  std::vector<uint64_t> table_;  // [slope][offset]
};

}  // namespace texsim
