// Weight maps: the generator stores the function rounded into the element format, the reader
// returns entries exactly at their positions and interpolates within the analytic bound
// between them, the four kinds agree where they should, and EWA with a map reproduces EWA with
// the same weights computed.
#include <gtest/gtest.h>
#include <toml++/toml.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/texture/footprint/ewa_filter.h"
#include "blocks/texture/footprint/weight_map.h"

namespace texsim {
namespace {

double quantise(double w, WeightMap::Element e) {
  switch (e) {
    case WeightMap::Element::U8:
      return static_cast<float>(std::nearbyint(w * 255) / 255);
    case WeightMap::Element::U16:
      return static_cast<float>(std::nearbyint(w * 65535) / 65535);
    case WeightMap::Element::Float:
      return static_cast<float>(w);
  }
  return 0;
}

double lsb(WeightMap::Element e) {
  return e == WeightMap::Element::U8 ? 1.0 / 255
                                     : (e == WeightMap::Element::U16 ? 1.0 / 65535 : 1e-7);
}

TEST(WeightMap, GeneratorStoresTheFunction) {
  for (auto fn : {WeightMap::Function::Exp, WeightMap::Function::Pow8}) {
    for (auto el : {WeightMap::Element::U8, WeightMap::Element::U16, WeightMap::Element::Float}) {
      WeightMap::Config c;
      c.kind = WeightMap::Kind::Quarter;
      c.element = el;
      c.size = 17;
      c.function = fn;
      const WeightMap m(c);
      EXPECT_EQ(m.width(), 17);
      EXPECT_EQ(m.height(), 17);
      for (int j = 0; j < 17; ++j) {
        for (int i = 0; i < 17; ++i) {
          const double x = i / 16.0, y = j / 16.0;
          ASSERT_EQ(m.entry(i, j), static_cast<float>(quantise(m.function(x * x + y * y), el)));
        }
      }
    }
  }
  WeightMap::Config c;
  c.function = WeightMap::Function::Pow8;
  const WeightMap m(c);
  EXPECT_DOUBLE_EQ(m.function(0), 1.0);
  EXPECT_NEAR(m.function(0.5), std::pow(1 - 2.0 * 0.5 / 8, 8), 1e-15);
  EXPECT_EQ(m.function(1.0001), 0.0);
  EXPECT_EQ(m.function(-1), 0.0);
  c.function = WeightMap::Function::Exp;
  EXPECT_NEAR(WeightMap(c).function(0.7), std::exp(-2.0 * 0.7), 1e-15);
}

TEST(WeightMap, SizesAndBytes) {
  WeightMap::Config c;
  c.kind = WeightMap::Kind::Quarter;
  c.size = 32;
  c.element = WeightMap::Element::U16;
  EXPECT_EQ(WeightMap(c).bytes(), 2048u);
  c.kind = WeightMap::Kind::Full2D;
  c.element = WeightMap::Element::Float;
  EXPECT_EQ(WeightMap(c).bytes(), 32u * 32u * 4u);
  c.kind = WeightMap::Kind::RadialR2;
  c.element = WeightMap::Element::U8;
  EXPECT_EQ(WeightMap(c).bytes(), 32u);
  EXPECT_EQ(WeightMap(c).height(), 1);
}

// Interpolation error against the function, inside cells that do not cross r = 1 (where the
// 2-D kinds interpolate across the cut-off). Bound: linear interpolation with spacing h errs by
// at most M·h²/8 per axis (M = max |f''| along it): exp(−2r²) has |∂²/∂x²| ≤ 4 on the disc, and
// as a function of r² it has f'' = 4·exp(−2s) ≤ 4; plus half an element LSB.
TEST(WeightMap, ReadWithinInterpolationBound) {
  for (auto kind : {WeightMap::Kind::Full2D, WeightMap::Kind::Quarter, WeightMap::Kind::RadialR,
                    WeightMap::Kind::RadialR2}) {
    for (auto el : {WeightMap::Element::U8, WeightMap::Element::U16, WeightMap::Element::Float}) {
      for (int size : {16, 64}) {
        WeightMap::Config c;
        c.kind = kind;
        c.element = el;
        c.size = size;
        const WeightMap m(c);
        const double h = (kind == WeightMap::Kind::Full2D ? 2.0 : 1.0) / (size - 1);
        const double axes =
            (kind == WeightMap::Kind::Full2D || kind == WeightMap::Kind::Quarter) ? 2 : 1;
        const double bound = axes * 4.0 * h * h / 8.0 + 0.5 * lsb(el) + 1e-6;
        double worst = 0;
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> uni(-1, 1);
        uint32_t reads = 0;
        int calls = 0;
        for (int k = 0; k < 20000; ++k) {
          const double x = uni(rng), y = uni(rng);
          const double r = std::sqrt(x * x + y * y);
          if (r > 1.0 - 1.5 * h) continue;
          const double got = m.read(static_cast<float>(x), static_cast<float>(y), reads);
          ++calls;
          worst = std::max(worst, std::fabs(got - m.function(x * x + y * y)));
        }
        EXPECT_LE(worst, bound) << to_string(kind) << " " << to_string(el) << " " << size;
        EXPECT_EQ(reads, static_cast<uint32_t>(calls) * (axes == 2 ? 4u : 2u));
      }
    }
  }
}

TEST(WeightMap, EntriesAreReadExactlyAndOutsideIsZero) {
  WeightMap::Config c;
  c.kind = WeightMap::Kind::Quarter;
  c.element = WeightMap::Element::Float;
  c.size = 9;
  const WeightMap m(c);
  uint32_t reads = 0;
  for (int i = 0; i < 9; ++i) {
    for (int j = 0; j < 9; ++j) {
      const float x = static_cast<float>(i / 8.0), y = static_cast<float>(j / 8.0);
      EXPECT_FLOAT_EQ(m.read(x, y, reads), m.entry(i, j));
      EXPECT_FLOAT_EQ(m.read(-x, y, reads), m.entry(i, j));  // quarter: |x|, |y|
    }
  }
  EXPECT_EQ(m.read(1.01f, 0.0f, reads), 0.0f);
  EXPECT_EQ(m.read(0.0f, -1.5f, reads), 0.0f);
  EXPECT_EQ(m.read(std::nanf(""), 0.0f, reads), 0.0f);
  c.kind = WeightMap::Kind::RadialR;
  const WeightMap r(c);
  EXPECT_EQ(r.read(0.8f, 0.8f, reads), 0.0f);                                      // r > 1
  EXPECT_FLOAT_EQ(r.read(0.0f, 1.0f, reads), static_cast<float>(std::exp(-2.0)));  // edge entry
}

TEST(WeightMap, OpsPerKind) {
  WeightMap::Config c;
  c.kind = WeightMap::Kind::RadialR;
  const OpCounts r = WeightMap(c).ops_per_item();
  c.kind = WeightMap::Kind::RadialR2;
  const OpCounts r2 = WeightMap(c).ops_per_item();
  EXPECT_EQ(r.sqrt, 1u);
  EXPECT_EQ(r2.sqrt, 0u);  // indexing by r² removes the square root
  EXPECT_EQ(r.mem, 2u);
  c.kind = WeightMap::Kind::Quarter;
  EXPECT_EQ(WeightMap(c).ops_per_item().mem, 4u);
  c.transform = WeightMap::Transform::Jacobian;
  EXPECT_EQ(WeightMap(c).ops_per_step().add, 2u);
  c.transform = WeightMap::Transform::Cholesky;
  EXPECT_EQ(WeightMap(c).ops_per_step().add, 1u);
  const TimingSpec t = WeightMap(c).timing(TechTable::defaults());
  EXPECT_GE(t.latency, 5u);
}

TEST(WeightMap, ConfigFromToml) {
  auto t = toml::parse("kind = \"radial_r2\"\nelement = \"u8\"\nsize = 128\nfunction = \"pow8\"\n");
  const auto c = WeightMap::Config::from_toml(ConfigReader(t, "s.toml", "weight_map"));
  EXPECT_EQ(c.kind, WeightMap::Kind::RadialR2);
  EXPECT_EQ(c.element, WeightMap::Element::U8);
  EXPECT_EQ(c.size, 128);
  EXPECT_EQ(c.function, WeightMap::Function::Pow8);
  auto bad = toml::parse("kind = \"half\"\n");
  EXPECT_THROW(WeightMap::Config::from_toml(ConfigReader(bad, "s.toml", "weight_map")), InputError);
  auto bad2 = toml::parse("sizes = 3\n");
  EXPECT_THROW(WeightMap::Config::from_toml(ConfigReader(bad2, "s.toml", "weight_map")),
               InputError);
}

// EWA with a float radial-r² map of the same function equals EWA computing the weights, up to
// the map's interpolation error.
TEST(WeightMap, EwaWithMapMatchesComputedWeights) {
  std::vector<float> px(size_t{64} * 64 * 4);
  std::mt19937 rng(8);
  std::uniform_real_distribution<float> uni(0, 1);
  for (float& p : px) p = uni(rng);
  const Texture tex = Texture::from_rgba("n", 64, 64, px, TexelFormat::Rgba32f, true);
  EwaFilter::Config cc;
  cc.weight = EwaFilter::Weight::Pow8;
  cc.arith = NumberFormat::Double;
  EwaFilter::Config cm = cc;
  cm.weight = EwaFilter::Weight::Map;
  WeightMap::Config mc;
  mc.kind = WeightMap::Kind::RadialR2;
  mc.element = WeightMap::Element::Float;
  mc.size = 256;
  mc.function = WeightMap::Function::Pow8;
  const EwaFilter computed(cc), mapped(cm, std::make_shared<const WeightMap>(mc));
  std::uniform_real_distribution<double> ud(0, 1);
  double worst = 0;
  for (int k = 0; k < 300; ++k) {
    Fragment f;
    f.u = ud(rng);
    f.v = ud(rng);
    f.dudx = (ud(rng) * 8 - 4) / 64;
    f.dvdx = (ud(rng) * 8 - 4) / 64;
    f.dudy = (ud(rng) * 8 - 4) / 64;
    f.dvdy = (ud(rng) * 8 - 4) / 64;
    OpCounts o1, o2;
    const FilterOutput a = computed.filter(tex, f, nullptr, o1),
                       b = mapped.filter(tex, f, nullptr, o2);
    EXPECT_EQ(a.stats.texels, b.stats.texels);
    EXPECT_GT(b.stats.map_reads, 0u);
    for (int ch = 0; ch < 3; ++ch)
      worst = std::max(worst, static_cast<double>(std::fabs(a.colour[ch] - b.colour[ch])));
  }
  std::printf("EWA radial r^2 float map (256) vs computed pow8: max colour difference %.3g\n",
              worst);
  EXPECT_LT(worst, 1e-4);
}

}  // namespace
}  // namespace texsim
