// Derivative blocks against the long double map (analytic and forward differences), the
// iterative formulas' errata, and the ellipse set-up (incl. F' = AC - B²/4 = F).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "blocks/geometry/projective_map.h"
#include "blocks/texture/derivs/derivatives_analytic.h"
#include "blocks/texture/derivs/derivatives_forward_diff.h"
#include "blocks/texture/derivs/derivatives_iterative.h"
#include "blocks/texture/derivs/derivatives_quad.h"
#include "blocks/texture/derivs/ellipse_setup.h"

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

double deriv_err(const CoordDerivs& d, const DerivsL& r) {
  if (!d.valid) return INFINITY;
  return std::max(
      {std::fabs(d.ux - static_cast<double>(r.ux)), std::fabs(d.vx - static_cast<double>(r.vx)),
       std::fabs(d.uy - static_cast<double>(r.uy)), std::fabs(d.vy - static_cast<double>(r.vy))});
}

const RowSpan kRow{5, 140, 480};

TEST(DerivativesAnalytic, MatchesReference) {
  const ProjectiveMap m = tilted(70);
  std::vector<CoordDerivs> out(kRow.n);
  DerivativesAnalytic().eval_row(to_coeffs<double>(m), kRow, out.data());
  double e = 0;
  for (int n = 0; n < kRow.n; ++n)
    e = std::max(e, deriv_err(out[n], analytic_derivs(m, kRow.x0 + n, kRow.y)));
  EXPECT_LT(e, 1e-9);
}

TEST(DerivativesForwardDiff, ClassicAndAcceleratedMatchForwardDifferences) {
  const ProjectiveMap m = tilted(70);
  for (auto f :
       {DerivativesForwardDiff::Form::Classic, DerivativesForwardDiff::Form::Accelerated}) {
    DerivativesForwardDiff::Config c;
    c.form = f;
    std::vector<CoordDerivs> out(kRow.n);
    DerivativesForwardDiff(c).eval_row(to_coeffs<double>(m), kRow, out.data());
    double e = 0;
    for (int n = 0; n < kRow.n; ++n)
      e = std::max(e, deriv_err(out[n], forward_diff_derivs(m, kRow.x0 + n, kRow.y)));
    EXPECT_LT(e, 1e-8);
  }
}

TEST(DerivativesQuad, SharesTheTopLeftDifferences) {
  const ProjectiveMap m = tilted(60);
  std::vector<CoordDerivs> out(kRow.n);
  DerivativesQuad().eval_row(to_coeffs<double>(m), kRow, out.data());
  for (int n = 0; n < kRow.n; ++n) {
    const int32_t qx = (kRow.x0 + n) & ~1, qy = kRow.y & ~1;
    ASSERT_LT(deriv_err(out[n], forward_diff_derivs(m, qx, qy)), 1e-8) << n;
  }
}

TEST(DerivativesIterative, CorrectedFormulasEqualForwardDifferences) {
  const ProjectiveMap m = tilted(75, 35);
  DerivativesIterative::Config c;
  const DerivativesIterative it(c);
  std::vector<CoordDerivs> out(kRow.n);
  it.eval_row(to_coeffs<double>(m), it.setup_triangle(to_coeffs<double>(m)), kRow, out.data());
  double e = 0;
  for (int n = 0; n < kRow.n; ++n)
    e = std::max(e, deriv_err(out[n], forward_diff_derivs(m, kRow.x0 + n, kRow.y)));
  EXPECT_LT(e, 1e-8);
}

TEST(DerivativesIterative, PrintedFormulasAreWrong) {
  // Erratum: the printed y denominators (K+Gx)(L+Gx) and dv/dx numerator DI-FG-DHy+EHy.
  const ProjectiveMap m = tilted(75, 35);
  DerivativesIterative::Config c;
  c.seed_misprints = true;
  const DerivativesIterative it(c);
  std::vector<CoordDerivs> out(kRow.n);
  it.eval_row(to_coeffs<double>(m), it.setup_triangle(to_coeffs<double>(m)), kRow, out.data());
  double ex = 0, ey = 0, eu = 0;
  for (int n = 0; n < kRow.n; ++n) {
    const DerivsL r = forward_diff_derivs(m, kRow.x0 + n, kRow.y);
    eu = std::max(eu, std::fabs(out[n].ux - static_cast<double>(r.ux)));
    ex = std::max(ex, std::fabs(out[n].vx - static_cast<double>(r.vx)) /
                          std::fabs(static_cast<double>(r.vx)));
    ey = std::max(ey, std::fabs(out[n].uy - static_cast<double>(r.uy)) /
                          std::fabs(static_cast<double>(r.uy)));
  }
  EXPECT_LT(eu, 1e-8);  // du/dx was printed correctly
  EXPECT_GT(ex, 0.01);  // dv/dx numerator misprint: off by more than 1 %
  EXPECT_GT(ey, 0.01);  // y denominators misprint
}

