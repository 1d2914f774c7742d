// PolygonRotation and SampleProjection against independent computations: rotation matrices
// built with glm from angles (atan2, trigonometric calls), and the camera's projection
// xs = cx + f·X/Z of the unrotated points.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/ext/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <random>
#include <tuple>

#include "blocks/geometry/polygon_rotation.h"
#include "blocks/geometry/sample_projection.h"

namespace texsim {
namespace {

glm::dvec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  for (;;) {
    const glm::dvec3 v{g(rng), g(rng), g(rng)};
    const double l = glm::length(v);
    if (l > 1e-3) return v / l;
  }
}

// The rotation from angles: α about x, then β about y, with the signs of the seed's formulas.
glm::dmat4 rotation_from_angles(const glm::dvec3& n) {
  const double alpha = std::atan2(n.y, n.z);
  const double beta = std::atan2(n.x, std::sqrt(n.y * n.y + n.z * n.z));
  // The seed's R_x: y' = y cos α − z sin α (a rotation by +α about x in glm's sense gives
  // y' = y cos α − z sin α); R_y: x' = x cos β − z sin β, i.e. glm's rotation by −β about y.
  const glm::dmat4 rx = glm::rotate(glm::dmat4(1.0), alpha, glm::dvec3(1, 0, 0));
  const glm::dmat4 ry = glm::rotate(glm::dmat4(1.0), -beta, glm::dvec3(0, 1, 0));
  return ry * rx;
}

TEST(PolygonRotation, MatchesTheRotationBuiltFromAngles) {
  std::mt19937_64 rng(14);
  for (int t = 0; t < 2000; ++t) {
    glm::dvec3 n = random_unit(rng);
    OpCounts ops;
    const Rotation r = PolygonRotation::setup(n, ops);
    if (n.z < 0) n = -n;
    ASSERT_EQ(r.kind, RotationCase::General);
    const glm::dmat4 m = rotation_from_angles(n);
    for (int k = 0; k < 4; ++k) {
      const glm::dvec3 p = random_unit(rng) * 7.0;
      const glm::dvec3 want = glm::dvec3(m * glm::dvec4(p, 1));
      const glm::dvec2 xy = PolygonRotation::rotate_xy(r, p, ops);
      EXPECT_NEAR(xy.x, want.x, 1e-12);
      EXPECT_NEAR(xy.y, want.y, 1e-12);
      EXPECT_NEAR(PolygonRotation::rotate_z(r, p, ops), want.z, 1e-12);
      const glm::dvec3 back = PolygonRotation::inverse(r, want, ops);
      EXPECT_NEAR(glm::length(back - p), 0, 1e-12);
    }
    // The normal turns into the view axis: the polygon is parallel to the screen.
    const glm::dvec2 nxy = PolygonRotation::rotate_xy(r, n, ops);
    EXPECT_NEAR(nxy.x, 0, 1e-14);
    EXPECT_NEAR(nxy.y, 0, 1e-14);
    EXPECT_NEAR(PolygonRotation::rotate_z(r, n, ops), 1, 1e-14);
  }
}

TEST(PolygonRotation, ErratumDIsTheRootOfTheSumOfSquares) {
  // With the seed's d = √(Ny² − Nz²) the cosines would not be those of a rotation.
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, 0.4, 0.5));
  OpCounts ops;
  const Rotation r = PolygonRotation::setup(n, ops);
  EXPECT_NEAR(r.cos_a * r.cos_a + r.sin_a * r.sin_a, 1, 1e-15);
  EXPECT_NEAR(r.cos_b * r.cos_b + r.sin_b * r.sin_b, 1, 1e-15);
  EXPECT_NEAR(r.cos_b, std::sqrt(n.y * n.y + n.z * n.z), 1e-15);
}

TEST(PolygonRotation, AllRotatedVerticesShareOneDepth) {
  std::mt19937_64 rng(7);
  for (int t = 0; t < 200; ++t) {
    const glm::dvec3 a = random_unit(rng) * 3.0, b = random_unit(rng) * 3.0,
                     c = random_unit(rng) * 3.0;
    OpCounts ops;
    const Rotation r = PolygonRotation::setup(PolygonRotation::unit_normal(a, b, c, ops), ops);
    const double za = PolygonRotation::rotate_z(r, a, ops);
    EXPECT_NEAR(PolygonRotation::rotate_z(r, b, ops), za, 1e-11);
    EXPECT_NEAR(PolygonRotation::rotate_z(r, c, ops), za, 1e-11);
  }
}

