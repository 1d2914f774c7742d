#pragma once
// DistanceMapBuilder: the precompute tool of the distance-map relief method (thesis ch. 4,
// fig. 14–16; docs/derivations/relief.md §2–3). From a height map it builds
//  - the classic map (Donnelly): per voxel, the Euclidean distance from its centre to the
//    centre of the nearest solid voxel;
//  - the refined map (thesis ch. 4): per voxel, the smallest step that an admissible view ray
//    through it, not blocked before it, can take and still land inside its first solid run.
// It runs once per height map, off the pipeline, so it is a tool, not a clocked block: the
// tracer that reads its maps (SphereTracer) is the block.
// Arithmetic: double for every distance and ray parameter; the maps store float.
#include <cstdint>
#include <string>

#include "blocks/texture/relief/relief_types.h"

namespace texsim {

class ConfigReader;

class DistanceMapBuilder {
 public:
  struct Config {
    int32_t depth = 16;          // layers of the volume (height 1 = depth layers)
    double cone_deg = 45;        // admissible view directions: within this angle of the normal
    int32_t polar_steps = 4;     // sampled polar angles in (0, cone_deg] (plus the normal)
    int32_t azimuth_steps = 16;  // sampled azimuths per polar angle
    double penetration = 0.5;    // how far past the entry into solid a refined step may land
    static Config from_toml(const ConfigReader& r);
  };

  DistanceMapBuilder() = default;
  explicit DistanceMapBuilder(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // Classic map. Exact: a voxel's nearest solid centre is in a column within its height + 1
  // (the base lies that far below it), so only that window is searched.
  DistanceMap classic(const ReliefHeightMap& hm) const;
  // Refined map. A voxel that no sampled admissible ray reaches unblocked, or whose every such
  // ray leaves the volume without a hit, keeps its classic value.
  DistanceMap refined(const ReliefHeightMap& hm) const;

  // The refined value of one voxel (also used by tests); `classic_value` is the fallback.
  double refined_voxel(const ReliefHeightMap& hm, int32_t x, int32_t y, int32_t z,
                       double classic_value) const;
  // Layers solid in column (x, y): voxel z is solid when z < solid_layers (NaN heights: 0).
  double solid_layers(const ReliefHeightMap& hm, int32_t x, int32_t y) const {
    return static_cast<double>(hm.texel(x, y)) * cfg_.depth;
  }
  std::string name() const { return "relief.distance_map_builder"; }

 private:
  Config cfg_{};
};

}  // namespace texsim
