// The scalar product of two vectors in polar (2-D) and spherical (3-D) coordinates
// (PolarDotProduct) against long double references: the cosine table's bound, random vectors,
// the hard cases (wrap near ±π, zero magnitudes, non-finite inputs) and the operation counts
// against the Cartesian dot product.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>

#include "blocks/base/derive_timing.h"
#include "blocks/base/tech_table.h"
#include "blocks/lighting/polar_dot_product.h"

namespace texsim {
namespace {

using LD = long double;
constexpr LD kPiL = std::numbers::pi_v<LD>;

PolarDotProduct make(int dims, int32_t table = 1024) {
  PolarDotProduct::Config c;
  c.dims = dims;
  c.table_size = table;
  return PolarDotProduct(c);
}

// Worst |cos(x) − unit(x)| over [0, π] (dense sweep).
double worst_cosine(const PolarDotProduct& p) {
  double worst = 0;
  for (int k = 0; k <= 400000; ++k) {
    const float x = static_cast<float>(kPiL * k / 400000);
    bool oor = false;
    OpCounts ops;
    const LD err = std::fabs(static_cast<LD>(p.cosine(x, oor, ops)) - std::cos(static_cast<LD>(x)));
    worst = std::max(worst, static_cast<double>(err));
  }
  return worst;
}

TEST(PolarDotProduct, CosineTableMeetsItsBound) {
  // Linear interpolation errs by at most h²/8, h = π/N, plus the float rounding of the entries
  // and of the interpolation (a few 10⁻⁸).
  const double w1024 = worst_cosine(make(2, 1024)), w256 = worst_cosine(make(2, 256));
  const double h = std::numbers::pi / 1024;
  std::printf("cosine table: worst error %.3g (1024 intervals, bound h²/8 = %.3g), %.3g (256)\n",
              w1024, h * h / 8, w256);
  EXPECT_LT(w1024, h * h / 8 + 1e-7);
  EXPECT_GT(w1024, 0.9 * h * h / 8);  // the bound is reached, not just respected
  EXPECT_GT(w256, 10 * w1024);        // a coarser table fails the 1024 bound
}

TEST(PolarDotProduct, TwoDMatchesLongDouble) {
  const PolarDotProduct p = make(2);
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<float> r(0, 10),
      t(-std::numbers::pi_v<float>, std::numbers::pi_v<float>);
  double worst = 0;
  for (int i = 0; i < 100000; ++i) {
    const float ra = r(rng), ta = t(rng), rb = r(rng), tb = t(rng);
    OpCounts ops;
    const auto res = p.dot2(ra, ta, rb, tb, ops);
    ASSERT_FALSE(res.invalid || res.out_of_range);
    EXPECT_EQ(ops, p.ops_per_item());
    const LD ref = static_cast<LD>(ra) * rb * std::cos(static_cast<LD>(ta) - tb);
    const LD scale = std::max<LD>(static_cast<LD>(ra) * rb, 1e-30L);
    worst = std::max(worst, static_cast<double>(std::fabs(res.value - ref) / scale));
  }
  std::printf("2-D: worst error / (|a||b|) %.3g\n", worst);
  EXPECT_LT(worst, 2e-6);
}

TEST(PolarDotProduct, ThreeDMatchesLongDoubleCartesian) {
  const PolarDotProduct p = make(3);
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<float> r(0, 10), th(0, std::numbers::pi_v<float>),
      ph(-std::numbers::pi_v<float>, std::numbers::pi_v<float>);
  double worst = 0, worst_cart = 0;
  for (int i = 0; i < 100000; ++i) {
    const float ra = r(rng), ta = th(rng), pa = ph(rng), rb = r(rng), tb = th(rng), pb = ph(rng);
    OpCounts ops;
    const auto res = p.dot3(ra, ta, pa, rb, tb, pb, ops);
    ASSERT_FALSE(res.invalid || res.out_of_range);
    EXPECT_EQ(ops, p.ops_per_item());
    // The Cartesian vectors in long double, then their dot product.
    auto cart = [](LD rr, LD t, LD f) {
      return std::array<LD, 3>{rr * std::sin(t) * std::cos(f), rr * std::sin(t) * std::sin(f),
                               rr * std::cos(t)};
    };
    const auto a = cart(ra, ta, pa), b = cart(rb, tb, pb);
    const LD ref = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const LD scale = std::max<LD>(static_cast<LD>(ra) * rb, 1e-30L);
    worst = std::max(worst, static_cast<double>(std::fabs(res.value - ref) / scale));
    // Beside it, the float Cartesian product of the float-converted vectors (correctly rounded
    // sin and cos: the best a conversion can do).
    auto cart_f = [](float rr, float t, float f) {
      return std::array<float, 3>{rr * std::sin(t) * std::cos(f), rr * std::sin(t) * std::sin(f),
                                  rr * std::cos(t)};
    };
    const auto af = cart_f(ra, ta, pa), bf = cart_f(rb, tb, pb);
    const float cd = af[0] * bf[0] + af[1] * bf[1] + af[2] * bf[2];
    worst_cart = std::max(worst_cart, static_cast<double>(std::fabs(cd - ref) / scale));
  }
  std::printf("3-D: worst error / (|a||b|) %.3g; float conversion + Cartesian product %.3g\n",
              worst, worst_cart);
  EXPECT_LT(worst, 4e-6);
  EXPECT_LT(worst_cart, worst);  // the table, not the float datapath, bounds the polar form
}

TEST(PolarDotProduct, HardCases) {
  const PolarDotProduct p2 = make(2), p3 = make(3);
  OpCounts ops;
  const float pi = std::numbers::pi_v<float>;
  // Across the ±π seam: θa just below π, θb just above −π are 2ε apart, cos ≈ 1.
  for (int k = 1; k < 1000; k *= 3) {
    const float a = std::nextafter(pi, 0.0F), b = -a;
    const float ta = a - static_cast<float>(k) * 1e-6F, tb = b + static_cast<float>(k) * 1e-6F;
    const auto r = p2.dot2(2, ta, 3, tb, ops);
    const LD ref = 6 * std::cos(static_cast<LD>(ta) - tb);
    EXPECT_NEAR(r.value, static_cast<double>(ref), 6 * 2e-6) << k;
    EXPECT_FALSE(r.out_of_range);
  }
  // Opposite and equal directions, exactly.
  EXPECT_NEAR(p2.dot2(2, pi, 3, 0, ops).value, -6.0F, 1e-5F);
  EXPECT_NEAR(p2.dot2(2, -pi, 3, pi, ops).value, 6.0F, 1e-5F);
  EXPECT_EQ(p2.dot2(2, 0.7F, 3, 0.7F, ops).value, 6.0F);
  // Zero magnitudes: exactly 0 (and −0 is 0).
  EXPECT_EQ(p2.dot2(0, 1.0F, 5, -2.0F, ops).value, 0.0F);
  EXPECT_EQ(p3.dot3(4, 1.0F, 2.0F, 0, 0.3F, -1.0F, ops).value, 0.0F);
  // Non-finite inputs: 0, flagged.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (const auto& r :
       {p2.dot2(nan, 0, 1, 0, ops), p2.dot2(1, inf, 1, 0, ops), p2.dot2(1, 0, inf, 0, ops),
        p3.dot3(1, 0, 0, 1, nan, 0, ops), p3.dot3(1, 0, -inf, 1, 0, 0, ops)}) {
    EXPECT_TRUE(r.invalid);
    EXPECT_EQ(r.value, 0.0F);
  }
  // Angles beyond ±π: reduced by a remainder, flagged, still right.
  const auto far = p2.dot2(1, 9.0F, 1, -9.0F, ops);
  EXPECT_TRUE(far.out_of_range);
  EXPECT_NEAR(far.value, std::cos(18.0), 2e-6);
  // 3-D: parallel, antiparallel and perpendicular vectors, the poles (φ meaningless there).
  EXPECT_NEAR(p3.dot3(2, 1.1F, -2.5F, 3, 1.1F, -2.5F, ops).value, 6.0F, 2e-5F);
  EXPECT_NEAR(p3.dot3(2, 0, 1.0F, 3, pi, -2.0F, ops).value, -6.0F, 2e-5F);
  EXPECT_NEAR(p3.dot3(2, pi / 2, 0, 3, pi / 2, pi / 2, ops).value, 0.0F, 2e-5F);
  EXPECT_NEAR(p3.dot3(2, 0, 3.0F, 3, 0, -3.0F, ops).value, 6.0F, 2e-5F);
}

TEST(PolarDotProduct, CostsBesideTheCartesianProduct) {
  const TechTable t = TechTable::defaults();
  const PolarDotProduct p2 = make(2), p3 = make(3);
  EXPECT_EQ(p2.ops_per_item().lut, 1U);
  EXPECT_EQ(p3.ops_per_item().lut, 3U);
  // Cartesian inputs: the Cartesian product is cheaper (2 mul 1 add, 3 mul 2 add).
  EXPECT_LT(PolarDotProduct::cartesian_ops(3, false).total(), p3.ops_per_item().total());
  // Polar inputs: the polar form needs fewer table reads and multiplies than converting first.
  for (const int d : {2, 3}) {
    const OpCounts conv = PolarDotProduct::cartesian_ops(d, true);
    const OpCounts polar = (d == 2 ? p2 : p3).ops_per_item();
    EXPECT_LT(polar.lut, conv.lut) << d;
    EXPECT_LT(polar.mul, conv.mul) << d;
  }
  EXPECT_EQ(p3.timing(t).ii, 1U);
  for (const int d : {2, 3}) {
    const TimingSpec polar = (d == 2 ? p2 : p3).timing(t);
    const TimingSpec cart =
        derive_timing(t, PolarDotProduct::cartesian_ops(d, false),
                      PolarDotProduct::cartesian_critical_path(d, false), Datapath::Spatial);
    const TimingSpec conv =
        derive_timing(t, PolarDotProduct::cartesian_ops(d, true),
                      PolarDotProduct::cartesian_critical_path(d, true), Datapath::Spatial);
    std::printf("%d-D latency/area: polar %u/%.1f, Cartesian %u/%.1f, polar->Cartesian %u/%.1f\n",
                d, polar.latency, polar.area, cart.latency, cart.area, conv.latency, conv.area);
    EXPECT_LT(cart.area, polar.area);
  }
  EXPECT_GT(p3.timing(t).latency, p2.timing(t).latency);
}

}  // namespace
}  // namespace texsim
