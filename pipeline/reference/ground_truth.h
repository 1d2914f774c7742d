#pragma once
// Ground truth for image accuracy: the level-0 texture, reconstructed bilinearly in double,
// integrated over the pixel (docs/architecture.md#reference-generator-and-ground-truth): a box
// over the pixel's square, or the Gaussian pixel of EWA's model. The integral is taken either
// adaptively (nested grids refined until the estimate settles, the default) or on a fixed n×n
// stratified grid.
#include <algorithm>
#include <glm/common.hpp>
#include <string>
#include <vector>

#include "blocks/base/fragment.h"
#include "blocks/texture/memory/texture_memory.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/reference/footprint_reference.h"
#include "pipeline/scene/scene.h"

namespace texsim {

// Sample positions (relative to the pixel's corner) and weights of one pixel model: the box
// takes n×n samples over the pixel's square, weight 1; the Gaussian (PixelModel defaults:
// σ = ½ px, truncated at R = 1 px) takes ⌈2R·n⌉² samples over the square ±R around the
// centre, each weighted by the Gaussian (so n samples per pixel width in both).
struct PixelSamples {
  std::vector<double> x, y, w;
  double weight_sum = 0;
  static PixelSamples make(TruthPixel p, int n);
  std::string describe(TruthPixel p, int n) const;
};

// How the truth samples each pixel ([reference] samples).
//  - fixed n ≥ 1: the n×n stratified grid of PixelSamples (the reference before adaptive
//    sampling; samples = 8 reproduces its figures);
//  - adaptive (fixed = 0): nested trapezoid grids of (kx+1)(ky+1) points over the pixel
//    model's square, kx : ky the footprint's aspect (a power of two up to 64:1, so a
//    grazing pixel gets its points along its long axis), both doubled per level and each level
//    reusing every point of the one before. It stops at the first level that is dense enough
//    (a point every kTexelsPerPoint level-0 texels of the footprint along both axes, or
//    kMinPointsCap points) and whose estimate T differs from the previous level's T' by less
//    than kTolerance in every channel, and returns T + (T − T')/3 (one Richardson step; it
//    moves the estimate by less than kTolerance/3). Bound, and what it assumes: if the
//    integrand is smooth at the grid's scale the trapezoid error falls 4× per level, so T's
//    error is about (T − T')/3 < 1/3060 and the extrapolated estimate's is far smaller. That
//    is a heuristic, not a guarantee: detail finer than the grid (or the kinks of bilinear
//    reconstruction) can make two levels agree by chance; the density minimum guards against
//    the common case. Pixels that have not settled at kx·ky ≥ kMaxGrid² (footprints of
//    thousands of texels) return the finest level's T, whose error is not bounded.
struct TruthSampling {
  int fixed = 0;
  static constexpr double kTolerance = 1.0 / 1020;  // ¼ LSB of 8-bit, per channel
  static constexpr int kMaxGrid = 64;       // the finest level has kx·ky ≥ kMaxGrid² intervals
  static constexpr int kMaxAspect = 64;     // kx : ky between 1 : 64 and 64 : 1
  static constexpr int kMinPointsCap = 81;  // the footprint's minimum asks at most 9×9 points
  static constexpr double kTexelsPerPoint = 2;  // the minimum: a point every 2 texels
  bool adaptive() const { return fixed <= 0; }
  std::string describe(TruthPixel p) const;
};

// Integrates one pixel under a pixel model and a sampling: f(dx, dy) gives the colour at the
// offset (dx, dy) from the pixel's corner (the pixel's square is [0, 1]²).
class PixelIntegrator {
 public:
  PixelIntegrator(TruthPixel pixel, TruthSampling sampling);
  // texels: level-0 texels the pixel's footprint spans along screen x and y (its shape and
  // minimum for the adaptive grid); *samples (if not null) receives the points evaluated.
  template <class F>
  glm::dvec4 operator()(F&& f, glm::dvec2 texels, int* samples) const;
  TruthPixel pixel() const { return pixel_; }
  const TruthSampling& sampling() const { return sampling_; }
  const PixelSamples& fixed_samples() const { return fixed_; }

