#pragma once
// NormalUnit: the per-fragment normal of the lighting subsystem (ПРО; docs/derivations/
// lighting.md §2), from one of three sources:
//  - a normal map texel (RGB in [0, 1] encoding n = 2c - 1, tangent space, z out of the surface);
//  - a height map: central differences of the four neighbouring texels, scaled by bump_scale
//    (tangent space);
//  - terrain: the gradient of a finite-function height field, n = (-∂y/∂x, 1, -∂y/∂z)
//    (world space, y up: TerrainHeightEvaluator::sample gives the gradient).
// A non-finite or zero normal is replaced by the source's up vector (flagged).
// Arithmetic: float (the colour datapath's format); the height map's float heights.
#include <cstdint>
#include <glm/vec3.hpp>
#include <string>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/relief/relief_types.h"

namespace texsim {

class ConfigReader;

class NormalUnit {
 public:
  enum class Source { NormalMap, HeightMap, Terrain };
  struct Config {
    Source source = Source::NormalMap;
    double bump_scale = 4.0;  // HeightMap: height units per texel of the relief
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };
  struct Result {
    glm::vec3 n{0, 0, 1};
    bool fallback = false;  // the input gave no usable normal: the up vector was used
  };

  NormalUnit() = default;
  explicit NormalUnit(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  Result from_map(const glm::vec3& rgb, OpCounts& ops) const;
  Result from_height(const ReliefHeightMap& hm, int32_t x, int32_t y, OpCounts& ops) const;
  Result from_terrain(double dydx, double dydz, OpCounts& ops) const;

  // Item: one normal of the configured source.
  OpCounts ops_per_item() const;
  OpCounts critical_path() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "lighting.normal_unit"; }
  std::string arithmetic() const { return "float"; }

 private:
  static Result normalise(const glm::vec3& v, const glm::vec3& up);
  Config cfg_{};
};

}  // namespace texsim
