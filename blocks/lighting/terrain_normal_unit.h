#pragma once
// TerrainNormalUnit: the normal of a finite-function terrain for lighting (seed 003 §2.3, §3;
// docs/derivations/lighting.md §2), at the fragment's marched grid position (x, z):
//  - Gradient: one evaluation of height and gradient, n = (-∂y/∂x, 1, -∂y/∂z) (the seed's
//    formula after eq. 2.52);
//  - CentralDifference: the seed's synthesis program, four height evaluations at x ± ε, z ± ε
//    (NORMAL_EPSILON = 0.004), ∂y/∂x ≈ (y(x + ε) - y(x - ε)) / 2ε.
// The heights come from TerrainHeightEvaluator (double, as the relief's marcher); the normal is
// normalised in float by NormalUnit (the colour datapath's format). Grid frame: x, z on the
// map, y up. A non-finite or zero normal is the up vector (flagged).
#include <cstdint>
#include <glm/vec3.hpp>
#include <string>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/geometry/terrain/terrain_grid.h"
#include "blocks/geometry/terrain/terrain_height_evaluator.h"
#include "blocks/lighting/normal_unit.h"

namespace texsim {

class ConfigReader;

class TerrainNormalUnit {
 public:
  enum class Method : uint8_t { Gradient, CentralDifference };
  struct Config {
    TerrainHeightEvaluator::Config evaluator{};  // the relief's finite function
    Method method = Method::Gradient;
    double epsilon = 0.004;  // CentralDifference: the seed's NORMAL_EPSILON, grid units
    Datapath datapath = Datapath::Spatial;
    // Keys `method` (gradient, central_difference), `epsilon`, `datapath` and the evaluator's
    // `function`, `deformation`, `blend_shift`.
    static Config from_toml(const ConfigReader& r);
  };
  struct Result {
    glm::vec3 n{0, 1, 0};  // unit, grid frame, y up
    bool fallback = false;
  };

  TerrainNormalUnit() = default;
  explicit TerrainNormalUnit(const Config& c);
  const Config& config() const { return cfg_; }

  Result normal(const TerrainGrid& g, double x, double z, OpCounts& ops) const;

  // Item: one normal (the evaluations, the differences, the float normalisation).
  OpCounts ops_per_item() const;
  OpCounts critical_path() const;
  TimingSpec timing(const TechTable& t) const;
  // Height evaluations per normal: 1 or 4.
  uint32_t evaluations() const { return cfg_.method == Method::Gradient ? 1 : 4; }
  std::string name() const {
    return cfg_.method == Method::Gradient ? "lighting.terrain_normal[gradient]"
                                           : "lighting.terrain_normal[central_difference]";
  }
  std::string arithmetic() const { return "double heights, float normalisation"; }

 private:
  OpCounts difference_ops() const;  // the part between the evaluations and the normaliser
  Config cfg_{};
  TerrainHeightEvaluator eval_{};
  NormalUnit normalise_{};
};

}  // namespace texsim
