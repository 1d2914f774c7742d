#pragma once
// Multi-ellipse probe filter (Mavridis & Papaioannou; seed 004 eq. 12–17): the footprint
// ellipse approximated by N trilinear probes along its major axis, N = 2·R_major/(α·R_minor) − 1
// (odd), spread over L = 2·(R_major − α·R_minor), weighted by a Gaussian of their distance to
// the centre; optionally half the probes per frame, alternating
// (docs/derivations/anisotropic-filters.md §4). Arithmetic (Config::arith): set-up = footprint,
// axes, N, LOD, probe positions and weights.
//  - float:  footprint set-up in float32; axes, N, positions and weights evaluated in double
//            from it (the block's original model, kept bit-identical).
//  - double: the same in double throughout.
//  - fixed:  every set-up quantity in the ProbeFx formats below (round half up, saturating):
//            square roots by a digit-recurrence unit, the axis angle and the major-axis vector
//            by CORDIC (vectoring, then rotation: no atan/cos/sin tables), log2 and exp2 by
//            tables of 1024 entries, the probe-count quotient by a 6-step restoring divider.
// In every mode the probes run through the trilinear texel address generator (float32
// coordinates, u0.8 weights) and are blended in float32.
// The probe executor is in probe_executor.h, the fixed-point set-up units in probe_setup_fx.h
// (both shared with FelineFilter).
#include <array>
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
#include "rtl_model/number/fixed.h"
#include "rtl_model/number/number_format.h"

namespace texsim {

class MultiProbeFilter {
 public:
  struct Config {
    double alpha = 1.0;   // the seed's α: a probe's radius in minor radii (spacing α·R_minor)
    int max_probes = 15;  // odd, ≤ 31
    double weight_alpha = 2.0;  // probe weight exp(−w_α·(d/R_major)²): EWA's pixel model
    double radius_px = 1.0;     // R: footprint radius in pixels
    double max_aniso = 64;      // minor axis stretched to ≥ major/max_aniso before N is taken
    bool seed_theta = false;    // θ = atan(B/(A−C))/2 as printed (loses the quadrant)
    bool temporal = false;  // alternate probe subsets between frames (0, ±2, ±4 … / 0, ±1, ±3 …)
    NumberFormat arith = NumberFormat::Float;  // set-up arithmetic (see the header comment)
    AddressMode address_u = AddressMode::Wrap;
    AddressMode address_v = AddressMode::Wrap;
    // Keys: alpha, max_probes, weight_alpha, radius_px, max_aniso, seed_theta, temporal,
    // arith (float|double|fixed), address_u, address_v.
    static Config from_toml(const ConfigReader& r);
  };

  MultiProbeFilter() : MultiProbeFilter(Config{}) {}
  explicit MultiProbeFilter(const Config& c);
  const Config& config() const { return cfg_; }

  // The probes of one fragment (positions, weights, LOD) in the configured arithmetic; adds
  // the set-up operations.
  ProbeSet probes(const Texture& tex, const Fragment& f, OpCounts& ops,
                  FilterStats* st = nullptr) const;
  FilterOutput filter(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                      OpCounts& ops) const;

  // Major-axis angle from the footprint covariance: ½·atan2(2Σuv, Σuu − Σvv), or the seed's
  // printed ½·atan(B/(A − C)) with A = Σvv, B = −2Σuv, C = Σuu of the quadratic form.
  static double major_angle(double suu, double suv, double svv, bool seed_literal);

  // Cycles one fragment occupies the probe datapath: one probe per cycle.
  uint32_t issue_cycles(const FilterStats& s) const { return s.probes > 0 ? s.probes : 1; }
  OpCounts setup_ops() const;
  // Item: one probe: position, weight, address (trilinear), blend.
  OpCounts ops_per_item() const;
  OpCounts probe_setup_ops() const;  // per probe: position and weight only
  TimingSpec timing(const TechTable& tech) const;
  // Name of the arithmetic for reports.
  std::string arithmetic() const;
  std::string name() const { return "filter.multi_probe"; }

 private:
  // The set-up in one number format (T = float or double; fixed point: probes_fixed).
  template <class T>
  ProbeSet probes_t(const Texture& tex, const Fragment& f, FilterStats* st) const;
  ProbeSet probes_fixed(const Texture& tex, const Fragment& f, FilterStats* st) const;
  Config cfg_;
  TexelAddressGen addr_;
};

}  // namespace texsim
