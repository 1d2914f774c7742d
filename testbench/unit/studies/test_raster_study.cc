// study raster: the rectangle scan's digital rows against the edge rasteriser with exact
// Heckbert coordinates, on the study's own grid of tilts and azimuths.
#include <gtest/gtest.h>

#include "pipeline/studies/study_raster.h"

namespace texsim {
namespace {

TEST(StudyRaster, DigitalRowsDivideOncePerRowAndMissByHalfAPixelAtMost) {
  const std::vector<RasterStudyRow> rows = measure_raster_study();
  ASSERT_EQ(rows.size(), 12u);
  for (const RasterStudyRow& r : rows) {
    EXPECT_EQ(r.pixels, 512u * 512u);
    // One reciprocal per textured row of each of the two triangles.
    EXPECT_GE(r.rows, 1023u);
    EXPECT_LT(r.rows, r.pixels / 200);
    EXPECT_GT(r.memory_cycles, r.pixels);  // every textured pixel at the memory clock
    if (r.tilt_deg == 0) {
      // Screen-parallel: q is constant, every row is exact.
      EXPECT_EQ(r.max_err_texels, 0);
      continue;
    }
    // A digital row lies within 1/2 pixel of its exact line: uniformly spread offsets give a
    // mean of 1/4 pixel; the maximum adds the slope's quantisation and, near the horizon, the
    // map's curvature.
    EXPECT_NEAR(r.mean_err_minor_px, 0.25, 0.01) << r.tilt_deg << " " << r.azimuth_deg;
    EXPECT_LT(r.max_err_minor_px, r.tilt_deg >= 85 ? 2.5 : 0.8);
    EXPECT_GT(r.compared, r.pixels / 2);
  }
}

}  // namespace
}  // namespace texsim
