// V(d) sub-texel cut-off as a weighting option of the footprint filters: SPAF's per-edge
// coverage against the Gaussian texel's volume integrated numerically, for a straight edge
// at a distance measured geometrically; the polynomial evaluators within their measured error;
// coverage in [0, 1] for every input; finite non-negative filter results for degenerate and
// non-finite fragments; per-material selection in a scene and its errors.
#include <gtest/gtest.h>
#include <toml++/toml.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/texture/footprint/ewa_filter.h"
#include "blocks/texture/footprint/spaf_filter.h"
#include "blocks/texture/subtexel/subtexel_cutoff.h"
#include "pipeline/scene/scene.h"
#include "pipeline/studies/study_vd.h"
#include "pipeline/texture/effect_registry.h"
#include "testbench/lib/filter_fixtures.h"

namespace texsim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSigma = VdSeedCoefficients::kSigma;

// ∫_a^b of the 1-D Gaussian of σ = 0.2 by composite Simpson (2000 intervals: error ~10⁻¹³),
// independent of erfc.
double gauss_mass(double a, double b) {
  if (!(b > a)) return 0.0;
  const int n = 2000;
  const double h = (b - a) / n;
  auto phi = [](double x) {
    return std::exp(-x * x / (2 * kSigma * kSigma)) / (kSigma * std::sqrt(2 * kPi));
  };
  double s = phi(a) + phi(b);
  for (int i = 1; i < n; ++i) s += (i % 2 ? 4.0 : 2.0) * phi(a + i * h);
  return s * h / 3.0;
}

// The part of a Gaussian texel (σ = 0.2, the strip |t| ≤ ½ across the edge) on the inner side
// of an edge at signed distance d from its centre (d > 0: centre outside).
double reference_coverage(double d) {
  const double lo = std::clamp(d, -0.5, 0.5);
  return gauss_mass(lo, 0.5) / gauss_mass(-0.5, 0.5);
}

// A random edge at a known distance from the texel centre (0, 0): its L1-normalised normal
// (deu, dev), the edge function E at the centre, and the Euclidean signed distance d computed
// from the two points with the cross product (not from E).
struct Edge {
  double deu, dev, e, d;
};
Edge random_edge(std::mt19937& rng, double max_dist) {
  std::uniform_real_distribution<double> uni(0, 1);
  const double th = uni(rng) * 2 * kPi, off = (2 * uni(rng) - 1) * max_dist;
  const double nx = std::cos(th), ny = std::sin(th);
  // Two points on the line n·p = off, spread along it.
  const double l0 = -1 - 3 * uni(rng), l1 = 1 + 3 * uni(rng);
  const double p0x = off * nx - l0 * ny, p0y = off * ny + l0 * nx;
  const double p1x = off * nx - l1 * ny, p1y = off * ny + l1 * nx;
  const double du = p1x - p0x, dv = p1y - p0y, n1 = std::fabs(du) + std::fabs(dv);
  Edge g;
  g.deu = dv / n1;
  g.dev = -du / n1;
  g.e = (0 - p0x) * g.deu + (0 - p0y) * g.dev;
  const double cross = du * (0 - p0y) - dv * (0 - p0x);
  g.d = std::fabs(cross) / std::hypot(du, dv) * (g.e < 0 ? 1.0 : -1.0);
  return g;
}

SpafFilter spaf_vd(VdEvaluatorKind k, NumberFormat f) {
  SpafFilter::Config c;
  c.coverage = SpafFilter::Coverage::Vd;
  c.vd.evaluator = k;
  c.vd.format = f;
  return SpafFilter(c);
}

