// Stability suite of the anisotropic filter family: zero-area footprints, magnification,
// anisotropy 10⁴:1, derivatives of 10⁶ texels, NaN/Inf inputs, all weights zero, footprints
// across the borders in each addressing mode, 1×1 textures. Every case asserts a numeric bound
// or the documented fallback (docs/derivations/anisotropic-filters.md §7).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "blocks/texture/footprint/ewa_filter.h"
#include "blocks/texture/footprint/feline_filter.h"
#include "blocks/texture/footprint/multi_probe_filter.h"
#include "blocks/texture/footprint/spaf_filter.h"
#include "blocks/texture/footprint/weight_map.h"
#include "pipeline/reference/footprint_reference.h"
#include "testbench/lib/filter_fixtures.h"

namespace texsim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Subject {
  std::string name;
  std::function<FilterOutput(const Texture&, const Fragment&, std::vector<TexelRef>*, OpCounts&)>
      run;
  uint32_t max_texels;  // the documented bound on texels per fragment
  std::function<uint32_t(const FilterStats&)> cycles;
  uint32_t max_cycles;
};

std::vector<Subject> subjects(AddressMode am = AddressMode::Wrap) {
  std::vector<Subject> s;
  auto ewa = [&](const std::string& name, EwaFilter::Config c) {
    c.address_u = c.address_v = am;
    auto f = std::make_shared<const EwaFilter>(c);
    // Box ≤ budget per level, two levels with linear mip, + 4 for the fallback.
    const auto bound =
        static_cast<uint32_t>(c.texel_budget * (c.mip == EwaFilter::Mip::Linear ? 2 : 1) + 4);
    s.push_back({name,
                 [f](const Texture& t, const Fragment& fr, std::vector<TexelRef>* v, OpCounts& o) {
                   return f->filter(t, fr, v, o);
                 },
                 bound, [f](const FilterStats& st) { return f->issue_cycles(st); },
                 static_cast<uint32_t>((bound + 64 * 4) / static_cast<uint32_t>(c.lanes) + 1)});
  };
  EwaFilter::Config c;
  ewa("ewa lut float", c);
  c.arith = NumberFormat::S18_30;
  ewa("ewa lut fixed", c);
  c = EwaFilter::Config{};
  c.arith = NumberFormat::Double;
  c.weight = EwaFilter::Weight::Pow8;
  c.mip = EwaFilter::Mip::Linear;
  c.scan = EwaFilter::Scan::RowSpan;
  ewa("ewa pow8 linear row-span", c);
  c = EwaFilter::Config{};
  c.weight = EwaFilter::Weight::Map;
  ewa("ewa map", c);
  c = EwaFilter::Config{};
  c.reconstruction = 0;
  ewa("ewa no reconstruction", c);
  c = EwaFilter::Config{};
  c.edge = EwaFilter::Edge::Vd;
  c.vd.format = NumberFormat::Fx16;
  ewa("ewa V(d) edge P2 fx16", c);
  MultiProbeFilter::Config mc;
  mc.address_u = mc.address_v = am;
  auto mp = std::make_shared<const MultiProbeFilter>(mc);
  s.push_back({"multi-probe",
               [mp](const Texture& t, const Fragment& fr, std::vector<TexelRef>* v, OpCounts& o) {
                 return mp->filter(t, fr, v, o);
               },
               15 * 8, [mp](const FilterStats& st) { return mp->issue_cycles(st); }, 15});
  FelineFilter::Config fc;
  fc.address_u = fc.address_v = am;
  auto fl = std::make_shared<const FelineFilter>(fc);
  s.push_back({"feline",
               [fl](const Texture& t, const Fragment& fr, std::vector<TexelRef>* v, OpCounts& o) {
                 return fl->filter(t, fr, v, o);
               },
               16 * 8, [fl](const FilterStats& st) { return fl->issue_cycles(st); }, 16});
  fc.axis = FelineFilter::Axis::Parallelogram;
  auto tx = std::make_shared<const FelineFilter>(fc);
  s.push_back({"texram",
               [tx](const Texture& t, const Fragment& fr, std::vector<TexelRef>* v, OpCounts& o) {
                 return tx->filter(t, fr, v, o);
               },
               16 * 8, [tx](const FilterStats& st) { return tx->issue_cycles(st); }, 16});
  SpafFilter::Config sc;
  sc.address_u = sc.address_v = am;
  auto sp = std::make_shared<const SpafFilter>(sc);
  // The scan stops at 4× the budget (beyond it the fallback's 4 texels are read).
  s.push_back({"spaf",
               [sp](const Texture& t, const Fragment& fr, std::vector<TexelRef>* v, OpCounts& o) {
                 return sp->filter(t, fr, v, o);
               },
               4 * 64 + 4, [sp](const FilterStats& st) { return sp->issue_cycles(st); },
               4 * 64 / 4 + 1});
  // V(d) coverage (one cut-off unit per lane: a texel takes up to 4 slots) and fixed point.
  for (const auto& [name, cov, ar] :
       {std::tuple{"spaf V(d) P1 fx8", SpafFilter::Coverage::Vd, NumberFormat::Float},
        std::tuple{"spaf fixed", SpafFilter::Coverage::Mask, NumberFormat::S20_28HalfUp}}) {
    SpafFilter::Config vc = sc;
    vc.coverage = cov;
    vc.vd.evaluator = VdEvaluatorKind::P1;
    vc.vd.format = NumberFormat::Fx8;
    vc.arith = ar;
    auto sv = std::make_shared<const SpafFilter>(vc);
    s.push_back({name,
                 [sv](const Texture& t, const Fragment& fr, std::vector<TexelRef>* v, OpCounts& o) {
                   return sv->filter(t, fr, v, o);
                 },
                 4 * 64 + 4, [sv](const FilterStats& st) { return sv->issue_cycles(st); },
                 4 * 4 * 64 / 4 + 1});
  }
  return s;
}

