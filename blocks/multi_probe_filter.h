#pragma once
// Multi-ellipse probe filter (Mavridis & Papaioannou; seed 004 eq. 12–17): the footprint
// ellipse approximated by N trilinear probes along its major axis, N = 2·R_major/(α·R_minor) − 1
// (odd), spread over L = 2·(R_major − α·R_minor), weighted by a Gaussian of their distance to
// the centre; optionally half the probes per frame, alternating (docs/anisotropic-filters.md §4).
// Arithmetic: float32 set-up and probe positions; probes through the trilinear texel address
// generator (u0.8 weights); float32 blend. This header also holds the probe executor that
// FelineFilter shares.
#include <array>
#include <cstdint>
#include <vector>

#include "blocks/config_reader.h"
#include "blocks/ewa_filter.h"
#include "blocks/op_counts.h"
#include "blocks/tech_table.h"
#include "blocks/texel_address_gen.h"
#include "blocks/texture_memory.h"
#include "blocks/timing_spec.h"
#include "traces/fragment.h"

namespace texsim {

// A set of weighted isotropic probes at one LOD (normalised coordinates).
struct ProbeSet {
  static constexpr int kMax = 31;
  int n = 0;
  std::array<double, kMax> u{}, v{};
  std::array<float, kMax> w{};
  float lambda = 0;
};

// Runs each probe as a trilinear lookup (TexelAddressGen, one probe per cycle), blends its 8
// taps and sums the probes with their weights, normalised by Σw (all weights zero: the
// probes' plain mean). Appends the taps' texels to `fetched`; counts address, blend and
// weighting operations.
FilterOutput run_probes(const TexelAddressGen& addr, const Texture& tex, const ProbeSet& probes,
                        std::vector<TexelRef>* fetched, OpCounts& ops);
// Operations of run_probes per probe besides TexelAddressGen's (blend 8 taps, weighting) and
// per fragment (normalisation).
OpCounts probe_blend_ops();
// A trilinear probe's blend (8 taps through TexelBlend) plus its weighting.
OpCounts trilinear_probe_blend_ops();
OpCounts probe_normalise_ops();

class MultiProbeFilter {
 public:
  struct Config {
    double alpha = 1.0;        // the seed's α: a probe's radius in minor radii (spacing α·R_minor)
    int max_probes = 15;       // odd, ≤ 31
    double weight_alpha = 2.0; // probe weight exp(−w_α·(d/R_major)²): EWA's pixel model
    double radius_px = 1.0;    // R: footprint radius in pixels
    double max_aniso = 64;     // minor axis stretched to ≥ major/max_aniso before N is taken
    bool seed_theta = false;   // θ = atan(B/(A−C))/2 as printed (loses the quadrant)
    bool temporal = false;     // alternate probe subsets between frames (0, ±2, ±4 … / 0, ±1, ±3 …)
    AddressMode address_u = AddressMode::Wrap;
    AddressMode address_v = AddressMode::Wrap;
    // Keys: alpha, max_probes, weight_alpha, radius_px, max_aniso, seed_theta, temporal,
    // address_u, address_v.
    static Config from_toml(const ConfigReader& r);
  };

  MultiProbeFilter() : MultiProbeFilter(Config{}) {}
  explicit MultiProbeFilter(const Config& c);
  const Config& config() const { return cfg_; }

  // The probes of one fragment (positions, weights, LOD); adds the set-up operations.
  ProbeSet probes(const Texture& tex, const Fragment& f, OpCounts& ops, FilterStats* st = nullptr) const;
  FilterOutput filter(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                      OpCounts& ops) const;

  // Major-axis angle from the footprint covariance: ½·atan2(2Σuv, Σuu − Σvv), or the seed's
  // printed ½·atan(B/(A − C)) with A = Σvv, B = −2Σuv, C = Σuu of the quadratic form.
  static double major_angle(double suu, double suv, double svv, bool seed_literal);

  // Cycles one fragment occupies the probe datapath: one probe per cycle.
  uint32_t issue_cycles(const FilterStats& s) const { return s.probes > 0 ? s.probes : 1; }
  OpCounts setup_ops() const;
  OpCounts per_probe_ops() const;  // position, weight, address (trilinear), blend
  TimingSpec timing(const TechTable& tech) const;

 private:
  Config cfg_;
  TexelAddressGen addr_;
};

}  // namespace texsim