TEST(VdWeighting, ExactCoverageMatchesGaussianIntegral) {
  struct Case {
    NumberFormat f;
    double bound;
  };
  // Fixed: d rounded into s1.F (½ LSB × slope ≤ 2.03), W rounded into u1.F, 1/W(−½) and the
  // product each rounded (½ LSB): within 3 LSB of u1.F. float: erfcf and float rounding.
  const Case cases[] = {{NumberFormat::Double, 1e-9},
                        {NumberFormat::Float, 1e-6},
                        {NumberFormat::Fx16, 3 * VdFx16::Out::lsb()},
                        {NumberFormat::Fx12, 3 * VdFx12::Out::lsb()}};
  for (const Case& cs : cases) {
    const SpafFilter sp = spaf_vd(VdEvaluatorKind::Exact, cs.f);
    std::mt19937 rng(11);
    double worst = 0;
    for (int i = 0; i < 3000; ++i) {
      const Edge g = random_edge(rng, 0.8);
      const double cov = sp.vd_coverage(g.deu, g.dev, g.e);
      worst = std::max(worst, std::fabs(cov - reference_coverage(g.d)));
    }
    std::printf("exact V(d) coverage, format %s: max error %.3g against the Gaussian integral\n",
                kVdFormats.key_of(cs.f).data(), worst);
    EXPECT_LE(worst, cs.bound) << kVdFormats.key_of(cs.f);
  }
  // The L1-normalised E is not the distance: at 45° it is √2 times too small, which the
  // coverage must undo. An edge at 45° whose E at the centre is −0.3 is 0.424 away.
  const SpafFilter sp = spaf_vd(VdEvaluatorKind::Exact, NumberFormat::Double);
  EXPECT_NEAR(sp.vd_coverage(0.5, 0.5, -0.3), reference_coverage(0.3 * std::sqrt(2.0)), 1e-9);
  EXPECT_GT(std::fabs(reference_coverage(0.3 * std::sqrt(2.0)) - reference_coverage(0.3)), 0.03);
  // A centre on the edge keeps exactly half; |E| ≥ ½ is fully in or out in every direction.
  EXPECT_NEAR(sp.vd_coverage(1, 0, 0), 0.5, 1e-12);
  for (double deu : {1.0, 0.7, 0.5, 0.0, -0.3}) {
    const double dev = 1 - std::fabs(deu);
    EXPECT_EQ(sp.vd_coverage(deu, dev, 0.5), 1.0) << deu;
    EXPECT_EQ(sp.vd_coverage(deu, dev, -0.5), 0.0) << deu;
  }
}

// Ŵ/Ŵ(−½) − W/W(−½) = (Ŵ − W)/Ŵ(−½) + (W/W(−½))·(W(−½) − Ŵ(−½))/Ŵ(−½), and both W errors are
// differences of two V errors: at most 4·ε_V/Ŵ(−½), ε_V the evaluator's measured maximum.
TEST(VdWeighting, PolynomialCoverageWithinEvaluatorBound) {
  for (VdEvaluatorKind k : {VdEvaluatorKind::P3, VdEvaluatorKind::P2, VdEvaluatorKind::P1}) {
    for (NumberFormat f : {NumberFormat::Double, NumberFormat::Fx16}) {
      const double eps = measure_vd_error(k, f, 200000).max_abs;
      const SubtexelCutoff cut = SpafFilter(spaf_vd(k, f)).cutoff();
      const double full = cut.weight(-0.5);
      // Fixed: d's rounding (½ LSB of s1.16 × slope ≤ 2.4) and the two output roundings.
      const double quant = f == NumberFormat::Fx16 ? 3 * VdFx16::Out::lsb() : 1e-12;
      const double bound = 4 * eps / full + quant;
      const SpafFilter sp = spaf_vd(k, f);
      std::mt19937 rng(12);
      double worst = 0;
      for (int i = 0; i < 4000; ++i) {
        const Edge g = random_edge(rng, 0.6);
        worst =
            std::max(worst, std::fabs(sp.vd_coverage(g.deu, g.dev, g.e) - reference_coverage(g.d)));
      }
      std::printf("%s %s: coverage error %.4f, bound 4·%.4f/%.4f = %.4f\n",
                  vd_evaluator_name(k).data(), kVdFormats.key_of(f).data(), worst, eps, full,
                  bound);
      EXPECT_LE(worst, bound) << vd_evaluator_name(k);
      // And the polynomial's error really shows (the bound is not vacuous).
      EXPECT_GE(worst, 0.5 * eps) << vd_evaluator_name(k);
    }
  }
}

