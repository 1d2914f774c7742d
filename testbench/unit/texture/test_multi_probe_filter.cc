// Multi-ellipse probes (Mavridis & Papaioannou, seed 004 eq. 12–17): probe count, spacing and
// span from the formulas, probes on the major axis, the printed θ formula's quadrant error,
// temporal subsets, Gaussian weights, constant textures exact, bounded error on smooth ones.
// The double and fixed set-ups against a long-double reference of the probes, their hard
// cases, their colours on a photograph, and their op counts and timing.
#include <gtest/gtest.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/texture/footprint/multi_probe_filter.h"
#include "pipeline/reference/footprint_reference.h"
#include "pipeline/scene/texture_loader.h"
#include "testbench/lib/probe_reference.h"

namespace texsim {
namespace {

constexpr double kPi = 3.14159265358979323846;

Texture smooth_texture(int size) {
  std::vector<float> px(static_cast<size_t>(size) * static_cast<size_t>(size) * 4);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const double u = (x + 0.5) / size, v = (y + 0.5) / size;
      const size_t i =
          (static_cast<size_t>(y) * static_cast<size_t>(size) + static_cast<size_t>(x)) * 4;
      px[i] = static_cast<float>(0.5 + 0.3 * std::sin(2 * kPi * (2 * u + v)));
      px[i + 1] = static_cast<float>(0.5 + 0.3 * std::cos(2 * kPi * (u - 3 * v)));
      px[i + 2] = static_cast<float>(0.5 + 0.2 * std::sin(2 * kPi * 3 * u));
      px[i + 3] = 1;
    }
  }
  return Texture::from_rgba("s", size, size, px, TexelFormat::Rgba32f, true);
}

Fragment footprint(double u, double v, double major, double minor, double theta, int size) {
  return ellipse_fragment(u, v, major, minor, theta, size, size);
}

TEST(MultiProbe, ProbeCountSpacingAndAxis) {
  const Texture tex = smooth_texture(256);
  for (double alpha : {1.0, 2.0}) {
    MultiProbeFilter::Config c;
    c.alpha = alpha;
    c.max_probes = 31;
    const MultiProbeFilter mp(c);
    for (double theta : {0.0, 0.4, 1.3, 2.5}) {
      const double major = 16, minor = 2;
      const Fragment f = footprint(0.5, 0.5, major, minor, theta, 256);
      OpCounts ops;
      const ProbeSet p = mp.probes(tex, f, ops);
      // N = 2·R_major/(α·R_minor) − 1 = 15 (α = 1) or 7 (α = 2), odd.
      const int n = static_cast<int>(2 * major / (alpha * minor) - 1);
      ASSERT_EQ(p.n, n) << alpha;
      EXPECT_NEAR(p.lambda, std::log2(alpha * minor), 1e-5);
      // Positions: k·step along (cos θ, sin θ), step = L/(N−1), L = 2(R_major − α R_minor).
      const double step = 2 * (major - alpha * minor) / (n - 1);
      for (int k = 0; k < p.n; ++k) {
        const double du = (p.u[static_cast<size_t>(k)] - 0.5) * 256,
                     dv = (p.v[static_cast<size_t>(k)] - 0.5) * 256;
        const double along = du * std::cos(theta) + dv * std::sin(theta);
        const double across = -du * std::sin(theta) + dv * std::cos(theta);
        EXPECT_NEAR(across, 0.0, 1e-3) << theta;
        EXPECT_NEAR(std::fabs(along), std::fabs(k - (n - 1) / 2) * step, 1e-3);
        // Gaussian weight of the distance along the major axis.
        EXPECT_NEAR(p.w[static_cast<size_t>(k)], std::exp(-2.0 * (along / major) * (along / major)),
                    1e-5);
      }
    }
  }
  // Isotropic: one probe. Clamped: at most max_probes.
  OpCounts ops;
  EXPECT_EQ(MultiProbeFilter().probes(tex, footprint(0.3, 0.3, 4, 4, 0, 256), ops).n, 1);
  EXPECT_EQ(MultiProbeFilter().probes(tex, footprint(0.3, 0.3, 400, 1, 0, 256), ops).n, 15);
}

