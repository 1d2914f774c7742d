// scenes/footprint_filters.toml compares four filters material by material, so each material
// must cover comparable pixels: the same number, on the same rows (a row is one depth), with
// footprints of the same size and elongation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "pipeline/raster/fragment_generator.h"
#include "pipeline/scene/scene.h"

namespace texsim {
namespace {

// What one material's pixels look like.
struct MaterialPixels {
  int fragments = 0;
  int first_row = 1 << 30, last_row = -1;
  std::map<int, int> per_row;
  double log2_aniso = 0;  // mean log2(major / minor) of the pixel footprint
  double log2_major = 0;  // mean log2 of the major axis (the level of detail, in texture widths)
};

std::map<std::string, MaterialPixels> pixels_by_material(const Scene& scene) {
  std::map<std::string, MaterialPixels> by;
  for (const Fragment& f : generate_fragments(scene)) {
    MaterialPixels& m = by[scene.materials[scene.primitives[f.prim].material].name];
    const int y = static_cast<int>(f.y);
    ++m.fragments;
    m.first_row = std::min(m.first_row, y);
    m.last_row = std::max(m.last_row, y);
    ++m.per_row[y];
    const double lx = std::hypot(f.dudx, f.dvdx), ly = std::hypot(f.dudy, f.dvdy);
    const double major = std::max(lx, ly);
    const double minor = std::abs(f.dudx * f.dvdy - f.dvdx * f.dudy) / major;
    m.log2_aniso += std::log2(major / minor);
    m.log2_major += std::log2(major);
  }
  for (auto& [name, m] : by) {
    m.log2_aniso /= m.fragments;
    m.log2_major /= m.fragments;
  }
  return by;
}

TEST(FootprintFiltersScene, EachMaterialCoversComparablePixels) {
  const Scene scene = load_scene(std::string(TEXSIM_SOURCE_DIR) + "/scenes/footprint_filters.toml");
  const auto by = pixels_by_material(scene);
  ASSERT_EQ(by.size(), 4u);
  const MaterialPixels& first = by.begin()->second;
  EXPECT_GT(first.fragments, 2000);
  for (const auto& [name, m] : by) {
    // Fragment counts within 1% of each other (the layout gives equal widths on every row;
    // only pixel-centre rounding at the strips' edges differs).
    EXPECT_NEAR(m.fragments, first.fragments, 0.01 * first.fragments) << name;
    // The same depth range: the same first and last rows.
    EXPECT_NEAR(m.first_row, first.first_row, 1) << name;
    EXPECT_NEAR(m.last_row, first.last_row, 1) << name;
    // Row by row, the same width to a pixel or two.
    for (const auto& [y, n] : first.per_row) {
      const auto it = m.per_row.find(y);
      EXPECT_NEAR(it == m.per_row.end() ? 0 : it->second, n, 2) << name << " row " << y;
    }
    // The same obliqueness: footprints as elongated and as large.
    EXPECT_NEAR(m.log2_aniso, first.log2_aniso, 0.05) << name;
    EXPECT_NEAR(m.log2_major, first.log2_major, 0.05) << name;
  }
}

}  // namespace
}  // namespace texsim
