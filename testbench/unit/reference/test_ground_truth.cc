// The ground truth's bilinear reference on coordinates far outside the texture: every
// addressing mode still names the texel its definition gives, without converting a double
// that does not fit a long long (undefined behaviour, found by fuzz_scene).
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace texsim