TEST(PolygonRotation, OpCountsOfOneVertex) {
  OpCounts ops;
  const Rotation r = PolygonRotation::setup(glm::normalize(glm::dvec3(1, 2, 3)), ops);
  OpCounts v;
  (void)PolygonRotation::rotate_xy(r, {1, 2, 3}, v);
  EXPECT_EQ(v, PolygonRotation().ops_per_item());
  EXPECT_GT(PolygonRotation().timing(TechTable::defaults()).latency, 0u);
}

TEST(SampleProjection, MatchesTheCameraProjectionOfTheUnrotatedPoint) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  const double f = 277.1, cx = 160, cy = 120;
  for (int t = 0; t < 500; ++t) {
    // A plane through a point in front of the eye with a random normal.
    const glm::dvec3 o{u(rng) * 2, u(rng) * 2, 4 + 3 * u(rng)};
    const glm::dvec3 n = random_unit(rng);
    OpCounts ops;
    const Rotation r = PolygonRotation::setup(n, ops);
    const double z = PolygonRotation::rotate_z(r, o, ops);
    const SampleProjection::Setup s = SampleProjection::setup(r, z, f, cx, cy, ops);
    const glm::dvec3 e1 = glm::normalize(glm::cross(n, glm::dvec3(0.3, 0.7, 0.1)));
    const glm::dvec3 e2 = glm::cross(n, e1);
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 p = o + e1 * u(rng) + e2 * u(rng);
      if (p.z < 0.5) continue;
      const glm::dvec2 xy = PolygonRotation::rotate_xy(r, p, ops);
      const ProjectedSample ps = SampleProjection::project(s, xy.x, xy.y, ops);
      ASSERT_TRUE(ps.valid);
      EXPECT_NEAR(ps.x, cx + f * p.x / p.z, 1e-9);
      EXPECT_NEAR(ps.y, cy + f * p.y / p.z, 1e-9);
      EXPECT_NEAR(ps.depth, p.z, 1e-11);
    }
  }
}

TEST(SampleProjection, BehindTheEyeIsInvalid) {
  OpCounts ops;
  const Rotation r = PolygonRotation::setup({0, 0, 1}, ops);
  const SampleProjection::Setup s = SampleProjection::setup(r, -2.0, 100, 0, 0, ops);
  EXPECT_FALSE(SampleProjection::project(s, 0, 0, ops).valid);
  const SampleProjection::Setup z0 = SampleProjection::setup(r, 0.0, 100, 0, 0, ops);
  EXPECT_FALSE(SampleProjection::project(z0, 1, 1, ops).valid);  // on the eye's plane: w = 0
  OpCounts one;
  (void)SampleProjection::project(z0, 1, 1, one);
  EXPECT_EQ(one, SampleProjection().ops_per_item());
}

}  // namespace
}  // namespace texsim

