#pragma once
// TerrainHeightEvaluator: the height y(x, z) = Σ h_ij f^k(x - i) f^k(z - j) of a terrain grid
// interpolated with a finite function (seed 003 §2.3–2.4; docs/derivations/terrain.md), and its
// normal from the gradient of F = y(x, z) - Y.
//  - 2 × 2 supports (no deformation, variant 2): the seed's 3-multiplication form
//    A = h2 + (h1 - h2) f(zd), B = h4 + (h3 - h4) f(zd), y = B + (A - B) f(xd) (eq. 2.51–2.52);
//    the 8-multiplication form (eq. 2.50) is kept as the comparison.
//  - variant 1 (support 3/2): y = F(xp) Ŷ F(zp)ᵀ over 3 × 3 heights, x̂ = ⌊x + 1/2⌋.
// Arithmetic: double.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/geometry/terrain/finite_function.h"
#include "blocks/geometry/terrain/terrain_grid.h"

namespace texsim {

class ConfigReader;

// A grid node an evaluation read, clamped to the grid as the read is (TerrainGrid::node).
struct TerrainNode {
  int32_t i = 0, j = 0;
  bool operator==(const TerrainNode&) const = default;
};

class TerrainHeightEvaluator {
 public:
  struct Config {
    FiniteBasis basis{};
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };
  struct Sample {
    double y = 0;
    double dydx = 0, dydz = 0;  // the gradient (with_gradient only)
  };

  TerrainHeightEvaluator() = default;
  explicit TerrainHeightEvaluator(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // Height at (x, z); non-finite x or z reads the node (0, 0). `reads`, when given, gets the
  // nodes read, in read order (fetches_per_item() of them, or the one node (0, 0)).
  double height(const TerrainGrid& g, double x, double z, OpCounts& ops,
                std::vector<TerrainNode>* reads = nullptr) const;
  // Height and gradient (normal = (-dydx, 1, -dydz), the seed's eq. after 2.52).
  Sample sample(const TerrainGrid& g, double x, double z, OpCounts& ops) const;
  // The 8-multiplication form of eq. 2.50 (2 × 2 supports only; variant 1 falls back to
  // height()).
  double height_8mul(const TerrainGrid& g, double x, double z, OpCounts& ops) const;

  // Item: one height evaluation.
  OpCounts ops_per_item() const;
  OpCounts critical_path() const;
  OpCounts gradient_ops() const;  // added by sample() for the gradient
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "terrain.height_evaluator"; }
  std::string arithmetic() const { return "double"; }
  // Heights read per evaluation: 4, or 9 for variant 1.
  int32_t fetches_per_item() const {
    return cfg_.basis.deformation == Deformation::Widened ? 9 : 4;
  }

 private:
  Sample sample_2x2(const TerrainGrid& g, double x, double z, bool grad,
                    std::vector<TerrainNode>* reads = nullptr) const;
  Sample sample_3x3(const TerrainGrid& g, double x, double z, bool grad,
                    std::vector<TerrainNode>* reads = nullptr) const;
  OpCounts basis_ops() const;  // one f^k evaluation
  Config cfg_{};
};

}  // namespace texsim
