#pragma once
// ParallaxMapper: parallax mapping over a height map with a tangent-space view vector
// (docs/derivations/relief.md §1): offset parallax (one height read; with or without offset
// limiting) and the iterative variant (steep parallax's linear search over depth layers, then
// relief mapping's binary refinement). The polygon lies on the top of the relief (height 1);
// height h lies (1 - h)·depth_texels below it.
// Arithmetic: double throughout; heights are the map's float values, read bilinearly.
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/relief/relief_types.h"

namespace texsim {

class ConfigReader;

class ParallaxMapper {
 public:
  enum class Method { Offset, Iterative };
  struct Config {
    Method method = Method::Iterative;
    double depth_texels = 4;      // depth of the relief (height 0) below the polygon, in texels
    bool offset_limiting = true;  // Offset: shift by V.xy·d, not V.xy/V.z·d (bounded at grazing)
    double min_view_z = 0.05;     // V.z (of the unit view vector) is clamped up to this
    int32_t min_layers = 8;       // Iterative: layers at normal incidence ...
    int32_t max_layers = 32;      // ... and at grazing incidence (the iteration cap)
    int32_t binary_steps = 5;     // Iterative: halvings of the bracketing layer
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };
  struct Result {
    double u = 0, v = 0;  // shifted texel coordinates
    double depth = 0;     // depth of the found point, 0 (polygon) .. 1 (height 0)
    uint32_t linear_steps = 0, binary_steps = 0;
    uint32_t samples = 0;    // bilinear height reads (4 texels each)
    bool bad_input = false;  // non-finite u, v or view vector: (u, v) returned unshifted
  };

  ParallaxMapper() = default;
  explicit ParallaxMapper(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // (u, v): texel coordinates where the view ray meets the polygon; (vx, vy, vz): tangent-space
  // vector from the surface towards the eye (any length; vz > 0 above the surface). A view
  // vector parallel to (or below) the surface is clamped to vz = min_view_z. `reads`, when
  // given, gets the texels of every height read (for a cache model).
  Result map(const ReliefHeightMap& hm, double u, double v, double vx, double vy, double vz,
             OpCounts& ops, std::vector<ReliefRead>* reads = nullptr) const;

  // Item: one height step (a linear or binary step, or the offset method's one read).
  OpCounts ops_per_item() const;
  OpCounts critical_path() const;
  OpCounts fragment_setup_ops() const;  // per fragment: normalise V, clamp, 1/V.z, layer count
  TimingSpec timing(const TechTable& t) const;
  std::string name() const {
    return cfg_.method == Method::Offset ? "relief.parallax_offset" : "relief.parallax_iterative";
  }
  std::string arithmetic() const { return "double"; }

 private:
  Result offset(const ReliefHeightMap& hm, double u, double v, double sx, double sy, double lx,
                double ly, OpCounts& ops, std::vector<ReliefRead>* reads) const;
  Result iterative(const ReliefHeightMap& hm, double u, double v, double sx, double sy, double vz,
                   OpCounts& ops, std::vector<ReliefRead>* reads) const;
  Config cfg_{};
};

}  // namespace texsim
