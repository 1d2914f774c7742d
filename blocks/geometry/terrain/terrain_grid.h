#pragma once
// TerrainGrid: the height map H = [h_ij] of seed 003 §2.3 on a unit grid (node (i, j) at
// x = i, z = j), heights in world units. Reads outside the grid clamp to its edge; a NaN
// height (a DEM's no-data value) reads as `no_data` (the defined fallback).
// Arithmetic: heights stored as float, returned as double.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace texsim {

struct TerrainGrid {
  int32_t nx = 0, nz = 0;
  std::vector<float> h;  // h[j·nx + i]
  double no_data = 0.0;

  TerrainGrid() = default;
  TerrainGrid(int32_t w, int32_t d, float fill = 0.0F)
      : nx(w), nz(d), h(static_cast<size_t>(w) * static_cast<size_t>(d), fill) {}
  float& at(int32_t i, int32_t j) {
    return h[static_cast<size_t>(j) * static_cast<size_t>(nx) + static_cast<size_t>(i)];
  }
  double node(int32_t i, int32_t j) const {
    i = std::clamp(i, 0, nx - 1);
    j = std::clamp(j, 0, nz - 1);
    const float v = h[static_cast<size_t>(j) * static_cast<size_t>(nx) + static_cast<size_t>(i)];
    return std::isnan(v) ? no_data : static_cast<double>(v);
  }
  // The highest node (no-data counted as `no_data`): rays above it going up cannot hit.
  double max_height() const {
    double m = h.empty() ? no_data : -std::numeric_limits<double>::infinity();
    for (const float v : h) m = std::max(m, std::isnan(v) ? no_data : static_cast<double>(v));
    return m;
  }
};

}  // namespace texsim
