#pragma once
// Weight map (thesis ch. 3): generator of the precomputed weight texture W over normalised
// footprint coordinates, and the reader that replaces the per-texel weight computation by a
// bilinear (1-D: linear) read of it (docs/derivations/anisotropic-filters.md §2).
// Arithmetic: the generator evaluates W in double and rounds it into the element format
// (u0.8, u0.16 or float); the reader's transform and interpolation are float32.
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/config_reader.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"

namespace texsim {

class WeightMap {
 public:
  // Full2D: W(x, y) on [−1, 1]²; Quarter: W(|x|, |y|) on [0, 1]² (functions symmetric in both
  // axes, 4× less memory); RadialR: W indexed by r = √(x² + y²); RadialR2: indexed by r²
  // (no square root).
  enum class Kind : int { Full2D, Quarter, RadialR, RadialR2 };
  enum class Element : int { U8, U16, Float };
  // The weight function the map holds, of r² = x² + y² (0 from r = 1 on):
  // Exp: exp(−α·r²); Pow8: (1 − α·r²/8)^8, the thesis's formula (4) at q = 2α·r².
  enum class Function : int { Exp, Pow8 };
  // Transform of a texel offset (U, V) to map coordinates (x, y): Jacobian = the thesis's
  // (x, y) = J⁻¹(U, V) with J the fragment's derivatives (ignores the filter's reconstruction
  // term and anisotropy clamp); Cholesky = the triangular square root of the filter's actual
  // quadratic form (x² + y² = Q exactly; y is constant along a row); Seed = the thesis's own
  // formula (5), literally (SeedTransform below: the thesis configuration, exact only for
  // axis-aligned footprints, docs/studies/thesis-configuration.md).
  enum class Transform : int { Jacobian, Cholesky, Seed };

  struct Config {
    Kind kind = Kind::Quarter;
    Element element = Element::U16;
    int size = 64;  // entries per side (2-D kinds) or in all (1-D kinds), ≥ 2
    Function function = Function::Exp;
    double alpha = 2.0;
    Transform transform = Transform::Cholesky;
    // Keys: kind (full2d|quarter|radial_r|radial_r2), element (u8|u16|float), size,
    // function (exp|pow8), alpha, transform (jacobian|cholesky|seed).
    static Config from_toml(const ConfigReader& r);
  };

  WeightMap();
  explicit WeightMap(const Config& c);  // generates the map
  const Config& config() const { return cfg_; }

  // The generator's exact function of r² (double).
  double function(double r2) const;
  int width() const { return w_; }
  int height() const { return h_; }
  // Entry (i, j) as stored (after rounding into the element format).
  float entry(int i, int j) const {
    return data_[static_cast<size_t>(j) * static_cast<size_t>(w_) + static_cast<size_t>(i)];
  }
  // Bytes the map occupies in memory.
  uint64_t bytes() const;

  // Weight at normalised footprint coordinates (x, y) (r = 1 is the footprint's edge): a
  // bilinear read (2-D kinds) or linear read (1-D kinds) of the map, 0 outside the domain.
  // Adds the entries read to `reads` (4 or 2 per call: the datapath reads before the range
  // test selects). Entry k of an axis sits at t = k/(size − 1), so the
  // centre and the edge r = 1 are entries, not interpolated.
  float read(float x, float y, uint32_t& reads) const;

  // Item: one read. Operations: index arithmetic, range test, interpolation, entry reads.
  OpCounts ops_per_item() const;
  OpCounts read_critical_path() const;
  // Per-footprint constants of the transform and per-step increments.
  OpCounts setup_ops() const;
  // Per scanned texel: the incremental transform (2 adds with the Jacobian and the seed's
  // formula, 1 with Cholesky).
  OpCounts ops_per_step() const;
  // One read per cycle per lane, fully pipelined.
  TimingSpec timing(const TechTable& tech) const;
  std::string name() const;        // e.g. "quarter 64x64 u16"
  std::string arithmetic() const;  // the element format, e.g. "u16"

 private:
  Config cfg_;
  int w_ = 0, h_ = 0;
  std::vector<float> data_;
};

// The thesis's formula (5), literally: with the derivatives Ux = ∂u/∂x, Vx = ∂v/∂x,
// Uy = ∂u/∂y, Vy = ∂v/∂y (texels per pixel), A = Vx² + Vy², C = Ux² + Uy² and the footprint
// centre (u0, v0) in texels,
//   x = (Kx − Vy·u + Vx·v)·S,  y = (Ky − Uy·u + Ux·v)·S,
//   S = 1/√(AC),  Kx = u0·Vy − v0·Vx,  Ky = u0·Uy − v0·Ux,
// for a texel at absolute texel coordinates (u, v). Kx, Ky, S are per-footprint constants; the
// per-texel work is one add per coordinate (x += −Vy·S along a row). It pairs x with the V row of
// J and scales by 1/√(AC) instead of 1/det, so it equals J⁻¹(U, V) up to the signs of x and y
// only when Uy = Vx = 0 (an axis-aligned footprint); skewed or rotated footprints get a wrong
// radius (testbench/unit/texture/test_weight_map_seed.cc measures it).
struct SeedTransform {
  double kxs = 0, kys = 0;       // Kx·S, Ky·S
  double xu = 0, xv = 0;         // −Vy·S, Vx·S: ∂x/∂u, ∂x/∂v
  double yu = 0, yv = 0;         // −Uy·S, Ux·S: ∂y/∂u, ∂y/∂v
  double s = 0, kx = 0, ky = 0;  // S, Kx, Ky as the thesis names them
  // S = 0 (A·C = 0 or not finite) maps every texel to (0, 0).
  static SeedTransform from(double ux, double vx, double uy, double vy, double u0, double v0);
  double x(double u, double v) const { return kxs + xu * u + xv * v; }
  double y(double u, double v) const { return kys + yu * u + yv * v; }
  // Per footprint: A, C (4 mul, 2 add), A·C (1 mul), 1/√ (1 sqrt, 1 rcp), Kx, Ky (4 mul,
  // 2 add), the six constants × S (6 mul).
  static OpCounts setup_ops();
};

const char* to_string(WeightMap::Kind k);
const char* to_string(WeightMap::Element e);

}  // namespace texsim
