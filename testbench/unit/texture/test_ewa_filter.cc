// EWA filter: constant textures are reproduced, the result matches the Gaussian-footprint
// reference on smooth textures, the fixed-point Q datapath tracks double, the weight table's
// error is within its analytic bound, texel counts obey the budget, and op counts agree with
// the texels reported; the V(d) edge cut-off: its boundary distance against geometry, its
// weights on a circle, and edge = "none" leaving every variant unchanged.
#include <gtest/gtest.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/texture/footprint/ewa_filter.h"
#include "pipeline/reference/footprint_reference.h"

namespace texsim {
namespace {

constexpr double kPi = 3.14159265358979323846;

Texture make_texture(int size, const std::function<glm::vec4(double, double)>& fn,
                     TexelFormat fmt = TexelFormat::Rgba32f) {
  std::vector<float> px(static_cast<size_t>(size) * static_cast<size_t>(size) * 4);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const glm::vec4 c = fn((x + 0.5) / size, (y + 0.5) / size);
      const size_t i =
          (static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x)) * 4;
      px[i] = c.r;
      px[i + 1] = c.g;
      px[i + 2] = c.b;
      px[i + 3] = c.a;
    }
  }
  return Texture::from_rgba("t", size, size, px, fmt, true);
}

// A smooth periodic texture: a few low-frequency waves per channel.
glm::vec4 smooth(double u, double v) {
  const double a = 0.5 + 0.25 * std::sin(2 * kPi * (2 * u + v)) + 0.2 * std::cos(2 * kPi * 3 * v);
  const double b = 0.5 + 0.4 * std::sin(2 * kPi * (u - 2 * v));
  const double c = 0.5 + 0.3 * std::cos(2 * kPi * 4 * u) * std::sin(2 * kPi * v);
  return {static_cast<float>(a), static_cast<float>(b), static_cast<float>(c), 1.0f};
}

// A fragment at (u, v) whose footprint has major radius `major` and minor radius `minor`
// level-0 texels (R = 1 pixel) on a `size` texture, major axis at angle `theta`.
Fragment footprint(double u, double v, double major, double minor, double theta, int size) {
  Fragment f;
  f.u = u;
  f.v = v;
  const double c = std::cos(theta), s = std::sin(theta);
  // Screen x maps to the major axis, screen y to the minor axis.
  f.dudx = major * c / size;
  f.dvdx = major * s / size;
  f.dudy = -minor * s / size;
  f.dvdy = minor * c / size;
  return f;
}

double max_channel_diff(const glm::dvec4& a, const glm::dvec4& b) {
  double m = 0;
  for (int k = 0; k < 3; ++k) m = std::max(m, std::fabs(a[k] - b[k]));
  return m;
}

TEST(EwaFilter, ConstantTextureIsExact) {
  const Texture tex =
      make_texture(64, [](double, double) { return glm::vec4(0.25f, 0.5f, 0.75f, 1.0f); });
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> uni(0, 1);
  for (NumberFormat ar : {NumberFormat::Float, NumberFormat::Double, NumberFormat::S18_30}) {
    for (EwaFilter::Weight wt : {EwaFilter::Weight::Lut, EwaFilter::Weight::Exp,
                                 EwaFilter::Weight::Pow8, EwaFilter::Weight::Map}) {
      EwaFilter::Config c;
      c.arith = ar;
      c.weight = wt;
      const EwaFilter ewa(c);
      for (int k = 0; k < 200; ++k) {
        const double major = std::exp2(uni(rng) * 8 - 2), minor = major / (1 + 20 * uni(rng));
        const Fragment f = footprint(uni(rng), uni(rng), major, minor, uni(rng) * kPi, 64);
        OpCounts ops;
        const FilterOutput o = ewa.filter(tex, f, nullptr, ops);
        ASSERT_NEAR(o.colour.r, 0.25, 2e-6);
        ASSERT_NEAR(o.colour.g, 0.5, 2e-6);
        ASSERT_NEAR(o.colour.b, 0.75, 2e-6);
        ASSERT_GE(o.stats.texels, 1u);
      }
    }
  }
}