namespace texsim {
namespace {

// [x″ y″ z″] from the matrices: P·R_xy⁻¹·(x′, y′, z′, 1) with R_xy from the angles (glm's
// inverse, not a transpose) and P keeping z with w = 1 + r z, then the division by w.
glm::dvec3 closed_form_by_matrices(double alpha, double beta, double r, const glm::dvec3& p) {
  const glm::dmat4 rx = glm::rotate(glm::dmat4(1.0), alpha, glm::dvec3(1, 0, 0));
  const glm::dmat4 ry = glm::rotate(glm::dmat4(1.0), -beta, glm::dvec3(0, 1, 0));
  glm::dmat4 proj(1.0);
  proj[2][3] = r;  // column 2, row 3: w = z·r + 1
  const glm::dvec4 q = proj * glm::inverse(ry * rx) * glm::dvec4(p, 1);
  return glm::dvec3(q) / q.w;
}

Rotation rotation_of_angles(double alpha, double beta) {
  Rotation rot;
  rot.cos_a = std::cos(alpha);
  rot.sin_a = std::sin(alpha);
  rot.cos_b = std::cos(beta);
  rot.sin_b = std::sin(beta);
  // The unit normal the rotation turns into the z axis: (sin β, sin α cos β, cos α cos β).
  rot.normal = {rot.sin_b, rot.sin_a * rot.cos_b, rot.cos_a * rot.cos_b};
  rot.kind = RotationCase::General;
  return rot;
}

TEST(SampleProjection, ThesisClosedFormsAgainstTheMatrixProduct) {
  std::mt19937_64 rng(27);
  std::uniform_real_distribution<double> angle(-1.5, 1.5), coord(-5, 5), zc(2, 50);
  int printed_wrong = 0, points = 0;
  double worst_corrected = 0;
  for (int t = 0; t < 2000; ++t) {
    const double alpha = angle(rng), beta = angle(rng), r = -1 / zc(rng);
    const Rotation rot = rotation_of_angles(alpha, beta);
    const glm::dvec3 p{coord(rng), coord(rng), coord(rng)};
    const glm::dvec3 want = closed_form_by_matrices(alpha, beta, r, p);
    if (!(std::fabs(1 + r * (rot.normal.z * p.z - rot.sin_a * p.y - rot.cos_a * rot.sin_b * p.x)) >
          0.05))
      continue;  // near the eye plane w = 0: the division amplifies rounding
    ++points;
    OpCounts ops;
    const glm::dvec3 c = SampleProjection::thesis_closed_form(
        rot, p, r, SampleProjection::ClosedForm::Corrected, ops);
    EXPECT_EQ(ops.mul, 12u);
    EXPECT_EQ(ops.add, 6u);
    EXPECT_EQ(ops.rcp, 1u);
    worst_corrected =
        std::max(worst_corrected, glm::length(c - want) / std::max(1.0, glm::length(want)));
    const glm::dvec3 pr =
        SampleProjection::thesis_closed_form(rot, p, r, SampleProjection::ClosedForm::Printed, ops);
    if (glm::length(pr - want) > 1e-6 * std::max(1.0, glm::length(want))) ++printed_wrong;
    // The printed numerators are right; only the denominator's x′ term is not: with x′ = 0 the
    // printed form equals the product.
    const glm::dvec3 p0{0, p.y, p.z};
    EXPECT_LT(glm::length(SampleProjection::thesis_closed_form(
                              rot, p0, r, SampleProjection::ClosedForm::Printed, ops) -
                          closed_form_by_matrices(alpha, beta, r, p0)),
              1e-9 * std::max(1.0, glm::length(closed_form_by_matrices(alpha, beta, r, p0))));
  }
  EXPECT_LT(worst_corrected, 1e-11);
  // The printed D has −r·Ny·x′ where the product gives −r·cos α sin β·x′: wrong almost always.
  EXPECT_GT(printed_wrong, points * 95 / 100);
  std::printf("closed forms: %d points, corrected worst relative error %.3g, printed wrong at %d\n",
              points, worst_corrected, printed_wrong);
}

TEST(SampleProjection, PrintedDenominatorHoldsOnlyWhereNyEqualsCosAlphaSinBeta) {
  // Ny = sin α cos β and cos α sin β agree when tan α = tan β (α = β): there the printed form is
  // right for every point; at α = 0.3, β = −0.2 it is not.
  OpCounts ops;
  const glm::dvec3 p{1.7, -0.4, 2.2};
  const double r = -1.0 / 8;
  for (const auto& [a, b, right] : {std::tuple{0.4, 0.4, true}, std::tuple{0.3, -0.2, false}}) {
    const glm::dvec3 pr = SampleProjection::thesis_closed_form(
        rotation_of_angles(a, b), p, r, SampleProjection::ClosedForm::Printed, ops);
    const double err = glm::length(pr - closed_form_by_matrices(a, b, r, p));
    if (right) {
      EXPECT_LT(err, 1e-12);
    } else {
      EXPECT_GT(err, 1e-2);
    }
  }
}

}  // namespace
}  // namespace texsim
