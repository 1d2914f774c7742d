// The ground truth's bilinear reference on coordinates far outside the texture: every
// addressing mode still names the texel its definition gives, without converting a double
// that does not fit a long long (undefined behaviour, found by fuzz_scene). The two pixel
// models: the box is the n×n average, the Gaussian a symmetric weighting whose result on a
// ramp is the value at the pixel's centre and whose reach is one pixel, not half.
#include <gtest/gtest.h>

#include <cmath>
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
  EXPECT_NEAR(ground_truth_footprint(t, a, a, f, g).r, 19.8, 1e-9);
  EXPECT_NEAR(ground_truth_footprint(t, a, a, f, 8).r, 19.8, 1e-9);
  // Near the clamped end the Gaussian reaches a pixel (4 texels) out, the box half of that: at
  // 2.5 texels from the end only the Gaussian sees the flat part.
  f.u = 61.5 / 64;
  EXPECT_NEAR(ground_truth_footprint(t, a, a, f, 8).r, 61.0, 1e-9);
  EXPECT_LT(ground_truth_footprint(t, a, a, f, g).r, 61.0 - 1e-3);
}

}  // namespace
}  // namespace texsim
