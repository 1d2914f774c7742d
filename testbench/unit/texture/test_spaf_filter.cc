// SPAF: the mask table against exact sub-texel masks and exact areas, edge functions that
// classify fully covered and uncovered texels, half-covered texels on edges through texel
// centres, constant textures exact, the Gaussian-weighted result against the reference; V(d)
// coverage of texels cut through their centres, its ops and timing; the fixed-point and float
// edge-function datapaths against double, and the fixed datapath's range guard.
#include <gtest/gtest.h>
#include <toml++/toml.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/texture/footprint/spaf_filter.h"
#include "pipeline/reference/footprint_reference.h"

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
    std::printf(
        "SPAF %dx%d masks (64 slopes x 32 offsets): %.3f wrong bits per mask, max area error "
        "%.3f\n",
        side, side, static_cast<double>(bit_errors) / samples, worst_area);
    // A sub-texel grid of side n misjudges at most the cells the edge crosses (≤ 2n of n²)
    // plus the table's quantisation: the area error stays below 2/n + 1/16.
    EXPECT_LT(worst_area, 2.0 / side + 1.0 / 16) << side;
  }
}

TEST(Spaf, EdgesThroughTexelCentresHalfCover) {
  // An axis-aligned 4×4-texel quadrilateral whose edges pass through texel centres.
  std::vector<float> px(size_t{16} * 16 * 4, 0.0f);
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
  std::vector<float> fl(size_t{64} * 64 * 4, 0.8f);
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
  std::printf("SPAF (Gaussian, ±1 px quadrilateral) vs reference, smooth texture: max error %.4f\n",
              worst);
  // The quadrilateral's corners (beyond r = 1 px, weights ≤ e^-4) and point-sampled texels of
  // a level whose minor axis spans 1–2 texels keep the error small on smooth textures.
  EXPECT_LT(worst, 0.02);
}

// An axis-aligned quadrilateral whose edges pass through the centres of texel columns and rows
// 5 and 10: border texels are cut by one edge at d = 0, corners by two. With the area filter
// (no Gaussian) and a texture that is 1 on that ring and 0 inside, the result is
// Σ ring weights / Σ weights = (16h + 4h²)/(16 + 16h + 4h²), h the coverage at d = 0.
TEST(Spaf, VdCoverageOfTexelsCutThroughTheirCentres) {
  std::vector<float> px(size_t{16} * 16 * 4, 0.0f);
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 16; ++x) {
      const bool ring = (x == 5 || x == 10 || y == 5 || y == 10);
      px[static_cast<size_t>(y * 16 + x) * 4] = ring ? 1.0f : 0.0f;
    }
  }
  const Texture tex = Texture::from_rgba("ring", 16, 16, px, TexelFormat::Rgba32f, false);
  Fragment f;
  f.u = f.v = 8.0 / 16;  // centre 7.5: edges at 5 and 10
  f.dudx = f.dvdy = 2.5 / 16;
  auto run = [&](SpafFilter::Config c, FilterOutput* o = nullptr) {
    c.gaussian = false;
    c.texel_budget = 1024;
    OpCounts ops;
    const FilterOutput r = SpafFilter(c).filter(tex, f, nullptr, ops);
    if (o) *o = r;
    return static_cast<double>(r.colour.r);
  };
  // h2: a corner's coverage h·h, rounded as the datapath rounds the product (into u1.F, HalfUp).
  auto expect = [](double h, double h2) { return (16 * h + 4 * h2) / (16 + 16 * h + 4 * h2); };
  SpafFilter::Config mask;
  EXPECT_NEAR(run(mask), expect(0.5, 0.25), 1e-6);  // the 4×4 mask at E = 0 holds half the bits
  for (VdEvaluatorKind k : kVdEvaluatorKinds) {
    for (NumberFormat fm : {NumberFormat::Double, NumberFormat::Fx16, NumberFormat::Fx8}) {
      SpafFilter::Config c;
      c.coverage = SpafFilter::Coverage::Vd;
      c.vd.evaluator = k;
      c.vd.format = fm;
      const double h = SpafFilter(c).vd_coverage(1, 0, 0);
      const int fbits = fm == NumberFormat::Fx8 ? VdFx8::Out::kFracBits : VdFx16::Out::kFracBits;
      const double h2 = fm == NumberFormat::Double
                            ? h * h
                            : std::floor(std::ldexp(h * h, fbits) + 0.5) / std::ldexp(1.0, fbits);
      // W(0)/W(−½) = ½ for the exact evaluator and P2 (V(0) = ½); P3 and P1 have V̂(0) ≠ ½.
      if (k == VdEvaluatorKind::Exact || k == VdEvaluatorKind::P2) {
        EXPECT_NEAR(h, 0.5,
                    fm == NumberFormat::Double
                        ? 1e-12
                        : 2 * std::ldexp(1.0, fm == NumberFormat::Fx8 ? -7 : -15));
      } else {
        EXPECT_GT(std::fabs(h - 0.5), 1e-3) << vd_evaluator_name(k);
      }
      for (NumberFormat ar :
           {NumberFormat::Float, NumberFormat::Double, NumberFormat::S20_28HalfUp}) {
        c.arith = ar;
        FilterOutput o;
        EXPECT_NEAR(run(c, &o), expect(h, h2), 1e-6)
            << vd_evaluator_name(k) << " " << static_cast<int>(ar);
        EXPECT_EQ(o.stats.texels, 36u);
        // One cut-off unit per lane: the four corner texels (two cut edges) take two slots.
        EXPECT_EQ(o.stats.visited, 36u + 4u);
      }
      c.vd.lanes = 2;
      FilterOutput o;
      run(c, &o);
      EXPECT_EQ(o.stats.visited, 36u);
    }
  }
}

