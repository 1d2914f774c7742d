// Finite-function terrain (seed 003 §2.3–2.4): the base functions' properties, the
// 3-multiplication evaluator against the 8-multiplication form and a long double direct sum,
// the gradient normal, and the measured properties of the deformations (partition-of-unity
// ripple, slope jumps, terraces) — measured, not taken from the seed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/base/tech_table.h"
#include "blocks/geometry/terrain/terrain_height_evaluator.h"
#include "blocks/geometry/terrain/terrain_measures.h"

namespace texsim {
namespace {

constexpr FiniteKind kBase[] = {FiniteKind::Cosine, FiniteKind::Quadratic, FiniteKind::Exp2};
const char* kind_name(FiniteKind k) {
  switch (k) {
    case FiniteKind::Cosine:
      return "cosine";
    case FiniteKind::Quadratic:
      return "quadratic";
    case FiniteKind::Exp2:
      return "exp2";
    case FiniteKind::Tent:
      return "tent";
  }
  return "?";
}

TerrainHeightEvaluator make(FiniteKind k, Deformation d, int shift = 1) {
  TerrainHeightEvaluator::Config c;
  c.basis.kind = k;
  c.basis.deformation = d;
  c.basis.blend_shift = shift;
  return TerrainHeightEvaluator(c);
}

TEST(FiniteFunction, BaseFunctionsAreEvenFiniteC1PartitionsOfUnity) {
  for (const FiniteKind k : kBase) {
    EXPECT_DOUBLE_EQ(finite_value(k, 0), 1.0) << kind_name(k);
    EXPECT_EQ(finite_value(k, 1), 0.0);
    EXPECT_EQ(finite_value(k, -1.5), 0.0);
    EXPECT_NEAR(finite_derivative(k, 1e-12), 0.0, 1e-9);
    EXPECT_NEAR(finite_derivative(k, 1 - 1e-12), 0.0, 1e-9);
    double pu = 0, dd = 0, jump = 0;
    for (int n = 0; n <= 1000; ++n) {
      const double t = n / 1000.0;
      EXPECT_EQ(finite_value(k, t), finite_value(k, -t));
      pu = std::max(pu, std::fabs(finite_value(k, t) + finite_value(k, t - 1) - 1));
      // The analytic derivative against a central difference of the value.
      const double h = 1e-6, tt = -0.999 + 1.998 * n / 1000.0;
      const double num = (finite_value(k, tt + h) - finite_value(k, tt - h)) / (2 * h);
      dd = std::max(dd, std::fabs(num - finite_derivative(k, tt)));
    }
    // C¹ at the joints of the piecewise functions (|t| = 1/2) and at 0.
    for (const double t : {-0.5, 0.0, 0.5}) {
      jump = std::max(jump,
                      std::fabs(finite_derivative(k, t + 1e-12) - finite_derivative(k, t - 1e-12)));
    }
    EXPECT_LT(pu, 1e-15) << kind_name(k);
    EXPECT_LT(dd, 1e-6) << kind_name(k);
    EXPECT_LT(jump, 1e-9) << kind_name(k);
  }
}

TerrainGrid random_grid(std::mt19937_64& rng, int32_t n) {
  std::uniform_real_distribution<float> u(0.0F, 100.0F);
  TerrainGrid g(n, n);
  for (auto& v : g.h) v = u(rng);
  return g;
}

// Direct sum Σ h_ij f(x - i) f(z - j) over every node, in long double.
long double direct_sum(const TerrainGrid& g, const FiniteBasis& f, double x, double z) {
  long double s = 0;
  for (int32_t j = 0; j < g.nz; ++j) {
    for (int32_t i = 0; i < g.nx; ++i) {
      s += static_cast<long double>(g.node(i, j)) * f.value(x - i) * f.value(z - j);
    }
  }
  return s;
}

TEST(TerrainHeight, ThreeMultiplicationFormMatchesEightAndDirectSum) {
  std::mt19937_64 rng(5);
  const TerrainGrid g = random_grid(rng, 12);
  std::uniform_real_distribution<double> pos(2, 9);
  for (const FiniteKind k : kBase) {
    for (const Deformation d : {Deformation::None, Deformation::Widened, Deformation::Blended}) {
      const TerrainHeightEvaluator e = make(k, d);
      double worst3 = 0, worst8 = 0;
      for (int n = 0; n < 500; ++n) {
        const double x = pos(rng), z = pos(rng);
        OpCounts o3, o8;
        const double y3 = e.height(g, x, z, o3), y8 = e.height_8mul(g, x, z, o8);
        const long double ref = direct_sum(g, e.config().basis, x, z);
        worst3 = std::max(worst3, std::fabs(y3 - static_cast<double>(ref)));
        worst8 = std::max(worst8, std::fabs(y8 - static_cast<double>(ref)));
        if (d != Deformation::Widened) {
          EXPECT_EQ(o3.mul, 3U);
          EXPECT_EQ(o8.mul, 8U);
        }
      }
      // Heights up to 100: within a few ulps of 100 (rounding only).
      EXPECT_LT(worst3, 1e-12) << kind_name(k) << ' ' << static_cast<int>(d);
      EXPECT_LT(worst8, 1e-12) << kind_name(k) << ' ' << static_cast<int>(d);
    }
  }
}

TEST(TerrainHeight, GradientMatchesCentralDifferences) {
  std::mt19937_64 rng(9);
  const TerrainGrid g = random_grid(rng, 10);
  std::uniform_real_distribution<double> pos(2, 7);
  for (const FiniteKind k : kBase) {
    for (const Deformation d : {Deformation::None, Deformation::Widened, Deformation::Blended}) {
      const TerrainHeightEvaluator e = make(k, d);
      for (int n = 0; n < 200; ++n) {
        double x = pos(rng), z = pos(rng);
        // Keep clear of the nodes, where variant 2's tent has one-sided slopes.
        x = std::floor(x) + 0.05 + 0.9 * (x - std::floor(x));
        z = std::floor(z) + 0.05 + 0.9 * (z - std::floor(z));
        OpCounts ops;
        const auto s = e.sample(g, x, z, ops);
        const double h = 1e-6;
        const double gx = (e.height(g, x + h, z, ops) - e.height(g, x - h, z, ops)) / (2 * h);
        const double gz = (e.height(g, x, z + h, ops) - e.height(g, x, z - h, ops)) / (2 * h);
        EXPECT_NEAR(s.dydx, gx, 1e-6 * (1 + std::fabs(gx))) << kind_name(k);
        EXPECT_NEAR(s.dydz, gz, 1e-6 * (1 + std::fabs(gz))) << kind_name(k);
      }
    }
  }
}

// flat_ripple, ripple_1d, slope_jump_ratio and terrace_measure are the shared measures of
// blocks/geometry/terrain/terrain_measures.h (texsim study terrain reports them too).
TEST(TerrainHeight, PartitionOfUnityRippleOnFlatTerrain) {
  // Measured: variant 1 keeps the three-term partition of unity only for the cosine function.
  // In 1-D the quadratic and 2^(-x²) functions leave 1/27 = 3.70 % (at the nodes:
  // (2/3)(1 + 2·(2/9)) = 26/27) and 2.02 % ((2/3)(1 + 2(1 - 2^(-4/9))) - 1). On a flat 2-D grid
  // the error is the product S(x)·S(z) - 1: 7.54 % and 4.08 % (measured over a cell at 1/256).
  for (const FiniteKind k : kBase) {
    const double none = flat_ripple(make(k, Deformation::None));
    const double wide = flat_ripple(make(k, Deformation::Widened));
    const double blend = flat_ripple(make(k, Deformation::Blended));
    const double wide_1d = ripple_1d(make(k, Deformation::Widened).config().basis);
    std::printf(
        "flat-terrain ripple %-9s none %.1e  variant 1: 1-D %.4f %%, 2-D %.4f %%  "
        "variant 2 %.1e\n",
        kind_name(k), none, 100 * wide_1d, 100 * wide, blend);
    EXPECT_LT(none, 1e-14);
    EXPECT_LT(blend, 1e-14);
    if (k == FiniteKind::Cosine) {
      EXPECT_LT(wide_1d, 1e-14);
      EXPECT_LT(wide, 1e-14);
    }
    if (k == FiniteKind::Quadratic) {
      EXPECT_NEAR(wide_1d, 1.0 / 27, 1e-9);
      EXPECT_NEAR(wide, 0.07545, 1e-4);
    }
    if (k == FiniteKind::Exp2) {
      EXPECT_NEAR(wide_1d, 2.0 / 3 * (1 + 2 * (1 - std::exp2(-4.0 / 9))) - 1, 1e-9);
      EXPECT_NEAR(wide, 0.04076, 1e-4);
    }
  }
}

TEST(TerrainHeight, SlopeJumpsAtNodes) {
  for (const FiniteKind k : kBase) {
    double lo = 0;
    EXPECT_LT(slope_jump_ratio(make(k, Deformation::None), lo), 1e-6) << kind_name(k);
    EXPECT_LT(slope_jump_ratio(make(k, Deformation::Widened), lo), 1e-6) << kind_name(k);
  }
  // Variant 2 with the tent: y'(i+) - y'(i-) = (1 - a)·Δ²y_i, a = 2^-d.
  for (const int d : {0, 1, 2, 3}) {
    double lo = 0;
    const double hi = slope_jump_ratio(make(FiniteKind::Cosine, Deformation::Blended, d), lo);
    std::printf("variant 2 (cosine, tent) d = %d: slope jump / |second difference| %.6f .. %.6f\n",
                d, lo, hi);
    EXPECT_NEAR(hi, 1 - std::ldexp(1.0, -d), 1e-6);
    EXPECT_NEAR(lo, 1 - std::ldexp(1.0, -d), 1e-6);
  }
}

TEST(TerrainHeight, TerracesOnALongMonotoneSlope) {
  // Heights h_i = i (slope 1) along x; terrace measure 1 - (smallest slope / largest slope)
  // over a cell (1: flat steps at the nodes; 0: a straight ramp); "dev" the largest deviation
  // from the line.
  const auto measure = [](const TerrainHeightEvaluator& e, double& dev) {
    return terrace_measure(e, dev);
  };
  for (const FiniteKind k : kBase) {
    double d0 = 0, d1 = 0, d2 = 0;
    const double t0 = measure(make(k, Deformation::None), d0);
    const double t1 = measure(make(k, Deformation::Widened), d1);
    const double t2 = measure(make(k, Deformation::Blended), d2);
    std::printf(
        "terraces %-9s none %.3f (dev %.4f)  variant 1 %.3f (dev %.4f)  variant 2 "
        "a=1/2 %.3f (dev %.4f)\n",
        kind_name(k), t0, d0, t1, d1, t2, d2);
    EXPECT_NEAR(t0, 1.0, 1e-9);  // slope 0 at every node
    EXPECT_LT(t2, t0);           // variant 2 always softens the steps
    if (k == FiniteKind::Cosine) {
      EXPECT_NEAR(t1, 0.5, 1e-3);  // variant 1 halves them (measured)
    } else {
      // Measured: without the partition of unity, variant 1 on a ramp at heights ~7 adds a
      // ripple larger than the steps it removes (quadratic: the slope changes sign).
      EXPECT_GT(t1, 1.0);
      EXPECT_GT(d1, d0);
    }
  }
}

TEST(TerrainHeight, TimingAndFetches) {
  const auto e = make(FiniteKind::Cosine, Deformation::None);
  EXPECT_EQ(e.fetches_per_item(), 4);
  EXPECT_EQ(make(FiniteKind::Cosine, Deformation::Widened).fetches_per_item(), 9);
  EXPECT_GE(e.timing(TechTable::defaults()).latency, 1U);
}

TEST(TerrainHeight, TentWithoutDeformationIsBilinear) {
  // The tent is the bilinear kernel: the finite functions are its C¹ alternatives for height
  // data, and the tent's slope jumps by exactly the second difference at every node.
  std::mt19937_64 rng(3);
  const TerrainGrid g = random_grid(rng, 8);
  const auto e = make(FiniteKind::Tent, Deformation::None);
  OpCounts ops;
  const double x = 3.3, z = 4.6;
  const double h00 = g.node(3, 4), h10 = g.node(4, 4), h01 = g.node(3, 5), h11 = g.node(4, 5);
  const double bil =
      (1 - 0.6) * ((1 - 0.3) * h00 + 0.3 * h10) + 0.6 * ((1 - 0.3) * h01 + 0.3 * h11);
  EXPECT_NEAR(e.height(g, x, z, ops), bil, 1e-12);
  double lo = 0;
  EXPECT_NEAR(slope_jump_ratio(e, lo), 1.0, 1e-6);
  EXPECT_NEAR(lo, 1.0, 1e-6);
}

TEST(TerrainHeight, ConfigsReadAndReject) {
  const toml::table t =
      toml::parse("function = \"exp2\"\ndeformation = \"blended\"\nblend_shift = 2\n");
  const auto c = TerrainHeightEvaluator::Config::from_toml(ConfigReader(t, "s.toml", "terrain"));
  EXPECT_EQ(c.basis.kind, FiniteKind::Exp2);
  EXPECT_EQ(c.basis.deformation, Deformation::Blended);
  EXPECT_DOUBLE_EQ(c.basis.blend_weight(), 0.25);
  for (const char* bad : {"function = \"sinc\"\n", "blend_shift = 31\n", "shift = 1\n"}) {
    const toml::table b = toml::parse(bad);
    EXPECT_THROW(TerrainHeightEvaluator::Config::from_toml(ConfigReader(b, "s.toml", "terrain")),
                 InputError);
  }
}

}  // namespace
}  // namespace texsim
