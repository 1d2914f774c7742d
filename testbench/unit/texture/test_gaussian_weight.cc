// Gaussian pixel-model weight unit: power-8 form against exp(−q/2), fixed-point datapath
// bit-exact against an integer model, the exact quadratic form against the screen-space
// distance, and the seed's θ/L/d axis rules' error for rotated footprints (the table in
// docs/derivations/gaussian-weights.md is printed by AxesErrorTable).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>

#include "blocks/base/input_error.h"
#include "blocks/texture/footprint/gaussian_weight.h"

namespace texsim {
namespace {

using D = GaussianWeightFormat<double>;
using Fx = GaussianWeightFx16;
constexpr double kPi = 3.14159265358979323846;

// ---- Power 8 against exp -----------------------------------------------------------------
struct MaxAt {
  double max = 0, at = 0;
};

MaxAt pow8_vs_exp(double lo, double hi, int n) {
  MaxAt m;
  for (int i = 0; i <= n; ++i) {
    const double q = lo + (hi - lo) * i / n;
    const double e =
        std::fabs(GaussianWeight::weight_pow8<D>(q) - GaussianWeight::weight_exp<D>(q));
    if (e > m.max) m = {e, q};
  }
  return m;
}

TEST(GaussianWeight, Pow8AgainstExp) {
  // Documented in docs/derivations/gaussian-weights.md: max |(1 − q/16)^8 − exp(−q/2)| on [0, 16).
  const MaxAt m = pow8_vs_exp(0.0, 16.0, 1'600'000);
  std::printf("pow8 vs exp on [0,16): max %.6f at q = %.5f\n", m.max, m.at);
  EXPECT_LE(m.max, 0.03531);
  EXPECT_GE(m.max, 0.03530);
  EXPECT_NEAR(m.at, 3.826, 0.002);
  // The power-8 form is below exp everywhere on (0, 16): (1 − x/n)^n < e^−x.
  for (double q = 0.01; q < 16; q += 0.01) {
    ASSERT_LT(GaussianWeight::weight_pow8<D>(q), GaussianWeight::weight_exp<D>(q)) << q;
  }
  // From 16 on the power-8 form is 0; exp's tail there is at most exp(−8).
  for (double q : {16.0, 16.0001, 20.0, 1e6, std::numeric_limits<double>::infinity()}) {
    EXPECT_EQ(GaussianWeight::weight_pow8<D>(q), 0.0) << q;
  }
  EXPECT_NEAR(pow8_vs_exp(16.0, 64.0, 100000).max, std::exp(-8.0), 1e-15);
  // Continuous at 16 (unlike a truncated exp): the value just below is tiny.
  EXPECT_LT(GaussianWeight::weight_pow8<D>(std::nextafter(16.0, 0.0)), 1e-100);
  // The block equals the formula.
  for (double q = 0; q < 16; q += 0.37) {
    EXPECT_NEAR(GaussianWeight::weight_pow8<D>(q), std::pow(1 - q / 16, 8), 1e-15);
    EXPECT_EQ(GaussianWeight::weight_exp<D>(q), std::exp(-0.5 * q));
  }
}

TEST(GaussianWeight, OutOfRangeInputs) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(GaussianWeight::weight_pow8<D>(nan), 0.0);
  EXPECT_EQ(GaussianWeight::weight_exp<D>(nan), 0.0);
  EXPECT_EQ(GaussianWeight::weight_pow8<D>(-1e-12), 1.0);
  EXPECT_EQ(GaussianWeight::weight_exp<D>(-1e-12), 1.0);
  EXPECT_EQ(GaussianWeight::weight_exp<D>(std::numeric_limits<double>::infinity()), 0.0);
}

// Integer model of the u5.11 → u1.15 power-8 datapath: t = 2^15 − q_raw exactly, three
// squarings each rounded half-up to 15 fraction bits.
int64_t rhu(int64_t x, int s) { return (x + (int64_t{1} << (s - 1))) >> s; }

TEST(GaussianWeight, FixedPow8BitExactAndWithinBudget) {
  double worst = 0, worst_q = 0;
  for (int64_t code = 0; code < (int64_t{1} << 16); ++code) {
    const Fx::Q q = Fx::Q::from_raw(code);
    int64_t expect = 0;
    if (code < int64_t{16} * 2048) {
      const int64_t t = 32768 - code;
      const int64_t t2 = rhu(t * t, 15), t4 = rhu(t2 * t2, 15);
      expect = rhu(t4 * t4, 15);
    }
    const auto w = GaussianWeight::weight_pow8<Fx>(q);
    ASSERT_EQ(w.raw(), expect) << "q code " << code;
    const long double x = static_cast<long double>(q.to_double());
    const long double real = x < 16 ? std::pow(1.0L - x / 16, 8) : 0.0L;
    const double err =
        static_cast<double>(std::fabs(static_cast<long double>(w.to_double()) - real));
    if (err > worst) {
      worst = err;
      worst_q = static_cast<double>(x);
    }
  }
  std::printf("u5.11->u1.15 power 8: max error vs real (1-q/16)^8 = %.3g (%.2f LSB) at q = %.5g\n",
              worst, worst / Fx::W::lsb(), worst_q);
  // Rounding budget: ½ LSB per squaring, doubled by each later squaring (t ≤ 1): ½+1+2 = 3.5.
  EXPECT_LE(worst, 3.5 * Fx::W::lsb());
}

TEST(GaussianWeight, FixedExpWithinHalfLsb) {
  for (int64_t code = 0; code < (int64_t{1} << 16); code += 3) {
    const Fx::Q q = Fx::Q::from_raw(code);
    const long double real = std::exp(-0.5L * static_cast<long double>(q.to_double()));
    ASSERT_LE(
        std::fabs(static_cast<long double>(GaussianWeight::weight_exp<Fx>(q).to_double()) - real),
        0.5L * Fx::W::lsb() + 1e-18L)
        << code;
  }
}

// ---- Axes rules ----------------------------------------------------------------------------
// Footprint J = R(φ)·diag(r, 1)·R(ψ): columns are the derivative vectors (Ux, Vx), (Uy, Vy).
// ψ = 0 makes them orthogonal (the screen axes map onto the ellipse axes); ψ ≠ 0 skews them.
struct Jac {
  double ux, vx, uy, vy;
};
Jac footprint(double r, double phi, double psi) {
  const double cp = std::cos(phi), sp = std::sin(phi), cq = std::cos(psi), sq = std::sin(psi);
  // diag(r,1)·R(ψ) = [[r cq, −r sq], [sq, cq]]; then R(φ)·that.
  const double m00 = r * cq, m01 = -r * sq, m10 = sq, m11 = cq;
  return {cp * m00 - sp * m10, sp * m00 + cp * m10, cp * m01 - sp * m11, sp * m01 + cp * m11};
}

// Max |exp(−q'/2) − exp(−q/2)| over texels at screen offsets (x, y) ∈ [−8, 8]², where
// (U, V) = J·(x, y) and q = x² + y² is exact.
double axes_weight_error(GaussianAxes rule, const Jac& j) {
  const auto e = GaussianWeight::setup<double>(rule, j.ux, j.vx, j.uy, j.vy);
  double worst = 0;
  for (int iy = -100; iy <= 100; ++iy) {
    for (int ix = -100; ix <= 100; ++ix) {
      const double x = 0.08 * ix, y = 0.08 * iy;
      const double U = j.ux * x + j.uy * y, V = j.vx * x + j.vy * y;
      const double w = std::exp(-0.5 * (x * x + y * y));
      const double w2 = GaussianWeight::weight_exp<D>(GaussianWeight::q_of(e, U, V));
      worst = std::max(worst, std::fabs(w2 - w));
    }
  }
  return worst;
}

TEST(GaussianWeight, QuadraticFormIsScreenDistance) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-4, 4);
  for (int n = 0; n < 2000; ++n) {
    const Jac j{u(rng), u(rng), u(rng), u(rng)};
    const double det = j.ux * j.vy - j.uy * j.vx;
    if (std::fabs(det) < 1e-3) continue;
    const auto e =
        GaussianWeight::setup<double>(GaussianAxes::QuadraticForm, j.ux, j.vx, j.uy, j.vy);
    ASSERT_FALSE(e.degenerate);
    const double x = u(rng), y = u(rng);
    const double q = GaussianWeight::q_of(e, j.ux * x + j.uy * y, j.vx * x + j.vy * y);
    ASSERT_NEAR(q, x * x + y * y, 1e-9 * (1 + x * x + y * y) / std::min(1.0, std::fabs(det))) << n;
  }
  EXPECT_LT(axes_weight_error(GaussianAxes::QuadraticForm, footprint(16, 0.3, 0.7)), 1e-12);
}

