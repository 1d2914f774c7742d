// Stability of border and mirror-clamp addressing and texel offsets in the LOD → address → blend
// path and the truth: coordinates NaN, ±Inf and ±1e30 in border mode give the border colour or a
// defined texel (never a read outside a level), and offsets at the ends of −8..7 on a 1×1 texture
// stay on its one texel (or the border).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "blocks/texture/sampler/lod_unit.h"
#include "blocks/texture/sampler/texel_address_gen.h"
#include "blocks/texture/sampler/texel_blend.h"
#include "pipeline/reference/ground_truth.h"

namespace texsim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

constexpr FilterMode kFilters[] = {FilterMode::Nearest, FilterMode::Bilinear,
                                   FilterMode::Trilinear};
constexpr AddressMode kModes[] = {AddressMode::Wrap, AddressMode::Clamp, AddressMode::Mirror,
                                  AddressMode::Border, AddressMode::MirrorClamp};

Texture ramp(int w, int h) {
  std::vector<float> px(static_cast<size_t>(w) * h * 4);
  for (size_t i = 0; i < px.size(); ++i) px[i] = static_cast<float>(i % 97) / 97.0f;
  return Texture::from_rgba("ramp", w, h, px, TexelFormat::Rgba8, true);
}

// Every tap inside its level or a border tap (counted as one), and a finite colour.
void expect_defined(const Texture& tex, const FilterTaps& t, const Rgba& c, const char* what) {
  int border = 0;
  for (int k = 0; k < t.count; ++k) {
    const TexelTap& p = t.tap[static_cast<size_t>(k)];
    ASSERT_GE(p.level, 0) << what;
    ASSERT_LT(p.level, tex.levels()) << what;
    if (p.x == kBorderTexel || p.y == kBorderTexel) {
      ++border;
      continue;
    }
    EXPECT_GE(p.x, 0) << what;
    EXPECT_LT(p.x, tex.width(p.level)) << what;
    EXPECT_GE(p.y, 0) << what;
    EXPECT_LT(p.y, tex.height(p.level)) << what;
    EXPECT_TRUE(std::isfinite(p.w)) << what;
  }
  EXPECT_EQ(border, t.border_taps) << what;
  for (int ch = 0; ch < 4; ++ch) EXPECT_TRUE(std::isfinite(c[ch])) << what;
}

TEST(StabilityBorder, NonFiniteAndHugeCoordinates) {
  const Texture tex = ramp(24, 10);
  const Rgba border(0.3f, 0.6f, 0.9f, 1.0f);
  const double values[] = {kNaN, kInf, -kInf, 1e30, -1e30, 0.5};
  for (FilterMode f : kFilters) {
    for (AddressMode m : kModes) {
      TexelAddressGen::Config c;
      c.filter = f;
      c.address_u = AddressMode::Border;
      c.address_v = m;
      c.border = border;
      c.offset_u = 7;
      c.offset_v = -8;
      const TexelAddressGen g(c);
      for (double u : values) {
        for (double v : values) {
          for (int probes : {1, 16}) {
            LodResult lod;
            lod.lambda = 1.5f;
            lod.probes = probes;
            lod.axis_u = probes > 1 ? 1e30f : 0.0f;
            FilterTaps t;
            g.taps(tex, u, v, lod, t);
            const Rgba col = TexelBlend().blend(t, tex);
            expect_defined(tex, t, col, to_string(m));
            // ±1e30 along the border axis is far outside: every tap reads the border.
            if (std::fabs(u) == 1e30 && probes == 1) {
              EXPECT_EQ(t.border_taps, t.count) << u;
              for (int ch = 0; ch < 4; ++ch) EXPECT_NEAR(col[ch], border[ch], 1e-6);
            }
          }
          // The truth: the border colour or a texel's mixture, never NaN.
          SamplerExtras ex;
          ex.border = glm::dvec4(border);
          ex.offset_u = 7;
          const glm::dvec4 r = reference_bilinear(tex, AddressMode::Border, m, u, v, ex);
          for (int ch = 0; ch < 4; ++ch) EXPECT_TRUE(std::isfinite(r[ch])) << u << " " << v;
        }
      }
    }
  }
}

TEST(StabilityBorder, OffsetsAtTheRangeEndsOnOneTexel) {
  const std::vector<float> px = {0.2f, 0.4f, 0.6f, 1.0f};
  const Texture tex = Texture::from_rgba("one", 1, 1, px, TexelFormat::Rgba32f, true);
  const Rgba border(1.0f, 0.0f, 0.0f, 1.0f);
  for (FilterMode f : kFilters) {
    for (AddressMode m : kModes) {
      for (int ou : {TexelAddressGen::Config::kMinTexelOffset, 0,
                     TexelAddressGen::Config::kMaxTexelOffset}) {
        for (int ov :
             {TexelAddressGen::Config::kMinTexelOffset, TexelAddressGen::Config::kMaxTexelOffset}) {
          TexelAddressGen::Config c;
          c.filter = f;
          c.address_u = c.address_v = m;
          c.border = border;
          c.offset_u = ou;
          c.offset_v = ov;
          FilterTaps t;
          LodResult lod;
          lod.lambda = 3.0f;
          TexelAddressGen(c).taps(tex, 0.5, 0.5, lod, t);
          const Rgba col = TexelBlend().blend(t, tex);
          expect_defined(tex, t, col, to_string(m));
          // Every mode but border keeps the one texel; border at an offset of ≥ 1 texel in v
          // reads only the border colour.
          const Rgba want = m == AddressMode::Border ? border : Rgba(0.2f, 0.4f, 0.6f, 1.0f);
          for (int ch = 0; ch < 4; ++ch) EXPECT_NEAR(col[ch], want[ch], 1e-6) << to_string(m);
          SamplerExtras ex;
          ex.border = glm::dvec4(border);
          ex.offset_u = ou;
          ex.offset_v = ov;
          const glm::dvec4 r = reference_bilinear(tex, m, m, 0.5, 0.5, ex);
          for (int ch = 0; ch < 4; ++ch) EXPECT_NEAR(r[ch], want[ch], 1e-6) << to_string(m);
        }
      }
    }
  }
}

}  // namespace
}  // namespace texsim
