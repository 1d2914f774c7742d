// 3-D texture addressing (VolumeAddressGen, docs/texture-types.md §7): the three layouts'
// indices, eight taps per level and trilinear across 3-D mips, λ from all three derivatives
// (a 2-D footprint, a control, picks another level), nearest's floor on r (a half-up rounding,
// a control, differs), and the hard cases: depth 1, NaN and Inf r.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

#include "blocks/texture/volume/volume_address_gen.h"

namespace texsim {
namespace {

TEST(VolumeAddressGen, LayoutsPlaceEveryTexelOnce) {
  for (const TexelLayout layout :
       {TexelLayout::Linear, TexelLayout::Tiled4x4, TexelLayout::Morton}) {
    const VolumeSize s{5, 3, 7};
    std::set<uint64_t> seen;
    for (int z = 0; z < s.depth; ++z)
      for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
          const uint64_t i = VolumeAddressGen::texel_index(layout, s, x, y, z);
          EXPECT_LT(i, VolumeAddressGen::level_texels(layout, s)) << to_string(layout);
          EXPECT_TRUE(seen.insert(i).second) << to_string(layout) << " " << x << y << z;
        }
  }
  // 3-D Morton interleaves x, y, z bit by bit; bricks hold 4 × 4 × 4 texels.
  const VolumeSize c{8, 8, 8};
  EXPECT_EQ(VolumeAddressGen::texel_index(TexelLayout::Morton, c, 1, 0, 0), 1u);
  EXPECT_EQ(VolumeAddressGen::texel_index(TexelLayout::Morton, c, 0, 1, 0), 2u);
  EXPECT_EQ(VolumeAddressGen::texel_index(TexelLayout::Morton, c, 0, 0, 1), 4u);
  EXPECT_EQ(VolumeAddressGen::texel_index(TexelLayout::Morton, c, 3, 3, 3), 63u);
  EXPECT_EQ(VolumeAddressGen::texel_index(TexelLayout::Morton, c, 4, 0, 0), 64u);
  EXPECT_EQ(VolumeAddressGen::texel_index(TexelLayout::Tiled4x4, c, 3, 3, 3), 63u);
  EXPECT_EQ(VolumeAddressGen::texel_index(TexelLayout::Tiled4x4, c, 4, 0, 0), 64u);
  EXPECT_EQ(VolumeAddressGen::texel_index(TexelLayout::Tiled4x4, c, 0, 0, 4), 4u * 64u);
  EXPECT_EQ(VolumeAddressGen::texel_index(TexelLayout::Linear, c, 1, 2, 3), (3u * 8 + 2) * 8 + 1);
}

TEST(VolumeAddressGen, EightTapsPerLevelTrilinearAcrossLevels) {
  const VolumeSize base{16, 16, 16};
  EXPECT_EQ(VolumeAddressGen::level_count(base), 5);
  EXPECT_EQ(VolumeAddressGen::level_size({16, 4, 2}, 2).depth, 1);
  VolumeAddressGen::Taps t{};
  VolumeAddressGen bil(
      {FilterMode::Bilinear, AddressMode::Clamp, AddressMode::Clamp, AddressMode::Clamp});
  // At the centre of texel (2, 1, 3) of level 0: all the weight on it.
  ASSERT_EQ(bil.taps(base, 2.5 / 16, 1.5 / 16, 3.5 / 16, 0.0f, t), 8);
  for (int k = 0; k < 8; ++k) {
    const bool it = t[k].x == 2 && t[k].y == 1 && t[k].z == 3;
    EXPECT_FLOAT_EQ(t[k].weight, it ? 1.0f : 0.0f) << k;
  }
  VolumeAddressGen tri(
      {FilterMode::Trilinear, AddressMode::Wrap, AddressMode::Wrap, AddressMode::Wrap});
  ASSERT_EQ(tri.taps(base, 0.3, 0.7, 0.55, 1.25f, t), 16);
  float sum = 0, lo = 0;
  for (int k = 0; k < 16; ++k) {
    sum += t[k].weight;
    if (t[k].level == 1) lo += t[k].weight;
    EXPECT_TRUE(t[k].level == 1 || t[k].level == 2);
  }
  EXPECT_NEAR(sum, 1.0f, 1e-6f);
  EXPECT_NEAR(lo, 0.75f, 1e-6f);
}

TEST(VolumeAddressGen, LevelOfDetailUsesAllThreeDerivatives) {
  const VolumeSize base{16, 16, 64};
  // One texel of u per pixel along x, four texels of r along y: ρ = 4, λ = 2.
  const double dx[3] = {1.0 / 16, 0, 0}, dy[3] = {0, 0, 4.0 / 64};
  EXPECT_FLOAT_EQ(VolumeAddressGen::lambda(dx, dy, base), 2.0f);
  // The control: a 2-D footprint (∂r left out) gives λ = 0, another level.
  const double dy2[3] = {0, 0, 0};
  EXPECT_FLOAT_EQ(VolumeAddressGen::lambda(dx, dy2, base), 0.0f);
  const double zero[3] = {0, 0, 0}, bad[3] = {NAN, INFINITY, 0};
  EXPECT_EQ(VolumeAddressGen::lambda(zero, zero, base), -INFINITY);
  EXPECT_EQ(VolumeAddressGen::lambda(bad, zero, base), -INFINITY);
  const double huge[3] = {1e300, 1e300, 1e300};
  EXPECT_TRUE(std::isfinite(VolumeAddressGen::lambda(huge, zero, base)));
}

TEST(VolumeAddressGen, NearestTakesTheFloorOfR) {
  VolumeAddressGen near(
      {FilterMode::Nearest, AddressMode::Clamp, AddressMode::Clamp, AddressMode::Clamp});
  VolumeAddressGen::Taps t{};
  ASSERT_EQ(near.taps({4, 4, 4}, 0.1, 0.1, 0.45, 0.0f, t), 1);
  EXPECT_EQ(t[0].z, 1);                                         // r·d = 1.8: ⌊1.8⌋ = 1
  const int half_up = static_cast<int>(std::lround(0.45 * 4));  // the control's rounding
  EXPECT_NE(t[0].z, half_up);
}

TEST(VolumeAddressGen, DepthOneAndNonFiniteRStayInside) {
  VolumeAddressGen tri(
      {FilterMode::Trilinear, AddressMode::Mirror, AddressMode::Wrap, AddressMode::Wrap});
  VolumeAddressGen::Taps t{};
  EXPECT_EQ(VolumeAddressGen::level_count({8, 8, 1}), 4);
  const double inf = std::numeric_limits<double>::infinity();
  for (const double r : {0.0, 0.99, -3.7, std::nan(""), inf, -inf, 1e30}) {
    const int n = tri.taps({8, 8, 1}, 0.4, 0.6, r, 0.5f, t);
    ASSERT_EQ(n, 16);
    float sum = 0;
    for (int k = 0; k < n; ++k) {
      EXPECT_EQ(t[k].z, 0) << r;
      EXPECT_GE(t[k].x, 0);
      EXPECT_LT(t[k].x, 8 >> t[k].level);
      sum += t[k].weight;
    }
    EXPECT_NEAR(sum, 1.0f, 1e-6f) << r;
  }
  // Border addressing marks taps outside the level.
  VolumeAddressGen border(
      {FilterMode::Bilinear, AddressMode::Border, AddressMode::Border, AddressMode::Border});
  ASSERT_EQ(border.taps({4, 4, 4}, 0.5, 0.5, 0.0, 0.0f, t), 8);
  int outside = 0;
  for (int k = 0; k < 8; ++k) outside += t[k].x < 0 ? 1 : 0;
  EXPECT_EQ(outside, 4);  // r = 0: k0 = −1 on half the corners
}

}  // namespace
}  // namespace texsim