TEST(MultiProbe, PrintedThetaLosesTheQuadrant) {
  // Σuu > Σvv: the printed atan(B/(A − C))/2 is the major axis; Σvv > Σuu: it is the minor.
  for (double theta : {0.1, 0.3, 0.7}) {
    const double c = std::cos(theta), s = std::sin(theta);
    const double a = 100, b = 4;  // eigenvalues
    const double suu = a * c * c + b * s * s, svv = a * s * s + b * c * c, suv = (a - b) * c * s;
    const double exact = MultiProbeFilter::major_angle(suu, suv, svv, false);
    const double printed = MultiProbeFilter::major_angle(suu, suv, svv, true);
    EXPECT_NEAR(exact, theta, 1e-12);
    if (theta < kPi / 4)
      EXPECT_NEAR(printed, theta, 1e-12);
    else
      EXPECT_NEAR(std::fabs(printed - theta), kPi / 2, 1e-12);
  }
}

TEST(MultiProbe, TemporalSubsetsAlternate) {
  const Texture tex = smooth_texture(256);
  MultiProbeFilter::Config c;
  c.temporal = true;
  const MultiProbeFilter mp(c);
  Fragment f = footprint(0.5, 0.5, 14, 2, 0.0, 256);  // N = 13
  OpCounts ops;
  f.frame = 0;
  const ProbeSet even = mp.probes(tex, f, ops);
  f.frame = 1;
  const ProbeSet odd = mp.probes(tex, f, ops);
  EXPECT_EQ(even.n + odd.n, 13 + 1);  // the centre probe is in both frames
  EXPECT_EQ(even.n, 7);
  EXPECT_EQ(odd.n, 7);
}

// The temporal subsets are meant to be averaged over two frames (the eye, or a temporal
// filter): on a photograph, against the Gaussian-pixel truth, each frame alone is worse than all
// probes at once; the two frames' average is better than either frame but does not come back to
// all probes at once — the centre probe is in both subsets and each frame normalises its own
// weights, so the average over-weights the centre. Measured (printed): mean squared error per
// channel of all probes, frame 0, frame 1 and the average, over anisotropic footprints (4:1 and
// more; docs/derivations/anisotropic-filters.md §4, "Temporal subsets").
TEST(MultiProbe, TemporalAverageBeatsOneFrameButNotAllProbes) {
  const Texture tex = load_texture("/usr/share/glmark2/textures/crate-base.png", "");
  const int w0 = tex.width(0), h0 = tex.height(0);
  MultiProbeFilter::Config c;
  const MultiProbeFilter full(c);
  c.temporal = true;
  const MultiProbeFilter split(c);
  std::mt19937 rng(31);
  double e_full = 0, e0 = 0, e1 = 0, e_avg = 0;
  int n = 0;
  FootprintReferenceConfig truth_cfg;
  truth_cfg.samples_per_texel = 2;
  while (n < 120) {
    Fragment f = random_ellipse_footprint(rng, w0, h0);
    const double ax = std::hypot(f.dudx * w0, f.dvdx * h0),
                 ay = std::hypot(f.dudy * w0, f.dvdy * h0);
    const double det = std::fabs(f.dudx * w0 * f.dvdy * h0 - f.dudy * w0 * f.dvdx * h0);
    const double major = std::max(ax, ay);
    if (!(det > 0) || major * major / det < 4 || major < 8) continue;  // anisotropic, minified
    const glm::dvec4 truth = footprint_reference_affine(tex, f, truth_cfg).colour;
    OpCounts ops;
    f.frame = 0;
    const Rgba a = full.filter(tex, f, nullptr, ops).colour;
    const Rgba b = split.filter(tex, f, nullptr, ops).colour;
    f.frame = 1;
    const Rgba d = split.filter(tex, f, nullptr, ops).colour;
    for (int ch = 0; ch < 3; ++ch) {
      const double t = truth[ch];
      e_full += (a[ch] - t) * (a[ch] - t);
      e0 += (b[ch] - t) * (b[ch] - t);
      e1 += (d[ch] - t) * (d[ch] - t);
      const double avg = 0.5 * (static_cast<double>(b[ch]) + static_cast<double>(d[ch]));
      e_avg += (avg - t) * (avg - t);
    }
    ++n;
  }
  const double k = 1.0 / (3.0 * n);
  std::printf(
      "multi-probe temporal, MSE per channel: all probes %.3g, frame 0 %.3g, frame 1 %.3g, "
      "two-frame average %.3g\n",
      e_full * k, e0 * k, e1 * k, e_avg * k);
  EXPECT_GT(e0, e_full);
  EXPECT_GT(e1, e_full);
  EXPECT_LT(e_avg, 0.6 * std::min(e0, e1));
  EXPECT_GT(e_avg, 1.2 * e_full);
}