TEST(Spaf, VdOpsAndTiming) {
  const TechTable tech = TechTable::defaults();
  SpafFilter::Config c;
  const SpafFilter mask(c);
  c.coverage = SpafFilter::Coverage::Vd;
  uint32_t prev_latency = 0;
  // Cut-off critical paths grow exact (one table) < P1 < P2 < P3 with the default table.
  for (VdEvaluatorKind k :
       {VdEvaluatorKind::Exact, VdEvaluatorKind::P1, VdEvaluatorKind::P2, VdEvaluatorKind::P3}) {
    c.vd.evaluator = k;
    const SpafFilter sp(c);
    const OpCounts e = sp.per_partial_edge_ops(), cut = sp.cutoff().ops_per_item();
    EXPECT_EQ(e.mul, cut.mul + 3) << vd_evaluator_name(k);  // distance, 1/W(−½), product
    EXPECT_EQ(e.add, cut.add);
    EXPECT_EQ(e.cmp, cut.cmp + 1);
    EXPECT_EQ(e.lut, cut.lut);
    EXPECT_EQ(sp.per_inside_ops().lut, mask.per_inside_ops().lut - 1);  // no popcount
    const TimingSpec t = sp.timing(tech);
    EXPECT_GE(t.latency, prev_latency) << vd_evaluator_name(k);
    prev_latency = t.latency;
    c.vd.lanes = 4;
    EXPECT_GT(SpafFilter(c).timing(tech).area, t.area);
    c.vd.lanes = 1;
  }
  EXPECT_GT(prev_latency, mask.timing(tech).latency);
  c = SpafFilter::Config{};
  c.arith = NumberFormat::S20_28HalfUp;
  EXPECT_GT(SpafFilter(c).timing(tech).area, mask.timing(tech).area);  // the range guard
  EXPECT_EQ(SpafFilter(c).timing(tech).latency, mask.timing(tech).latency);
}

// The fixed s20.28 and float datapaths against double on a smooth texture. With V(d) coverage
// (continuous in E) the difference comes from the set-up in float32 (relative 6·10⁻⁸ of the
// corners and normals), the E and Q drift (≤ n·2⁻²⁹, n²·2⁻²⁹ over a box of side n ≤ 32 here)
// and W's rounding; masks can switch a table column where E crosses a column boundary (a
// coverage step of a few sub-texels), which smooth textures keep small.
TEST(Spaf, FixedAndFloatTrackDouble) {
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
  for (SpafFilter::Coverage cov : {SpafFilter::Coverage::Mask, SpafFilter::Coverage::Vd}) {
    SpafFilter::Config c;
    c.coverage = cov;
    c.vd.format = NumberFormat::Double;
    c.texel_budget = 256;
    c.arith = NumberFormat::Double;
    const SpafFilter sd(c);
    c.arith = NumberFormat::S20_28HalfUp;
    const SpafFilter sx(c);
    c.arith = NumberFormat::Float;
    const SpafFilter sf(c);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> uni(0, 1);
    double worst_fixed = 0, worst_float = 0;
    for (int k = 0; k < 400; ++k) {
      const double minor = 0.5 + 3 * uni(rng), major = minor * (1 + 30 * uni(rng)),
                   th = uni(rng) * kPi;
      Fragment f;
      f.u = uni(rng) * 4 - 2;
      f.v = uni(rng) * 4 - 2;
      f.dudx = major * std::cos(th) / size;
      f.dvdx = major * std::sin(th) / size;
      f.dudy = -minor * std::sin(th) / size;
      f.dvdy = minor * std::cos(th) / size;
      OpCounts o1, o2, o3;
      std::vector<TexelRef> t1, t2;
      const FilterOutput a = sd.filter(tex, f, &t1, o1), b = sx.filter(tex, f, &t2, o2);
      const FilterOutput d = sf.filter(tex, f, nullptr, o3);
      ASSERT_FALSE(b.stats.fallback);  // within the fixed datapath's range
      EXPECT_EQ(a.stats.level, b.stats.level);
      EXPECT_NEAR(static_cast<double>(t1.size()), static_cast<double>(t2.size()), 2.0);
      for (int ch = 0; ch < 3; ++ch) {
        worst_fixed =
            std::max(worst_fixed, static_cast<double>(std::fabs(a.colour[ch] - b.colour[ch])));
        worst_float =
            std::max(worst_float, static_cast<double>(std::fabs(a.colour[ch] - d.colour[ch])));
      }
    }
    std::printf("SPAF %s: fixed %s vs double max colour difference %.3g, float vs double %.3g\n",
                cov == SpafFilter::Coverage::Vd ? "V(d)" : "mask", SpafFixed::name().c_str(),
                worst_fixed, worst_float);
    const double bound = cov == SpafFilter::Coverage::Vd ? 1e-4 : 5e-3;
    EXPECT_LT(worst_fixed, bound);
    EXPECT_LT(worst_float, bound);
  }
}

