// Visibility-aware anisotropic filtering (thesis ch. 4): equal to plain EWA where nothing is
// hidden, hidden texels replaced by their occluders (counted once through the buffer) behind a
// wall, the row rule against the exact per-texel classification, and the extra fetches.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/base/tech_table.h"
#include "blocks/texture/relief/visibility_aware_filter.h"

namespace texsim {
namespace {

using Filter = VisibilityAwareFilter;

Filter::ColourMap gradient_colours(int32_t w, int32_t h) {
  Filter::ColourMap t{w, h, {}};
  for (int32_t y = 0; y < h; ++y) {
    for (int32_t x = 0; x < w; ++x) {
      t.c.emplace_back(static_cast<float>(x) / static_cast<float>(w),
                       static_cast<float>(y) / static_cast<float>(h), 0.5F, 1.0F);
    }
  }
  return t;
}

Filter make(bool visibility, bool row_rule = true) {
  Filter::Config c;
  c.visibility = visibility;
  c.row_rule = row_rule;
  return Filter(c);
}

TEST(VisibilityAwareFilter, FlatReliefEqualsPlainFiltering) {
  const ReliefHeightMap hm(32, 32, 0.5F);
  const auto tex = gradient_colours(32, 32);
  const Filter::Footprint fp{16.3, 15.7, 3.0, 0.5, -0.4, 1.2};
  OpCounts ov, op;
  const auto v = make(true).filter(hm, tex, fp, 0.5, 0.2, 0.6, ov);
  const auto p = make(false).filter(hm, tex, fp, 0.5, 0.2, 0.6, op);
  EXPECT_EQ(v.colour, p.colour);
  EXPECT_EQ(v.stats.hidden, 0U);
  EXPECT_EQ(v.stats.visible, v.stats.texels);
  EXPECT_EQ(v.stats.colour_reads, p.stats.colour_reads);
  EXPECT_GT(v.stats.trace_reads, 0U);  // the extra cost even when nothing is hidden
  EXPECT_GT(ov.mem, op.mem);
  EXPECT_EQ(p.stats.traced, 0U);
}

TEST(VisibilityAwareFilter, WallHidesTexelsAndTheBufferCountsOccludersOnce) {
  // Height 0 for x < 8, a wall of height 1 from x = 8; the eye is towards +x at 45°.
  ReliefHeightMap hm(16, 16, 0.0F);
  for (int32_t y = 0; y < 16; ++y) {
    for (int32_t x = 8; x < 16; ++x) hm.at(x, y) = 1.0F;
  }
  const auto tex = gradient_colours(16, 16);
  const Filter::Footprint fp{7, 8, 3, 0, 0, 1};  // 3 texels along u
  OpCounts ops;
  const auto exact = make(true, false).filter(hm, tex, fp, 1, 0, 1, ops);
  const auto rule = make(true, true).filter(hm, tex, fp, 1, 0, 1, ops);
  const auto plain = make(false).filter(hm, tex, fp, 1, 0, 1, ops);
  EXPECT_GT(exact.stats.hidden, 0U);
  EXPECT_GT(exact.stats.buffer_hits, 0U);  // several hidden texels of a row share an occluder
  // Hidden texels (x < 8) give way to the wall's texels: the colour moves towards larger x.
  EXPECT_GT(exact.colour.x, plain.colour.x);
  // On a straight wall the row rule classifies exactly as the per-texel traces, with fewer.
  EXPECT_EQ(rule.colour, exact.colour);
  EXPECT_GT(rule.stats.skipped, 0U);
  EXPECT_LT(rule.stats.traced, exact.stats.traced);
  std::printf(
      "wall: %u texels, hidden %u (exact) / %u traced + %u skipped (row rule), buffer "
      "hits %u\n",
      exact.stats.texels, exact.stats.hidden, rule.stats.traced, rule.stats.skipped,
      exact.stats.buffer_hits);
}

TEST(VisibilityAwareFilter, RowRuleAgainstExactClassificationOnRandomRelief) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  ReliefHeightMap hm(64, 64);
  for (auto& h : hm.h) h = u(rng) < 0.1F ? 1.0F : 0.3F * u(rng);
  const auto tex = gradient_colours(64, 64);
  std::uniform_real_distribution<double> pos(16, 48), d(-3, 3), ang(0, 6.283), tilt(0.3, 1.3);
  double err_rule = 0, extra_reads = 0, plain_reads = 0, skipped = 0, hidden = 0, texels = 0;
  const int n = 300;
  for (int i = 0; i < n; ++i) {
    const Filter::Footprint fp{pos(rng), pos(rng), d(rng), d(rng), d(rng), d(rng)};
    const double a = ang(rng), t = tilt(rng);
    const double vx = std::sin(t) * std::cos(a), vy = std::sin(t) * std::sin(a), vz = std::cos(t);
    OpCounts ops;
    const auto ex = make(true, false).filter(hm, tex, fp, vx, vy, vz, ops);
    const auto ru = make(true, true).filter(hm, tex, fp, vx, vy, vz, ops);
    const auto pl = make(false).filter(hm, tex, fp, vx, vy, vz, ops);
    err_rule += std::fabs(ru.colour.x - ex.colour.x) + std::fabs(ru.colour.y - ex.colour.y);
    extra_reads += static_cast<double>(ru.stats.trace_reads) + ru.stats.colour_reads -
                   static_cast<double>(pl.stats.colour_reads);
    plain_reads += pl.stats.colour_reads;
    skipped += ru.stats.skipped;
    hidden += ex.stats.hidden;
    texels += ex.stats.texels;
    EXPECT_EQ(ex.stats.texels, pl.stats.texels);
    EXPECT_EQ(ru.stats.traced + ru.stats.skipped, ru.stats.texels);
  }
  std::printf(
      "random relief: %.1f %% of texels hidden (exact), row rule skips %.1f %%; mean "
      "|colour(rule) - colour(exact)| %.4f; extra reads per plain colour read %.2f\n",
      100 * hidden / texels, 100 * skipped / texels, err_rule / (2 * n), extra_reads / plain_reads);
  EXPECT_GT(hidden, 0);
  EXPECT_LT(err_rule / (2 * n), 0.05);
}

TEST(VisibilityAwareFilter, CloserToAFineTraceReferenceThanPlainFiltering) {
  // Reference: the exact classification with traces in steps of 1/20 texel. Error: mean
  // absolute colour difference (two channels, colours in [0, 1]) over random footprints.
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  ReliefHeightMap hm(64, 64);
  for (auto& h : hm.h) h = u(rng) < 0.1F ? 1.0F : 0.3F * u(rng);
  const auto tex = gradient_colours(64, 64);
  Filter::Config rc;
  rc.row_rule = false;
  rc.trace_step = 0.05;
  rc.max_trace_steps = 4096;
  const Filter ref(rc);
  std::uniform_real_distribution<double> pos(16, 48), d(-3, 3), ang(0, 6.283), tilt(0.3, 1.3);
  double e_plain = 0, e_rule = 0, e_exact = 0;
  const int n = 300;
  for (int i = 0; i < n; ++i) {
    const Filter::Footprint fp{pos(rng), pos(rng), d(rng), d(rng), d(rng), d(rng)};
    const double a = ang(rng), t = tilt(rng);
    const double vx = std::sin(t) * std::cos(a), vy = std::sin(t) * std::sin(a), vz = std::cos(t);
    OpCounts ops;
    const auto r = ref.filter(hm, tex, fp, vx, vy, vz, ops).colour;
    auto err = [&](const glm::vec4& c) { return std::fabs(c.x - r.x) + std::fabs(c.y - r.y); };
    e_plain += err(make(false).filter(hm, tex, fp, vx, vy, vz, ops).colour);
    e_rule += err(make(true, true).filter(hm, tex, fp, vx, vy, vz, ops).colour);
    e_exact += err(make(true, false).filter(hm, tex, fp, vx, vy, vz, ops).colour);
  }
  std::printf(
      "against the fine-trace reference: mean colour error plain EWA %.4f, visibility "
      "with row rule %.4f, exact classification (step 1/2) %.4f\n",
      e_plain / (2 * n), e_rule / (2 * n), e_exact / (2 * n));
  EXPECT_LT(e_rule, e_plain);
  EXPECT_LT(e_exact, e_plain);
}

TEST(VisibilityAwareFilter, BadInputsFallBack) {
  const ReliefHeightMap hm(8, 8, 0.5F);
  const auto tex = gradient_colours(8, 8);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  OpCounts ops;
  const Filter::Footprint fp{4, 4, 1, 0, 0, 1};
  const auto v = make(true).filter(hm, tex, fp, nan, 0, 1, ops);  // plain filtering
  const auto p = make(false).filter(hm, tex, fp, 0, 0, 1, ops);
  EXPECT_TRUE(v.stats.fallback);
  EXPECT_EQ(v.colour, p.colour);
  EXPECT_EQ(v.stats.traced, 0U);
  const auto bad = make(true).filter(hm, tex, {nan, 4, 1, 0, 0, 1}, 0, 0, 1, ops);
  EXPECT_TRUE(bad.stats.fallback);
  EXPECT_EQ(bad.stats.texels, 0U);
  // A huge footprint is capped at max_radius.
  const auto big = make(true).filter(hm, tex, {4, 4, 1e6, 0, 0, 1e6}, 0, 0, 1, ops);
  EXPECT_LE(big.stats.texels, 65U * 65U);
  EXPECT_GE(make(true).timing(TechTable::defaults()).latency, 1U);
}

TEST(VisibilityAwareFilter, ConfigsReadAndReject) {
  const toml::table t = toml::parse("row_rule = false\ntrace_step = 0.25\n");
  const auto c = Filter::Config::from_toml(ConfigReader(t, "s.toml", "visibility"));
  EXPECT_FALSE(c.row_rule);
  EXPECT_DOUBLE_EQ(c.trace_step, 0.25);
  for (const char* bad : {"trace_step = 0\n", "rowrule = true\n"}) {
    const toml::table b = toml::parse(bad);
    EXPECT_THROW(Filter::Config::from_toml(ConfigReader(b, "s.toml", "visibility")), InputError);
  }
}

}  // namespace
}  // namespace texsim
