#pragma once
// Ground truth for image accuracy: the level-0 texture, reconstructed bilinearly in double,
// integrated over the pixel (docs/architecture.md#reference-generator-and-ground-truth): a box
// over the pixel's square, or the Gaussian pixel of EWA's model. The integral is taken either
// adaptively (nested grids refined until the estimate settles, the default) or on a fixed n×n
// stratified grid.
#include <algorithm>
#include <array>
#include <cstdint>
#include <glm/common.hpp>
#include <string>
#include <type_traits>
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
//  Tiers (docs/architecture.md#reference-generator-and-ground-truth): tier k stops at the
//  tolerance kTolerance / 4^k instead. A run asks a pixel for a finer tier where the filter's
//  own error there is small (refine_tier), so that the truth's error stays small beside it.
//  A pixel's tier-k value is the same bits whether computed alone or after tier 0 (the same
//  nested sums): tier 0's stop at difference d also is tier k's for every k with d < tol(k),
//  and a pixel that reached the cap has one value for every tier (its reach, below).
struct TruthSampling {
  int fixed = 0;
  int tier = 0;  // 0 … kTiers − 1: the tolerance kTolerance / 4^tier
  static constexpr double kTolerance = 1.0 / 1020;  // ¼ LSB of 8-bit, per channel
  static constexpr int kTiers = 4;                  // the finest: kTolerance / 64
  // A pixel asks for the first tier with tol(k) ≤ e / kTierRatio, e its filter error
  // (largest over R, G, B against tier 0's truth; where that is below its material's RMS
  // error E, E² over it instead): measured, the PSNR then moves by under 0.005 dB from 43 to
  // 63 dB (docs/performance.md#the-ground-truth).
  static constexpr double kTierRatio = 48;
  static constexpr double tolerance_of(int tier) {
    return kTolerance / static_cast<double>(1 << (2 * tier));
  }
  double tolerance() const { return tolerance_of(tier); }
  // The tier a pixel needs for a filter error `err` (0 when err is NaN).
  static int refine_tier(double err);
  static constexpr int kMaxGrid = 64;       // the finest level has kx·ky ≥ kMaxGrid² intervals
  static constexpr int kMaxAspect = 64;     // kx : ky between 1 : 64 and 64 : 1
  static constexpr int kMinPointsCap = 81;  // the footprint's minimum asks at most 9×9 points
  static constexpr double kTexelsPerPoint = 2;  // the minimum: a point every 2 texels
  bool adaptive() const { return fixed <= 0; }
  std::string describe(TruthPixel p) const;
};

// The adaptive grid's points for one shape (kx : ky = ax : ay), in the order the integral adds
// them: the first level's points, then each finer level's new points, with their weights
// (trapezoid × pixel model; points outside the truncated Gaussian left out). Built once per
// pixel model and shape, so a pixel's integral only maps and samples its points.
struct AdaptiveGrid {
  struct Level {
    int kx = 0, ky = 0;
    uint32_t end = 0;  // the level's points are [previous level's end, end)
    double wsum = 0;   // the weights of every point up to end, summed in order
  };
  std::vector<double> dx, dy, w;
  std::vector<Level> levels;
  // The 13 shapes: ax = 1, 2, …, 64 with ay = 1 (index log2 ax), then ay = 2, …, 64 with
  // ax = 1 (index 6 + log2 ay).
  static constexpr int kShapes = 13;
  static int shape_index(int ax, int ay);
};

