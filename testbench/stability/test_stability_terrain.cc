// Hard cases of the terrain relief effect (the ground of the terrain flyover scenes): views
// parallel to the surface, heights at 0 and at the maximum, NaN heights and view vectors, a
// one-texel spike. Each has a bound or a defined result (docs/scenes.md#terrain-flyovers).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "pipeline/texture/surface_effects.h"

namespace texsim {
namespace {

constexpr int kSize = 32;
constexpr double kScale = 8;

Texture heights(float fill, int spike_x = -1, int spike_y = -1) {
  std::vector<float> rgba;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const float h = x == spike_x && y == spike_y ? 1.0F : fill;
      rgba.insert(rgba.end(), {h, h, h, 1.0F});
    }
  }
  return Texture::from_rgba("h", kSize, kSize, rgba, TexelFormat::Rgba32f, false);
}

ReliefEffect effect(const Texture& t) {
  ReliefSetup s;
  s.method = ReliefSetup::Method::Terrain;
  s.height_texture = "h";
  s.scale = kScale;
  return ReliefEffect(s, t);
}

// (u, v) of texel centre (x, y) and back.
double u_of(double x) { return (x + 0.5) / kSize; }
double x_of(double u) { return u * kSize - 0.5; }

// A unit view vector `elev` degrees above the surface, towards +x (the ray runs towards -x).
glm::dvec3 view(double elev_deg) {
  const double e = elev_deg * 3.14159265358979323846 / 180;
  return {std::cos(e), 0, std::sin(e)};
}

ReliefEffect::Shift shift(const ReliefEffect& fx, double x, double y, const glm::dvec3& v) {
  OpCounts ops;
  // One world unit per texel: u_len = v_len = kSize.
  return fx.shift(u_of(x), u_of(y), v, kSize, kSize, ops);
}

TEST(StabilityTerrain, FlatMapsAtZeroAndMaximum) {
  // Height 0: the ray meets the ground scale / tan(45°) = 8 texels away.
  const auto low = shift(effect(heights(0)), 20, 16, view(45));
  EXPECT_NEAR(x_of(low.u), 12, 1e-2);
  EXPECT_NEAR(x_of(low.v), 16, 1e-9);
  // The march skips to the grid's top bound (here the ground): two steps and 10 halvings.
  EXPECT_LE(low.steps, 2U + 10U);
  // Height 1 (the polygon itself): hit at once, no shift.
  const auto top = shift(effect(heights(1)), 20, 16, view(45));
  EXPECT_NEAR(x_of(top.u), 20, 1e-2);
  EXPECT_LE(top.steps, 2U + 10U);
}

TEST(StabilityTerrain, ViewParallelToTheSurfaceIsCappedAndUnshifted) {
  for (const float fill : {0.0F, 0.5F, 1.0F}) {
    const auto s = shift(effect(heights(fill)), 20, 16, glm::dvec3(1, 0, 0));
    EXPECT_DOUBLE_EQ(s.u, u_of(20)) << fill;  // no hit: the fragment keeps its (u, v)
    EXPECT_DOUBLE_EQ(s.v, u_of(16));
    EXPECT_LE(s.steps, 4096U + 10U);  // max_steps + refine_steps
  }
}

TEST(StabilityTerrain, NaNViewAndNaNHeights) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto s = shift(effect(heights(0.5F)), 20, 16, glm::dvec3(nan, 0, 1));
  EXPECT_DOUBLE_EQ(s.u, u_of(20));
  EXPECT_EQ(s.steps, 0U);
  EXPECT_EQ(s.fetches, 0U);
  // NaN heights read as 0 (TerrainGrid's no-data fallback): the same hit as a flat 0 map.
  const auto n = shift(effect(heights(std::numeric_limits<float>::quiet_NaN())), 20, 16, view(45));
  const auto z = shift(effect(heights(0)), 20, 16, view(45));
  EXPECT_DOUBLE_EQ(n.u, z.u);
}

TEST(StabilityTerrain, OneTexelSpikeStopsTheRay) {
  // The ray drops 1/2 per texel (elevation atan(1/2)); without the spike it meets the ground
  // 16 texels away, at x = 4; the spike (height 8 at x = 12) is 4 below the ray there.
  const double elev = std::atan(0.5) * 180 / 3.14159265358979323846;
  const auto open = shift(effect(heights(0)), 20, 16, view(elev));
  EXPECT_NEAR(x_of(open.u), 4, 1e-2);
  const auto hit = shift(effect(heights(0, 12, 16)), 20, 16, view(elev));
  EXPECT_GT(x_of(hit.u), 11);
  EXPECT_LT(x_of(hit.u), 13.5);
}

}  // namespace
}  // namespace texsim