// Common checks: finite colour inside the texture's value range (all weights are ≥ 0, so the
// result is a convex combination), texel and cycle bounds, fetched coordinates in range.
void check_common(const Subject& s, const Texture& tex, const FilterOutput& o,
                  const std::vector<TexelRef>& fetched, const OpCounts& ops,
                  const std::string& what) {
  for (int c = 0; c < 4; ++c) {
    ASSERT_TRUE(std::isfinite(o.colour[c])) << s.name << " " << what;
    ASSERT_GE(o.colour[c], 0.1f / 1.01f - 1e-3f) << s.name << " " << what;
    ASSERT_LE(o.colour[c], 1.0f + 1e-5f) << s.name << " " << what;
  }
  ASSERT_EQ(fetched.size(), o.stats.texels) << s.name << " " << what;
  ASSERT_EQ(ops.mem, o.stats.texels + o.stats.map_reads) << s.name << " " << what;
  ASSERT_LE(o.stats.texels, s.max_texels) << s.name << " " << what;
  ASSERT_LE(s.cycles(o.stats), s.max_cycles) << s.name << " " << what;
  for (const TexelRef& t : fetched) {
    ASSERT_GE(t.level, 0);
    ASSERT_LT(t.level, tex.levels());
    ASSERT_GE(t.x, 0) << s.name << " " << what;
    ASSERT_LT(t.x, tex.width(t.level)) << s.name << " " << what;
    ASSERT_GE(t.y, 0) << s.name << " " << what;
    ASSERT_LT(t.y, tex.height(t.level)) << s.name << " " << what;
  }
}

FilterOutput run(const Subject& s, const Texture& tex, const Fragment& f, const std::string& what) {
  std::vector<TexelRef> fetched;
  OpCounts ops;
  const FilterOutput o = s.run(tex, f, &fetched, ops);
  check_common(s, tex, o, fetched, ops, what);
  return o;
}

