// study terrain: the rows the study reports, checked against the closed forms of
// docs/derivations/terrain.md (variant 1's ripple, variant 2's slope jumps, the factored form's
// three multiplications).
#include <gtest/gtest.h>

#include <cmath>

#include "pipeline/studies/study_terrain.h"

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

}  // namespace
}  // namespace texsim