TEST(MultiProbe, ConstantExactSmoothBoundedCountsAgree) {
  std::vector<float> px(size_t{64} * 64 * 4, 0.375f);
  const Texture flat = Texture::from_rgba("c", 64, 64, px, TexelFormat::Rgba32f, true);
  const Texture tex = smooth_texture(256);
  const MultiProbeFilter mp;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(0, 1);
  FootprintReferenceConfig rc;
  double worst = 0;
  for (int k = 0; k < 200; ++k) {
    const double minor = 1 + 2 * uni(rng), major = minor * (1 + 15 * uni(rng)), th = uni(rng) * kPi;
    OpCounts ops;
    std::vector<TexelRef> fetched;
    const FilterOutput c =
        mp.filter(flat, footprint(uni(rng), uni(rng), major / 4, minor / 4, th, 64), &fetched, ops);
    ASSERT_NEAR(c.colour.r, 0.375, 1e-5);
    ASSERT_EQ(fetched.size(), c.stats.texels);
    ASSERT_EQ(c.stats.texels, 8u * c.stats.probes);
    ASSERT_EQ(ops.mem, c.stats.texels);
    const Fragment f = footprint(uni(rng), uni(rng), major, minor, th, 256);
    const FilterOutput o = mp.filter(tex, f, nullptr, ops);
    const glm::dvec4 ref = footprint_reference_affine(tex, f, rc).colour;
    for (int ch = 0; ch < 3; ++ch) worst = std::max(worst, std::fabs(o.colour[ch] - ref[ch]));
  }
  std::printf("multi-ellipse probes vs Gaussian reference, smooth texture: max error %.4f\n",
              worst);
  // Trilinear probes blur by their box-filtered levels; on waves of ≥ 85 texels that stays small.
  EXPECT_LT(worst, 0.03);
}

TEST(MultiProbe, ConfigAndTiming) {
  auto t = toml::parse("alpha = 2.0\nmax_probes = 9\ntemporal = true\n");
  const auto c = MultiProbeFilter::Config::from_toml(ConfigReader(t, "s.toml", "multi_probe"));
  EXPECT_EQ(c.alpha, 2.0);
  EXPECT_EQ(c.max_probes, 9);
  EXPECT_TRUE(c.temporal);
  auto even = toml::parse("max_probes = 8\n");
  EXPECT_THROW(MultiProbeFilter::Config::from_toml(ConfigReader(even, "s.toml", "multi_probe")),
               InputError);
  auto unknown = toml::parse("probes = 8\n");
  EXPECT_THROW(MultiProbeFilter::Config::from_toml(ConfigReader(unknown, "s.toml", "multi_probe")),
               InputError);
  EXPECT_EQ(c.arith, NumberFormat::Float);
  auto fx = toml::parse("arith = \"fixed\"\n");
  EXPECT_EQ(MultiProbeFilter::Config::from_toml(ConfigReader(fx, "s.toml", "multi_probe")).arith,
            NumberFormat::S16_24HalfUp);
  auto bad = toml::parse("arith = \"half\"\n");
  try {
    (void)MultiProbeFilter::Config::from_toml(ConfigReader(bad, "s.toml", "multi_probe"));
    ADD_FAILURE() << "arith = half accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("arith"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("s.toml"), std::string::npos) << e.what();
  }
  const TimingSpec ts = MultiProbeFilter().timing(TechTable::defaults());
  EXPECT_GT(ts.latency, 20u);
  EXPECT_GT(ts.area, 100.0);
  FilterStats s;
  s.probes = 7;
  EXPECT_EQ(MultiProbeFilter().issue_cycles(s), 7u);
}

// ---- double and fixed set-up ------------------------------------------------------------