// Against the Gaussian-footprint reference (affine map, same pixel model) on a smooth texture:
// at level 0 the only differences are the discrete sum over texel centres, the reconstruction
// term (texel-sized blur) and the weight table.
TEST(EwaFilter, MatchesReferenceOnSmoothTexture) {
  const Texture tex = make_texture(256, smooth);
  FootprintReferenceConfig rc;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> uni(0, 1);
  for (NumberFormat ar : {NumberFormat::Float, NumberFormat::Double, NumberFormat::S18_30}) {
    EwaFilter::Config c;
    c.arith = ar;
    c.minor_texels = 64;  // stay on level 0 for footprints up to 64 texels
    c.texel_budget = 1 << 16;
    c.max_aniso = 64;
    const EwaFilter ewa(c);
    double worst = 0;
    for (int k = 0; k < 300; ++k) {
      const double minor = 1 + 3 * uni(rng), major = minor * (1 + 15 * uni(rng));
      const Fragment f = footprint(uni(rng), uni(rng), major, minor, uni(rng) * kPi, 256);
      OpCounts ops;
      const FilterOutput o = ewa.filter(tex, f, nullptr, ops);
      ASSERT_EQ(o.stats.level, 0);
      const glm::dvec4 ref = footprint_reference_affine(tex, f, rc).colour;
      worst = std::max(worst, max_channel_diff(glm::dvec4(o.colour), ref));
    }
    std::printf("EWA %d vs reference, smooth texture, level 0: max error %.5f\n",
                static_cast<int>(ar), worst);
    // The texture's largest gradient is ~2π·1.3 per unit = 0.032 per texel; the table's step
    // (α/N ≈ 0.008 relative) and the one-texel² reconstruction blur (second derivative
    // ~(2π·4/256)²·0.3·1 ≈ 3·10⁻³) bound the error well below 0.01.
    EXPECT_LT(worst, 0.01);
  }
}

TEST(EwaFilter, LutErrorWithinBound) {
  for (int n : {32, 256, 1024}) {
    for (int bits : {0, 8, 16}) {
      EwaFilter::Config c;
      c.lut_size = n;
      c.lut_bits = bits;
      const EwaFilter ewa(c);
      double worst = 0;
      for (int i = 0; i < 100000; ++i) {
        const double q = i / 100000.0;
        worst = std::max(worst, std::fabs(ewa.weight_of(q) - std::exp(-2.0 * q)));
      }
      // Midpoint table: |exp(−αq) − exp(−α·mid)| ≤ α/(2N) (slope ≤ α), plus half an LSB.
      const double bound = 2.0 / (2.0 * n) + (bits > 0 ? std::ldexp(0.5, -bits) : 1e-7);
      EXPECT_LE(worst, bound) << n << " " << bits;
      EXPECT_GE(worst, 0.5 * 2.0 / (2.0 * n) * std::exp(-2.0)) << n << " " << bits;
    }
  }
  EwaFilter ewa;
  EXPECT_EQ(ewa.weight_of(1.0), 0.0);
  EXPECT_EQ(ewa.weight_of(7.0), 0.0);
  EXPECT_EQ(ewa.weight_of(std::nan("")), 0.0);
}

TEST(EwaFilter, FixedTracksDouble) {
  const Texture tex = make_texture(256, smooth);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(0, 1);
  EwaFilter::Config cd, cx;
  cd.arith = NumberFormat::Double;
  cx.arith = NumberFormat::S18_30;
  cd.weight = cx.weight = EwaFilter::Weight::Exp;
  const EwaFilter ed(cd), ex(cx);
  double worst = 0;
  for (int k = 0; k < 500; ++k) {
    const double major = std::exp2(uni(rng) * 10 - 2), minor = major / (1 + 30 * uni(rng));
    const Fragment f =
        footprint(uni(rng) * 4 - 2, uni(rng) * 4 - 2, major, minor, uni(rng) * kPi, 256);
    OpCounts o1, o2;
    std::vector<TexelRef> t1, t2;
    const FilterOutput a = ed.filter(tex, f, &t1, o1), b = ex.filter(tex, f, &t2, o2);
    worst = std::max(worst, max_channel_diff(glm::dvec4(a.colour), glm::dvec4(b.colour)));
    // Same level and nearly the same texels (a texel on the ellipse's edge may flip).
    EXPECT_EQ(a.stats.level, b.stats.level);
    EXPECT_NEAR(static_cast<double>(t1.size()), static_cast<double>(t2.size()),
                1.0 + 0.02 * static_cast<double>(t1.size()));
  }
  std::printf("EWA fixed s18.30 Q vs double: max colour difference %.3g\n", worst);
  EXPECT_LT(worst, 2e-3);
}

