#pragma once
// EWA filter (Greene & Heckbert): footprint set-up with max-anisotropy clamp, reconstruction
// term and texel budget, level selection from the minor axis, bounding-box (or row-span) scan
// with incremental Q, and Gaussian weights from a LUT, computed (exp or power-8) or read from
// a weight map (docs/derivations/anisotropic-filters.md §1–§3); optionally a V(d) sub-texel cut-off
// of the texels within half a texel of the ellipse boundary (§9). Arithmetic: set-up in float or
// double; per-texel Q in float, double or fixed s18.30; colour accumulation in float (double for
// the double datapath); with edge = "vd" the boundary distance in float (double for the double
// datapath) and the cut-off fraction in the cut-off's format (float, double, fixed u0.F/s1.F/u1.F).
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
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

class WeightMap;

// A fixed-point Q datapath: 18 integer bits (with sign) hold Q at the bounding-box corners of
// footprints up to 256:1 anisotropy; 30 fraction bits keep the incremental drift along a row of
// 1024 texels below 2.5·10⁻⁴ (docs/derivations/anisotropic-filters.md §1.4).
using EwaQFixed = number_format_t<NumberFormat::S18_30>;

class EwaFilter {
 public:
  // Thesis: the thesis configuration's weight, (1 − q′/16)^8 at q′ = 2α·(x′²/L² + y′²/d²) with
  // the seed's θ/L/d rule as printed (cos θ = Ux/L, sin θ = Vy/d, L² = C, d² = A: GaussianAxes::
  // SeedLiteral) from the fragment's J scaled by R at the level read; wrong even for axis-aligned
  // footprints (weight error 0.25 on a circle), kept so its error can be measured
  // (docs/studies/thesis-configuration.md). The inside test stays the filter's Q < 1.
  enum class Weight : int { Lut, Exp, Pow8, Map, Uniform, Thesis };
  enum class Mip : int { Nearest, Linear };
  enum class Scan : int { Box, RowSpan };
  // arith: "float", "double" or "fixed" (Q in EwaQFixed).
  static constexpr NumberFormatChoices<NumberFormat::Float, NumberFormat::Double,
                                       NumberFormat::S18_30>
      kArith{{"float", "double", "fixed"}};
  enum class Edge : int { None, Vd };

  struct Config {
    Weight weight = Weight::Lut;  // Uniform: weight 1 inside the ellipse (no pixel model)
    int lut_size = 256;           // Gaussian table entries over Q ∈ [0, 1)
    int lut_bits = 16;            // fraction bits of a table entry (0 = float entries)
    double alpha = 2.0;           // weight exp(−α·Q): σ = R/√(2α) pixels
    double radius_px = 1.0;       // R: the ellipse Q = 1 is the pixel footprint scaled by R
    double max_aniso = 16;        // minor axis stretched to at least major/max_aniso
    int texel_budget = 1024;      // bounding-box texels per level at most (coarser level else)
    double reconstruction = 1.0;  // texel² added to Σ's diagonal at the level read (0 = off)
    double minor_texels = 1.0;  // level: minor radius / 2^level ∈ [minor_texels, 2·minor_texels)
    Mip mip = Mip::Nearest;
    Scan scan = Scan::Box;
    NumberFormat arith = NumberFormat::Float;
    AddressMode address_u = AddressMode::Wrap;
    AddressMode address_v = AddressMode::Wrap;
    int lanes = 4;  // texels whose weight is evaluated per cycle
    // Vd: a texel inside the ellipse whose centre lies within half a texel of the boundary
    // Q = 1 gets its weight × W(d)/W(−½) (SubtexelCutoff), d the distance to the boundary in
    // texels (d < 0 inside). vd.lanes = cut-off units per texel lane.
    Edge edge = Edge::None;
    SubtexelCutoff::Config vd;
    // Keys: weight (lut|exp|pow8|map|uniform|thesis), lut_size, lut_bits, alpha, radius_px,
    // max_aniso, texel_budget, reconstruction, minor_texels, mip (nearest|linear), scan
    // (box|row_span), arith (float|double|fixed), address_u, address_v (wrap|clamp|mirror), lanes,
    // the subtable weight_map (WeightMap::Config) for weight = "map", edge (none|vd) and the
    // subtable vd (SubtexelCutoff::Config: evaluator, format, lanes) for edge = "vd".
    static Config from_toml(const ConfigReader& r);
  };