// The probes from the documented formulas in long double: the clamped ellipse
// (reference_ellipse(); eigenvectors unchanged by the clamp, so θ is that of Σ), N, L, step,
// positions, weights and λ. q = 2·R_major/(α·R_minor): N = ⌈q − 1⌉ (odd, clamped); len = R_major.
RefProbes reference(const MultiProbeFilter::Config& c, const Fragment& f, int w0, int h0) {
  using L = long double;
  RefProbes r;
  const RefEllipse e = reference_ellipse(f, w0, h0, c.radius_px, c.max_aniso);
  r.u[0] = f.u;
  r.v[0] = f.v;
  r.w[0] = 1;
  if (!(e.minor2 > 0)) {
    r.special = true;
    return r;
  }
  r.len = std::sqrt(e.major2);
  const L ar = c.alpha * std::sqrt(e.minor2);
  r.lambda = std::log2(ar) + f.lod_bias;
  r.q = 2 * r.len / ar;
  int n = std::max(static_cast<int>(std::ceil(std::min(r.q, L(1e6)) - 1)), 1);
  if (n % 2 == 0) ++n;
  n = std::min(n, c.max_probes);
  r.n = n;
  if (n == 1) return r;
  const L step = 2 * std::max(r.len - ar, L(0)) / (n - 1);
  const L th = c.seed_theta
                   ? (e.d == 0 ? (e.suv == 0 ? L(0) : std::copysign(std::acos(L(-1)) / 4, e.suv))
                               : std::atan(e.suv / e.d) / 2)
                   : std::atan2(e.suv, e.d) / 2;
  const int half = (n - 1) / 2;
  for (int k = -half; k <= half; ++k) {
    const auto i = static_cast<size_t>(k) + static_cast<size_t>(half);
    r.u[i] = f.u + k * step * std::cos(th) / w0;
    r.v[i] = f.v + k * step * std::sin(th) / h0;
    const L dd = k * step / r.len;
    r.w[i] = std::exp(-c.weight_alpha * dd * dd);
  }
  return r;
}

Texture sized(int w, int h) {
  std::vector<float> px(static_cast<size_t>(w) * static_cast<size_t>(h) * 4, 0.5f);
  return Texture::from_rgba("t", w, h, px, TexelFormat::Rgba32f, true);
}

TEST(MultiProbe, DoubleAndFixedAgainstLongDoubleReference) {
  // Bounds (texels of level 0 for positions, see ProbeBound): double — rounding of doubles,
  // 10⁻⁹·(1 + R_major); fixed — the CORDIC residual angles (vectoring atan(2^-19) halved with θ,
  // rotation atan(2^-19): 2.9·10⁻⁶ rad) on offsets up to R_major, with the s16.24/s17.24
  // roundings 3·10⁻⁶·(1 + R_major), plus the centre's, offsets' and derivatives' roundings
  // (ProbeBound). Weights: the 2^-f table's index rounding ln2·2^-11 = 3.4·10⁻⁴ plus ½ LSB of
  // u1.15; λ: log2 table 1.44·2^-11/2 = 3.5·10⁻⁴ plus s8.16 rounding, and the float LOD output
  // 2^-24·|λ|.
  const std::vector<std::pair<int, int>> sizes = {{256, 256}, {384, 96}};
  for (NumberFormat a : {NumberFormat::Double, NumberFormat::S16_24HalfUp}) {
    for (bool seed : {false, true}) {
      Deviation d;
      for (auto [w0, h0] : sizes) {
        const Texture tex = sized(w0, h0);
        MultiProbeFilter::Config c;
        c.arith = a;
        c.max_probes = 31;
        c.seed_theta = seed;
        for (double alpha : {1.0, 2.0}) {
          c.alpha = alpha;
          const MultiProbeFilter mp(c);
          std::mt19937 rng(11);
          for (int k = 0; k < 1500; ++k) {
            const Fragment f = random_footprint(rng, w0, h0, k % 3 == 0);
            OpCounts ops;
            // N = ⌈q − 1⌉ reaches max_probes for every q above max_probes + 2.
            const ProbeBound b{w0, h0, a == NumberFormat::S16_24HalfUp ? 3e-6 : 1e-9,
                               a == NumberFormat::S16_24HalfUp, c.max_probes + 2};
            compare_probes(mp.probes(tex, f, ops), reference(c, f, w0, h0), b, d);
          }
        }
      }
      std::printf("multi-probe %s%s vs long double: %s\n", kProbeArith.key_of(a).data(),
                  seed ? " (printed θ)" : "", describe(d).c_str());
      EXPECT_EQ(d.n_mismatch, 0);
      EXPECT_GT(d.compared, 5500);
      EXPECT_LT(d.near_boundary, 60);
      EXPECT_LE(d.pos, 1.0);
      if (a == NumberFormat::Double) {
        EXPECT_LT(d.w, 1e-7);  // the float weight output: 2^-24
        EXPECT_LT(d.lambda, 2e-6);
      } else {
        EXPECT_LT(d.w, 3.4e-4 + 1.6e-5);
        EXPECT_LT(d.lambda, 3.5e-4 + 1e-5);
      }
    }
  }
}

