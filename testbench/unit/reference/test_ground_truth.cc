// The ground truth's bilinear reference on coordinates far outside the texture: every
// addressing mode still names the texel its definition gives, without converting a double
// that does not fit a long long (undefined behaviour, found by fuzz_scene). The two pixel
// models: the box is the n×n average, the Gaussian a symmetric weighting whose result on a
// ramp is the value at the pixel's centre and whose reach is one pixel, not half.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "pipeline/reference/ground_truth.h"

namespace texsim {
namespace {

// 4x4, texel (x, y) has red = x + 4y.
Texture numbered() {
  std::vector<float> rgba(size_t{4} * 4 * 4, 1.0f);
  for (int i = 0; i < 16; ++i) rgba[static_cast<size_t>(i) * 4] = static_cast<float>(i);
  return Texture::from_rgba("numbered", 4, 4, rgba, TexelFormat::Rgba32f, false);
}

TEST(GroundTruth, HugeCoordinatesAddressTheTexelTheirModeGives) {
  const Texture t = numbered();
  // v = 0.375 is row 1 exactly; u·4 = ±1e19 is column ±1e19 exactly (beyond long long).
  const double v = 0.375;
  EXPECT_EQ(reference_bilinear(t, AddressMode::Clamp, AddressMode::Clamp, 2.5e18, v).r, 7.0);
  EXPECT_EQ(reference_bilinear(t, AddressMode::Clamp, AddressMode::Clamp, -2.5e18, v).r, 4.0);
  EXPECT_EQ(reference_bilinear(t, AddressMode::Wrap, AddressMode::Clamp, 2.5e18, v).r, 4.0);
  EXPECT_EQ(reference_bilinear(t, AddressMode::Mirror, AddressMode::Clamp, 2.5e18, v).r, 4.0);
  // Coordinates whose texel position overflows to infinity have no texel: black, like NaN.
  const glm::dvec4 inf = reference_bilinear(t, AddressMode::Clamp, AddressMode::Clamp, 1e308, v);
  EXPECT_EQ(inf, glm::dvec4(0, 0, 0, 0));
}

TEST(GroundTruth, BoxPixelIsTheAverageOfItsSquaresSamples) {
  const PixelSamples s = PixelSamples::make(TruthPixel::Box, 4);
  ASSERT_EQ(s.w.size(), 16u);
  EXPECT_EQ(s.weight_sum, 16.0);
  EXPECT_EQ(s.x[1], 0.375);
  EXPECT_EQ(s.y[4], 0.375);
  for (double w : s.w) EXPECT_EQ(w, 1.0);
}

// A horizontal ramp (red = u·4 − ½ between texel centres, clamped): an affine footprint of
// 0.1 texel per pixel, away from the ends.
Texture ramp() {
  std::vector<float> rgba(size_t{64} * 4, 1.0f);
  for (int x = 0; x < 64; ++x) rgba[static_cast<size_t>(x) * 4] = static_cast<float>(x);
  return Texture::from_rgba("ramp", 64, 1, rgba, TexelFormat::Rgba32f, false);
}

TEST(GroundTruth, GaussianPixelIsSymmetricAndReachesOnePixel) {
  const PixelSamples g = PixelSamples::make(TruthPixel::Gaussian, 8);
  // ⌈2·8⌉² = 256 positions, those beyond R = 1 px dropped.
  EXPECT_LT(g.w.size(), 256u);
  EXPECT_GT(g.w.size(), 190u);
  double mx = 0, my = 0, reach = 0;
  for (size_t k = 0; k < g.w.size(); ++k) {
    mx += g.w[k] * (g.x[k] - 0.5);
    my += g.w[k] * (g.y[k] - 0.5);
    reach = std::max(reach, std::hypot(g.x[k] - 0.5, g.y[k] - 0.5));
  }
  EXPECT_NEAR(mx / g.weight_sum, 0, 1e-12);
  EXPECT_NEAR(my / g.weight_sum, 0, 1e-12);
  EXPECT_GT(reach, 0.9);
  EXPECT_LE(reach, 1.0);

  const Texture t = ramp();
  Fragment f;
  f.u = 20.3 / 64;
  f.v = 0.5;
  f.dudx = 4.0 / 64;  // 4 texels per pixel along x
  f.dvdy = 1.0 / 64;
  const auto a = AddressMode::Clamp;
  // A linear function: both pixels give the value at the centre, u·64 − ½ = 19.8.
  const PixelIntegrator gauss(TruthPixel::Gaussian, {8}), gauss_auto(TruthPixel::Gaussian, {0});
  EXPECT_NEAR(ground_truth_footprint(t, a, a, f, gauss).r, 19.8, 1e-9);
  EXPECT_NEAR(ground_truth_footprint(t, a, a, f, gauss_auto).r, 19.8, 1e-9);
  EXPECT_NEAR(ground_truth_footprint(t, a, a, f, 8).r, 19.8, 1e-9);
  // Near the clamped end the Gaussian reaches a pixel (4 texels) out, the box half of that: at
  // 2.5 texels from the end only the Gaussian sees the flat part.
  f.u = 61.5 / 64;
  EXPECT_NEAR(ground_truth_footprint(t, a, a, f, 8).r, 61.0, 1e-9);
  EXPECT_LT(ground_truth_footprint(t, a, a, f, gauss).r, 61.0 - 1e-3);
  EXPECT_NEAR(ground_truth_footprint(t, a, a, f, gauss_auto).r,
              ground_truth_footprint(t, a, a, f, gauss).r, 0.01);
}

// The plane map in double, rebased at each pixel's corner (PixelMap), against PlaneProjection's
// long double evaluation over every 8th pixel of the built-in scene and two shipped ones (an
// aviation camera over a wide ground plane, a terrain fly-over) at 16 offsets each: the
// largest difference, in texels of a 4096-texel texture, is far below what moves a bilinear
// weight by an 8-bit step (1/255 texel). Measured: 4.7e-10 texels; 1e-6 is the bound held.
TEST(GroundTruth, DoubleMapMatchesLongDoubleMap) {
  double worst = 0;
  const std::string dir = std::string(TEXSIM_SOURCE_DIR) + "/scenes/";
  for (const Scene& scene : {default_scene(), load_scene(dir + "flight.toml"),
                             load_scene(dir + "terrain_flyover.toml")}) {
    for (const ScenePrimitive& prim : scene.primitives) {
      const PlaneProjection map(scene, prim);
      for (int py = 0; py < scene.height; py += 8) {
        for (int px = 0; px < scene.width; px += 8) {
          if (!map.at(px + 0.5, py + 0.5).inside) continue;
          const PixelMap pm(map, px, py);
          for (int k = 0; k < 16; ++k) {
            const int col = k % 4, row = k / 4;  // a 4×4 grid of offsets
            const double dx = (col + 0.5) / 4, dy = (row + 0.5) / 4;
            const UvSample e = map.at(px + dx, py + dy);
            double u = 0, v = 0;
            pm.uv(dx, dy, u, v);
            worst = std::max({worst, std::fabs(u - e.u) * 4096, std::fabs(v - e.v) * 4096});
          }
        }
      }
    }
  }
  EXPECT_LT(worst, 1e-6) << "largest difference " << worst << " texels";
  std::printf("largest difference %.3g texels\n", worst);
}

// 4×4 checks of red 0 and 1 (magnified: a pixel sees about a quarter texel).
Texture checks() {
  std::vector<float> rgba(size_t{4} * 4 * 4, 1.0f);
  for (int i = 0; i < 16; ++i)
    rgba[static_cast<size_t>(i) * 4] = static_cast<float>((i + i / 4) % 2);
  return Texture::from_rgba("checks", 4, 4, rgba, TexelFormat::Rgba8, false);
}

// Adaptive sampling: a flat pixel stops at the first comparison (3×3 points); a pixel across
// texel boundaries refines, and lands within the tolerance of a dense fixed grid; the fixed
// grid is PixelSamples' (samples = 8 is the reference before adaptive sampling).
TEST(GroundTruth, AdaptiveSamplingRefinesUntilTheEstimateSettles) {
  const Texture t = ramp();
  const auto c = AddressMode::Clamp;
  const PixelIntegrator adaptive(TruthPixel::Box, {0}), dense(TruthPixel::Box, {64});
  Fragment f;
  f.u = 70.0 / 64;  // beyond the clamped end: flat
  f.v = 0.5;
  f.dudx = 0.25 / 64;  // a quarter texel each way (the texture is one texel high)
  f.dvdy = 0.25;
  int n = 0;
  EXPECT_EQ(ground_truth_footprint(t, c, c, f, adaptive, &n).r, 63.0);
  EXPECT_EQ(n, 9);

  const Texture k = checks();
  const auto w = AddressMode::Wrap;
  for (double u0 : {0.23, 0.49, 0.5, 0.71}) {
    f.u = u0;
    f.v = 0.37;
    f.dudx = 0.31 / 4;
    f.dvdx = 0.05 / 4;
    f.dvdy = 0.27 / 4;
    const glm::dvec4 a = ground_truth_footprint(k, w, w, f, adaptive, &n);
    const glm::dvec4 d = ground_truth_footprint(k, w, w, f, dense);
    EXPECT_NEAR(a.r, d.r, 2 * TruthSampling::kTolerance) << "u " << u0;
    EXPECT_GT(n, 9) << "u " << u0;
  }
  // Fixed grids are the old reference's, and count their samples.
  EXPECT_EQ(ground_truth_footprint(k, w, w, f, 8).r,
            ground_truth_footprint(k, w, w, f, PixelIntegrator(TruthPixel::Box, {8}), &n).r);
  EXPECT_EQ(n, 64);
}

// The batched kernel of the exact truth's points (AVX2 where the CPU has it) against the
// portable one, bit for bit: random projective maps, far and near, through every addressing
// mode on power-of-two and other sizes, with batches of every length up to 13 (the tails), and
// the hard points: no map (a zero denominator), coordinates far outside, NaN and infinities.
TEST(GroundTruth, BatchedKernelEqualsPortableBitForBit) {
  if (!exact_points_avx2_available()) GTEST_SKIP() << "this CPU has no AVX2: one kernel only";
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> any(-1, 1);
  const AddressMode modes[] = {AddressMode::Wrap, AddressMode::Clamp, AddressMode::Mirror};
  const int sizes[][2] = {{1, 1}, {2, 1}, {4, 4}, {5, 3}, {64, 16}, {37, 129}};
  uint64_t points = 0;
  for (const auto& sz : sizes) {
    std::vector<float> rgba(static_cast<size_t>(sz[0]) * sz[1] * 4);
    for (float& c : rgba) c = static_cast<float>(rng() % 256) / 255.0f;
    const Texture t = Texture::from_rgba("random", sz[0], sz[1], rgba, TexelFormat::Rgba8, false);
    for (int trial = 0; trial < 200; ++trial) {
      ProjectiveMap m;
      const double scale = trial % 4 == 0 ? 1e6 : (trial % 4 == 1 ? 40 : 1);
      m.A = any(rng) * scale, m.B = any(rng) * scale, m.C = any(rng) * scale * 10;
      m.D = any(rng) * scale, m.E = any(rng) * scale, m.F = any(rng) * scale * 10;
      m.G = any(rng) * 0.3, m.H = any(rng) * 0.3, m.I = 1 + any(rng);
      if (trial % 50 == 7) m.G = m.H = m.I = 0;  // no map anywhere
      const PixelMap pm(m, static_cast<int>(rng() % 64), static_cast<int>(rng() % 64));
      const size_t n = 1 + static_cast<size_t>(trial % 13);
      std::vector<double> dx(n), dy(n);
      for (size_t k = 0; k < n; ++k) {
        dx[k] = (any(rng) + 1) / 2;
        dy[k] = (any(rng) + 1) / 2;
      }
      if (trial % 25 == 3) dx[0] = std::numeric_limits<double>::quiet_NaN();
      if (trial % 25 == 4) dy[n - 1] = std::numeric_limits<double>::infinity();
      if (trial % 25 == 5) dx[n / 2] = 1e300;
      for (AddressMode au : modes) {
        for (AddressMode av : modes) {
          std::vector<glm::dvec4> fast(n), portable(n);
          sample_exact_points(t, au, av, pm, dx.data(), dy.data(), n, fast.data());
          sample_exact_points(t, au, av, pm, dx.data(), dy.data(), n, portable.data(),
                              ExactKernel::Portable);
          for (size_t k = 0; k < n; ++k, ++points) {
            auto bits = [](const glm::dvec4& c) {
              return std::array<uint64_t, 4>{
                  std::bit_cast<uint64_t>(c.r), std::bit_cast<uint64_t>(c.g),
                  std::bit_cast<uint64_t>(c.b), std::bit_cast<uint64_t>(c.a)};
            };
            ASSERT_EQ(bits(fast[k]), bits(portable[k]))
                << sz[0] << "x" << sz[1] << " trial " << trial << " point " << k << ": "
                << fast[k].r << " against " << portable[k].r;
          }
        }
      }
    }
  }
  EXPECT_GT(points, 50000u);
}

}  // namespace
}  // namespace texsim
