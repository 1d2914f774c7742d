// PolygonRotation and SampleProjection against independent computations: rotation matrices
// built with glm from angles (atan2, trigonometric calls), and the camera's projection
// xs = cx + f·X/Z of the unrotated points.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/ext/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <random>

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