TEST(MultiProbe, FixedPointUnitsWithinTheirBounds) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uni(0, 1);
  double e_sqrt = 0, e_log = 0, e_exp = 0, e_vec = 0, e_mag = 0, e_rot = 0;
  for (int k = 0; k < 20000; ++k) {
    // √: rounded to nearest from the exact raw value: ≤ ½ LSB of s17.16 (+ the input's rounding).
    const ProbeFx::Sigma x(std::exp2(uni(rng) * 58 - 27));
    const double r = probe_fx::sqrt_len(x).to_double();
    e_sqrt = std::max(e_sqrt, std::fabs(r - std::sqrt(x.to_double())) / ProbeFx::Len::lsb());
    // log2 and 2^-y from the 10-bit tables.
    const double y = std::exp2(uni(rng) * 40 - 20);
    e_log = std::max(e_log, std::fabs(probe_fx::log2_of(ProbeFx::Sigma(y).raw(), 28).to_double() -
                                      std::log2(ProbeFx::Sigma(y).to_double())));
    const ProbeFx::Arg ya(uni(rng) * 20);
    e_exp =
        std::max(e_exp, std::fabs(probe_fx::exp2_neg(ya).to_double() - std::exp2(-ya.to_double())));
    // CORDIC vectoring and rotation.
    const double px = (uni(rng) - 0.5) * std::exp2(uni(rng) * 40 - 10),
                 py = (uni(rng) - 0.5) * std::exp2(uni(rng) * 40 - 10);
    ProbeFx::Sigma mag;
    const ProbeFx::Sigma sx(px), sy(py);
    const double ang = probe_fx::vector_angle(sx, sy, false, mag).to_double();
    const double exact = std::atan2(sy.to_double(), sx.to_double());
    double da = std::fabs(ang - exact);
    da = std::min(da, 2 * kPi - da);
    const double hyp = std::hypot(sx.to_double(), sy.to_double());
    if (hyp > 1e-3) e_vec = std::max(e_vec, da);
    // Magnitude: the inputs' own rounding aside, the CORDIC is normalised (2^-59 relative), so
    // what remains is 1/K's and the result's rounding: ≤ 10⁻⁹ relative + 1 LSB.
    e_mag = std::max(
        e_mag,
        (std::fabs(mag.to_double() / probe_fx::cordic_gain() - hyp) - ProbeFx::Sigma::lsb()) / hyp);
    const double th = (uni(rng) - 0.5) * kPi;
    const double len = std::exp2(uni(rng) * 20 - 4);
    ProbeFx::Vec rx, ry;
    probe_fx::rotate(ProbeFx::Vec(len / probe_fx::cordic_gain()), ProbeFx::Angle(th), rx, ry);
    e_rot = std::max(
        e_rot,
        std::hypot(rx.to_double() - len * std::cos(th), ry.to_double() - len * std::sin(th)) / len);
  }
  std::printf(
      "fixed units: sqrt %.3g LSB, log2 %.3g, exp2 %.3g, vectoring angle %.3g rad, magnitude %.3g "
      "rel, "
      "rotation %.3g rel\n",
      e_sqrt, e_log, e_exp, e_vec, e_mag, e_rot);
  EXPECT_LE(e_sqrt, 0.5 + 1e-9 + 0.5 * ProbeFx::Sigma::lsb() / ProbeFx::Len::lsb());
  EXPECT_LE(e_log, std::log2(std::exp(1.0)) * std::exp2(-11) +
                       std::exp2(-17));  // index ±2^-11, slope ≤ 1/ln2
  EXPECT_LE(e_exp,
            std::log(2.0) * std::exp2(-11) + std::exp2(-16) + 1e-9);  // slope ≤ ln2, ½ LSB u1.15
  EXPECT_LE(e_vec, std::atan(std::exp2(-19)) + 1e-6);  // residual after 20 steps (+ truncation)
  EXPECT_LE(e_mag, 1e-9);
  EXPECT_LE(e_rot, std::atan(std::exp2(-19)) + 1e-6);
  // Exact points: log2 of powers of two, 2^0 = 1, √ of squares.
  EXPECT_EQ(probe_fx::log2_of(int64_t{1} << 40, 28).to_double(), 12.0);
  EXPECT_EQ(probe_fx::exp2_neg(ProbeFx::Arg(0.0)).to_double(), 1.0);
  EXPECT_EQ(probe_fx::exp2_neg(ProbeFx::Arg(3.0)).to_double(), 0.125);
  EXPECT_EQ(probe_fx::sqrt_len(ProbeFx::Sigma(2.25)).to_double(), 1.5);
}