TEST(GaussianWeight, SeedAxesExactOnlyForOrthogonalDerivatives) {
  for (double r : {1.0, 2.0, 4.0, 16.0}) {
    for (int deg = 0; deg < 180; deg += 15) {
      EXPECT_LT(axes_weight_error(GaussianAxes::SeedAxes, footprint(r, deg * kPi / 180, 0)), 1e-12)
          << r << " " << deg;
    }
  }
  // Isotropic footprints have orthogonal derivatives whatever the skew angle.
  EXPECT_LT(axes_weight_error(GaussianAxes::SeedAxes, footprint(1, 0.4, 0.5)), 1e-12);
  // Skewed anisotropic footprints: a real error.
  EXPECT_GT(axes_weight_error(GaussianAxes::SeedAxes, footprint(2, 0.0, 30 * kPi / 180)), 0.05);
  EXPECT_GT(axes_weight_error(GaussianAxes::SeedAxes, footprint(8, 0.5, 20 * kPi / 180)), 0.1);
}

// The printed rule sin θ = Vy/d gives cos θ = sin θ = 1 for an axis-aligned footprint, so
// q' = (U+V)²/L² + (V−U)²/d²: for the unit footprint q' = 2q and the worst weight error is
// max(e^(−q/2) − e^(−q)) = 1/4 (at e^(−q/2) = 1/2). The literal reading fails even there.
TEST(GaussianWeight, SeedLiteralFailsEvenAxisAligned) {
  const double e = axes_weight_error(GaussianAxes::SeedLiteral, footprint(1, 0, 0));
  EXPECT_NEAR(e, 0.25, 2e-4);
  EXPECT_GT(axes_weight_error(GaussianAxes::SeedLiteral, footprint(4, 0, 0)), 0.2);
}