TEST(StabilityFilters, ZeroAreaFootprints) {
  const Texture tex = noise_texture(128, 128, 1);
  for (const Subject& s : subjects()) {
    // Parallel derivative vectors, one zero vector, both zero.
    run(s, tex, texel_fragment(0.3, 0.6, 8, 4, 16, 8, 128), "parallel");
    run(s, tex, texel_fragment(0.3, 0.6, 8, 4, 0, 0, 128), "one zero vector");
    run(s, tex, texel_fragment(0.3, 0.6, 0, 0, 0, 0, 128), "point");
  }
  // EWA without reconstruction: a point footprint between texel centres has no texel inside →
  // the documented fallback, the bilinear sample at the centre of level 0.
  EwaFilter::Config c;
  c.reconstruction = 0;
  const EwaFilter e(c);
  OpCounts ops, ops2;
  const Fragment f = texel_fragment(0.3 + 0.25 / 128, 0.6 + 0.25 / 128, 0, 0, 0, 0, 128);
  const FilterOutput o = e.filter(tex, f, nullptr, ops);
  EXPECT_TRUE(o.stats.fallback);
  const Rgba b =
      bilinear_fallback(tex, 0, f.u, f.v, AddressMode::Wrap, AddressMode::Wrap, nullptr, ops2);
  for (int ch = 0; ch < 4; ++ch) EXPECT_EQ(o.colour[ch], b[ch]);
}

TEST(StabilityFilters, MagnificationMatchesReference) {
  const Texture tex = noise_texture(64, 64, 2);
  FootprintReferenceConfig rc;
  for (const Subject& s : subjects()) {
    for (double size : {0.01, 0.1, 0.5}) {
      const Fragment f = texel_fragment(0.4, 0.7, size, 0, 0, size, 64);
      const FilterOutput o = run(s, tex, f, "magnification");
      EXPECT_EQ(o.stats.level, 0) << s.name;
      // Much smaller than a texel. Methods that reconstruct bilinearly (EWA with its
      // reconstruction term, the probe filters) stay close to the bilinear reference sample
      // (measured: at most 0.031 on values spread over 0.8). SPAF and EWA without
      // reconstruction are box filters over the texels the footprint touches: their colour is
      // a convex blend of the 2×2 texels around the sample point (25..26 × 44..45).
      const glm::dvec4 ref = footprint_reference_affine(tex, f, rc).colour;
      const bool box = s.name.find("spaf") != std::string::npos ||
                       s.name.find("no reconstruction") != std::string::npos;
      for (int ch = 0; ch < 3; ++ch) {
        if (!box) {
          EXPECT_LT(std::fabs(o.colour[ch] - ref[ch]), 0.04) << s.name << " " << size;
          continue;
        }
        double lo = 1, hi = 0;
        for (int y : {44, 45}) {
          for (int x : {25, 26}) {
            lo = std::min(lo, static_cast<double>(tex.texel(0, x, y)[ch]));
            hi = std::max(hi, static_cast<double>(tex.texel(0, x, y)[ch]));
          }
        }
        EXPECT_GE(o.colour[ch], lo - 1e-6) << s.name << " " << size;
        EXPECT_LE(o.colour[ch], hi + 1e-6) << s.name << " " << size;
      }
    }
  }
}

TEST(StabilityFilters, ExtremeAnisotropyIsClampedAndBounded) {
  const Texture tex = noise_texture(256, 256, 3);
  for (const Subject& s : subjects()) {
    for (double th : {0.0, 0.3, 0.785, 1.2}) {
      const double major = 1e4 * 0.5, minor = 0.5;  // 10⁴:1
      const Fragment f = texel_fragment(0.5, 0.5, major * std::cos(th), major * std::sin(th),
                                        -minor * std::sin(th), minor * std::cos(th), 256);
      run(s, tex, f, "aniso 1e4");
    }
  }
}

