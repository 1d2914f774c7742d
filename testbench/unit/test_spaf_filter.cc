// SPAF: the mask table against exact sub-texel masks and exact areas, edge functions that
// classify fully covered and uncovered texels, half-covered texels on edges through texel
// centres, constant textures exact, the Gaussian-weighted result against the reference.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <toml++/toml.h>

#include "blocks/input_error.h"
#include "blocks/spaf_filter.h"
#include "testbench/lib/footprint_reference.h"

namespace texsim {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Area of the unit texel square [−½, ½]² where e + x·deu + y·dev ≥ 0 (dense grid).
double exact_area(double deu, double dev, double e) {
  constexpr int n = 400;
  int in = 0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double x = (i + 0.5) / n - 0.5, y = (j + 0.5) / n - 0.5;
      if (e + x * deu + y * dev >= 0) ++in;
    }
  }
  return static_cast<double>(in) / (n * n);
}

TEST(Spaf, MaskTableAgainstExactMasksAndAreas) {
  for (int side : {2, 4, 8}) {
    SpafFilter::Config c;
    c.mask_side = side;
    c.slope_steps = 64;
    c.offset_steps = 32;
    const SpafFilter sp(c);
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> uni(-1, 1), ue(-0.5, 0.5);
    int bit_errors = 0, samples = 0;
    double worst_area = 0;
    for (int k = 0; k < 2000; ++k) {
      const double deu = uni(rng);
      const double dev = (uni(rng) > 0 ? 1 : -1) * (1 - std::fabs(deu));
      const double e = ue(rng);
      const uint64_t m = sp.mask(deu, dev, e), x = sp.exact_mask(deu, dev, e);
      bit_errors += std::popcount(m ^ x);
      ++samples;
      const double cover = static_cast<double>(std::popcount(m)) / sp.mask_bits();
      worst_area = std::max(worst_area, std::fabs(cover - exact_area(deu, dev, e)));
    }
    std::printf("SPAF %dx%d masks (64 slopes x 32 offsets): %.3f wrong bits per mask, max area error %.3f\n",
                side, side, static_cast<double>(bit_errors) / samples, worst_area);
    // A sub-texel grid of side n misjudges at most the cells the edge crosses (≤ 2n of n²)
    // plus the table's quantisation: the area error stays below 2/n + 1/16.
    EXPECT_LT(worst_area, 2.0 / side + 1.0 / 16) << side;
  }
}

TEST(Spaf, EdgesThroughTexelCentresHalfCover) {
  // An axis-aligned 4×4-texel quadrilateral whose edges pass through texel centres.
  std::vector<float> px(16 * 16 * 4, 0.0f);
  // Mark texel (x, y) with its index in red so the weights can be recovered.
  const Texture tex = Texture::from_rgba("c", 16, 16, px, TexelFormat::Rgba32f, false);
  SpafFilter::Config c;
  c.half_px = 1.0;
  c.gaussian = false;
  c.texel_budget = 1024;
  const SpafFilter sp(c);
  Fragment f;
  f.u = 8.0 / 16;  // centre at texel coordinate 7.5 (between texels 7 and 8)
  f.v = 8.0 / 16;
  f.dudx = 2.0 / 16;  // ±1 px → ±2 texels: edges at 5.5 and 9.5 → through no centre
  f.dvdy = 2.0 / 16;
  OpCounts ops;
  std::vector<TexelRef> fetched;
  const FilterOutput o = sp.filter(tex, f, &fetched, ops);
  // Edges at x = 5.5 and 9.5 are texel borders: exactly texels 6..9 × 6..9 are covered.
  EXPECT_EQ(o.stats.texels, 16u);
  EXPECT_FALSE(o.stats.fallback);
  f.dudx = 2.5 / 16;  // edges at 5 and 10: texel centres 5 and 10 half covered
  f.dvdy = 2.5 / 16;
  fetched.clear();
  const FilterOutput h = sp.filter(tex, f, &fetched, ops);
  EXPECT_EQ(h.stats.texels, 36u);  // 6 × 6 including the half-covered border
}

