#pragma once
// TerrainRayMarcher: synthesis of finite-function terrain by reverse ray marching (seed 003 §3;
// docs/derivations/terrain.md §5): the view ray of a pixel of the aviation camera advances by
// dt until it is below the interpolated surface, the last step is refined by bisection, and the
// normal is the gradient of F = y(x, z) - Y (or the seed's central differences, ε = 0.004).
// Arithmetic: double throughout (camera, ray, heights).
#include <cstdint>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/geometry/aviation_camera.h"
#include "blocks/geometry/terrain/terrain_height_evaluator.h"
#include "blocks/texture/relief/relief_types.h"

namespace texsim {

class ConfigReader;

class TerrainRayMarcher {
 public:
  enum class NormalMode { Gradient, CentralDifference };
  struct Config {
    TerrainHeightEvaluator::Config evaluator{};
    double step = 0.25;  // dt, in grid units along the unit view ray
    // k of the altitude-dependent step max(dt, k·(Y - y(X, Z))): the ray's height above the
    // ground where it is, times k (0: off, every step dt). Larger steps high above the ground;
    // a step can then cross a ridge that rises ahead of the ray (measured, terrain.md §5.1).
    double altitude_step = 0;
    int32_t max_steps = 4096;   // the iteration cap of the march
    int32_t refine_steps = 10;  // bisections of the last step
    NormalMode normal = NormalMode::Gradient;
    double normal_epsilon = 0.004;  // CentralDifference: the seed's NORMAL_EPSILON
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };
  struct Result {
    bool hit = false;
    bool capped = false;  // max_steps reached without a hit or an exit
    double t = 0;         // ray parameter of the hit (unit view ray)
    glm::dvec3 point{0.0};
    glm::dvec3 normal{0, 1, 0};  // unit, pointing up
    uint32_t steps = 0, refinements = 0;
    uint32_t evaluations = 0;  // height evaluations
    uint32_t fetches = 0;      // grid heights read
  };

  TerrainRayMarcher() = default;
  explicit TerrainRayMarcher(const Config& c) : cfg_(c), eval_(c.evaluator) {}
  const Config& config() const { return cfg_; }
  const TerrainHeightEvaluator& evaluator() const { return eval_; }

  // An upper bound of the interpolated heights of `g` (once per grid).
  double top_bound(const TerrainGrid& g) const;
  // Marches the view ray of pixel (xs, ys). `top` bounds the interpolated heights (top_bound):
  // the march starts where the ray comes down to it, and a ray above it going up misses.
  Result march(const AviationCamera& cam, const TerrainGrid& g, double top, double xs, double ys,
               OpCounts& ops) const;
  // The same march for any ray from `eye` along `dir` (any length; grid units, y up), without
  // the normal (`normal` stays up): the terrain relief effect feeds it the view rays of the
  // scene camera's fragments (pipeline/texture/surface_effects.h). `reads`, when given, gets
  // every grid node the evaluator reads, in read order, as the height texel (i, j)
  // (ReliefRead::kHeightRead): the grid is a height map's level 0, node (i, j) its texel (i, j).
  Result march_ray(const TerrainGrid& g, double top, const glm::dvec3& eye, const glm::dvec3& dir,
                   OpCounts& ops, std::vector<ReliefRead>* reads = nullptr) const;

  // Item: one march step (position update, one height evaluation, the compare).
  OpCounts ops_per_item() const;
  OpCounts critical_path() const;
  OpCounts ray_setup_ops() const;  // the view vector, its normalisation, the skip to `top`
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "relief.terrain_ray_marcher"; }
  std::string arithmetic() const { return "double"; }

 private:
  glm::dvec3 normal_at(const TerrainGrid& g, double x, double z, Result& r, OpCounts& ops) const;
  Config cfg_{};
  TerrainHeightEvaluator eval_{};
};

}  // namespace texsim