TEST(StabilityFilters, HugeDerivativesGiveTheTextureMean) {
  const Texture tex = noise_texture(64, 64, 4);
  const Rgba mean = tex.texel(tex.levels() - 1, 0, 0);  // the 1×1 level
  for (const Subject& s : subjects()) {
    for (double d : {1e6, 1e12, 1e30}) {
      const Fragment f = texel_fragment(0.2, 0.9, d, 0.3 * d, -0.2 * d, d, 64);
      const FilterOutput o = run(s, tex, f, "huge derivatives");
      EXPECT_EQ(o.stats.level, tex.levels() - 1) << s.name << " " << d;
      for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(o.colour[ch], mean[ch], 1e-5) << s.name << " " << d;
    }
  }
}

TEST(StabilityFilters, NonFiniteInputsTakeThePointFootprint) {
  const Texture tex = noise_texture(64, 64, 5);
  for (const Subject& s : subjects()) {
    OpCounts ops;
    const FilterOutput ref = s.run(tex, texel_fragment(0.25, 0.5, 0, 0, 0, 0, 64), nullptr, ops);
    for (double bad : {kNaN, kInf, -kInf}) {
      const FilterOutput a =
          run(s, tex, texel_fragment(0.25, 0.5, bad, 1, 1, 1, 64), "non-finite derivative");
      EXPECT_TRUE(a.stats.bad_input) << s.name;
      for (int ch = 0; ch < 4; ++ch) EXPECT_EQ(a.colour[ch], ref.colour[ch]) << s.name;
      Fragment f = texel_fragment(bad, 0.5, 1, 0, 0, 1, 64);
      const FilterOutput b = run(s, tex, f, "non-finite u");
      (void)b;
      f = texel_fragment(0.25, bad, 1, 0, 0, 1, 64);
      run(s, tex, f, "non-finite v");
    }
  }
}

TEST(StabilityFilters, AllWeightsZeroFallsBack) {
  const Texture tex = noise_texture(64, 64, 6);
  // Weights that underflow the table: α = 64 with 8-bit entries leaves only Q < 0.087 non-zero;
  // a tiny footprint without reconstruction centred between texels has no texel there.
  EwaFilter::Config c;
  c.alpha = 64;
  c.lut_bits = 8;
  c.reconstruction = 0;
  const EwaFilter e(c);
  OpCounts ops, ops2;
  const Fragment f = texel_fragment(0.5, 0.5, 0.8, 0, 0, 0.8, 64);  // centre on a texel corner
  const FilterOutput o = e.filter(tex, f, nullptr, ops);
  EXPECT_TRUE(o.stats.fallback);
  const Rgba b =
      bilinear_fallback(tex, 0, 0.5, 0.5, AddressMode::Wrap, AddressMode::Wrap, nullptr, ops2);
  for (int ch = 0; ch < 4; ++ch) EXPECT_EQ(o.colour[ch], b[ch]);
  // Probes: Gaussian weights of 0 (w_α huge) leave the probes' plain mean.
  MultiProbeFilter::Config mc;
  mc.weight_alpha = 64;
  const MultiProbeFilter mp(mc);
  const FilterOutput p = mp.filter(tex, texel_fragment(0.5, 0.5, 2000, 0, 0, 1, 64), nullptr, ops);
  EXPECT_TRUE(std::isfinite(p.colour.r));
}

// A footprint whose only covered texel lies far out on the Gaussian: its weight, and so the
// weight sum, is subnormal, and 1/sum overflows float32. Found by the anisotropic envelope
// check (testbench/conformance); the sum now counts as zero and the bilinear fallback answers.
TEST(StabilityFilters, SubnormalWeightSumsFallBack) {
  const Texture tex = noise_texture(256, 256, 3);
  SpafFilter::Config c;
  c.half_px = 0.5;
  const SpafFilter spaf(c);
  Fragment f;
  f.u = 0.024769837334611987;
  f.v = 0.54184392590860142;
  f.dudx = 0.00043065549993926891;
  f.dvdx = 0.0014077893602729495;
  f.dudy = -0.001494111480067677;
  f.dvdy = -0.0035912819298586007;
  OpCounts ops;
  const FilterOutput o = spaf.filter(tex, f, nullptr, ops);
  for (int ch = 0; ch < 4; ++ch) {
    EXPECT_TRUE(std::isfinite(o.colour[ch]));
    EXPECT_GE(o.colour[ch], 0.0f);
    EXPECT_LE(o.colour[ch], 1.0f);
  }
  EXPECT_TRUE(o.stats.fallback);
}