TEST(MultiProbe, HardCasesDefinedInEveryArithmetic) {
  const Texture tex = smooth_texture(256);
  // The texture mean: the 1×1 level.
  const Rgba mean = tex.texel(tex.levels() - 1, 0, 0);
  for (NumberFormat a : {NumberFormat::Float, NumberFormat::Double, NumberFormat::S16_24HalfUp}) {
    SCOPED_TRACE(kProbeArith.key_of(a).data());
    MultiProbeFilter::Config c;
    c.arith = a;
    const MultiProbeFilter mp(c);
    auto run = [&](const Fragment& f, ProbeSet& p, FilterOutput& o) {
      OpCounts ops;
      p = mp.probes(tex, f, ops);
      std::vector<TexelRef> fetched;
      o = mp.filter(tex, f, &fetched, ops);
      for (int ch = 0; ch < 4; ++ch) ASSERT_TRUE(std::isfinite(o.colour[ch]));
      ASSERT_EQ(fetched.size(), o.stats.texels);
    };
    ProbeSet p;
    FilterOutput o;
    // Anisotropy 10⁴:1: clamped to 64:1, so N = max_probes and λ = log2(R_major/64).
    Fragment f = footprint(0.3, 0.6, 4000, 0.4, 0.7, 256);
    run(f, p, o);
    EXPECT_EQ(p.n, 15);
    EXPECT_NEAR(p.lambda, std::log2(4000.0 / 64), 1e-3);
    for (int k = 0; k < p.n; ++k) {  // on the major axis
      const double du = (p.u[static_cast<size_t>(k)] - 0.3) * 256,
                   dv = (p.v[static_cast<size_t>(k)] - 0.6) * 256;
      EXPECT_NEAR(-du * std::sin(0.7) + dv * std::cos(0.7), 0.0, 2e-3);
    }
    // det = 0: parallel derivative vectors. The clamp makes R_minor = R_major/64.
    f = Fragment{};
    f.u = f.v = 0.5;
    f.dudx = 8.0 / 256;
    f.dvdx = 4.0 / 256;
    f.dudy = 16.0 / 256;
    f.dvdy = 8.0 / 256;
    run(f, p, o);
    EXPECT_EQ(p.n, 15);
    EXPECT_NEAR(p.lambda, std::log2(std::sqrt(80.0 * 5) / 64), 1e-3);  // λ₊ = |(8,4)|² + |(16,8)|²
    // Zero derivatives: a point, one probe at level 0.
    f.dudx = f.dvdx = f.dudy = f.dvdy = 0;
    run(f, p, o);
    EXPECT_EQ(p.n, 1);
    EXPECT_LT(p.lambda, -1e20f);
    // NaN and ±Inf derivatives: flagged, the same point footprint.
    for (double bad :
         {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
          -std::numeric_limits<double>::infinity()}) {
      f.dudx = bad;
      run(f, p, o);
      EXPECT_TRUE(o.stats.bad_input);
      EXPECT_EQ(p.n, 1);
      EXPECT_LT(p.lambda, -1e20f);
    }
    // Derivatives of 10⁶ texels (fixed: saturate s16.16 → most minified level; float/double:
    // λ ≈ 14 > the top level): every read is the 1×1 level, the colour is the texture mean.
    f.dudx = 1e6 / 256;
    f.dvdx = 3e5 / 256;
    f.dudy = -2e5 / 256;
    f.dvdy = 9e5 / 256;
    run(f, p, o);
    for (int ch = 0; ch < 4; ++ch) EXPECT_NEAR(o.colour[ch], mean[ch], 1e-5);
    // NaN coordinates: replaced by 0.
    f = footprint(std::numeric_limits<double>::quiet_NaN(), 0.5, 12, 2, 0.3, 256);
    run(f, p, o);
  }
}

