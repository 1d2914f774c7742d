// The sampling operations against the Vulkan checker (vulkan_ops_conformance.h): texsim's depth
// comparison (PCF), gather, explicit LOD and unnormalised coordinates, all through the texture
// unit, are accepted on random queries; controls the checker must reject: the comparison
// applied after filtering, a wrong gather order, the LOD clamped before the bias, unnormalised
// coordinates scaled twice. Stability: NaN and infinite references, gradients of 0 and 1e38,
// unnormalised coordinates far outside.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "blocks/base/sample_op.h"
#include "pipeline/texture/texture_unit.h"
#include "testbench/conformance/vulkan_ops_conformance.h"
#include "testbench/lib/filter_fixtures.h"

namespace texsim {
namespace {

constexpr AddressMode kModes[] = {AddressMode::Wrap, AddressMode::Clamp, AddressMode::Mirror,
                                  AddressMode::Border, AddressMode::MirrorClamp};
constexpr FilterMode kFilters[] = {FilterMode::Nearest, FilterMode::Bilinear,
                                   FilterMode::Trilinear};

MaterialSetup random_material(std::mt19937_64& rng, bool mips = true) {
  std::uniform_int_distribution<int> mode(0, 4), filter(0, mips ? 2 : 1), off(-8, 7);
  std::uniform_real_distribution<double> coin(0, 1);
  MaterialSetup m;
  m.name.push_back('m');  // (not `= "m"`: GCC 12's false -Wrestrict once inlined)
  m.filter.filter = kFilters[filter(rng)];
  m.filter.address_u = kModes[mode(rng)];
  m.filter.address_v = kModes[mode(rng)];
  m.filter.border = Rgba(static_cast<float>(coin(rng)), 0.25f, 0.5f, 1.0f);
  if (coin(rng) < 0.4) {
    m.filter.offset_u = off(rng);
    m.filter.offset_v = off(rng);
  }
  if (mips && coin(rng) < 0.6) {
    m.lod.lod_bias = static_cast<float>(coin(rng) * 4 - 2);
    m.lod.min_lod = static_cast<float>(coin(rng) * 2);
    m.lod.max_lod = m.lod.min_lod + static_cast<float>(coin(rng) * 3);
  }
  return m;
}

VkSamplerState vk_state(const MaterialSetup& m) { return vk_sampler_of(m.filter, m.lod); }

Fragment random_fragment(std::mt19937_64& rng, int w, int h) {
  std::uniform_real_distribution<double> uv(-1.5, 2.5), sc(-4, 6), ang(0, 6.283185307179586);
  Fragment f;
  f.u = uv(rng);
  f.v = uv(rng);
  const double len = std::exp2(sc(rng)), a = ang(rng);
  f.dudx = len * std::cos(a) / w;
  f.dvdx = len * std::sin(a) / h;
  f.dudy = -len * std::sin(a) / w;
  f.dvdy = len * std::cos(a) / h;
  return f;
}

// One fragment through a functional texture unit with material m.
Rgba run(const MaterialSetup& m, const Texture& tex, const Fragment& f) {
  TextureSet set;
  set.add(tex);
  TextureUnit unit(set, {m}, PipelineSetup{}, TechTable::defaults(), false);
  return unit.process(f, 0);
}

// A control counts where its answer differs from texsim's by more than the checker's
// precision windows can explain (a wrong answer a hair away may be a legal one).
bool differs(const Rgba& a, const Rgba& b) {
  for (int c = 0; c < 4; ++c)
    if (std::fabs(a[c] - b[c]) > 0.05f) return true;
  return false;
}

struct Tally {
  int queries = 0, accepted = 0, controls = 0, rejected = 0;
  void print(const char* what) const {
    std::printf("%s: texsim %d/%d accepted; control rejected %d/%d\n", what, accepted, queries,
                rejected, controls);
  }
};

TEST(VulkanOpsConformance, DepthComparisonBeforeFiltering) {
  std::mt19937_64 rng(0xC0A1ull);
  const Texture depths[] = {random_texture(16, 16, 7),
                            random_texture(16, 16, 8).converted(StorageFormat::D16)};
  std::uniform_int_distribution<int> op(1, 8);
  // References near the middle of the depths, out of [0, 1] now and then (D16 clamps them).
  std::uniform_real_distribution<double> ref(0.3, 0.7), far(-0.5, 1.5), coin(0, 1);
  Tally t;
  for (int k = 0; k < 1500; ++k) {
    const Texture& depth = depths[k % 2];
    MaterialSetup m = random_material(rng);
    if (m.filter.filter == FilterMode::Nearest && coin(rng) < 0.7)
      m.filter.filter = FilterMode::Bilinear;  // PCF: most queries filter
    m.filter.compare = static_cast<CompareOp>(op(rng));
    Fragment f = random_fragment(rng, 16, 16);
    f.compare_ref = static_cast<float>(coin(rng) < 0.15 ? far(rng) : ref(rng));
    // Every other query at an explicit LOD: one level (or two, trilinear) within 2^-8, where the
    // control's 0 or 1 cannot hide behind another legal level's result.
    // No border addressing there either: a border texel is a legal answer at a level's edge
    // within the sub-texel window (test_conformance_border covers border colours).
    const bool explicit_lod = k % 2 == 1;
    if (explicit_lod) {
      f.op = static_cast<uint8_t>(SampleOp::kSampleLod);
      f.lod = static_cast<float>(coin(rng) * 4);
      for (AddressMode* a : {&m.filter.address_u, &m.filter.address_v})
        if (*a == AddressMode::Border) *a = AddressMode::Clamp;
    }
    const VulkanOpsConformance chk(vk_state(m), VkFilterPrecision{});
    const Rgba got = run(m, depth, f);
    ++t.queries;
    const ConformanceVerdict v =
        chk.check_compare(depth, vk_query_of(f), m.filter.compare, f.compare_ref, got);
    t.accepted += v.pass;
    EXPECT_TRUE(v.pass) << v.reason;
    // Control: the depths filtered first, then the one filtered depth compared.
    MaterialSetup plain = m;
    plain.filter.compare = CompareOp::None;
    const float ref_seen = depth.storage() == StorageFormat::D16
                               ? std::clamp(f.compare_ref, 0.0f, 1.0f)
                               : f.compare_ref;
    const float p =
        VulkanOpsConformance::passes(m.filter.compare, ref_seen, run(plain, depth, f)[0]) ? 1.0f
                                                                                          : 0.0f;
    const Rgba wrong(p, p, p, 1.0f);
    if (!explicit_lod || !differs(wrong, got)) continue;
    ++t.controls;
    t.rejected +=
        !chk.check_compare(depth, vk_query_of(f), m.filter.compare, f.compare_ref, wrong).pass;
  }
  t.print("compare");
  EXPECT_EQ(t.accepted, t.queries);
  EXPECT_GT(t.controls, 40);
  EXPECT_EQ(t.rejected, t.controls);
}

TEST(VulkanOpsConformance, GatherOrder) {
  std::mt19937_64 rng(0x6A7Eull);
  const Texture tex = random_texture(13, 9, 9);
  std::uniform_int_distribution<int> comp(0, 3), off(-8, 7);
  Tally t;
  for (int k = 0; k < 600; ++k) {
    const MaterialSetup m = random_material(rng);
    Fragment f = random_fragment(rng, 13, 9);
    f.op = static_cast<uint8_t>(SampleOp::kGather);
    f.gather_component = static_cast<uint8_t>(comp(rng));
    if (k % 2) {
      f.offset_u = static_cast<int8_t>(off(rng));
      f.offset_v = static_cast<int8_t>(off(rng));
    }
    const VulkanOpsConformance chk(vk_state(m), VkFilterPrecision{});
    const Rgba got = run(m, tex, f);
    ++t.queries;
    const ConformanceVerdict v =
        chk.check_gather(tex, vk_query_of(f), f.gather_component, f.offset_u, f.offset_v, got);
    t.accepted += v.pass;
    EXPECT_TRUE(v.pass) << v.reason;
    // Control: the four texels in row order (i0,j0), (i1,j0), (i0,j1), (i1,j1).
    const Rgba wrong(got[3], got[2], got[0], got[1]);
    if (!differs(wrong, got)) continue;
    ++t.controls;
    t.rejected +=
        !chk.check_gather(tex, vk_query_of(f), f.gather_component, f.offset_u, f.offset_v, wrong)
             .pass;
  }
  t.print("gather");
  EXPECT_EQ(t.accepted, t.queries);
  EXPECT_EQ(t.rejected, t.controls);
  EXPECT_GT(t.controls, 300);
}

TEST(VulkanOpsConformance, ExplicitLodBiasThenClamp) {
  std::mt19937_64 rng(0x10DDull);
  const Texture tex = random_texture(32, 32, 10);
  std::uniform_real_distribution<double> lod(-2, 7);
  Tally t;
  for (int k = 0; k < 600; ++k) {
    MaterialSetup m = random_material(rng);
    // No border addressing here (test_conformance_border covers it): a border colour is a legal
    // answer near a level's edge on any level, which would hide the control's wrong level.
    for (AddressMode* a : {&m.filter.address_u, &m.filter.address_v})
      if (*a == AddressMode::Border) *a = AddressMode::Clamp;
    m.lod.lod_bias = static_cast<float>(lod(rng) / 2);
    Fragment f = random_fragment(rng, 32, 32);
    f.op = static_cast<uint8_t>(SampleOp::kSampleLod);
    f.lod = static_cast<float>(lod(rng));
    const VulkanOpsConformance chk(vk_state(m), VkFilterPrecision{});
    const Rgba got = run(m, tex, f);
    ++t.queries;
    const ConformanceVerdict v = chk.filter().check(tex, vk_query_of(f), got);
    t.accepted += v.pass;
    EXPECT_TRUE(v.pass) << v.reason;
    // Control: λ = clamp(lod) + bias, unclamped after.
    MaterialSetup wrong_m = m;
    wrong_m.lod = LodUnit::Config{};
    wrong_m.lod.min_lod = -1000;
    Fragment g = f;
    g.lod = std::clamp(f.lod, m.lod.min_lod, m.lod.max_lod) + m.lod.lod_bias;
    const Rgba wrong = run(wrong_m, tex, g);
    if (!differs(wrong, got)) continue;
    ++t.controls;
    t.rejected += !chk.filter().check(tex, vk_query_of(f), wrong).pass;
  }
  t.print("explicit lod");
  EXPECT_EQ(t.accepted, t.queries);
  EXPECT_GT(t.controls, 50);
  EXPECT_EQ(t.rejected, t.controls);
}

TEST(VulkanOpsConformance, UnnormalisedCoordinates) {
  std::mt19937_64 rng(0x0E11ull);
  const Texture tex = random_texture(16, 8, 11);
  std::uniform_real_distribution<double> x(-6, 22), coin(0, 1);
  Tally t;
  for (int k = 0; k < 600; ++k) {
    MaterialSetup m = random_material(rng, false);
    m.filter.address_u = coin(rng) < 0.5 ? AddressMode::Clamp : AddressMode::Border;
    m.filter.address_v = coin(rng) < 0.5 ? AddressMode::Clamp : AddressMode::Border;
    m.filter.offset_u = m.filter.offset_v = 0;
    m.filter.unnormalized = true;
    m.lod = LodUnit::Config{};
    m.lod.max_lod = 0;
    Fragment f = random_fragment(rng, 16, 8);
    f.u = x(rng);
    f.v = x(rng) / 2;
    f.op = static_cast<uint8_t>(SampleOp::kSampleLod);  // explicit LOD 0: all Vulkan allows
    f.lod = 0;
    const VulkanOpsConformance chk(vk_state(m), VkFilterPrecision{});
    const Rgba got = run(m, tex, f);
    ++t.queries;
    const ConformanceVerdict v = chk.filter().check(tex, vk_query_of(f), got);
    t.accepted += v.pass;
    EXPECT_TRUE(v.pass) << v.reason;
    // Control: the texel coordinates taken as normalised (scaled by the size a second time).
    MaterialSetup twice = m;
    twice.filter.unnormalized = false;
    const Rgba wrong = run(twice, tex, f);
    if (!differs(wrong, got)) continue;
    ++t.controls;
    t.rejected += !chk.filter().check(tex, vk_query_of(f), wrong).pass;
  }
  t.print("unnormalized");
  EXPECT_EQ(t.accepted, t.queries);
  EXPECT_GT(t.controls, 300);
  EXPECT_EQ(t.rejected, t.controls);
}

bool finite(const Rgba& c) {
  return std::isfinite(c[0]) && std::isfinite(c[1]) && std::isfinite(c[2]) && std::isfinite(c[3]);
}

TEST(VulkanOpsStability, NonFiniteReferencesHugeGradientsAndFarTexels) {
  const Texture depth = random_texture(16, 16, 12).converted(StorageFormat::D32f);
  MaterialSetup m;
  m.name = "m";
  m.filter.compare = CompareOp::Less;
  Fragment f;
  f.u = f.v = 0.4;
  f.dudx = f.dvdy = 1.0 / 16;
  // NaN fails LESS, passes NOT_EQUAL; +inf fails LESS (nothing is above it), −inf passes.
  f.compare_ref = std::nanf("");
  EXPECT_EQ(run(m, depth, f), Rgba(0, 0, 0, 1));
  m.filter.compare = CompareOp::NotEqual;
  EXPECT_EQ(run(m, depth, f), Rgba(1, 1, 1, 1));
  m.filter.compare = CompareOp::Less;
  f.compare_ref = INFINITY;
  EXPECT_EQ(run(m, depth, f), Rgba(0, 0, 0, 1));
  f.compare_ref = -INFINITY;
  EXPECT_EQ(run(m, depth, f), Rgba(1, 1, 1, 1));
  // Gradients of 0 and 1e38 (textureGrad): level 0 and the last level, finite results.
  const Texture tex = random_texture(16, 16, 13);
  MaterialSetup t;
  t.name = "t";
  t.filter.filter = FilterMode::Trilinear;
  Fragment g;
  g.u = g.v = 0.3;
  g.op = static_cast<uint8_t>(SampleOp::kSampleGrad);
  const Rgba at0 = run(t, tex, g);
  EXPECT_TRUE(finite(at0));
  g.dudx = g.dvdy = 1e38;
  g.dvdx = g.dudy = -1e38;
  const Rgba top = run(t, tex, g);
  EXPECT_TRUE(finite(top));
  for (int c = 0; c < 4; ++c)  // the 1×1 level (four taps of it, summed)
    EXPECT_NEAR(top[c], tex.texel(tex.levels() - 1, 0, 0)[c], 1e-6f) << c;
  // Unnormalised coordinates far outside: the edge texels (clamp) or the border colour.
  MaterialSetup u;
  u.name = "u";
  u.filter.unnormalized = true;
  u.filter.address_u = u.filter.address_v = AddressMode::Clamp;
  u.lod.max_lod = 0;
  Fragment h;
  h.u = 1e30;
  h.v = -1e30;
  h.op = static_cast<uint8_t>(SampleOp::kSampleLod);
  EXPECT_EQ(run(u, tex, h), tex.texel(0, 15, 0));
  u.filter.address_u = u.filter.address_v = AddressMode::Border;
  u.filter.border = Rgba(0.0f, 0.0f, 0.0f, 1.0f);
  EXPECT_EQ(run(u, tex, h), Rgba(0, 0, 0, 1));
  h.u = std::nan("");
  EXPECT_TRUE(finite(run(u, tex, h)));
}

}  // namespace
}  // namespace texsim