TEST(StabilityFilters, BordersInEachAddressMode) {
  // A horizontal ramp (not periodic): wrap, clamp and mirror give different answers at u = 0.
  const int size = 64;
  std::vector<float> px(static_cast<size_t>(size) * size * 4);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const size_t i = (static_cast<size_t>(y) * size + static_cast<size_t>(x)) * 4;
      px[i] = 0.1f + 0.8f * static_cast<float>(x) / (size - 1);
      px[i + 1] = 0.1f + 0.8f * static_cast<float>(y) / (size - 1);
      px[i + 2] = 0.5f;
      px[i + 3] = 1.0f;
    }
  }
  const Texture tex = Texture::from_rgba("ramp", size, size, px, TexelFormat::Rgba32f, true);
  {
    // The modes really differ here: wrap pulls in the far end of the ramp.
    EwaFilter::Config cw, cc;
    cc.address_u = cc.address_v = AddressMode::Clamp;
    OpCounts ops;
    const Fragment f = texel_fragment(0.0, 0.5, 3, 0.5, -0.5, 2, size);
    const float rw = EwaFilter(cw).filter(tex, f, nullptr, ops).colour.r;
    const float rcl = EwaFilter(cc).filter(tex, f, nullptr, ops).colour.r;
    EXPECT_GT(rw - rcl, 0.2f);
    EXPECT_EQ(subjects().size(), 12u);
  }
  for (AddressMode am :
       {AddressMode::Wrap, AddressMode::Clamp, AddressMode::Mirror, AddressMode::MirrorClamp}) {
    FootprintReferenceConfig rc;
    rc.address_u = rc.address_v = am;
    for (const Subject& s : subjects(am)) {
      for (double u : {0.0, -0.3 / size, 1.0 + 0.2 / size}) {
        const Fragment f = texel_fragment(u, 0.0, 3, 0.5, -0.5, 2, size);
        const FilterOutput o = run(s, tex, f, std::string("border ") + to_string(am));
        const glm::dvec4 ref = footprint_reference_affine(tex, f, rc).colour;
        // Wrap mixes both ends of the ramp (0.1 and 0.9): each method must follow the mode.
        for (int ch = 0; ch < 2; ++ch) {
          EXPECT_LT(std::fabs(o.colour[ch] - ref[ch]), 0.12)
              << s.name << " " << to_string(am) << " u=" << u;
        }
      }
    }
  }
}

TEST(StabilityFilters, OneTexelTextures) {
  std::vector<float> px = {0.2f, 0.4f, 0.6f, 1.0f};
  const Texture tex = Texture::from_rgba("one", 1, 1, px, TexelFormat::Rgba32f, true);
  for (AddressMode am :
       {AddressMode::Wrap, AddressMode::Clamp, AddressMode::Mirror, AddressMode::MirrorClamp}) {
    for (const Subject& s : subjects(am)) {
      for (double d : {0.0, 0.01, 1.0, 50.0, 1e6}) {
        std::vector<TexelRef> fetched;
        OpCounts ops;
        const FilterOutput o =
            s.run(tex, texel_fragment(0.37, -2.5, d, 0.5 * d, 0.1 * d, d, 1), &fetched, ops);
        EXPECT_NEAR(o.colour.r, 0.2, 1e-6) << s.name;
        EXPECT_NEAR(o.colour.g, 0.4, 1e-6) << s.name;
        EXPECT_NEAR(o.colour.b, 0.6, 1e-6) << s.name;
        for (const TexelRef& t : fetched) {
          EXPECT_EQ(t.level, 0);
          EXPECT_EQ(t.x, 0);
          EXPECT_EQ(t.y, 0);
        }
      }
    }
  }
}

}  // namespace
}  // namespace texsim
