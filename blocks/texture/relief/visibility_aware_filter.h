#pragma once
// VisibilityAwareFilter: anisotropic filtering on a relief surface that leaves out texels the
// viewer cannot see (thesis ch. 4, fig. 11–13; docs/derivations/relief.md §6). The footprint is
// the EWA ellipse of the pixel (Gaussian weights); its texels are scanned row by row, and each
// scanned texel's visibility is found by tracing the view vector from its surface point up
// through the height field:
//  - a visible texel is counted with its weight;
//  - a hidden texel is replaced by the texel that hides it (the one the view ray sees), which
//    a buffer of already-counted texels keeps from being counted twice;
//  - at the first hidden texel of a row the forward scan stops, and the row is scanned again
//    from its last texel backwards until the next hidden texel; the texels between are taken
//    as hidden without tracing.
// Extra work against plain filtering: the traces' height reads, the occluders' colour reads,
// and the buffer look-ups, all counted.
// Arithmetic: double positions and weights, float colours and heights; nearest-texel height
// reads along the traces.
#include <cstdint>
#include <glm/vec4.hpp>
#include <string>
#include <vector>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/relief/relief_types.h"

namespace texsim {

class ConfigReader;

class VisibilityAwareFilter {
 public:
  struct Config {
    double depth_texels = 4;       // relief depth (height 0) below the polygon, in texels
    double trace_step = 0.5;       // step of a visibility trace, texels along the ray
    int32_t max_trace_steps = 64;  // a trace that reaches it counts the texel visible
    double min_view_z = 0.05;      // V.z (unit V) clamped up to this
    int32_t max_radius = 32;       // footprint half-extent cap, texels
    bool row_rule = true;          // false: trace every texel (the exact classification)
    bool visibility = true;        // false: plain EWA (every texel counted)
    Datapath datapath = Datapath::Spatial;
    static Config from_toml(const ConfigReader& r);
  };
  // A colour texture at the height map's resolution.
  struct ColourMap {
    int32_t width = 0, height = 0;
    std::vector<glm::vec4> c;
    glm::vec4 texel(int32_t x, int32_t y) const;
  };
  struct Footprint {
    double u = 0, v = 0;                    // centre, texel coordinates
    double ux = 1, vx = 0, uy = 0, vy = 1;  // derivatives, texels per pixel
  };
  struct Stats {
    uint32_t texels = 0;  // texels inside the ellipse
    uint32_t traced = 0;  // visibility traces run
    uint32_t visible = 0, hidden = 0;
    uint32_t skipped = 0;       // taken as hidden by the row rule, not traced
    uint32_t trace_reads = 0;   // height reads of the traces
    uint32_t colour_reads = 0;  // colour texels read (visible texels and occluders)
    uint32_t buffer_hits = 0;   // occluders already counted (double counts avoided)
    uint32_t capped = 0;        // traces that reached max_trace_steps
    bool fallback = false;      // nothing counted, or bad input: the centre texel / plain EWA
  };
  struct Result {
    glm::vec4 colour{0.0F};
    Stats stats;
  };

  VisibilityAwareFilter() = default;
  explicit VisibilityAwareFilter(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // (vx, vy, vz): tangent-space vector towards the eye (non-finite or zero: plain EWA,
  // flagged). `log`, when given, gets every counted height and colour read (for a cache model).
  Result filter(const ReliefHeightMap& hm, const ColourMap& tex, const Footprint& fp, double vx,
                double vy, double vz, OpCounts& ops, std::vector<ReliefRead>* log = nullptr) const;

  // Visibility of texel (x, y) along the unit view vector; on false, (ox, oy) is the texel
  // that hides it. Adds its height reads to `reads` (and their texels to `log` when given).
  bool visible(const ReliefHeightMap& hm, int32_t x, int32_t y, double nx, double ny, double nz,
               int32_t& ox, int32_t& oy, uint32_t& reads, bool& capped,
               std::vector<ReliefRead>* log = nullptr) const;

  // Item: one footprint texel (weight, colour read, accumulate) — the plain filter's cost.
  OpCounts ops_per_item() const;
  OpCounts trace_step_ops() const;  // one step of a visibility trace
  OpCounts critical_path() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "relief.visibility_aware_filter"; }
  std::string arithmetic() const { return "double weights, float colours"; }

 private:
  Config cfg_{};
};

}  // namespace texsim
