#pragma once
// SPAF, sub-texel precision anisotropic filter (Shin, Lee & Kim; seed 004 eq. 18–22): the
// footprint quadrilateral's four edge functions E = (u − u0)·deu + (v − v0)·dev with
// (deu, dev) = (ΔV, −ΔU)/(|ΔU| + |ΔV|); a texel with every |E| ≥ ½ is fully in or out,
// otherwise its coverage comes from sub-texel masks (a table indexed by (slope, E), ANDed and
// counted) or from the V(d) cut-off volume of a Gaussian texel (thesis, METHODS §5.4); the
// coverage multiplies a Gaussian weight (docs/derivations/anisotropic-filters.md §6, §9).
// Arithmetic: level selection and box in double (control decisions); per-level set-up
// (corners, normals, Q coefficients) in float32, double for arith = "double"; edge functions
// and Q stepped per texel in T = float32, double, or SpafFixed = s20.28 (HalfUp rounding,
// saturating; the set-up guards its range, see below); V(d) coverage in the cut-off's format
// (float, double, fixed u0.F/s1.F/u1.F); masks of side² ≤ 64 bits; float32 blend (double
// for arith = "double").
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/config_reader.h"
#include "blocks/base/fragment.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/footprint/footprint_types.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/subtexel/subtexel_cutoff.h"
#include "rtl_model/number/fixed.h"
#include "rtl_model/number/number_format.h"

namespace texsim {

// Fixed-point edge functions and Q of SPAF: one 48-bit format for both. 20 integer bits (with
// sign): |E| ≤ the scanned box's width + height ≤ 2·4·texel_budget, and Q and its steps at the
// box corners ≤ 3·Qb, Qb about 1–2·aniso² for a footprint fitted to the budget. The set-up
// checks both against 2^17 (a quarter of the range) and takes the bilinear fallback beyond, so
// a value never saturates mid-row (an incremental datapath cannot recover from a clipped
// value): an 8-texel footprint at 34° falls back from 512:1, one along a texel row from
// 4096:1. 28 fraction bits: stepping E and Q over a box of n texels side drifts by ≤ n·2^-29
// in E and ≈ n²·2^-29 in Q (1.2·10⁻⁴ for n = 256; the default budget's boxes are 8–16 texels
// wide). HalfUp: the cheapest rounding (one constant into the adder tree).
using SpafFixed = number_format_t<NumberFormat::S20_28HalfUp>;

class SpafFilter {
 public:
  enum class Coverage : int { Mask, Vd };
  // arith: "float", "double" or "fixed" (edge functions and Q in SpafFixed).
  static constexpr NumberFormatChoices<NumberFormat::Float, NumberFormat::Double,
                                       NumberFormat::S20_28HalfUp>
      kArith{{"float", "double", "fixed"}};

  struct Config {
    int mask_side = 4;      // sub-texels per side: masks of mask_side² bits (≤ 8)
    int slope_steps = 32;   // table rows over the edge normal's direction
    int offset_steps = 16;  // table columns over E ∈ (−½, ½)
    double half_px =
        1.0;  // quadrilateral = centre ± half_px·(J_x ± J_y) (the Gaussian's support square)
    bool gaussian = true;   // weight = coverage·exp(−α·Q) (else coverage only: an area filter)
    double alpha = 2.0;     // Q = the R = 1 px ellipse's quadratic form (EWA's pixel model)
    int texel_budget = 64;  // bounding-box texels: the finest level whose box fits (8×8)
    int lanes = 4;          // texels per cycle
    AddressMode address_u = AddressMode::Wrap;
    AddressMode address_v = AddressMode::Wrap;
    // Partly covered texels: "mask" = sub-texel masks; "vd" = Π over cut edges of
    // W(d)/W(−½), the Gaussian texel's volume inside the edge (SubtexelCutoff), d the texel
    // centre's Euclidean distance to the edge in texels. vd.lanes = cut-off units per lane.
    Coverage coverage = Coverage::Mask;
    SubtexelCutoff::Config vd;
    NumberFormat arith = NumberFormat::Float;
    // Keys: mask_side, slope_steps, offset_steps, half_px, gaussian, alpha, texel_budget,
    // lanes, address_u, address_v, coverage (mask|vd), vd (SubtexelCutoff::Config: evaluator,
    // format, lanes; only with coverage = "vd"), arith (float|double|fixed).
    static Config from_toml(const ConfigReader& r);
  };

  SpafFilter() : SpafFilter(Config{}) {}
  explicit SpafFilter(const Config& c);
  const Config& config() const { return cfg_; }
  const SubtexelCutoff& cutoff() const { return cut_; }

  // The sub-texel mask of a texel cut by an edge whose normalised normal is (deu, dev)
  // (|deu| + |dev| = 1) at value E ∈ (−½, ½) at the texel centre: the table's entry.
  uint64_t mask(double deu, double dev, double e) const;
  // The exact mask (every sub-texel centre tested), for the table's error measurement.
  uint64_t exact_mask(double deu, double dev, double e) const;
  int mask_bits() const { return cfg_.mask_side * cfg_.mask_side; }
  // Coverage of a texel by one edge with coverage = "vd": W(d)/W(−½) in the configured
  // evaluator and format, d = −E/‖(deu, dev)‖₂ (the centre's Euclidean distance to the edge,
  // positive outside), for any E (|E| ≥ ½ gives 0 or 1).
  double vd_coverage(double deu, double dev, double e) const;

  FilterOutput filter(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                      OpCounts& ops) const;
  // The datapath in one number format: T = float, double or SpafFixed.
  template <class T>
  FilterOutput filter_t(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                        OpCounts& ops) const;

  // Scan slots / lanes: a texel takes one slot, or ⌈cut edges / vd.lanes⌉ with V(d) coverage.
  uint32_t issue_cycles(const FilterStats& s) const;
  OpCounts setup_ops() const;
  OpCounts per_row_ops() const;  // row step of the four edges and of Q, row address
  // Item: one scanned texel (visit): four edge steps and the in/out tests, Q step.
  OpCounts ops_per_item() const;
  // An edge with |E| < ½: mask table index and read, AND; or distance, cut-off, ratio, product.
  OpCounts per_partial_edge_ops() const;
  OpCounts per_inside_ops() const;   // coverage, weight, address, read, MAC
  OpCounts fixed_guard_ops() const;  // the range checks of the fixed datapath (per level)
  TimingSpec timing(const TechTable& tech) const;
  uint64_t table_bytes() const;
  // Name of the arithmetic for reports (names the V(d) evaluator and format when used).
  std::string arithmetic() const;
  std::string name() const { return "filter.spaf"; }

 private:
  int slope_index(double deu, double dev) const;
  Config cfg_;
  SubtexelCutoff cut_;
  std::vector<uint64_t> table_;  // [slope][offset]
};

}  // namespace texsim