TEST(MultiProbe, FixedColoursTrackDoubleOnAPhotograph) {
  const Texture tex = load_texture("/usr/share/glmark2/textures/crate-base.png", "");
  const int w0 = tex.width(0), h0 = tex.height(0);
  MultiProbeFilter::Config cd, cx, cf;
  cd.arith = NumberFormat::Double;
  cx.arith = NumberFormat::S16_24HalfUp;
  const MultiProbeFilter md(cd), mx(cx), mf(cf);
  std::mt19937 rng(8);
  ColourDeviation dev, dev_float;
  for (int k = 0; k < 600; ++k) {
    const Fragment f = random_ellipse_footprint(rng, w0, h0);
    OpCounts ops;
    const FilterOutput a = md.filter(tex, f, nullptr, ops), b = mx.filter(tex, f, nullptr, ops),
                       c = mf.filter(tex, f, nullptr, ops);
    ASSERT_EQ(a.stats.probes, b.stats.probes);
    dev.add(a.colour, b.colour);
    dev_float.add(a.colour, c.colour);
  }
  std::printf(
      "multi-probe on crate-base.png: fixed vs double max %.3g mean %.3g; float vs double max "
      "%.3g\n",
      dev.worst, dev.mean(), dev_float.worst);
  // A position or λ change far below the address generator's 2^-8 steps can still move one
  // quantisation step (a u0.8 bilinear weight or the trilinear level weight by 1/256): the
  // colour then moves by at most 1/256 of a neighbouring texel difference.
  EXPECT_LT(dev.worst, 1.0 / 256);
  EXPECT_LT(dev.mean(), 1e-4);
}

TEST(MultiProbe, OpsAndTimingFollowTheArithmetic) {
  const Texture tex = smooth_texture(256);
  TexelAddressGen::Config ac;
  ac.filter = FilterMode::Trilinear;
  const TexelAddressGen addr(ac);
  MultiProbeFilter::Config cf, cx;
  cx.arith = NumberFormat::S16_24HalfUp;
  const MultiProbeFilter mf(cf), mx(cx);
  // The counted operations of a fragment are the declared set-up, per-probe and normalisation.
  for (const MultiProbeFilter* m : {&mf, &mx}) {
    const Fragment f = footprint(0.4, 0.4, 20, 2, 0.5, 256);
    OpCounts ops;
    const FilterOutput o = m->filter(tex, f, nullptr, ops);
    ASSERT_GT(o.stats.probes, 1u);
    const OpCounts expect = m->setup_ops() +
                            (m->ops_per_item() + addr.ops_setup(false)) * o.stats.probes +
                            probe_normalise_ops();
    EXPECT_EQ(ops, expect);
  }
  // Fixed: θ, cos and sin by two CORDIC passes instead of three tables; the probe-count
  // quotient by a short divider instead of a reciprocal; one divider for step/R_major.
  const OpCounts sf = mf.setup_ops(), sx = mx.setup_ops();
  EXPECT_EQ(sf.lut - sx.lut, 2u);  // atan2, cos, sin → log2 and 1/(N − 1) tables only
  EXPECT_EQ(sx.rcp, 0u);
  EXPECT_EQ(sx.div, 1u);
  EXPECT_EQ(sx.sqrt, 2u);
  EXPECT_GE(sx.add, sf.add + uint64_t{2} * 3 * ProbeFx::kCordicSteps - 10);
  EXPECT_EQ(mx.probe_setup_ops().add, mf.probe_setup_ops().add + 1);
  // Latency: two CORDIC passes of add + compare per step in sequence.
  const TechTable tech = TechTable::defaults();
  const TimingSpec tf = mf.timing(tech), tx = mx.timing(tech);
  EXPECT_GT(tx.latency, tf.latency + 2 * ProbeFx::kCordicSteps);
  EXPECT_EQ(tx.ii, 1u);
  EXPECT_GT(tx.area, tf.area);
  EXPECT_NE(mx.arithmetic().find(ProbeFx::Deriv::name()), std::string::npos);
  EXPECT_NE(mf.arithmetic().find("float32"), std::string::npos);
}

}  // namespace
}  // namespace texsim