TEST(EwaFilter, BudgetBoundsTexelsAndCountsAgree) {
  const Texture tex = make_texture(256, smooth, TexelFormat::Rgba8);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> uni(0, 1);
  for (int budget : {64, 256, 1024}) {
    for (EwaFilter::Scan sc : {EwaFilter::Scan::Box, EwaFilter::Scan::RowSpan}) {
      EwaFilter::Config c;
      c.texel_budget = budget;
      c.scan = sc;
      const EwaFilter ewa(c);
      for (int k = 0; k < 300; ++k) {
        const double major = std::exp2(uni(rng) * 16 - 4), minor = major / std::exp2(uni(rng) * 10);
        const Fragment f = footprint(uni(rng), uni(rng), major, minor, uni(rng) * kPi, 256);
        OpCounts ops;
        std::vector<TexelRef> fetched;
        const FilterOutput o = ewa.filter(tex, f, &fetched, ops);
        ASSERT_EQ(fetched.size(), o.stats.texels);
        ASSERT_EQ(ops.mem, o.stats.texels);
        // Box: (2h_u + 1)(2h_v + 1) ≥ texels in the box; the fallback adds 4.
        ASSERT_LE(o.stats.texels, static_cast<uint32_t>(budget) + 4);
        ASSERT_LE(o.stats.visited, static_cast<uint32_t>(budget) + 64);
        for (const TexelRef& t : fetched) {
          ASSERT_GE(t.x, 0);
          ASSERT_LT(t.x, tex.width(t.level));
          ASSERT_GE(t.y, 0);
          ASSERT_LT(t.y, tex.height(t.level));
        }
      }
    }
  }
}

TEST(EwaFilter, RowSpanReadsTheSameTexelsAsBox) {
  const Texture tex = make_texture(128, smooth);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uni(0, 1);
  EwaFilter::Config cb, cs;
  cb.arith = cs.arith = NumberFormat::Double;
  cs.scan = EwaFilter::Scan::RowSpan;
  const EwaFilter eb(cb), es(cs);
  uint64_t visited_box = 0, visited_span = 0;
  for (int k = 0; k < 300; ++k) {
    const double major = std::exp2(uni(rng) * 6), minor = major / (1 + 15 * uni(rng));
    const Fragment f = footprint(uni(rng), uni(rng), major, minor, uni(rng) * kPi, 128);
    OpCounts o1, o2;
    const FilterOutput a = eb.filter(tex, f, nullptr, o1), b = es.filter(tex, f, nullptr, o2);
    EXPECT_NEAR(static_cast<double>(a.stats.texels), static_cast<double>(b.stats.texels), 2.0);
    EXPECT_LT(max_channel_diff(glm::dvec4(a.colour), glm::dvec4(b.colour)), 1e-3);
    visited_box += a.stats.visited;
    visited_span += b.stats.visited;
  }
  std::printf("box scan visits %llu, row-span %llu\n", static_cast<unsigned long long>(visited_box),
              static_cast<unsigned long long>(visited_span));
  EXPECT_LT(visited_span, visited_box);
}

TEST(EwaFilter, AnisotropyClampAndLevel) {
  const Texture tex = make_texture(256, smooth);
  OpCounts ops;
  // 64:1 footprint, max 16: minor stretched to major/16.
  Fragment f = footprint(0.5, 0.5, 64, 1, 0.3, 256);
  const Footprint fp = footprint_setup<double>(f, 256, 256, 1.0, 16.0, ops);
  EXPECT_TRUE(fp.clamped);
  EXPECT_NEAR(fp.aniso, 64.0, 1e-9);
  EXPECT_NEAR(std::sqrt(fp.major2), 64.0, 1e-9);
  EXPECT_NEAR(std::sqrt(fp.minor2), 4.0, 1e-9);
  // Σ' keeps the major axis: eigenvalues of the clamped Σ.
  const double t = 0.5 * (fp.suu + fp.svv), d = 0.5 * (fp.suu - fp.svv);
  const double s = std::sqrt(d * d + fp.suv * fp.suv);
  EXPECT_NEAR(t + s, 64.0 * 64.0, 1e-6);
  EXPECT_NEAR(t - s, 16.0, 1e-6);
  // Level from the minor axis: minor 4 texels, minor_texels 1 → level 2.
  EwaFilter ewa;
  EXPECT_EQ(ewa.filter(tex, f, nullptr, ops).stats.level, 2);
  f = footprint(0.5, 0.5, 8, 8, 0, 256);  // isotropic, radius 8 → level 3
  EXPECT_EQ(ewa.filter(tex, f, nullptr, ops).stats.level, 3);
}