TEST(Spaf, ConstantExactSmoothBounded) {
  std::vector<float> fl(64 * 64 * 4, 0.8f);
  const Texture flat = Texture::from_rgba("f", 64, 64, fl, TexelFormat::Rgba32f, true);
  const int size = 256;
  std::vector<float> px(static_cast<size_t>(size) * size * 4);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const double u = (x + 0.5) / size, v = (y + 0.5) / size;
      const size_t i = (static_cast<size_t>(y) * size + static_cast<size_t>(x)) * 4;
      px[i] = static_cast<float>(0.5 + 0.3 * std::sin(2 * kPi * (2 * u + v)));
      px[i + 1] = static_cast<float>(0.5 + 0.3 * std::cos(2 * kPi * (u - 3 * v)));
      px[i + 2] = 0.5f;
      px[i + 3] = 1;
    }
  }
  const Texture tex = Texture::from_rgba("s", size, size, px, TexelFormat::Rgba32f, true);
  SpafFilter::Config c;
  c.texel_budget = 4096;
  const SpafFilter sp(c);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> uni(0, 1);
  FootprintReferenceConfig rc;
  double worst = 0;
  for (int k = 0; k < 200; ++k) {
    const double minor = 1 + 2 * uni(rng), major = minor * (1 + 7 * uni(rng)), th = uni(rng) * kPi;
    Fragment f;
    f.u = uni(rng);
    f.v = uni(rng);
    f.dudx = major * std::cos(th) / size;
    f.dvdx = major * std::sin(th) / size;
    f.dudy = -minor * std::sin(th) / size;
    f.dvdy = minor * std::cos(th) / size;
    OpCounts ops;
    std::vector<TexelRef> fetched;
    const FilterOutput cst = sp.filter(flat, f, &fetched, ops);
    ASSERT_NEAR(cst.colour.b, 0.8, 1e-5);
    ASSERT_EQ(fetched.size(), cst.stats.texels);
    ASSERT_EQ(ops.mem, cst.stats.texels);
    const FilterOutput o = sp.filter(tex, f, nullptr, ops);
    const glm::dvec4 ref = footprint_reference_affine(tex, f, rc).colour;
    for (int ch = 0; ch < 3; ++ch) worst = std::max(worst, std::fabs(o.colour[ch] - ref[ch]));
  }
  std::printf("SPAF (Gaussian, ±1 px quadrilateral) vs reference, smooth texture: max error %.4f\n", worst);
  // The quadrilateral's corners (beyond r = 1 px, weights ≤ e^-4) and point-sampled texels of
  // a level whose minor axis spans 1–2 texels keep the error small on smooth textures.
  EXPECT_LT(worst, 0.02);
}

TEST(Spaf, Config) {
  auto t = toml::parse("mask_side = 8\nslope_steps = 64\ngaussian = false\n");
  const auto c = SpafFilter::Config::from_toml(ConfigReader(t, "s.toml", "spaf"));
  EXPECT_EQ(c.mask_side, 8);
  EXPECT_EQ(c.slope_steps, 64);
  EXPECT_FALSE(c.gaussian);
  auto bad = toml::parse("mask_side = 9\n");
  EXPECT_THROW(SpafFilter::Config::from_toml(ConfigReader(bad, "s.toml", "spaf")), InputError);
  auto odd = toml::parse("slope_steps = 33\n");
  EXPECT_THROW(SpafFilter::Config::from_toml(ConfigReader(odd, "s.toml", "spaf")), InputError);
  SpafFilter::Config d;
  EXPECT_EQ(SpafFilter(d).table_bytes(), 32u * 16u * 2u);
  EXPECT_GT(SpafFilter(d).timing(TechTable::defaults()).latency, 10u);
}

}  // namespace
}  // namespace texsim
