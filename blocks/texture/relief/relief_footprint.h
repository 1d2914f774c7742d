#pragma once
// ReliefFootprint: the screen-space derivatives of the coordinates a relief method shifted
// (docs/derivations/relief-footprint.md), for LOD and the footprint filters. The shift moves
// (u, v) by a different amount at each pixel, so the footprint after it is deformed: stretched
// where the surface turns away from the view, compressed on slopes that face it.
//  - unshifted: the derivatives of the polygon's coordinates, passed on (no block);
//  - analytic: the chain rule through the shift — the Jacobian of the hit point against the
//    entry point, from the height map's gradient and the shift per unit depth s:
//      offset parallax  x' = x + l·(1 − h(x))        J = I − l ∇hᵀ   (∇h at the entry point)
//      ray hits         d = 1 − h(x + s·d)           J = I − s ∇hᵀ / (1 + ∇h·s)  (∇h at the hit)
//    with the view vector held constant across the pixel;
//  - quad (fine or coarse): differences of the shifted coordinates between the lanes of the
//    fragment's 2×2 quad (QuadAssembler's rules), each lane shifted along its own view ray.
// Units: texels of the height map (texel centres at integers). Arithmetic: double.
#include <cstdint>
#include <string>

#include "blocks/base/datapath.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/relief/relief_types.h"

namespace texsim {

class ConfigReader;

class ReliefFootprint {
 public:
  enum class Mode : uint8_t { Unshifted, Analytic, QuadFine, QuadCoarse };
  // How the shift depends on the entry point: offset parallax reads the height once at the
  // entry; the other methods stop where the ray meets the height field.
  enum class Kind : uint8_t { Offset, RayHit };
  struct Config {
    Mode mode = Mode::Unshifted;
    // Analytic: 1 + ∇h·s is clamped up to 1/max_stretch (near a silhouette the hit point runs
    // away from the entry point without bound).
    double max_stretch = 16;
    Datapath datapath = Datapath::Spatial;
    // Reads `footprint` (and `footprint_max_stretch`) from the relief table.
    static Config from_toml(const ConfigReader& r);
  };
  // Derivatives in height-map texels: (dx/dX, dy/dX) and (dx/dY, dy/dY).
  struct Derivs {
    double xx = 0, yx = 0, xy = 0, yy = 0;
  };

  ReliefFootprint() = default;
  explicit ReliefFootprint(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }
  bool active() const { return cfg_.mode != Mode::Unshifted; }
  bool quad() const { return cfg_.mode == Mode::QuadFine || cfg_.mode == Mode::QuadCoarse; }

  // Analytic: in, the derivatives of the entry point; (gx, gy) where the gradient is read (the
  // entry point for Offset, the hit for RayHit); (sx, sy) the texel shift per unit depth (for
  // Offset the shift per unit of 1 − h, i.e. l).
  Derivs analytic(const ReliefHeightMap& hm, Kind kind, double gx, double gy, double sx, double sy,
                  const Derivs& in, OpCounts& ops) const;
  // The gradient (∂h/∂x, ∂h/∂y) of the bilinear height at (x, y), as bilinear() reads it.
  static void gradient(const ReliefHeightMap& hm, double x, double y, double& hx, double& hy);
  // Quad: the operations of one fragment's differences (the lanes' shifts are the lanes' own).
  static void count_quad(OpCounts& ops) { ops.add += 4; }

  // Item: one fragment's derivatives.
  OpCounts ops_per_item() const;
  OpCounts critical_path() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const;
  std::string arithmetic() const { return "double"; }
  static const char* mode_name(Mode m);

 private:
  Config cfg_{};
};

}  // namespace texsim