TEST(GaussianWeight, AxesErrorTable) {
  // Rows: anisotropy r; columns: skew ψ; cell: max over φ ∈ {0°, 5°, …, 175°} of the max weight
  // error (exp weights) over the footprint.
  const int psis[] = {0, 10, 20, 30, 45};
  for (GaussianAxes rule : {GaussianAxes::SeedAxes, GaussianAxes::SeedLiteral}) {
    std::printf("\n%s: max |w' - w| over rotations phi, by anisotropy r and skew psi\n\n",
                rule == GaussianAxes::SeedAxes ? "seed_axes" : "seed_literal");
    std::printf("| r | psi = 0 | 10 deg | 20 deg | 30 deg | 45 deg |\n|---|---|---|---|---|---|\n");
    double prev_row_max = 0;
    for (double r : {1.0, 2.0, 4.0, 8.0, 16.0}) {
      std::printf("| %g |", r);
      double row_max = 0;
      for (int psi : psis) {
        double m = 0;
        for (int phi = 0; phi < 180; phi += 5) {
          m = std::max(m, axes_weight_error(rule, footprint(r, phi * kPi / 180, psi * kPi / 180)));
        }
        row_max = std::max(row_max, m);
        std::printf(" %.3g |", m);
        EXPECT_LE(m, 1.0);
      }
      std::printf("\n");
      if (rule == GaussianAxes::SeedAxes) {
        EXPECT_GE(row_max + 1e-12, prev_row_max) << r;
      }
      prev_row_max = row_max;
    }
  }
}

TEST(GaussianWeight, DegenerateFootprints) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (GaussianAxes rule :
       {GaussianAxes::QuadraticForm, GaussianAxes::SeedAxes, GaussianAxes::SeedLiteral}) {
    GaussianWeight::Config c;
    c.axes = rule;
    const GaussianWeight g(c);
    // Zero derivatives and NaN/Inf derivatives: every weight 0 (the filter's fallback applies).
    for (const Jac& j : {Jac{0, 0, 0, 0}, Jac{nan, 0, 0, 1}, Jac{inf, 0, 0, 1}}) {
      const auto e = GaussianWeight::setup<double>(rule, j.ux, j.vx, j.uy, j.vy);
      EXPECT_TRUE(e.degenerate);
      EXPECT_EQ(g.weight_at(e, 0.0, 0.0), 0.0);
      EXPECT_EQ(g.weight_at(e, 0.3, -0.2), 0.0);
    }
  }
  // Zero area (parallel derivative vectors): only the exact form can tell, and it does.
  const auto e = GaussianWeight::setup<double>(GaussianAxes::QuadraticForm, 1.0, 2.0, 2.0, 4.0);
  EXPECT_TRUE(e.degenerate);
}