TEST(EllipseSetup, NormalFormEqualsSquaredJacobian) {
  // Lagrange's identity: AC - B²/4 = (UxVy - UyVx)², so F' = F; the printed forms differ.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> d(-3, 3);
  for (int i = 0; i < 100; ++i) {
    const DerivsL j{d(rng), d(rng), d(rng), d(rng)};
    const EllipseL e = ellipse_reference(j);
    EXPECT_NEAR(static_cast<double>(e.a * e.c - e.b * e.b / 4 - e.f), 0.0, 1e-12);
    const long double plus = j.ux * j.vy + j.uy * j.vx;
    if (std::fabs(j.ux * j.vy * j.uy * j.vx) > 0.01L) {
      EXPECT_GT(std::fabs(static_cast<double>(plus * plus - e.f)), 1e-6);
    }
    if (std::fabs(e.a - 4) > 0.1L && std::fabs(e.b) > 0.1L) {
      EXPECT_GT(std::fabs(static_cast<double>(e.a * e.c - e.b * e.b / e.a - e.f)), 1e-6);
    }
  }
}

TEST(EllipseSetup, UnitCircleMapsOntoTheNormalisedEllipse) {
  const CoordDerivs d{1.5, 0.25, -0.5, 2.0, true};
  for (auto form : {EllipseSetup::FForm::Determinant, EllipseSetup::FForm::AcMinusB2}) {
    EllipseSetup::Config c;
    c.f_form = form;
    const EllipseCoeffs e = EllipseSetup(c).eval<double>(d);
    ASSERT_TRUE(e.valid);
    for (int k = 0; k < 16; ++k) {
      const double t = k * 0.3926990816987241, dx = std::cos(t), dy = std::sin(t);
      const double U = d.ux * dx + d.uy * dy, V = d.vx * dx + d.vy * dy;
      EXPECT_NEAR(e.an * U * U + e.bn * U * V + e.cn * V * V, 1.0, 1e-12);
    }
  }
}

TEST(EllipseSetup, CancellationOfTheNormalFormInFloat) {
  // A thin footprint (nearly parallel Jacobian columns, extreme anisotropy): AC - B²/4
  // cancels in float (AC ~ 5.8e6, F = 0.09), the determinant does not.
  const double uy = static_cast<double>(40.01f);  // inputs as the float block sees them
  const CoordDerivs d{40.0, 30.0, uy, 30.0, true};
  const EllipseL r = ellipse_reference({40.0L, 30.0L, uy, 30.0L});
  EllipseSetup::Config c;
  const EllipseCoeffs det = EllipseSetup(c).eval<float>(d);
  c.f_form = EllipseSetup::FForm::AcMinusB2;
  const EllipseCoeffs acb = EllipseSetup(c).eval<float>(d);
  const double f = static_cast<double>(r.f);
  ASSERT_TRUE(det.valid);
  // Determinant: two roundings of ~1200 before a subtraction leaving 0.3: relative error
  // <= 2·2^-24·1200/0.3 ≈ 5e-4 in the Jacobian, 1e-3 in its square.
  EXPECT_LT(std::fabs(det.f - f) / f, 1e-3);
  EXPECT_TRUE(!acb.valid || std::fabs(acb.f - f) / f > 0.1);
}

TEST(DerivativeOps, IterativeVersusBaselines) {
  const DerivativesIterative it;
  DerivativesForwardDiff::Config c;
  const DerivativesForwardDiff classic(c);
  c.form = DerivativesForwardDiff::Form::Accelerated;
  const DerivativesForwardDiff accel(c);
  EXPECT_EQ(it.ops_per_item().div + it.ops_per_item().rcp, 2u);
  EXPECT_EQ(classic.ops_per_item().div, 4u);
  EXPECT_LT(it.ops_per_item().arithmetic(), accel.ops_per_item().arithmetic() + 4);
  EXPECT_LT(it.ops_per_item().arithmetic(), classic.ops_per_item().arithmetic());
}

}  // namespace
}  // namespace texsim
