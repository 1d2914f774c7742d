// TexelReduce: min/max over the taps with non-zero weight, depth comparison before filtering
// (percentage-closer filtering) with all eight compare ops, the reference clamped for D16 and
// not for D32F, NaN references; the scene keys; and a comparing material through the texture
// unit (its own kernel, the same figures with or without the batch).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/texture/memory/storage_format.h"
#include "blocks/texture/sampler/texel_reduce.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {
namespace {

// 4×4 RGBA32F, no mips, texel (x, y) = (x + 10y) / 40 in every channel but alpha = 1 − that.
Texture ramp(StorageFormat storage = StorageFormat::Rgba32f) {
  std::vector<float> px(size_t{4} * 4 * 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x)
      for (int c = 0; c < 4; ++c) {
        const float v = static_cast<float>(x + 10 * y) / 40.0f;
        px[(static_cast<size_t>(y) * 4 + static_cast<size_t>(x)) * 4 + static_cast<size_t>(c)] =
            c == 3 ? 1.0f - v : v;
      }
  const Texture t = Texture::from_rgba("ramp", 4, 4, px, TexelFormat::Rgba32f, false);
  return storage == StorageFormat::Rgba32f ? t : t.converted(storage);
}

FilterTaps taps_of(std::initializer_list<TexelTap> list) {
  FilterTaps t;
  for (const TexelTap& x : list) t.tap[static_cast<size_t>(t.count++)] = x;
  return t;
}

TEST(TexelReduce, MinMaxOverTapsWithWeight) {
  const Texture tex = ramp();
  // Texel (3, 3) has weight 0: the weighted average would not use it.
  const FilterTaps t = taps_of({{0, 1, 0, 0.25f}, {0, 2, 1, 0.75f}, {0, 3, 3, 0.0f}});
  const Rgba mn = TexelReduce::minmax(t, tex, Reduction::Min);
  const Rgba mx = TexelReduce::minmax(t, tex, Reduction::Max);
  EXPECT_EQ(mn, Rgba(1 / 40.0f, 1 / 40.0f, 1 / 40.0f, 1 - 12 / 40.0f));  // per channel
  EXPECT_EQ(mx, Rgba(12 / 40.0f, 12 / 40.0f, 12 / 40.0f, 1 - 1 / 40.0f));
  // A border tap reduces with the border colour.
  FilterTaps b = taps_of({{0, 1, 0, 0.5f}, {0, kBorderTexel, 0, 0.5f}});
  b.border = Rgba(-1.0f);
  EXPECT_EQ(TexelReduce::minmax(b, tex, Reduction::Min), Rgba(-1.0f));
  // Through the address generator: a bilinear quad exactly on a texel centre has one tap of
  // weight 1, so min = max = that texel.
  TexelAddressGen::Config c;
  c.filter = FilterMode::Bilinear;
  FilterTaps q;
  TexelAddressGen(c).taps(tex, 1.5 / 4, 2.5 / 4, LodResult{}, q);
  EXPECT_EQ(TexelReduce::minmax(q, tex, Reduction::Min), tex.texel(0, 1, 2));
  EXPECT_EQ(TexelReduce::minmax(q, tex, Reduction::Max), tex.texel(0, 1, 2));
}

// Comparison first, then the weights: half the taps pass. Filtering the depths first (the
// negative control) gives 0.5 < 0.5, false: 0.
TEST(TexelReduce, ComparisonBeforeFiltering) {
  const Texture tex = ramp(StorageFormat::D32f);
  const FilterTaps t = taps_of({{0, 0, 1, 0.5f}, {0, 0, 3, 0.5f}});  // depths 10/40, 30/40
  const float ref = 0.5f;
  EXPECT_EQ(TexelReduce::compare(t, tex, CompareOp::Less, ref), Rgba(0.5f, 0.5f, 0.5f, 1.0f));
  const float filtered = 0.5f * tex.texel(0, 0, 1).r + 0.5f * tex.texel(0, 0, 3).r;
  EXPECT_NE(compare_passes(CompareOp::Less, ref, filtered) ? 1.0f : 0.0f, 0.5f);
}

TEST(TexelReduce, AllEightCompareOps) {
  struct Row {
    CompareOp op;
    bool below, equal, above;  // reference < texel, =, >
  };
  for (const Row r :
       {Row{CompareOp::Never, false, false, false}, Row{CompareOp::Less, true, false, false},
        Row{CompareOp::Equal, false, true, false}, Row{CompareOp::LessOrEqual, true, true, false},
        Row{CompareOp::Greater, false, false, true}, Row{CompareOp::NotEqual, true, false, true},
        Row{CompareOp::GreaterOrEqual, false, true, true},
        Row{CompareOp::Always, true, true, true}}) {
    SCOPED_TRACE(std::string(kCompareOpNames[static_cast<int>(r.op)]));
    EXPECT_EQ(compare_passes(r.op, 0.25f, 0.5f), r.below);
    EXPECT_EQ(compare_passes(r.op, 0.5f, 0.5f), r.equal);
    EXPECT_EQ(compare_passes(r.op, 0.75f, 0.5f), r.above);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(compare_passes(r.op, nan, 0.5f),
              r.op == CompareOp::NotEqual || r.op == CompareOp::Always);
  }
}

// D16 is UNORM: the reference is clamped to [0, 1] first; D32F keeps it.
TEST(TexelReduce, ReferenceClampedForUnormDepth) {
  const Texture d16 = ramp(StorageFormat::D16), d32 = ramp(StorageFormat::D32f);
  EXPECT_EQ(TexelReduce::reference(d16, 1.5f), 1.0f);
  EXPECT_EQ(TexelReduce::reference(d16, -2.0f), 0.0f);
  EXPECT_EQ(TexelReduce::reference(d32, 1.5f), 1.5f);
  EXPECT_TRUE(std::isnan(TexelReduce::reference(d16, std::nanf(""))));
  // Texel (0, 0) is depth 0: reference −2 ≥ 0 only after the clamp.
  const FilterTaps t = taps_of({{0, 0, 0, 1.0f}});
  EXPECT_EQ(TexelReduce::compare(t, d16, CompareOp::GreaterOrEqual, -2.0f).r, 1.0f);
  EXPECT_EQ(TexelReduce::compare(t, d32, CompareOp::GreaterOrEqual, -2.0f).r, 0.0f);
  const OpCounts o = TexelReduce::ops_per_tap(Reduction::WeightedAverage, CompareOp::Less);
  EXPECT_EQ(o.cmp, 1u);
  EXPECT_EQ(o.mul, 1u);
}

TEST(TexelReduce, SceneKeys) {
  static toml::table t;
  auto parse = [](const std::string& text) {
    t = toml::parse(std::string_view(text), std::string_view("m.toml"));
    return TexelAddressGen::Config::from_toml(ConfigReader(t, "m.toml", "filter"));
  };
  EXPECT_EQ(parse("reduction = 'max'").reduction, Reduction::Max);
  EXPECT_EQ(parse("compare = 'greater_or_equal'").compare, CompareOp::GreaterOrEqual);
  EXPECT_FALSE(parse("").reduces());
  std::string msg;
  try {
    parse("reduction = 'min'\ncompare = 'less'\n");
  } catch (const InputError& e) {
    msg = e.what();
  }
  EXPECT_NE(msg.find("m.toml:2:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("weighted_average"), std::string::npos) << msg;
  EXPECT_THROW(parse("compare = 'lesser'"), InputError);
}

// Percentage-closer filtering of a shadow map through the unit: a bilinear comparing material;
// the batch takes no part (the same colours and cycles through process_batch).
TEST(TexelReduce, ComparingMaterialThroughTheUnit) {
  TextureSet set;
  set.add(ramp(StorageFormat::D32f));
  MaterialSetup m;
  m.name = "shadow";
  m.filter.filter = FilterMode::Bilinear;
  m.filter.address_u = m.filter.address_v = AddressMode::Clamp;
  m.filter.compare = CompareOp::Less;
  std::vector<Fragment> frags;
  for (int i = 0; i < 64; ++i) {
    Fragment f;
    f.x = static_cast<uint32_t>(i);
    f.u = (i % 8) / 8.0 + 0.03;
    const int row = i / 8;
    f.v = row / 8.0 + 0.05;
    f.compare_ref = 0.4f;
    frags.push_back(f);
  }
  auto run = [&](bool batch) {
    PipelineSetup setup;
    TextureUnit unit(set, {m}, setup, TechTable::defaults(), true);
    std::vector<Rgba> out(frags.size());
    if (batch) {
      unit.process_batch(frags.data(), frags.size(), 0, out.data());
    } else {
      for (size_t i = 0; i < frags.size(); ++i) out[i] = unit.process(frags[i], 0);
    }
    return std::make_pair(out, unit.cycles());
  };
  const auto one = run(false);
  EXPECT_EQ(one, run(true));
  int partial = 0, lit = 0;
  for (const Rgba& c : one.first) {
    EXPECT_GE(c.r, 0.0f);
    EXPECT_LE(c.r, 1.0f);
    partial += c.r > 0.0f && c.r < 1.0f;
    lit += c.r == 1.0f;
  }
  EXPECT_GT(partial, 0);  // the shadow's edge is filtered
  EXPECT_GT(lit, 0);
  EXPECT_GT(one.second, 0u);
}

}  // namespace
}  // namespace texsim
