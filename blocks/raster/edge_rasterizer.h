#pragma once
// EdgeRasterizer: the edge-function rasteriser of the rasterisation subsystem (ПРП), the
// reference for coverage (docs/rasterizers.md §1). Vertices are snapped to a fixed-point grid of
// 2^-subpixel_bits pixel; the three edge functions are exact integers in 64 bits, stepped by
// additions over the triangle's bounding box clipped to the viewport scissor; a pixel is
// covered when its centre is inside with the top-left fill rule. Attributes are interpolated
// perspective-correctly from the edge values and 1/w of the vertices.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/raster/raster_types.h"

namespace texsim {

class ConfigReader;

// Why a triangle produced no pixels (None: it was rasterised).
enum class RasterReject : uint8_t {
  None,
  NotFinite,     // a vertex coordinate or w is NaN or infinite
  NonPositiveW,  // w <= 0: the vertex is behind the eye (clip first)
  OutOfRange,    // a snapped coordinate or the scissor is beyond the ±2^30 guard band
  Degenerate,    // zero area after snapping (collinear or coincident vertices)
};
const char* reject_reason(RasterReject r);

// Counters of a rasteriser: what it visited and what it produced.
struct EdgeRasterStats {
  uint64_t triangles = 0, rejected = 0, rows = 0, pixels_visited = 0, pixels_covered = 0;
};

class EdgeRasterizer {
 public:
  static constexpr int kMaxSubpixelBits = 16;
  // Guard band: every snapped coordinate and scissor corner is below 2^30 in magnitude (in
  // units of 2^-subpixel_bits pixel), so edge deltas fit in 31 bits, their products in 62 and
  // an edge value (a difference of two products) in 63: int64 never overflows.
  static constexpr int kCoordBits = 30;

  struct Config {
    int subpixel_bits = 8;  // vertex snapping: round to nearest (ties to even) on 2^-bits
    static Config from_toml(const ConfigReader& r);
  };

  // Per-triangle state after set-up. Vertices are stored in positive orientation (area2 > 0,
  // y down: clockwise on the screen); perm[i] is the input index of oriented vertex i. Edge e
  // runs from vertex e+1 to vertex e+2 (mod 3), opposite vertex e, and its value at a point p
  // is E_e(p) = dx_e·(p_y - a_y) - dy_e·(p_x - a_x) (twice the area of (a, b, p)).
  struct Setup {
    RasterReject reject = RasterReject::Degenerate;
    int bits = 0;
    std::array<int64_t, 3> vx{}, vy{}, dx{}, dy{};
    std::array<int64_t, 3> bias{};  // 0 on a top or left edge, -1 otherwise (E + bias >= 0)
    std::array<int, 3> perm{0, 1, 2};
    std::array<double, 3> inv_w{};  // 1/w of the oriented vertices
    int64_t area2 = 0;
    int32_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;  // pixel box ∩ scissor, inclusive
    bool ok() const { return reject == RasterReject::None; }
    bool box_empty() const { return x0 > x1 || y0 > y1; }
  };

  EdgeRasterizer() = default;
  explicit EdgeRasterizer(const Config& c) : cfg_(c) {}
  const Config& config() const { return cfg_; }

  Setup setup(const ScreenVertex v[3], const Scissor& sc) const;
  // E_e at the centre of pixel (x, y), exact (the pixel must be inside the guard band).
  static int64_t edge_value(const Setup& st, int e, int32_t x, int32_t y);
  static bool inside(const Setup& st, int e, int64_t value) { return value + st.bias[e] >= 0; }
  static bool covers(const Setup& st, int32_t x, int32_t y);

  // Visits the box row by row, stepping the edge values by additions; calls f(x, y, e) for
  // every covered pixel with e the three edge values there.
  template <class F>
  void scan(const Setup& st, F&& f, EdgeRasterStats* stats = nullptr) const {
    if (!st.ok() || st.box_empty()) return;
    const int64_t one = int64_t{1} << st.bits;
    std::array<int64_t, 3> row{}, step_x{}, step_y{};
    for (int e = 0; e < 3; ++e) {
      row[e] = edge_value(st, e, st.x0, st.y0);
      step_x[e] = -st.dy[e] * one;
      step_y[e] = st.dx[e] * one;
    }
    for (int32_t y = st.y0; y <= st.y1; ++y) {
      std::array<int64_t, 3> ev = row;
      uint64_t covered = 0;
      for (int32_t x = st.x0; x <= st.x1; ++x) {
        if (inside(st, 0, ev[0]) && inside(st, 1, ev[1]) && inside(st, 2, ev[2])) {
          f(x, y, ev);
          ++covered;
        }
        for (int e = 0; e < 3; ++e) ev[e] += step_x[e];
      }
      for (int e = 0; e < 3; ++e) row[e] += step_y[e];
      if (stats) {
        ++stats->rows;
        stats->pixels_visited += static_cast<uint64_t>(st.x1 - st.x0) + 1;
        stats->pixels_covered += covered;
      }
    }
  }

  // The covered pixels as row spans (a triangle's pixels in one row are contiguous).
  std::vector<RowSpan> rasterize(const ScreenVertex v[3], const Scissor& sc,
                                 EdgeRasterStats* stats = nullptr) const;
  // Perspective-correct barycentric weights (in the input vertex order) of a covered pixel
  // from its edge values: b_i = E_i/w_i, weight_i = b_i / Σ b (the area cancels). Double.
  static std::array<double, 3> perspective_weights(const Setup& st,
                                                   const std::array<int64_t, 3>& e);
  // Σ weight_i·a_i of one attribute given at the input vertices.
  static double interpolate(const std::array<double, 3>& weights, const double a[3]) {
    return weights[0] * a[0] + weights[1] * a[1] + weights[2] * a[2];
  }

  // Item: one pixel of the scanned box (three edge steps, three sign tests).
  OpCounts ops_per_item() const;
  OpCounts row_ops() const;             // per row: three edge steps in y
  OpCounts triangle_setup_ops() const;  // snapping, orientation, top-left, box, first values
  // Per covered pixel: the perspective-correct weights (plus 3 mul 2 add per attribute).
  OpCounts interpolation_ops() const;
  TimingSpec timing(const TechTable& t) const;
  std::string name() const { return "raster.edge"; }
  std::string arithmetic() const;

 private:
  Config cfg_{};
};

}  // namespace texsim
