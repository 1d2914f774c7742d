// Row and triangle polynomial approximations of the texture coordinates, and the A2 erratum.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "blocks/geometry/projective_map.h"
#include "blocks/texture/coords/uv_approximation.h"
#include "blocks/texture/coords/uv_approximation_triangle.h"

namespace texsim {
namespace {

ProjectiveMap tilted(double tilt, double az = 20.0) {
  PlaneView pv;
  pv.tilt_deg = tilt;
  pv.azimuth_deg = az;
  pv.u_offset = 512;
  pv.v_offset = 512;
  const long double xs[1] = {255.5L}, ys[1] = {255.5L};
  return ProjectiveMap::from_plane_view(pv).normalised(xs, ys, 1);
}

double row_error(const ProjectiveMap& m, const RowSpan& s, const std::vector<CoordSample>& out) {
  double e = 0;
  for (int32_t n = 0; n < s.n; ++n) {
    if (!out[n].valid) return INFINITY;
    e = std::max(e, std::fabs(out[n].u - static_cast<double>(m.u(s.x0 + n, s.y))));
    e = std::max(e, std::fabs(out[n].v - static_cast<double>(m.v(s.x0 + n, s.y))));
  }
  return e;
}

TEST(QuadraticErratum, CorrectedA2PassesThroughTheEndPoint) {
  // u(s) = A1 s² + A2 s + A3 must equal u2 at s = 1 and u1 at s = 1/2.
  const long double u0 = 3.25L, u1 = 7.5L, u2 = 20.0L;
  const auto c = quadratic_coeffs(u0, u1, u2);
  EXPECT_DOUBLE_EQ(static_cast<double>(c[0] + c[1] + c[2]), 20.0);
  EXPECT_DOUBLE_EQ(static_cast<double>(c[0] / 4 + c[1] / 2 + c[2]), 7.5);
  // The printed A2 = -3u0 + 4u1 - 2u2 misses u2 by exactly u2 (the curve ends at 0).
  const auto bad = quadratic_coeffs(u0, u1, u2, true);
  EXPECT_DOUBLE_EQ(static_cast<double>(bad[0] + bad[1] + bad[2]), 0.0);
}

TEST(CubicCoefficients, PassThroughTheFourPoints) {
  const double p[4] = {1.0, -2.0, 5.0, 11.0};
  const auto c = cubic_coeffs(p[0], p[1], p[2], p[3]);
  for (int i = 0; i < 4; ++i) {
    const double s = i / 3.0;
    EXPECT_NEAR(((c[0] * s + c[1]) * s + c[2]) * s + c[3], p[i], 1e-12);
  }
}

TEST(UvApproximation, ExactOnAnAffineMapAndOrderedOnPerspective) {
  ProjectiveMap affine;
  affine.A = 0.75L;
  affine.B = 0.1L;
  affine.C = 3;
  affine.D = -0.2L;
  affine.E = 1.5L;
  affine.F = 7;
  affine.G = 0;
  affine.H = 0;
  affine.I = 1;
  const ProjectiveMap persp = tilted(70);
  const RowSpan s{0, 120, 512};
  std::vector<CoordSample> out(512);
  double err[4] = {};
  for (auto o : {UvApproximation::Order::Affine, UvApproximation::Order::Quadratic,
                 UvApproximation::Order::Cubic}) {
    UvApproximation::Config c;
    c.order = o;
    const UvApproximation b(c);
    b.eval_row(to_coeffs<double>(affine), s, out.data());
    EXPECT_LT(row_error(affine, s, out), 1e-9);
    b.eval_row(to_coeffs<double>(persp), s, out.data());
    err[static_cast<int>(o)] = row_error(persp, s, out);
  }
  EXPECT_GT(err[1], 1.0);  // affine is wrong under perspective by texels
  EXPECT_LT(err[2], err[1] / 4);
  EXPECT_LT(err[3], err[2] / 4);
}

TEST(UvApproximation, ShortSpans) {
  const ProjectiveMap m = tilted(60);
  UvApproximation::Config c;
  c.order = UvApproximation::Order::Cubic;
  const UvApproximation b(c);
  for (int32_t n : {1, 2, 3}) {
    const RowSpan s{100, 150, n};
    std::vector<CoordSample> out(static_cast<size_t>(n));
    b.eval_row(to_coeffs<double>(m), s, out.data());
    EXPECT_LT(row_error(m, s, out), 1e-9) << n;  // a cubic through 4 exact points over <= 3 px
  }
}

TEST(UvApproximationTriangle, ReproducesNodesAndBeatsLowerOrder) {
  const ProjectiveMap m = tilted(65);
  UvApproximationTriangle::Triangle tri;
  tri.x[0] = 40;
  tri.y[0] = 30;
  tri.x[1] = 300;
  tri.y[1] = 60;
  tri.x[2] = 120;
  tri.y[2] = 220;
  double worst[2] = {};
  for (auto o :
       {UvApproximationTriangle::Order::Biquadratic, UvApproximationTriangle::Order::Bicubic}) {
    UvApproximationTriangle::Config c;
    c.order = o;
    const UvApproximationTriangle b(c);
    const auto st = b.setup_triangle(to_coeffs<double>(m), tri);
    ASSERT_TRUE(st.ok);
    // Evaluate the polynomial at every node: it must give the exact map value there.
    for (int i = 0; i < b.nodes(); ++i) {
      const auto l = UvApproximationTriangle::node(o, i);
      const double a = static_cast<double>(l[0]), bb = static_cast<double>(l[1]);
      const double mono[10] = {1,       a,         bb,         a * a,       a * bb,
                               bb * bb, a * a * a, a * a * bb, a * bb * bb, bb * bb * bb};
      double u = 0;
      for (int j = 0; j < b.nodes(); ++j) u += st.cu[j] * mono[j];
      const long double x = tri.x[0] + l[0] * (tri.x[1] - tri.x[0]) + l[1] * (tri.x[2] - tri.x[0]);
      const long double y = tri.y[0] + l[0] * (tri.y[1] - tri.y[0]) + l[1] * (tri.y[2] - tri.y[0]);
      EXPECT_NEAR(u, static_cast<double>(m.u(x, y)), 1e-8) << i;
    }
    // Rows through the triangle interior.
    double e = 0;
    for (int32_t y = 60; y < 200; y += 20) {
      const RowSpan s{110, y, 60};
      std::vector<CoordSample> out(60);
      b.eval_row(st, s, out.data());
      e = std::max(e, row_error(m, s, out));
    }
    worst[o == UvApproximationTriangle::Order::Bicubic] = e;
  }
  EXPECT_LT(worst[1], worst[0]);
  EXPECT_GT(worst[0], 1e-3);  // perspective is not a polynomial: the error is real
}

TEST(UvApproximationTriangle, MatrixOpsCounted) {
  UvApproximationTriangle::Config c;
  const UvApproximationTriangle q(c);
  EXPECT_EQ(q.ops_per_item().add, 4u);
  EXPECT_EQ(q.triangle_setup_ops().div, 12u);
  c.order = UvApproximationTriangle::Order::Bicubic;
  const UvApproximationTriangle cu(c);
  EXPECT_EQ(cu.ops_per_item().add, 6u);
  EXPECT_EQ(cu.triangle_setup_ops().div, 20u);
  EXPECT_GT(cu.triangle_setup_ops().mul, q.triangle_setup_ops().mul);
}

}  // namespace
}  // namespace texsim
