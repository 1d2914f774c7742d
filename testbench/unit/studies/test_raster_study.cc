// study raster: the rectangle scan's digital rows against the edge rasteriser with exact
// Heckbert coordinates, on the study's own grid of tilts and azimuths.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "pipeline/studies/study_raster.h"
#include "testbench/lib/temp_dir.h"

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

// raster.csv's derived columns against the columns they derive from.
TEST(StudyRaster, TableColumnsFollowTheirDefinitions) {
  const TempDir dir("raster_study");
  std::ostringstream log;
  ASSERT_EQ(run_study_raster(dir.file("out"), log), 0);
  std::ifstream in(dir.file("out/raster.csv"));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line,
            "tilt °,azimuth °,pixels,Heckbert divisions,rect-scan divisions,divisions per pixel,"
            "edge cycles,rect-scan fast / memory cycles,edge time µs,rect-scan time µs,pixels "
            "compared,mean error texels,max error texels,mean error px,max error px");
  int rows = 0;
  while (std::getline(in, line)) {
    std::vector<std::string> c(1);
    for (char ch : line) {
      if (ch == ',') {
        c.emplace_back();
      } else {
        c.back() += ch;
      }
    }
    ASSERT_EQ(c.size(), 15u) << line;
    const double pixels = std::stod(c[2]);
    EXPECT_EQ(c[3], c[2]) << "Heckbert: one division per pixel";
    const double dpp = std::stod(c[5]);  // 3 significant digits
    EXPECT_NEAR(dpp, std::stod(c[4]) / pixels, 5e-3 * dpp) << line;
    // Edge rasteriser: one visited pixel per cycle at the default 500 MHz.
    const double edge_us = std::stod(c[8]);
    EXPECT_NEAR(edge_us, std::stod(c[6]) / 500.0, 5e-5 * edge_us) << line;
    // The rectangle scan's two clocks (1000 and 250 MHz) run side by side: its time is at least
    // each clock's cycles.
    const size_t slash = c[7].find(" / ");
    ASSERT_NE(slash, std::string::npos) << line;
    const double fast = std::stod(c[7].substr(0, slash)), mem = std::stod(c[7].substr(slash + 3));
    EXPECT_GE(std::stod(c[9]) * (1 + 5e-5), std::max(fast / 1000.0, mem / 250.0)) << line;
    EXPECT_LE(std::stod(c[10]), pixels) << line;
    EXPECT_LE(std::stod(c[11]), std::stod(c[12]) * (1 + 5e-4)) << "mean <= max: " << line;
    EXPECT_LE(std::stod(c[13]), std::stod(c[14]) * (1 + 5e-3)) << "mean <= max: " << line;
    ++rows;
  }
  EXPECT_EQ(rows, 12);
}

}  // namespace
}  // namespace texsim