// The boundary distance d = 2(Q − √Q)/|∇Q| against the Euclidean distance to the ellipse
// (nearest boundary point: a 4000-point search refined by golden section): exact on circles
// and on the axes. Elsewhere the tangent at the point's radial projection is not the nearest
// point's: for |d| ≤ ½ and a minor radius of 1–4 texels (the reconstruction term's floor is 1)
// the error grows with the axis ratio, worst near the ends of the major axis, where the
// boundary's radius of curvature (minor²/major) falls below the half-texel band.
TEST(EwaFilter, BoundaryDistanceAgainstGeometry) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> uni(0, 1);
  struct Case {
    double ratio, max_bound, p95_bound;
  };
  for (const Case& cs :
       {Case{1, 1e-9, 1e-9}, Case{2, 0.04, 0.02}, Case{4, 0.15, 0.06}, Case{16, 0.6, 0.2}}) {
    std::vector<double> errs;
    for (int k = 0; k < 400; ++k) {
      const double rb = 1 + 3 * uni(rng), ra = rb * cs.ratio, th = uni(rng) * kPi;
      const double c = std::cos(th), s = std::sin(th);
      const double qa = c * c / (ra * ra) + s * s / (rb * rb);
      const double qc = s * s / (ra * ra) + c * c / (rb * rb);
      const double qb = 2 * c * s * (1 / (ra * ra) - 1 / (rb * rb));
      // A point about t from the boundary along its normal (t ∈ [−½, ½]), in the ellipse frame.
      const double phi = uni(rng) * 2 * kPi, t = uni(rng) - 0.5;
      const double bx = ra * std::cos(phi), by = rb * std::sin(phi);
      const double nx = bx / (ra * ra), ny = by / (rb * rb), nn = std::hypot(nx, ny);
      const double px = bx + t * nx / nn, py = by + t * ny / nn;
      const double U = c * px - s * py, V = s * px + c * py;
      const double q = (qa * U + qb * V) * U + qc * V * V;
      const double d = EwaFilter::boundary_distance(q, 2 * qa * U + qb * V, qb * U + 2 * qc * V);
      auto dist = [&](double a) {
        return std::hypot(ra * std::cos(a) - px, rb * std::sin(a) - py);
      };
      int best = 0;
      for (int i = 1; i < 4000; ++i) {
        if (dist(2 * kPi * i / 4000) < dist(2 * kPi * best / 4000)) best = i;
      }
      double lo = 2 * kPi * (best - 1) / 4000, hi = 2 * kPi * (best + 1) / 4000;
      for (int it = 0; it < 100; ++it) {
        const double m1 = lo + (hi - lo) * 0.382, m2 = lo + (hi - lo) * 0.618;
        if (dist(m1) < dist(m2))
          hi = m2;
        else
          lo = m1;
      }
      const double exact = (q < 1 ? -1 : 1) * dist(0.5 * (lo + hi));
      if (std::fabs(exact) > 0.5) continue;  // the band the cut-off uses
      errs.push_back(std::fabs(d - exact));
    }
    std::sort(errs.begin(), errs.end());
    const double worst = errs.back(), p95 = errs[errs.size() * 95 / 100];
    std::printf(
        "EWA boundary distance, axis ratio %g: max error %.4f, 95th percentile %.4f texel (%zu "
        "points)\n",
        cs.ratio, worst, p95, errs.size());
    EXPECT_LE(worst, cs.max_bound) << cs.ratio;
    EXPECT_LE(p95, cs.p95_bound) << cs.ratio;
    EXPECT_GT(errs.size(), 300u);
  }
  // On the axes: exact for any distance.
  const double ra = 4, rb = 1.5;
  for (double t : {-0.5, -0.2, 0.3}) {
    const double x = ra + t, qx = (x / ra) * (x / ra);
    EXPECT_NEAR(EwaFilter::boundary_distance(qx, 2 * x / (ra * ra), 0.0), t, 1e-12);
    const double y = rb + t, qy = (y / rb) * (y / rb);
    EXPECT_NEAR(EwaFilter::boundary_distance(qy, 0.0, 2 * y / (rb * rb)), t, 1e-12);
  }
  EXPECT_EQ(EwaFilter::boundary_distance(0.0, 0.0, 0.0), -std::numeric_limits<double>::infinity());
}