// Beyond the fixed format's range (Q at the box corners of a very thin footprint) the fixed
// datapath takes the bilinear fallback instead of stepping a saturated value; float scans.
// The footprint lies along a row of texel centres, so its Gaussian weights do not underflow
// (and V(d) coverage: masks of two close parallel edges can AND to nothing).
TEST(Spaf, FixedRangeGuard) {
  std::vector<float> fl(size_t{64} * 64 * 4, 0.8f);
  const Texture flat = Texture::from_rgba("f", 64, 64, fl, TexelFormat::Rgba32f, true);
  SpafFilter::Config c;
  c.coverage = SpafFilter::Coverage::Vd;
  c.vd.format = NumberFormat::Float;
  c.arith = NumberFormat::S20_28HalfUp;
  const SpafFilter sx(c);
  c.arith = NumberFormat::Float;
  const SpafFilter sf(c);
  int first_fallback = 0;
  for (int e = 0; e <= 14; ++e) {
    const double aniso = std::exp2(e), major = 8;
    Fragment f;
    f.u = 0.5;
    f.v = 32.5 / 64;
    f.dudx = major / 64;
    f.dvdy = major / aniso / 64;
    OpCounts ops;
    const FilterOutput a = sx.filter(flat, f, nullptr, ops), b = sf.filter(flat, f, nullptr, ops);
    EXPECT_FALSE(b.stats.fallback) << aniso;
    EXPECT_NEAR(a.colour.r, 0.8, 1e-5);
    if (a.stats.fallback && first_fallback == 0) first_fallback = static_cast<int>(aniso);
    if (first_fallback) {
      EXPECT_TRUE(a.stats.fallback) << aniso;  // and beyond it
    }
  }
  std::printf("SPAF fixed: first anisotropy taking the range fallback (8-texel major axis): %d:1\n",
              first_fallback);
  EXPECT_GE(first_fallback, 256);
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
  auto vd = toml::parse(
      "coverage = \"vd\"\narith = \"fixed\"\nvd = { evaluator = \"p3\", format = \"fx12\", lanes = "
      "2 }\n");
  const auto cv = SpafFilter::Config::from_toml(ConfigReader(vd, "s.toml", "spaf"));
  EXPECT_EQ(cv.coverage, SpafFilter::Coverage::Vd);
  EXPECT_EQ(cv.arith, NumberFormat::S20_28HalfUp);
  EXPECT_EQ(cv.vd.evaluator, VdEvaluatorKind::P3);
  EXPECT_EQ(cv.vd.format, NumberFormat::Fx12);
  EXPECT_EQ(cv.vd.lanes, 2u);
  const auto dflt = SpafFilter::Config::from_toml(ConfigReader(toml::table{}, "s.toml", "spaf"));
  EXPECT_EQ(dflt.coverage, SpafFilter::Coverage::Mask);  // existing results unchanged
  EXPECT_EQ(dflt.arith, NumberFormat::Float);
  SpafFilter::Config d;
  EXPECT_EQ(SpafFilter(d).table_bytes(), 32u * 16u * 2u);
  EXPECT_GT(SpafFilter(d).timing(TechTable::defaults()).latency, 10u);
}

}  // namespace
}  // namespace texsim