TEST(GaussianWeight, OpsAndTiming) {
  GaussianWeight::Config c;
  c.function = GaussianWeightFunction::Pow8;
  const GaussianWeight p8(c);
  c.function = GaussianWeightFunction::Exp;
  const GaussianWeight ex(c);
  EXPECT_EQ(p8.ops_per_item().mul, 5u + 3u);
  EXPECT_EQ(p8.ops_per_item().lut, 0u);
  EXPECT_EQ(ex.ops_per_item().mul, 5u + 1u);
  EXPECT_EQ(ex.ops_per_item().lut, 1u);
  TechTable t = TechTable::defaults();
  t.latency[static_cast<int>(OpKind::Mul)] = 4;
  t.latency[static_cast<int>(OpKind::Lut)] = 9;
  // q: 2 mul + 2 add on the path; power 8: add, range select, three squarings.
  EXPECT_EQ(p8.timing(t).latency,
            static_cast<uint32_t>(std::ceil(5 * 4 + 3 * t.lat(OpKind::Add) + t.lat(OpKind::Cmp))));
  EXPECT_EQ(ex.timing(t).latency, static_cast<uint32_t>(std::ceil(3 * 4 + 2 * t.lat(OpKind::Add) +
                                                                  t.lat(OpKind::Cmp) + 9)));
  EXPECT_DOUBLE_EQ(p8.timing(t).area, t.area_of(p8.ops_per_item()));
  // The seed's axis rules need square roots and divisions the quadratic form does not.
  c.axes = GaussianAxes::SeedLiteral;
  EXPECT_EQ(GaussianWeight(c).setup_ops().sqrt, 2u);
  EXPECT_EQ(GaussianWeight(c).setup_ops().div, 2u);
  c.axes = GaussianAxes::QuadraticForm;
  EXPECT_EQ(GaussianWeight(c).setup_ops().sqrt, 0u);
  EXPECT_EQ(GaussianWeight(c).setup_ops().rcp, 1u);
  EXPECT_GT(GaussianWeight(c).setup_timing(t).latency, 0u);
}

// Prints the default-table figures quoted in docs/derivations/gaussian-weights.md.
TEST(GaussianWeight, DefaultTableFigures) {
  const TechTable t = TechTable::defaults();
  for (GaussianAxes a :
       {GaussianAxes::QuadraticForm, GaussianAxes::SeedAxes, GaussianAxes::SeedLiteral}) {
    GaussianWeight::Config c;
    c.axes = a;
    const GaussianWeight g(c);
    const OpCounts o = g.setup_ops();
    std::printf(
        "setup %d: mul %llu add %llu rcp %llu div %llu sqrt %llu cmp %llu | latency %u area %g\n",
        static_cast<int>(a), static_cast<unsigned long long>(o.mul),
        static_cast<unsigned long long>(o.add), static_cast<unsigned long long>(o.rcp),
        static_cast<unsigned long long>(o.div), static_cast<unsigned long long>(o.sqrt),
        static_cast<unsigned long long>(o.cmp), g.setup_timing(t).latency, g.setup_timing(t).area);
    EXPECT_GT(g.setup_timing(t).latency, 0u);
  }
  for (GaussianWeightFunction f : {GaussianWeightFunction::Exp, GaussianWeightFunction::Pow8}) {
    GaussianWeight::Config c;
    c.function = f;
    const GaussianWeight g(c);
    const OpCounts o = g.ops_per_item();
    std::printf("texel %s: mul %llu add %llu cmp %llu lut %llu | latency %u area %g\n",
                f == GaussianWeightFunction::Exp ? "exp" : "pow8",
                static_cast<unsigned long long>(o.mul), static_cast<unsigned long long>(o.add),
                static_cast<unsigned long long>(o.cmp), static_cast<unsigned long long>(o.lut),
                g.timing(t).latency, g.timing(t).area);
    EXPECT_GT(g.timing(t).latency, 0u);
  }
}

TEST(GaussianWeight, ConfigFromToml) {
  toml::table ok = toml::parse(std::string_view("function = \"exp\"\naxes = \"seed_axes\"\n"),
                               std::string_view("g.toml"));
  const auto c = GaussianWeight::Config::from_toml(ConfigReader(ok, "g.toml", "gaussian"));
  EXPECT_EQ(c.function, GaussianWeightFunction::Exp);
  EXPECT_EQ(c.axes, GaussianAxes::SeedAxes);
  toml::table bad =
      toml::parse(std::string_view("function = \"pow4\"\n"), std::string_view("g.toml"));
  EXPECT_THROW(GaussianWeight::Config::from_toml(ConfigReader(bad, "g.toml", "gaussian")),
               InputError);
  toml::table typo =
      toml::parse(std::string_view("axis = \"seed_axes\"\n"), std::string_view("g.toml"));
  EXPECT_THROW(GaussianWeight::Config::from_toml(ConfigReader(typo, "g.toml", "gaussian")),
               InputError);
}

}  // namespace
}  // namespace texsim