// Integrates one pixel under a pixel model and a sampling: f(dx, dy) gives the colour at the
// offset (dx, dy) from the pixel's corner (the pixel's square is [0, 1]²). An f that also takes
// (const double* dx, const double* dy, size_t n, glm::dvec4* out) gets the points in batches
// (the same values, summed in the same order).
class PixelIntegrator {
 public:
  PixelIntegrator(TruthPixel pixel, TruthSampling sampling);
  // texels: level-0 texels the pixel's footprint spans along screen x and y (its shape and
  // minimum for the adaptive grid); *samples (if not null) receives the points evaluated,
  // *reach (if not null) the finest tier whose value this also is (kTiers − 1 for a pixel
  // that reached the cap, or a fixed grid).
  template <class F>
  glm::dvec4 operator()(F&& f, glm::dvec2 texels, int* samples, int* reach = nullptr) const;
  // The same integrator at another tier.
  PixelIntegrator at_tier(int tier) const {
    PixelIntegrator p = *this;
    p.sampling_.tier = tier;
    return p;
  }
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
  using Grids = std::array<AdaptiveGrid, AdaptiveGrid::kShapes>;
  static const Grids& grids(TruthPixel pixel);  // built on first use, shared by all threads
  TruthPixel pixel_;
  TruthSampling sampling_;
  PixelSamples fixed_;
  double origin_ = 0, size_ = 1;  // the adaptive grid's square: [origin, origin + size]²
  PixelModel gauss_;
  const Grids* grids_ = nullptr;
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

// What the truth takes of a sampler beyond its address modes: the border colour of border
// addressing (as the texture's format reads it, border_texel()) and the constant texel offset,
// added to the integer coordinates before addressing. The truth reconstructs level 0 only, so
// its offset is in level-0 texels (the unit's, in texels of the level it samples: the same
// when magnified).
struct SamplerExtras {
  glm::dvec4 border{0.0};
  int offset_u = 0, offset_v = 0;
};

// The exact truth's points in a batch: out[k] is the level-0 bilinear colour at the offset
// (dx[k], dy[k]) from the pixel's corner through the map, as ground_truth_exact's integrand.
// Auto takes the AVX2 kernel where the CPU has it (RGBA8 textures), Portable never; both give
// the same values bit for bit (test_ground_truth checks).
enum class ExactKernel : uint8_t { Auto, Portable };
void sample_exact_points(const Texture& tex, AddressMode au, AddressMode av, const PixelMap& pm,
                         const double* dx, const double* dy, size_t n, glm::dvec4* out,
                         ExactKernel kernel = ExactKernel::Auto, const SamplerExtras& extras = {});
bool exact_points_avx2_available();

// Level-0 texel lookup with bilinear reconstruction at normalised (u, v), in double. Under
// border addressing a texel outside the level is extras.border; the other modes never leave
// the level. The offset extras.offset_u/v joins the integer coordinates before addressing.
glm::dvec4 reference_bilinear(const Texture& tex, AddressMode au, AddressMode av, double u,
                              double v, const SamplerExtras& extras = {});

// Exact: sub-pixel positions mapped through the plane's projective map.
glm::dvec4 ground_truth_exact(const Texture& tex, AddressMode au, AddressMode av,
                              const ProjectiveMap& map, int px, int py,
                              const PixelIntegrator& integrate, int* samples = nullptr,
                              int* reach = nullptr, const SamplerExtras& extras = {});
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
                                  int* samples = nullptr, int* reach = nullptr,
                                  const SamplerExtras& extras = {});
glm::dvec4 ground_truth_footprint(const Texture& tex, AddressMode au, AddressMode av,
                                  const Fragment& f, int n);

template <class F>
glm::dvec4 PixelIntegrator::operator()(F&& f, glm::dvec2 texels, int* samples, int* reach) const {
  if (reach) *reach = TruthSampling::kTiers - 1;
  if (!sampling_.adaptive()) {
    const PixelSamples& s = fixed_;
    glm::dvec4 sum(0);
    for (size_t k = 0; k < s.w.size(); ++k) sum += s.w[k] * f(s.x[k], s.y[k]);
    if (samples) *samples = static_cast<int>(s.w.size());
    return sum / s.weight_sum;
  }
  const double tolerance = sampling_.tolerance();
  const GridShape g = grid_shape(texels);
  const AdaptiveGrid& grid = (*grids_)[AdaptiveGrid::shape_index(g.ax, g.ay)];
  glm::dvec4 sum(0);
  uint32_t next = 0;  // the first point not yet added
  // Adds the points up to a level's end: sum += w · f(point), in the grid's order.
  auto add_level = [&](const AdaptiveGrid::Level& level) {
    if constexpr (std::is_invocable_v<F&, const double*, const double*, size_t, glm::dvec4*>) {
      constexpr uint32_t kBatch = 64;
      glm::dvec4 c[kBatch];
      while (next < level.end) {
        const uint32_t n = std::min(kBatch, level.end - next);
        f(grid.dx.data() + next, grid.dy.data() + next, size_t{n}, c);
        for (uint32_t k = 0; k < n; ++k) sum += grid.w[next + k] * c[k];
        next += n;
      }
    } else {
      for (; next < level.end; ++next) sum += grid.w[next] * f(grid.dx[next], grid.dy[next]);
    }
  };
  add_level(grid.levels[0]);
  double wsum = grid.levels[0].wsum;
  glm::dvec4 est = wsum > 0 ? sum / wsum : glm::dvec4(0);
  glm::dvec4 prev = est;
  bool have_prev = wsum > 0;
  for (size_t l = 1; l < grid.levels.size(); ++l) {
    const AdaptiveGrid::Level& level = grid.levels[l];
    add_level(level);
    wsum = level.wsum;
    est = wsum > 0 ? sum / wsum : glm::dvec4(0);
    const int kx = level.kx, ky = level.ky;
    const bool dense =
        (kx >= g.min_kx && ky >= g.min_ky) || (kx + 1) * (ky + 1) >= TruthSampling::kMinPointsCap;
    if (have_prev && dense) {
      const glm::dvec4 d = glm::abs(est - prev);
      const double dmax = std::max(std::max(d.r, d.g), std::max(d.b, d.a));
      if (dmax < tolerance) {
        est += (est - prev) / 3.0;  // one Richardson step: the trapezoid's h² error removed
        if (reach) {
          int r = sampling_.tier;
          while (r + 1 < TruthSampling::kTiers && dmax < TruthSampling::tolerance_of(r + 1)) ++r;
          *reach = r;
        }
        break;
      }
    }
    prev = est;
    have_prev = wsum > 0;
  }
  if (samples) *samples = static_cast<int>(next);
  return est;
}

}  // namespace texsim