TEST(VdWeighting, CoverageInUnitIntervalForAnyInput) {
  const double specials[] = {std::numeric_limits<double>::quiet_NaN(),
                             std::numeric_limits<double>::infinity(),
                             -std::numeric_limits<double>::infinity(),
                             1e300,
                             -1e300,
                             0.0,
                             -0.0};
  for (VdEvaluatorKind k : kVdEvaluatorKinds) {
    for (NumberFormat f : kVdFormatKinds) {
      const SpafFilter sp = spaf_vd(k, f);
      for (int i = -3000; i <= 3000; ++i) {
        const double e = i / 3000.0, deu = 0.37, dev = -0.63;
        const double c = sp.vd_coverage(deu, dev, e);
        ASSERT_GE(c, 0.0) << vd_evaluator_name(k) << " " << e;
        ASSERT_LE(c, 1.0) << vd_evaluator_name(k) << " " << e;
      }
      for (double e : specials) {
        const double c = sp.vd_coverage(0.5, 0.5, e);
        ASSERT_TRUE(std::isfinite(c)) << vd_evaluator_name(k) << " " << e;
        ASSERT_GE(c, 0.0);
        ASSERT_LE(c, 1.0);
      }
    }
  }
}

// Non-finite, degenerate, extreme and ordinary fragments: every V(d)-weighted filter returns a
// finite colour inside the texels' range (weights ≥ 0, normalised) and counts what it fetched.
TEST(VdWeighting, FiltersStayFiniteAndInRange) {
  const Texture tex = noise_texture(64, 64, 3);
  const double nan = std::numeric_limits<double>::quiet_NaN(),
               inf = std::numeric_limits<double>::infinity();
  std::vector<Fragment> frags = {
      texel_fragment(0.3, 0.6, 0, 0, 0, 0, 64),
      texel_fragment(0.3, 0.6, 8, 4, 16, 8, 64),  // point, parallel
      texel_fragment(nan, 0.6, 2, 0, 0, 2, 64),
      texel_fragment(0.3, inf, 2, 0, 0, 2, 64),  // bad u, v
      texel_fragment(0.3, 0.6, nan, 1, 1, 1, 64),
      texel_fragment(0.3, 0.6, inf, 1, -inf, 1, 64),
      texel_fragment(0.3, 0.6, 5000, 0.5, -0.01, 0.5, 64),    // 10⁴:1
      texel_fragment(0.3, 0.6, 1e12, 3e11, -2e11, 1e12, 64),  // far beyond the texture
      texel_fragment(0.3, 0.6, 0.01, 0, 0, 0.01, 64)};        // magnified
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> uni(0, 1);
  for (int i = 0; i < 100; ++i) {
    const double major = std::exp2(uni(rng) * 8 - 1), minor = major / (1 + 30 * uni(rng)),
                 th = uni(rng) * kPi;
    frags.push_back(texel_fragment(uni(rng), uni(rng), major * std::cos(th), major * std::sin(th),
                                   -minor * std::sin(th), minor * std::cos(th), 64));
  }
  auto check = [&](const std::string& name, const auto& filt) {
    for (const Fragment& f : frags) {
      std::vector<TexelRef> fetched;
      OpCounts ops;
      const FilterOutput o = filt.filter(tex, f, &fetched, ops);
      for (int ch = 0; ch < 4; ++ch) {
        ASSERT_TRUE(std::isfinite(o.colour[ch])) << name;
        ASSERT_GE(o.colour[ch], 0.1f / 1.01f - 1e-3f) << name;
        ASSERT_LE(o.colour[ch], 1.0f + 1e-5f) << name;
      }
      ASSERT_EQ(fetched.size(), o.stats.texels) << name;
      ASSERT_EQ(ops.mem, o.stats.texels) << name;
    }
  };
  for (VdEvaluatorKind k : kVdEvaluatorKinds) {
    for (NumberFormat fm : {NumberFormat::Float, NumberFormat::Fx16, NumberFormat::Fx8}) {
      for (NumberFormat ar : {NumberFormat::Float, NumberFormat::S20_28HalfUp}) {
        SpafFilter::Config c;
        c.coverage = SpafFilter::Coverage::Vd;
        c.vd.evaluator = k;
        c.vd.format = fm;
        c.arith = ar;
        check(std::string("spaf ") + std::string(vd_evaluator_name(k)), SpafFilter(c));
      }
      for (NumberFormat ar : {NumberFormat::Float, NumberFormat::S18_30}) {
        EwaFilter::Config c;
        c.edge = EwaFilter::Edge::Vd;
        c.vd.evaluator = k;
        c.vd.format = fm;
        c.arith = ar;
        check(std::string("ewa ") + std::string(vd_evaluator_name(k)), EwaFilter(c));
        c.reconstruction = 0;  // footprints thinner than a texel: the band covers every texel
        check(std::string("ewa no reconstruction ") + std::string(vd_evaluator_name(k)),
              EwaFilter(c));
      }
    }
  }
}

