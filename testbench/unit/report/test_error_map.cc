// error.png: a fixed scale maps an error e to the colour of e / scale (saturating), the image
// keeps its size and pixels, and a colour bar below it runs from 0 to the scale with ticks.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include "pipeline/report/image_metrics.h"
#include "pipeline/report/label_font.h"
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
  const int bar = colour_bar_rows(2), ramp = 8;  // max(8, 2 / 12), then 7 + 4 label rows
  ASSERT_EQ(bar, ramp + 11);
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
    EXPECT_EQ(p.at(x, 2 + ramp - 1), (std::array<uint8_t, 3>{128, 128, 128})) << x;
  EXPECT_EQ(p.at(20, 2 + ramp - 1), heat_colour(20.0 / 63));
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

TEST(ErrorMap, LabelNumbersAndGlyphs) {
  EXPECT_EQ(label_number(0), "0");
  EXPECT_EQ(label_number(0.1 * 255 / 4), "6.38");
  EXPECT_EQ(label_number(0.1 * 255), "25.5");
  EXPECT_EQ(label_number(255), "255");
  EXPECT_EQ(label_number(0.25 * 255 / 4), "15.9");
  EXPECT_EQ(label_number(1e-5 * 255), "0.00255");
  EXPECT_EQ(label_number(1e-6), "1e-06");
  EXPECT_EQ(label_width("12", 1), 11);
  EXPECT_EQ(label_width("12", 3), 33);
  // '1' at scale 2: its stem is glyph column 2, rows 0-6 -> pixels x 4-5, y 0-13; its foot
  // (row 6) spans columns 1-3 -> x 2-7 at y 12-13.
  std::vector<uint8_t> rgb(size_t{20} * 16 * 3, 0);
  draw_label(rgb, 20, 16, 0, 0, "1", 2, {255, 255, 255});
  const auto lit = [&](int x, int y) { return rgb[(static_cast<size_t>(y) * 20 + x) * 3] != 0; };
  for (int y = 0; y < 14; ++y) EXPECT_TRUE(lit(4, y) && lit(5, y)) << y;
  EXPECT_FALSE(lit(3, 5));
  EXPECT_TRUE(lit(2, 12) && lit(7, 13));
  EXPECT_FALSE(lit(8, 13));
  EXPECT_FALSE(lit(4, 14));
  // Off the image: nothing written outside, no crash.
  draw_label(rgb, 20, 16, 18, 14, "888", 3, {255, 255, 255});
}

// The bar's values: below the ramp, one label per tick where there is room — 0 at the left
// edge, the scale with its unit ending at the right edge, the others centred on their ticks.
TEST(ErrorMap, TheBarCarriesItsValues) {
  TempDir d("errmap");
  ImageRgb img(320, 240, glm::dvec3(0)), ref(320, 240, glm::dvec3(0));
  write_error_heatmap(d.file("e.png"), img, ref, 0.1);
  const Png p = read_png(d.file("e.png"));
  const int ramp = 240 / 12, top = 240 + ramp;
  ASSERT_EQ(p.h, 240 + colour_bar_rows(240));
  ASSERT_EQ(colour_bar_rows(240), ramp + 7 + 4);
  // Columns with a lit pixel in the label rows, grouped into runs (a gap > 4 px ends a run).
  std::vector<std::pair<int, int>> runs;
  for (int x = 0; x < p.w; ++x) {
    bool any = false;
    for (int y = top; y < p.h; ++y) any = any || p.at(x, y)[0] != 0;
    if (!any) continue;
    if (!runs.empty() && x - runs.back().second <= 5) {
      runs.back().second = x;
    } else {
      runs.emplace_back(x, x);
    }
  }
  // "0", "6.38", "12.8", "19.1", "25.5 LSB" (the space inside the last splits it in two).
  ASSERT_EQ(runs.size(), 6u);
  EXPECT_EQ(runs[0].first, 0);
  EXPECT_EQ(runs.back().second, 319);
  for (int k = 1; k <= 3; ++k) {
    const int tick = k * 319 / 4, centre = (runs[k].first + runs[k].second) / 2;
    EXPECT_NEAR(centre, tick, 3) << k;
  }
  EXPECT_EQ(runs[1].second - runs[1].first + 1, label_width("6.38", 1));
  // The ramp's own rows are untouched by the labels: the last tick row still ends grey.
  EXPECT_EQ(p.at(319, top - 1), (std::array<uint8_t, 3>{128, 128, 128}));
  // Too narrow for all five: 0 and the scale only, never overlapping.
  ImageRgb narrow(64, 2, glm::dvec3(0)), nref(64, 2, glm::dvec3(0));
  write_error_heatmap(d.file("n.png"), narrow, nref, 0.1);
  const Png q = read_png(d.file("n.png"));
  int lit = 0;
  for (int x = 0; x < q.w; ++x)
    for (int y = 2 + 8; y < q.h; ++y) lit += q.at(x, y)[0] != 0 ? 1 : 0;
  EXPECT_GT(lit, 0);
  EXPECT_EQ(q.at(20, 2 + 8 + 4)[0], 0);  // between "0" and "25.5 LSB": nothing drawn
}

}  // namespace
}  // namespace texsim
