#pragma once
// Types the relief blocks share (docs/derivations/relief.md): the height map they read and the
// 3-D distance map of Donnelly's method.
// Arithmetic: heights and distances are stored as float; positions are double.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace texsim {

// One memory read of a relief block, for a cache model: height texel (x, y) (z = kHeightRead),
// colour texel (x, y) at the height map's resolution (z = kColourRead), or distance-map voxel
// (x, y, z ≥ 0).
struct ReliefRead {
  static constexpr int32_t kHeightRead = -1, kColourRead = -2;
  int32_t x, y, z;
};

// A height map: w × h texels, heights in [0, 1] (1 = the top of the relief). Texel (x, y) has
// its centre at (x, y). Reads clamp to the edge; a NaN height reads as 0 (the defined fallback:
// the base of the relief).
struct ReliefHeightMap {
  int32_t width = 0, height = 0;
  std::vector<float> h;  // row-major, h[y·width + x]

  ReliefHeightMap() = default;
  ReliefHeightMap(int32_t w, int32_t hh, float fill = 0.0F)
      : width(w), height(hh), h(static_cast<size_t>(w) * static_cast<size_t>(hh), fill) {}
  float& at(int32_t x, int32_t y) {
    return h[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
  }
  // The clamped, sanitised height of texel (x, y).
  float texel(int32_t x, int32_t y) const {
    x = std::clamp(x, 0, width - 1);
    y = std::clamp(y, 0, height - 1);
    const float v = h[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
    return std::isnan(v) ? 0.0F : std::clamp(v, 0.0F, 1.0F);
  }
  // Bilinear height at texel coordinates (x, y) (texel centres at integers); 4 texel reads.
  double bilinear(double x, double y) const {
    const double fx = std::floor(x), fy = std::floor(y);
    const double ax = x - fx, ay = y - fy;
    const auto ix = static_cast<int32_t>(std::clamp(fx, -1.0, static_cast<double>(width)));
    const auto iy = static_cast<int32_t>(std::clamp(fy, -1.0, static_cast<double>(height)));
    const double h00 = texel(ix, iy), h10 = texel(ix + 1, iy);
    const double h01 = texel(ix, iy + 1), h11 = texel(ix + 1, iy + 1);
    const double top = h00 + (h10 - h00) * ax, bot = h01 + (h11 - h01) * ax;
    return top + (bot - top) * ay;
  }
  // The 4 texels bilinear(x, y) reads, clamped as it clamps them (x, y finite).
  void bilinear_texels(double x, double y, std::vector<ReliefRead>& out) const {
    const auto ix =
        static_cast<int32_t>(std::clamp(std::floor(x), -1.0, static_cast<double>(width)));
    const auto iy =
        static_cast<int32_t>(std::clamp(std::floor(y), -1.0, static_cast<double>(height)));
    for (int32_t k = 0; k < 4; ++k) {
      out.push_back({std::clamp(ix + (k & 1), 0, width - 1),
                     std::clamp(iy + (k >> 1), 0, height - 1), ReliefRead::kHeightRead});
    }
  }
};

// Donnelly's distance map: w × h × d voxels over (x, y, layer). Voxel (x, y, z) has its centre
// at (x, y, z) and is solid when z < height·d (z = -1 is the solid base under every texel).
// Each voxel holds a distance in voxel units (0 in solid voxels).
struct DistanceMap {
  int32_t width = 0, height = 0, depth = 0;
  std::vector<float> d;

  DistanceMap() = default;
  DistanceMap(int32_t w, int32_t hh, int32_t dd)
      : width(w),
        height(hh),
        depth(dd),
        d(static_cast<size_t>(w) * static_cast<size_t>(hh) * static_cast<size_t>(dd), 0.0F) {}
  size_t index(int32_t x, int32_t y, int32_t z) const {
    return (static_cast<size_t>(z) * static_cast<size_t>(height) + static_cast<size_t>(y)) *
               static_cast<size_t>(width) +
           static_cast<size_t>(x);
  }
  float at(int32_t x, int32_t y, int32_t z) const { return d[index(x, y, z)]; }
  float& at(int32_t x, int32_t y, int32_t z) { return d[index(x, y, z)]; }
};

}  // namespace texsim
