#pragma once
// ObjectSpaceRaster: the rasteriser of object-space texturing (docs/derivations/object-space.md
// §2): it walks a polygon already rotated parallel to the screen (PolygonRotation) on a square
// grid of step h in its own plane and gives every sample its texture coordinates, which are
// affine in the plane (exact, no division), and one LOD for the whole polygon.
//
// Hole-free rule. With Jmax = max over the polygon of the screen length of a unit step in the
// plane, bounded by max_v (z_c / Z_v) · √(1 + max_v |q_v|²) over the vertices v (q = (X, Y)/Z;
// both factors are largest at a vertex of a convex polygon), the step is h = s / Jmax with
// s = max_step_px (default 3/4). Samples: the grid points inside the polygon, plus points on
// every edge at spacing <= h (vertices included). A point p of the polygon lies in a grid cell
// whose part inside the polygon is convex with diameter <= h√2; p is within h√2/√3 of one of
// its corners (a triangle with sides <= D is covered by disks of radius D/√3 at its vertices),
// and each corner is a sample or within h/2 of an edge sample along the edge: every point of the
// polygon is within (√(2/3) + 1/2) h ≈ 1.316 h of a sample along a path inside the polygon, so
// within 1.316 s < 1 pixel on the screen for s <= 3/4. Every pixel whose centre the polygon
// covers therefore gets a positive weight from the 4-pixel splat (weights vanish only at a
// distance of one pixel along x or y). Tested over a sweep of tilts and resolutions.
// Arithmetic: double.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/geometry/polygon_rotation.h"

namespace texsim {

class ConfigReader;

// Texture coordinates as an affine function of the rotated plane: u = u0 + ux x' + uy y'.
struct PlaneUvMap {
  double u0 = 0, ux = 0, uy = 0, v0 = 0, vx = 0, vy = 0;
};

struct PlaneSample {
  double x = 0, y = 0;  // in the rotated plane
  double u = 0, v = 0;  // normalised texture coordinates
};

struct ObjectSpaceRasterStats {
  uint64_t polygons = 0, rows = 0, grid_samples = 0, edge_samples = 0;
};

class ObjectSpaceRaster {
 public:
  struct Config {
    double max_step_px = 0.75;  // s: screen length of one grid step at most (hole-free: < 0.76)
    int lanes = 1;              // samples produced per cycle
    static Config from_toml(const ConfigReader& r);
  };
  ObjectSpaceRaster() = default;
  explicit ObjectSpaceRaster(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  // Jmax of a polygon given by its view-space vertices (all with Z > 0): pixels per unit step
  // in its plane at most. 0 if a vertex is not in front of the eye. Per vertex 1 rcp 5 mul 2
  // add 2 cmp, then 1 sqrt 1 mul 1 add.
  static double max_screen_scale(const std::vector<glm::dvec3>& view, double focal_px,
                                 OpCounts& ops);
  // h = max_step_px / Jmax (0 when Jmax is 0 or not finite): 1 rcp 1 mul.
  double step(double jmax, OpCounts& ops) const;
  // The polygon's one LOD: log2 of the texels (of a tw × th level 0) one step spans along the
  // longer of the two plane axes: 4 mul 2 add 2 mul 1 cmp 1 lut (log2) 1 sqrt.
  static double lod(const PlaneUvMap& m, double h, int tw, int th, OpCounts& ops);
  // The affine map of a polygon from three rotated vertices and their texture coordinates.
  static PlaneUvMap uv_map(const glm::dvec2 p[3], const glm::dvec2 uv[3], OpCounts& ops);
  // Upper bound of the samples of a polygon (area / h² plus the edge samples and one row and
  // column of slack), for refusing too dense polygons before walking them.
  static double sample_bound(const RotatedPolygon& poly, double h);
  // Walks the polygon: grid samples row by row (span ends per row from the edges, then one add
  // per sample and coordinate), then the edge samples. Calls emit(const PlaneSample&).
  template <class F>
  void rasterize(const RotatedPolygon& poly, double h, const PlaneUvMap& m, F&& emit,
                 ObjectSpaceRasterStats& st, OpCounts& ops) const;

  OpCounts ops_per_item() const;  // item: one sample (x step, u and v steps, span compare)
  OpCounts row_ops() const;       // per grid row: span ends from two edges and the first uv
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "raster.object_space"; }
  std::string arithmetic() const { return "double"; }

 private:
  // Span [xl, xr] of the convex polygon on the line y' = y; false if the line misses it.
  static bool span(const RotatedPolygon& poly, double y, double& xl, double& xr);
  Config cfg_{};
};

template <class F>
void ObjectSpaceRaster::rasterize(const RotatedPolygon& poly, double h, const PlaneUvMap& m,
                                  F&& emit, ObjectSpaceRasterStats& st, OpCounts& ops) const {
  ++st.polygons;
  const size_t n = poly.xy.size();
  if (n < 3 || !(h > 0)) return;
  double y0 = poly.xy[0].y, y1 = y0;
  for (const glm::dvec2& p : poly.xy) {
    y0 = std::min(y0, p.y);
    y1 = std::max(y1, p.y);
  }
  const OpCounts per_sample = ops_per_item(), per_row = row_ops();
  for (double j = std::ceil(y0 / h); j * h <= y1; j += 1) {
    const double y = j * h;
    double xl = 0, xr = 0;
    ops += per_row;
    ++st.rows;
    if (!span(poly, y, xl, xr)) continue;
    const double i0 = std::ceil(xl / h), i1 = std::floor(xr / h);
    PlaneSample s;
    s.y = y;
    for (double i = i0; i <= i1; i += 1) {
      s.x = i * h;
      // Evaluated directly (the hardware steps x, u and v by adds; the values are the same).
      s.u = m.u0 + m.ux * s.x + m.uy * y;
      s.v = m.v0 + m.vx * s.x + m.vy * y;
      emit(static_cast<const PlaneSample&>(s));
      ++st.grid_samples;
      ops += per_sample;
    }
  }
  for (size_t e = 0; e < n; ++e) {
    const glm::dvec2 a = poly.xy[e], b = poly.xy[(e + 1) % n];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    const auto k = static_cast<int64_t>(std::max(1.0, std::ceil(len / h)));
    ops.sqrt += 1;
    ops.div += 1;
    for (int64_t i = 0; i < k; ++i) {
      const double t = static_cast<double>(i) / static_cast<double>(k);
      PlaneSample s;
      s.x = a.x + t * (b.x - a.x);
      s.y = a.y + t * (b.y - a.y);
      s.u = m.u0 + m.ux * s.x + m.uy * s.y;
      s.v = m.v0 + m.vx * s.x + m.vy * s.y;
      emit(static_cast<const PlaneSample&>(s));
      ++st.edge_samples;
      ops += per_sample;
    }
  }
}

}  // namespace texsim
