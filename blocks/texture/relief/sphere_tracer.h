#pragma once
// SphereTracer: the ray loop of the distance-map relief method (Donnelly; thesis ch. 4): read
// the distance at the ray's voxel, step that far, until a solid voxel (distance 0) is reached,
// the ray leaves the volume, or the iteration cap is hit (docs/derivations/relief.md §2–4).
// The same loop reads the classic or the refined map: only the map differs.
// Arithmetic: double positions and steps; the map's float distances; nearest-voxel reads.
#include <cstdint>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/relief/relief_types.h"

namespace texsim {

class ConfigReader;

class SphereTracer {
 public:
  struct Config {
    int32_t max_iterations = 64;  // steps per ray; a ray that needs more ends Capped
    double min_step = 0.0;        // lower bound of a step (0: the map's value as is)
    // Subtracted from every distance read before stepping: a point of a voxel can be up to
    // √3/2 nearer the surface than the voxel's centre, so a margin trades iterations for fewer
    // voxels stepped through (docs/derivations/relief.md §4). Needs min_step > 0.
    double safety = 0.0;
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };
  enum class Status { Hit, Miss, Capped, Invalid };
  struct Result {
    Status status = Status::Invalid;
    glm::dvec3 pos{0.0};      // where the ray stopped (in the solid voxel on a hit)
    uint32_t iterations = 0;  // steps taken
    uint32_t fetches = 0;     // distance-map reads
  };

  SphereTracer() = default;
  explicit SphereTracer(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // Traces from `start` (voxel coordinates; a start above the volume first moves down to its
  // top) along `dir` (any length, normalised here). Non-finite or zero inputs: Invalid, no
  // reads. A ray parallel to the surface ends Miss at a side or Capped. `reads`, when given,
  // gets the voxel of every fetch (for a cache model).
  Result trace(const DistanceMap& m, const glm::dvec3& start, const glm::dvec3& dir, OpCounts& ops,
               std::vector<ReliefRead>* reads = nullptr) const;

  // Item: one iteration (read, hit test, step).
  OpCounts ops_per_item() const;
  OpCounts critical_path() const;
  // Once per ray: normalising the direction, moving to the volume's top.
  OpCounts ray_setup_ops() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "relief.sphere_tracer"; }
  std::string arithmetic() const { return "double positions, float distances"; }

 private:
  Config cfg_{};
};

}  // namespace texsim