// edge = "none" leaves EWA as it was: a configured but unused cut-off changes no bit, no op
// count, no timing and no arithmetic string.
TEST(EwaFilter, EdgeNoneIsUnchanged) {
  const Texture tex = make_texture(128, smooth);
  std::mt19937 rng(10);
  std::uniform_real_distribution<double> uni(0, 1);
  for (NumberFormat ar : {NumberFormat::Float, NumberFormat::Double, NumberFormat::S18_30}) {
    EwaFilter::Config a;
    a.arith = ar;
    EwaFilter::Config b = a;
    b.vd.evaluator = VdEvaluatorKind::P1;
    b.vd.format = NumberFormat::Fx8;
    const EwaFilter ea(a), eb(b);
    for (int k = 0; k < 200; ++k) {
      const double major = std::exp2(uni(rng) * 7 - 1), minor = major / (1 + 20 * uni(rng));
      const Fragment f = footprint(uni(rng), uni(rng), major, minor, uni(rng) * kPi, 128);
      OpCounts o1, o2;
      const FilterOutput x = ea.filter(tex, f, nullptr, o1), y = eb.filter(tex, f, nullptr, o2);
      for (int ch = 0; ch < 4; ++ch) ASSERT_EQ(x.colour[ch], y.colour[ch]);
      ASSERT_EQ(o1, o2);
      ASSERT_EQ(x.stats.visited, y.stats.visited);
    }
    const TechTable tech = TechTable::defaults();
    EXPECT_EQ(ea.timing(tech).latency, eb.timing(tech).latency);
    EXPECT_EQ(ea.timing(tech).area, eb.timing(tech).area);
    EXPECT_EQ(ea.arithmetic(), eb.arithmetic());
    EXPECT_EQ(ea.arithmetic().find("V(d)"), std::string::npos);
  }
}

// With uniform weights on a circular footprint every texel's weight is its cut-off fraction
// W(d)/W(−½) at d = ρ − R (ρ its centre's distance from the footprint centre, R the circle's
// radius with the reconstruction term), exact for circles: a texture that is 1 on one texel
// and 0 elsewhere returns that texel's fraction over the sum of all fractions (0 outside).
TEST(EwaFilter, EdgeCutoffWeightsOnACircle) {
  const int size = 64, cx = 30, cy = 33;
  const double ox = 0.3, oy = -0.2;  // footprint centre off the texel centre
  for (VdEvaluatorKind k : {VdEvaluatorKind::Exact, VdEvaluatorKind::P2}) {
    EwaFilter::Config c;
    c.arith = NumberFormat::Double;
    c.weight = EwaFilter::Weight::Uniform;
    c.minor_texels = 64;  // level 0
    c.edge = EwaFilter::Edge::Vd;
    c.vd.evaluator = k;
    c.vd.format = NumberFormat::Double;
    const EwaFilter ewa(c);
    const SubtexelCutoff cut = ewa.cutoff();
    const double rpx = 2.8, R = std::sqrt(rpx * rpx + c.reconstruction);
    auto weight = [&](int x, int y) {
      const double rho = std::hypot(x - (cx + ox), y - (cy + oy));
      if (!(rho < R)) return 0.0;
      return rho > R - 0.5 ? cut.fraction(rho - R) : 1.0;
    };
    double sum = 0;
    for (int y = 0; y < size; ++y) {
      for (int x = 0; x < size; ++x) sum += weight(x, y);
    }
    const Fragment f =
        footprint((cx + ox + 0.5) / size, (cy + oy + 0.5) / size, rpx, rpx, 0.0, size);
    int band = 0;
    for (int ty = cy - 4; ty <= cy + 4; ++ty) {
      for (int tx = cx - 4; tx <= cx + 4; ++tx) {
        std::vector<float> px(static_cast<size_t>(size) * size * 4, 0.0f);
        px[static_cast<size_t>(ty * size + tx) * 4] = 1.0f;
        const Texture tex = Texture::from_rgba("one", size, size, px, TexelFormat::Rgba32f, false);
        OpCounts ops;
        const FilterOutput o = ewa.filter(tex, f, nullptr, ops);
        const double w = weight(tx, ty);
        EXPECT_NEAR(o.colour.r, w / sum, 1e-6) << vd_evaluator_name(k) << " " << tx << "," << ty;
        if (w > 0 && w < 1) ++band;
      }
    }
    EXPECT_GE(band, 8);  // the test reaches the band
    const std::vector<float> flat(static_cast<size_t>(size) * size * 4, 0.5f);
    const Texture ft = Texture::from_rgba("flat", size, size, flat, TexelFormat::Rgba32f, false);
    OpCounts ops;
    EXPECT_NEAR(ewa.filter(ft, f, nullptr, ops).colour.r, 0.5, 1e-6);
    EXPECT_GT(ops.sqrt, 0u);
    EXPECT_GT(ewa.timing(TechTable::defaults()).latency,
              EwaFilter(EwaFilter::Config{}).timing(TechTable::defaults()).latency);
  }
}

