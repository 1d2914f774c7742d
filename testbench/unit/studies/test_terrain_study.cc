// study terrain: the rows the study reports, checked against the closed forms of
// docs/derivations/terrain.md (variant 1's ripple, variant 2's slope jumps, the factored form's
// three multiplications).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "pipeline/studies/study_terrain.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

TEST(StudyTerrain, RowsMatchTheClosedForms) {
  const std::vector<TerrainStudyRow> rows = measure_terrain_study();
  ASSERT_EQ(rows.size(), 14u);
  int widened = 0;
  for (const TerrainStudyRow& r : rows) {
    const Deformation d = r.basis.deformation;
    if (d == Deformation::Widened) {
      ++widened;
      EXPECT_EQ(r.heights, 9);
      EXPECT_FALSE(r.has_8mul);
    } else {
      EXPECT_EQ(r.heights, 4);
      EXPECT_EQ(r.ops3.mul, 3u) << r.function << " " << r.deformation;
      EXPECT_EQ(r.ops8.mul, 8u);
      EXPECT_LT(r.area3, r.area8);
      EXPECT_LT(r.ripple_2d, 1e-14);  // two-term partition of unity
    }
    if (d == Deformation::None) {
      EXPECT_NEAR(r.terrace, r.basis.kind == FiniteKind::Tent ? 0 : 1, 1e-9);
    }
    if (d == Deformation::Blended) {
      EXPECT_NEAR(r.jump_ratio, 1 - std::ldexp(1.0, -r.basis.blend_shift), 1e-6);
    }
    if (d == Deformation::Widened && r.basis.kind == FiniteKind::Cosine) {
      EXPECT_LT(r.ripple_1d, 1e-14);
    }
    if (d == Deformation::Widened && r.basis.kind == FiniteKind::Quadratic) {
      EXPECT_NEAR(r.ripple_1d, 1.0 / 27, 1e-9);
    }
    if (d == Deformation::Widened && r.basis.kind == FiniteKind::Exp2) {
      EXPECT_NEAR(r.ripple_1d, 2.0 / 3 * (1 + 2 * (1 - std::exp2(-4.0 / 9))) - 1, 1e-9);
    }
    if (r.basis.kind != FiniteKind::Tent && d != Deformation::Blended) {
      EXPECT_LT(r.jump_ratio, 1e-6);  // C¹
    }
  }
  EXPECT_EQ(widened, 4);
}

// terrain.csv against the measured rows: counts and operators as measured, ripples in per cent
// (4 decimals), the other figures to their printed digits; names with a comma are quoted (a
// variant 2 row once had an unquoted comma, one cell too many).
TEST(StudyTerrain, TableCellsAreTheMeasuredFigures) {
  const std::vector<TerrainStudyRow> rows = measure_terrain_study();
  const TempDir dir("terrain_study");
  std::ostringstream log;
  ASSERT_EQ(run_study_terrain(dir.file("out"), log), 0);
  std::ifstream in(dir.file("out/terrain.csv"));
  std::string line;
  std::getline(in, line);
  size_t k = 0;
  while (std::getline(in, line)) {
    std::vector<std::string> c(1);
    bool quoted = false;
    for (char ch : line) {
      if (ch == '"') {
        quoted = !quoted;
      } else if (ch == ',' && !quoted) {
        c.emplace_back();
      } else {
        c.back() += ch;
      }
    }
    ASSERT_EQ(c.size(), 13u) << line;
    ASSERT_LT(k, rows.size());
    const TerrainStudyRow& r = rows[k++];
    EXPECT_EQ(c[0], r.function);
    EXPECT_EQ(c[1], r.deformation);
    EXPECT_EQ(std::stoi(c[2]), r.heights);
    auto ops = [](const OpCounts& o) {
      return std::to_string(o.mul) + " / " + std::to_string(o.add) + " / " + std::to_string(o.lut);
    };
    EXPECT_EQ(c[3], ops(r.ops3)) << line;
    EXPECT_EQ(c[4], r.has_8mul ? ops(r.ops8) : "—") << line;
    EXPECT_NEAR(std::stod(c[5]), r.latency3, 5e-4 * r.latency3) << line;
    EXPECT_NEAR(std::stod(c[6]), r.area3, 5e-4 * r.area3) << line;
    EXPECT_NEAR(std::stod(c[7]), r.max_jump, 5e-3 * r.max_jump + 1e-12) << line;
    EXPECT_NEAR(std::stod(c[8]), r.jump_ratio, 5e-4 * r.jump_ratio + 1e-12) << line;
    EXPECT_NEAR(std::stod(c[9]), 100 * r.ripple_1d, 5e-5) << line;
    EXPECT_NEAR(std::stod(c[10]), 100 * r.ripple_2d, 5e-5) << line;
    EXPECT_NEAR(std::stod(c[11]), r.terrace, 5e-4 * std::abs(r.terrace) + 1e-12) << line;
  }
  EXPECT_EQ(k, rows.size());
}

}  // namespace
}  // namespace texsim
