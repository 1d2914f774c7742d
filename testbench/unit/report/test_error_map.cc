// error.png: a fixed scale maps an error e to the colour of e / scale (saturating), the image
// keeps its size and pixels, and a colour bar below it runs from 0 to the scale with ticks.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include "pipeline/report/image_metrics.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

struct Png {
  int w = 0, h = 0;
  std::vector<uint8_t> px;
  std::array<uint8_t, 3> at(int x, int y) const {
    const size_t i = (static_cast<size_t>(y) * w + x) * 3;
    return {px[i], px[i + 1], px[i + 2]};
  }
};

Png read_png(const std::string& path) {
  Png p;
  auto in = OIIO::ImageInput::open(path);
  if (!in) return p;
  p.w = in->spec().width;
  p.h = in->spec().height;
  p.px.resize(static_cast<size_t>(p.w) * p.h * 3);
  in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, p.px.data());
  return p;
}

TEST(ErrorMap, FixedScaleSaturatesAndTheBarRunsFromZeroToTheScale) {
  TempDir d("errmap");
  // Errors 0, 0.05, 0.1 and 0.2 in the red channel; scale 0.1.
  ImageRgb img(64, 2, glm::dvec3(0)), ref(64, 2, glm::dvec3(0));
  const float errs[4] = {0.0f, 0.05f, 0.1f, 0.2f};
  for (int x = 0; x < 4; ++x) {
    img.set(x, 0, glm::vec4(0.5f + errs[x], 0.5f, 0.5f, 1));
    ref.set(x, 0, glm::vec4(0.5f, 0.5f, 0.5f, 1));
  }
  write_error_heatmap(d.file("e.png"), img, ref, 0.1);
  const Png p = read_png(d.file("e.png"));
  const int bar = colour_bar_rows(2);
  ASSERT_EQ(bar, 8);
  ASSERT_EQ(p.w, 64);
  ASSERT_EQ(p.h, 2 + bar);
  EXPECT_EQ(p.at(0, 0), heat_colour(0));
  EXPECT_EQ(p.at(1, 0), heat_colour(0.5));
  EXPECT_EQ(p.at(2, 0), (std::array<uint8_t, 3>{255, 255, 255}));
  EXPECT_EQ(p.at(3, 0), (std::array<uint8_t, 3>{255, 255, 255}));  // above the scale: white
  EXPECT_EQ(p.at(1, 0), (std::array<uint8_t, 3>{255, 128, 0}));    // half-way: orange
  EXPECT_EQ(p.at(5, 1), (std::array<uint8_t, 3>{0, 0, 0}));        // not covered
  // The bar: two black rows, then the ramp, brighter to the right, white at the right end.
  for (int x = 0; x < 64; ++x) EXPECT_EQ(p.at(x, 2), (std::array<uint8_t, 3>{0, 0, 0}));
  int last = -1;
  for (int x = 0; x < 64; ++x) {
    const auto c = p.at(x, 4);
    const int sum = c[0] + c[1] + c[2];
    EXPECT_GE(sum, last) << x;
    last = sum;
  }
  EXPECT_EQ(p.at(0, 4), heat_colour(0));
  EXPECT_EQ(p.at(63, 4), heat_colour(1));
  // Ticks in the last two rows at 0, ¼, ½, ¾ and 1 of the width.
  for (int x : {0, 15, 31, 47, 63})
    EXPECT_EQ(p.at(x, 2 + bar - 1), (std::array<uint8_t, 3>{128, 128, 128})) << x;
  EXPECT_EQ(p.at(20, 2 + bar - 1), heat_colour(20.0 / 63));
}

TEST(ErrorMap, PlacedBufferKeepsTheCanvasAndItsPixels) {
  TempDir d("errmap");
  ImageRgb img(2, 1, 2, 2, 8, 6, glm::dvec3(0.5)), ref(2, 1, 2, 2, 8, 6, glm::dvec3(0.5));
  img.set(3, 2, glm::vec4(1, 0.5, 0.5, 1));
  ref.set(3, 2, glm::vec4(0.5, 0.5, 0.5, 1));
  write_error_heatmap(d.file("e.png"), img, ref, 0.5);
  const Png p = read_png(d.file("e.png"));
  ASSERT_EQ(p.w, 8);
  ASSERT_EQ(p.h, 6 + colour_bar_rows(6));
  EXPECT_EQ(p.at(3, 2), heat_colour(1));
  EXPECT_EQ(p.at(2, 1), heat_colour(0));  // in the buffer, not covered
  EXPECT_EQ(p.at(0, 0), heat_colour(0));  // outside the buffer
}

}  // namespace
}  // namespace texsim