  EwaFilter();
  explicit EwaFilter(const Config& c);
  // With weight = Map, `map` supplies the weights (the filter keeps a shared reference).
  EwaFilter(const Config& c, std::shared_ptr<const WeightMap> map);
  ~EwaFilter();
  EwaFilter(const EwaFilter&);
  EwaFilter& operator=(const EwaFilter&);

  const Config& config() const { return cfg_; }
  const std::vector<double>& lut() const { return lut_; }
  const WeightMap* weight_map() const { return map_.get(); }
  SubtexelCutoff cutoff() const { return SubtexelCutoff(cfg_.vd); }

  // Filters one fragment (u, v and derivatives in normalised coordinates). Appends every
  // texel read to `fetched` (if not null) and adds the operations performed to `ops`.
  FilterOutput filter(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                      OpCounts& ops) const;
  // The datapath in one number format: T = float, double or EwaQFixed.
  template <class T>
  FilterOutput filter_t(const Texture& tex, const Fragment& f, std::vector<TexelRef>* fetched,
                        OpCounts& ops) const;

  // Signed distance in texels from a point to the ellipse boundary Q = 1 (negative inside),
  // from Q ≥ 0 and ∇Q = (∂Q/∂U, ∂Q/∂V) there: d = (√Q − 1)/|∇√Q| = 2(Q − √Q)/|∇Q|, the
  // distance to the boundary's tangent at the point's radial projection onto it (exact on the
  // axes and for circles; docs/derivations/anisotropic-filters.md §9). ∇Q = 0 (the centre) gives
  // −∞.
  template <class S>
  static S boundary_distance(S q, S gx, S gy) {
    const S g2 = gx * gx + gy * gy;
    if (!(g2 > S(0))) return -std::numeric_limits<S>::infinity();
    return S(2) * (q - std::sqrt(q)) / std::sqrt(g2);
  }

  // Weight of a texel at normalised distance Q (the configured source; Map and Thesis
  // excluded: they depend on the texel's offset, not on Q alone).
  double weight_of(double q) const;
  // The Thesis weight of the texel at offset (U, V) texels from the centre of a footprint whose
  // derivatives (texels per pixel, R included) are ux = ∂u/∂x, vx, uy, vy: (1 − 2α·q′/16)^8.
  static double thesis_weight(double alpha, double ux, double vx, double uy, double vy, double U,
                              double V);

  // Scan cycles one fragment occupies: ⌈visited / lanes⌉, at least 1.
  uint32_t issue_cycles(const FilterStats& s) const;
  // Item: one scanned box texel (scan + inside test); per texel inside: weight, address,
  // read, multiply-accumulate.
  OpCounts ops_per_item() const;
  OpCounts ops_per_inside() const;
  // With edge = "vd": per level, the band set-up (minor radius, Q threshold); per texel in the
  // band, the boundary distance, the cut-off and the weight's scaling.
  OpCounts ops_edge_setup() const;
  OpCounts ops_per_edge_texel() const;
  // Latency: set-up, one texel's path and the normalisation in sequence; ii = 1 per lane
  // group; area: set-up + `lanes` texel datapaths + normaliser.
  TimingSpec timing(const TechTable& tech) const;
  // Name of the arithmetic for reports.
  std::string arithmetic() const;
  std::string name() const { return "filter.ewa"; }

 private:
  void build_lut();
  Config cfg_;
  std::vector<double> lut_;
  std::shared_ptr<const WeightMap> map_;
};

const char* to_string(EwaFilter::Weight w);

}  // namespace texsim