 private:
  // The adaptive grid: kx : ky = ax : ay (powers of two, the footprint's aspect), and the
  // smallest kx, ky that may stop.
  struct GridShape {
    int ax = 1, ay = 1;
    double min_kx = 0, min_ky = 0;
  };
  GridShape grid_shape(glm::dvec2 texels) const;
  TruthPixel pixel_;
  TruthSampling sampling_;
  PixelSamples fixed_;
  double origin_ = 0, size_ = 1;  // the adaptive grid's square: [origin, origin + size]²
  PixelModel gauss_;
};

// The plane's projective map rebased at a pixel's corner and rounded to double: u, v at the
// offset (dx, dy) from the corner cost 6 multiplications, 6 additions and one division, and
// each of the numerators and the denominator carries at most a few rounding errors of its
// largest term (measured against the long double map in test_ground_truth).
struct PixelMap {
  double A, B, D, E, G, H;  // as the map's
  double nu, nv, q;         // numerators and denominator at the corner
  PixelMap(const ProjectiveMap& m, int px, int py);
  void uv(double dx, double dy, double& u, double& v) const {
    const double den = q + G * dx + H * dy;
    if (den == 0) {  // as PlaneProjection::at: no map there
      u = v = 0;
      return;
    }
    u = (nu + A * dx + B * dy) / den;
    v = (nv + D * dx + E * dy) / den;
  }
  // Level-0 texels (of a w × h texture) the pixel spans along screen x and y at its centre.
  glm::dvec2 texels_across(int w, int h) const;
};

// The same from a fragment's derivatives.
glm::dvec2 texels_across(const Fragment& f, int w, int h);

// Level-0 texel lookup with bilinear reconstruction at normalised (u, v), in double.
glm::dvec4 reference_bilinear(const Texture& tex, AddressMode au, AddressMode av, double u,
                              double v);

// Exact: sub-pixel positions mapped through the plane's projective map.
glm::dvec4 ground_truth_exact(const Texture& tex, AddressMode au, AddressMode av,
                              const ProjectiveMap& map, int px, int py,
                              const PixelIntegrator& integrate, int* samples = nullptr);
// The box pixel with n×n samples, every sample through PlaneProjection::at in long double (the
// evaluation before PixelMap: the yardstick of its test, and the truth of the studies that
// build their own).
glm::dvec4 ground_truth_exact(const Texture& tex, AddressMode au, AddressMode av,
                              const PlaneProjection& map, int px, int py, int n);
// The same with any sample set (study filters' box truth: a grid stretched to the footprint).
glm::dvec4 ground_truth_exact(const Texture& tex, AddressMode au, AddressMode av,
                              const PlaneProjection& map, int px, int py, const PixelSamples& s);

// From a fragment alone: the pixel footprint is the parallelogram spanned by its derivatives
// (first-order approximation of the projective map; used for traces without a scene).
glm::dvec4 ground_truth_footprint(const Texture& tex, AddressMode au, AddressMode av,
                                  const Fragment& f, const PixelIntegrator& integrate,
                                  int* samples = nullptr);
glm::dvec4 ground_truth_footprint(const Texture& tex, AddressMode au, AddressMode av,
                                  const Fragment& f, int n);

template <class F>
glm::dvec4 PixelIntegrator::operator()(F&& f, glm::dvec2 texels, int* samples) const {
  if (!sampling_.adaptive()) {
    const PixelSamples& s = fixed_;
    glm::dvec4 sum(0);
    for (size_t k = 0; k < s.w.size(); ++k) sum += s.w[k] * f(s.x[k], s.y[k]);
    if (samples) *samples = static_cast<int>(s.w.size());
    return sum / s.weight_sum;
  }
  const GridShape g = grid_shape(texels);
  const bool box = pixel_ == TruthPixel::Box;
  glm::dvec4 sum(0);
  double wsum = 0;
  int evaluated = 0;
  // Adds the point (i, j) of the level with kx × ky intervals (trapezoid weights: ½ on each
  // edge of the square, so a point keeps its weight at every level).
  auto add = [&](int i, int j, int kx, int ky) {
    const double dx = origin_ + size_ * (static_cast<double>(i) / kx),
                 dy = origin_ + size_ * (static_cast<double>(j) / ky);
    double w = (i == 0 || i == kx ? 0.5 : 1.0) * (j == 0 || j == ky ? 0.5 : 1.0);
    if (!box) {
      const double cx = dx - 0.5, cy = dy - 0.5;
      w *= gauss_.weight(cx * cx + cy * cy);
      if (w == 0) return;  // outside the truncated Gaussian
    }
    sum += w * f(dx, dy);
    wsum += w;
    ++evaluated;
  };
  int kx = g.ax, ky = g.ay;
  for (int j = 0; j <= ky; ++j)
    for (int i = 0; i <= kx; ++i) add(i, j, kx, ky);
  glm::dvec4 est = wsum > 0 ? sum / wsum : glm::dvec4(0);
  glm::dvec4 prev = est;
  bool have_prev = wsum > 0;
  while (kx * ky < TruthSampling::kMaxGrid * TruthSampling::kMaxGrid) {
    kx *= 2;
    ky *= 2;
    for (int j = 0; j <= ky; ++j) {
      // Rows of the previous level gain their odd columns; new rows gain every column.
      const bool old_row = j % 2 == 0;
      for (int i = old_row ? 1 : 0; i <= kx; i += old_row ? 2 : 1) add(i, j, kx, ky);
    }
    est = wsum > 0 ? sum / wsum : glm::dvec4(0);
    const bool dense =
        (kx >= g.min_kx && ky >= g.min_ky) || (kx + 1) * (ky + 1) >= TruthSampling::kMinPointsCap;
    if (have_prev && dense) {
      const glm::dvec4 d = glm::abs(est - prev);
      if (std::max(std::max(d.r, d.g), std::max(d.b, d.a)) < TruthSampling::kTolerance) {
        est += (est - prev) / 3.0;  // one Richardson step: the trapezoid's h² error removed
        break;
      }
    }
    prev = est;
    have_prev = wsum > 0;
  }
  if (samples) *samples = evaluated;
  return est;
}

}  // namespace texsim