TEST(EwaFilter, ConfigFromToml) {
  auto t = toml::parse(R"(weight = "pow8"
lut_size = 64
max_aniso = 8.0
scan = "row_span"
arith = "fixed"
address_u = "clamp"
)");
  const EwaFilter::Config c = EwaFilter::Config::from_toml(ConfigReader(t, "t.toml", "ewa"));
  EXPECT_EQ(c.weight, EwaFilter::Weight::Pow8);
  EXPECT_EQ(c.lut_size, 64);
  EXPECT_EQ(c.max_aniso, 8.0);
  EXPECT_EQ(c.scan, EwaFilter::Scan::RowSpan);
  EXPECT_EQ(c.arith, NumberFormat::S18_30);
  EXPECT_EQ(c.address_u, AddressMode::Clamp);
  auto vd = toml::parse("edge = \"vd\"\nvd = { evaluator = \"exact\", format = \"fx12\" }\n");
  const EwaFilter::Config cv = EwaFilter::Config::from_toml(ConfigReader(vd, "t.toml", "ewa"));
  EXPECT_EQ(cv.edge, EwaFilter::Edge::Vd);
  EXPECT_EQ(cv.vd.evaluator, VdEvaluatorKind::Exact);
  EXPECT_EQ(cv.vd.format, NumberFormat::Fx12);
  EXPECT_NE(EwaFilter(cv).arithmetic().find("V(d) exact fx12"), std::string::npos);
  EXPECT_EQ(c.edge, EwaFilter::Edge::None);
  auto bad = toml::parse("lut_sise = 3\n");
  EXPECT_THROW(EwaFilter::Config::from_toml(ConfigReader(bad, "t.toml", "ewa")), InputError);
  auto bad2 = toml::parse("max_aniso = 0.5\n");
  EXPECT_THROW(EwaFilter::Config::from_toml(ConfigReader(bad2, "t.toml", "ewa")), InputError);
}

TEST(EwaFilter, TimingFromTechTable) {
  const TechTable tech = TechTable::defaults();
  EwaFilter::Config c;
  const TimingSpec t4 = EwaFilter(c).timing(tech);
  c.lanes = 8;
  const TimingSpec t8 = EwaFilter(c).timing(tech);
  EXPECT_EQ(t4.lanes, 4u);
  EXPECT_EQ(t8.latency, t4.latency);
  EXPECT_GT(t8.area, t4.area);
  EXPECT_GT(t4.latency, 20u);
  FilterStats s;
  s.visited = 9;
  EXPECT_EQ(EwaFilter(c).issue_cycles(s), 2u);
  s.visited = 0;
  EXPECT_EQ(EwaFilter(c).issue_cycles(s), 1u);
  std::printf("EWA default: latency %u cycles, lanes %u, area %.1f\n", t4.latency, t4.lanes,
              t4.area);
}

}  // namespace
}  // namespace texsim
