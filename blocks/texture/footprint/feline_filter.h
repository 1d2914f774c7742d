#pragma once
// Feline-style trilinear probes (McCormack et al.; Texram; seed 004): N trilinear probes along
// a line through the footprint centre — the longer side of the parallelogram spanned by the
// two derivative vectors (Texram) or the ellipse's major axis (Feline) — at the LOD of the
// shorter axis, equally or Gaussian weighted (docs/derivations/anisotropic-filters.md §5).
// Arithmetic (Config::arith): set-up = line, minor size, N, LOD, probe positions and weights.
//  - float:  the ellipse footprint set-up in float32, the rest (and the parallelogram axis) in
//            double (the block's original model, kept bit-identical).
//  - double: double throughout.
//  - fixed:  the ProbeFx formats of multi_probe_filter.h (round half up, saturating): the
//            ellipse's Σ, eigenvalues and 2θ from the shared fixed footprint set-up (one CORDIC
//            vectoring), the half line R_major·(cos θ, sin θ) by CORDIC rotation, lengths by a
//            digit-recurrence square root, N = ⌈|line|/minor⌉ by a 6-step restoring divider,
//            1/N from a 32-entry table, log2 and the Gaussian's exp2 from 1024-entry tables.
// In every mode the probes are trilinear lookups through the texel address generator (float32
// coordinates, u0.8 weights) blended in float32.
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/config_reader.h"
#include "blocks/base/fragment.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/footprint/footprint_types.h"
#include "blocks/texture/footprint/probe_executor.h"
#include "blocks/texture/footprint/probe_setup_fx.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/texel_address_gen.h"

namespace texsim {

class FelineFilter {
 public:
  enum class Axis : int { Parallelogram, Ellipse };
  enum class Weights : int { Equal, Gaussian };
  struct Config {
    Axis axis = Axis::Ellipse;
    Weights weights = Weights::Gaussian;
    int max_probes = 16;        // ≤ 31
    double weight_alpha = 2.0;  // Gaussian: exp(−w_α·t²), t ∈ (−1, 1) along the line
    double radius_px = 1.0;     // the line spans ±R pixels of footprint
    double max_aniso = 64;      // Ellipse axis: minor stretched to ≥ major/max_aniso
    NumberFormat arith = NumberFormat::Float;  // set-up arithmetic (see the header comment)
    AddressMode address_u = AddressMode::Wrap;
    AddressMode address_v = AddressMode::Wrap;
    // Keys: axis (parallelogram|ellipse), weights (equal|gaussian), max_probes, weight_alpha,
    // radius_px, max_aniso, arith (float|double|fixed), address_u, address_v.
    static Config from_toml(const ConfigReader& r);
  };

  FelineFilter() : FelineFilter(Config{}) {}
  explicit FelineFilter(const Config& c);
  const Config& config() const { return cfg_; }

  // Probes of one fragment: N = min(⌈|line|/minor⌉, max_probes) at the centres of N equal
  // segments of the line ±line, t_k = (2k + 1 − N)/N; λ = log2(max(minor, |line|/N)).
  ProbeSet probes(const Texture& tex, const Fragment& f, OpCounts& ops,
                  FilterStats* st = nullptr) const;
  FilterOutput filter(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                      OpCounts& ops) const;

  uint32_t issue_cycles(const FilterStats& s) const { return s.probes > 0 ? s.probes : 1; }
  OpCounts setup_ops() const;
  // Item: one probe (position, weight, trilinear address and blend).
  OpCounts ops_per_item() const;
  OpCounts probe_setup_ops() const;  // per probe: position and weight only
  TimingSpec timing(const TechTable& tech) const;
  // Name of the arithmetic for reports.
  std::string arithmetic() const;
  std::string name() const { return "filter.feline"; }

 private:
  // The set-up in one number format (T = float or double; fixed point: probes_fixed).
  template <class T>
  ProbeSet probes_t(const Texture& tex, const Fragment& f, FilterStats* st) const;
  ProbeSet probes_fixed(const Texture& tex, const Fragment& f, FilterStats* st) const;
  Config cfg_;
  TexelAddressGen addr_;
};

}  // namespace texsim