const SceneMaterial& material(const Scene& s, const std::string& name) {
  for (const SceneMaterial& m : s.materials) {
    if (m.name == name) return m;
  }
  ADD_FAILURE() << "no material " << name;
  return s.materials.front();
}

TEST(VdWeighting, SelectedPerMaterialInAScene) {
  const Scene s = load_scene(std::string(TEXSIM_SOURCE_DIR) + "/scenes/subtexel_cutoff.toml");
  auto filter_of = [&](const std::string& name) {
    const SceneMaterial& m = material(s, name);
    return material_from_toml(name, 0, *m.effects, s.path).footprint;
  };
  const auto spaf = filter_of("spaf_vd");
  ASSERT_NE(spaf, nullptr);
  EXPECT_EQ(spaf->name(), "filter.spaf");
  EXPECT_NE(spaf->arithmetic().find("V(d) P1 fx8"), std::string::npos) << spaf->arithmetic();
  const auto ewa = filter_of("ewa_vd");
  ASSERT_NE(ewa, nullptr);
  EXPECT_NE(ewa->arithmetic().find("V(d) P2 fx16"), std::string::npos) << ewa->arithmetic();
  EXPECT_EQ(filter_of("spaf")->arithmetic().find("V(d)"), std::string::npos);

  // The keys as a material writes them, parsed by the blocks' own from_toml.
  auto parse = [](const std::string& text) {
    static std::vector<std::shared_ptr<toml::table>> keep;  // the reader points into the table
    keep.push_back(std::make_shared<toml::table>(toml::parse(text, std::string_view("m.toml"))));
    return material_from_toml("m", 0, *keep.back(), "m.toml").footprint;
  };
  const auto p1 =
      parse("spaf = { coverage = \"vd\", vd = { evaluator = \"p1\", format = \"fx8\" } }\n");
  EXPECT_NE(p1->arithmetic().find("V(d) P1 fx8 (u0.8/s3.7/u1.7)"), std::string::npos)
      << p1->arithmetic();
  EXPECT_NE(parse("spaf = { arith = \"fixed\" }\n")->arithmetic().find(SpafFixed::name()),
            std::string::npos);
  EXPECT_NE(parse("spaf = {}\n")->arithmetic().find("mask"), std::string::npos);
  auto expect_error = [&](const std::string& text, const std::string& key) {
    try {
      parse(text);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("m.toml:1:"), std::string::npos) << what;
      EXPECT_NE(what.find(key), std::string::npos) << what;
    }
  };
  expect_error("spaf = { coverage = \"vd\", vd = { evaluator = \"p4\" } }\n", "evaluator");
  expect_error("ewa = { edge = \"vd\", vd = { evaluator = \"cubic\" } }\n", "evaluator");
  expect_error("spaf = { coverage = \"vd\", vd = { format = \"fx10\" } }\n", "format");
  expect_error("spaf = { vd = { evaluator = \"p2\" } }\n", "vd");  // without coverage = "vd"
  expect_error("ewa = { vd = { evaluator = \"p2\" } }\n", "vd");   // without edge = "vd"
  expect_error("spaf = { coverage = \"area\" }\n", "coverage");
  expect_error("ewa = { edge = \"soft\" }\n", "edge");
  expect_error("spaf = { arith = \"half\" }\n", "arith");
}

}  // namespace
}  // namespace texsim
