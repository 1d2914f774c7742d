#pragma once
// PolarDotProduct: the scalar product of two vectors given in polar coordinates (the tail
// article of seed 004, Romaniuk, Romaniuk, Blagodyr 2013; docs/derivations/lighting.md §4).
// The seed keeps only the article's title and abstract; the forms below are this project's:
//   2-D, a = (ra, θa), b = (rb, θb):  a·b = ra rb cos(θa − θb);
//   3-D, spherical (r, θ from the z axis, φ about it):
//     a·b = ra rb (sin θa sin θb cos(φa − φb) + cos θa cos θb)
//         = ra rb · ½ ((c1 + c2) + (c1 − c2) c3),
//     c1 = cos(θa − θb), c2 = cos(θa + θb), c3 = cos(φa − φb): three cosines of one unit, no sine.
// The cosine: the angle is wrapped once into [−π, π] (inputs in [−π, π] give differences in
// (−2π, 2π)), folded to |Δ| ∈ [0, π] (cos is even) and read from a table of `table_size`
// intervals over [0, π] holding (cos x_i, cos x_{i+1} − cos x_i), linearly interpolated:
// error ≤ h²/8 with h = π/table_size (1.2·10⁻⁶ for 1024) plus float rounding.
// Arithmetic: float. Any non-finite input gives 0, flagged `invalid`; an angle difference that
// one wrap leaves outside [−π, π] (inputs beyond ±π) is reduced by a remainder, flagged
// `out_of_range` (not part of the counted datapath).
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"

namespace texsim {

class ConfigReader;

class PolarDotProduct {
 public:
  struct Config {
    int dims = 3;               // 2 (polar) or 3 (spherical)
    int32_t table_size = 1024;  // intervals of the cosine table over [0, π], 16..65536
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };
  struct Result {
    float value = 0;
    bool invalid = false;       // a non-finite input: value 0
    bool out_of_range = false;  // an angle difference needed more than one wrap
  };

  PolarDotProduct() : PolarDotProduct(Config{}) {}
  explicit PolarDotProduct(const Config& c);
  const Config& config() const { return cfg_; }

  Result dot2(float ra, float ta, float rb, float tb, OpCounts& ops) const;
  Result dot3(float ra, float theta_a, float phi_a, float rb, float theta_b, float phi_b,
              OpCounts& ops) const;
  // The cosine unit alone (angle any finite float; out_of_range as above).
  float cosine(float angle, bool& out_of_range, OpCounts& ops) const;

  // Item: one product of the configured dimension.
  OpCounts ops_per_item() const;
  OpCounts critical_path() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const {
    return cfg_.dims == 2 ? "lighting.polar_dot_product[2d]" : "lighting.polar_dot_product[3d]";
  }
  std::string arithmetic() const { return "float, cosine by table + linear interpolation"; }

  // The comparison: a Cartesian dot product of `dims` components, and the same after turning
  // two polar vectors into Cartesian ones (each sin and cos from this block's cosine unit).
  static OpCounts cartesian_ops(int dims, bool from_polar);
  static OpCounts cartesian_critical_path(int dims, bool from_polar);

 private:
  static OpCounts cosine_ops();  // one cosine: wrap, fold, index, table read, interpolation
  Config cfg_{};
  std::vector<float> value_, slope_;  // table_size + 1 entries (the last for |Δ| = π)
  float scale_ = 0;                   // table_size / π
};

}  // namespace texsim
