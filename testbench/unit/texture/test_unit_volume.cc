// 3-D textures in the texture store and the unit: the 3-D mip chain (depth halves too), the
// texels' addresses under the three 3-D layouts (and the room they take), and the unit's
// one-by-one path: eight taps per level, λ from all three derivatives, trilinear across 3-D
// mips, border taps, the cache reading the lines of the 3-D addresses. Controls: a 2-D λ (r's
// derivative left out) and a slice-by-slice address would each fail a test here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <set>

#include "blocks/texture/volume/volume_address_gen.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {
namespace {

// Texel (x, y, z) of a w × h × d volume: R = (z + ½)/d, G = (x + ½)/w, B = (y + ½)/h (linear
// in each axis, so a level-0 trilinear sample at (u, v, r) inside the half-texel margins reads
// (r, u, v) exactly), A = the z checker (z mod 2).
std::vector<std::vector<float>> ramp_slices(int w, int h, int d) {
  std::vector<std::vector<float>> s(static_cast<size_t>(d));
  for (int z = 0; z < d; ++z) {
    auto& px = s[static_cast<size_t>(z)];
    px.resize(static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        float* t =
            &px[(static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) * 4];
        t[0] = (static_cast<float>(z) + 0.5f) / static_cast<float>(d);
        t[1] = (static_cast<float>(x) + 0.5f) / static_cast<float>(w);
        t[2] = (static_cast<float>(y) + 0.5f) / static_cast<float>(h);
        t[3] = static_cast<float>(z % 2);
      }
    }
  }
  return s;
}

Texture ramp_volume(int w, int h, int d, TexelFormat f = TexelFormat::Rgba32f) {
  return Texture::from_volume("vol", w, h, ramp_slices(w, h, d), f, true);
}

MaterialSetup material(FilterMode f, AddressMode a = AddressMode::Clamp) {
  MaterialSetup m;
  m.name.push_back('m');  // (not `= "m"`: GCC 12's false -Wrestrict once inlined)
  m.filter.filter = f;
  m.filter.address_u = m.filter.address_v = m.filter.address_w = a;
  return m;
}

Fragment frag(double u, double v, double r, double d = 1e-4) {
  Fragment f;
  f.u = u;
  f.v = v;
  f.w = r;
  f.dudx = f.dvdy = d;
  return f;
}

TEST(UnitVolume, MipChainHalvesDepth) {
  const Texture t = ramp_volume(8, 4, 16);
  EXPECT_EQ(t.shape().type, TextureType::Volume);
  EXPECT_TRUE(t.layered());
  ASSERT_EQ(t.mips(), 5);  // 8x4x16, 4x2x8, 2x1x4, 1x1x2, 1x1x1
  const int depth[] = {16, 8, 4, 2, 1}, width[] = {8, 4, 2, 1, 1};
  int levels = 0;
  for (int m = 0; m < 5; ++m) {
    EXPECT_EQ(t.volume_depth(m), depth[m]) << m;
    EXPECT_EQ(t.width(t.volume_level(m, 0)), width[m]) << m;
    levels += depth[m];
  }
  EXPECT_EQ(t.levels(), levels);
  // Mip 1's texel is the mean of its 2x2x2 block: R of z-slices 2 and 3 of 16, A of a 0 and 1.
  const Rgba c = t.texel(t.volume_level(1, 1), 0, 0);
  EXPECT_FLOAT_EQ(c.r, (2.5f + 3.5f) / 2 / 16);
  EXPECT_FLOAT_EQ(c.a, 0.5f);
  // Depth 1: a 2-D chain in one slice per mip.
  const Texture flat = ramp_volume(4, 4, 1);
  EXPECT_EQ(flat.mips(), 3);
  EXPECT_EQ(flat.volume_depth(2), 1);
}

TEST(UnitVolume, AddressesFollowTheThreeDLayouts) {
  for (TexelLayout l : {TexelLayout::Linear, TexelLayout::Tiled4x4, TexelLayout::Morton}) {
    TextureSet set;
    set.add(ramp_volume(8, 4, 6));
    std::vector<float> px(size_t{4} * 4 * 4, 0.5f);
    set.add(Texture::from_rgba("after", 4, 4, px, TexelFormat::Rgba32f, false));
    set.place(l);
    const Texture& t = set[0];
    uint64_t end = 0;
    for (int m = 0; m < t.mips(); ++m) {
      const VolumeSize s = VolumeAddressGen::level_size({8, 4, 6}, m);
      const uint64_t first = t.volume_address(m, 0, 0, 0);
      std::set<uint64_t> seen;
      for (int z = 0; z < s.depth; ++z)
        for (int y = 0; y < s.height; ++y)
          for (int x = 0; x < s.width; ++x) {
            const uint64_t a = t.volume_address(m, x, y, z);
            EXPECT_EQ(a, first + VolumeAddressGen::texel_index(l, s, x, y, z) * 16);
            seen.insert(a);
            end = std::max(end, a + 16);
          }
      EXPECT_EQ(seen.size(), static_cast<size_t>(s.width) * s.height * s.depth);
    }
    // The next texture starts past every mip's texel slots.
    EXPECT_GE(set[1].base(), end) << to_string(l);
  }
}

TEST(UnitVolume, LevelZeroIsTrilinearInSpace) {
  TextureSet set;
  set.add(ramp_volume(8, 8, 8));
  TextureUnit unit(set, {material(FilterMode::Trilinear)}, PipelineSetup{}, TechTable::defaults(),
                   true);
  for (const double r : {0.1, 0.37, 0.5, 0.81}) {
    const Rgba c = unit.process(frag(0.3, 0.6, r), 0);
    EXPECT_NEAR(c.r, r, 1e-5) << r;  // a 2-D unit (slice 0 only) would read 1/16
    EXPECT_NEAR(c.g, 0.3, 1e-5);
    EXPECT_NEAR(c.b, 0.6, 1e-5);
  }
  // Border in r: taps beyond the volume read the border colour.
  TextureSet bs;
  bs.add(ramp_volume(8, 8, 8));
  MaterialSetup m = material(FilterMode::Bilinear);
  m.filter.address_w = AddressMode::Border;
  m.filter.border = Rgba(1, 1, 1, 1);
  TextureUnit bu(bs, {m}, PipelineSetup{}, TechTable::defaults(), true);
  // r = 1: k0 = 7 (weight ½) and k1 = 8 (border, weight ½).
  EXPECT_NEAR(bu.process(frag(0.5, 0.5, 1.0), 0).r, 0.5 * (7.5 / 8) + 0.5, 1e-5);
}

TEST(UnitVolume, LodTakesTheDerivativeOfR) {
  // The A channel is the z checker: level 0 reads 0 or 1 at a slice centre, every coarser
  // level ½. A footprint of 2 slices in r (and none in u, v) is λ = 1.
  TextureSet set;
  set.add(ramp_volume(16, 16, 16));
  TextureUnit unit(set, {material(FilterMode::Trilinear)}, PipelineSetup{}, TechTable::defaults(),
                   true);
  Fragment f = frag(0.5, 0.5, 2.5 / 16, 0);
  EXPECT_NEAR(unit.process(f, 0).a, 0.0, 1e-6);  // magnified: slice 2
  f.dwdx = 2.0 / 16;
  EXPECT_NEAR(unit.process(f, 0).a, 0.5, 1e-6);  // a 2-D λ (no ∂r) would still read 0
  // Sixteen taps over two levels: twice the address slot's probes of a 2-D trilinear sample.
  f.dwdx = 3.0 / 16;
  (void)unit.process(f, 0);
  bool row = false;
  for (const BlockUse& b : unit.blocks()) row = row || b.name == "volume.r_axis";
  EXPECT_TRUE(row);
}

TEST(UnitVolume, LodBiasAndClampApplyToTheThreeDLambda) {
  // As above: a footprint of one slice in r is λ = 0 (A = 0 at slice 2), of two λ = 1 (½).
  TextureSet set;
  set.add(ramp_volume(16, 16, 16));
  MaterialSetup biased = material(FilterMode::Trilinear);
  biased.lod.lod_bias = 1;
  MaterialSetup clamped = material(FilterMode::Trilinear);
  clamped.lod.max_lod = 0;
  TextureUnit unit(set, {biased, clamped}, PipelineSetup{}, TechTable::defaults(), true);
  Fragment f = frag(0.5, 0.5, 2.5 / 16, 0);
  f.dwdx = 1.0 / 16;
  EXPECT_NEAR(unit.process(f, 0).a, 0.5, 1e-6);  // λ 0 + bias 1: level 1 (unbiased: 0)
  f.dwdx = 2.0 / 16;
  EXPECT_NEAR(unit.process(f, 1).a, 0.0, 1e-6);  // λ 1 clamped to 0: slice 2 (unclamped: ½)
}

TEST(UnitVolume, ExplicitLodPicksTheThreeDLevel) {
  // A magnified footprint (λ of the derivatives −∞: A = 0 at slice 2) asked for LOD 1 reads
  // level 1 (A = ½); the sampler's bias adds, the fragment's own bias does not (implicit LOD
  // only), the clamp bounds it. Ignoring the operation would read 0 throughout.
  TextureSet set;
  set.add(ramp_volume(16, 16, 16));
  MaterialSetup clamped = material(FilterMode::Trilinear);
  clamped.lod.max_lod = 0.5f;
  MaterialSetup biased = material(FilterMode::Trilinear);
  biased.lod.lod_bias = 1;
  TextureUnit unit(set, {material(FilterMode::Trilinear), clamped, biased}, PipelineSetup{},
                   TechTable::defaults(), true);
  Fragment f = frag(0.5, 0.5, 2.5 / 16, 0);
  f.op = static_cast<uint8_t>(SampleOp::kSampleLod);
  f.lod = 1;
  EXPECT_NEAR(unit.process(f, 0).a, 0.5, 1e-6);
  f.lod = 0.5f;
  EXPECT_NEAR(unit.process(f, 0).a, 0.25, 1e-6);  // half level 0 (0), half level 1 (½)
  f.lod = 1;
  EXPECT_NEAR(unit.process(f, 1).a, 0.25, 1e-6);  // clamped to 0.5
  f.lod = 0;
  f.lod_bias = 5;  // not applied to an explicit LOD
  EXPECT_NEAR(unit.process(f, 0).a, 0.0, 1e-6);
  EXPECT_NEAR(unit.process(f, 2).a, 0.5, 1e-6);  // the sampler's bias 1 is
  f.lod = std::nanf("");
  EXPECT_NEAR(unit.process(f, 0).a, 0.0, 1e-6);  // a NaN LOD reads as 0
  const TextureUnit::OpTally& t =
      unit.material_op_tallies(0)[static_cast<size_t>(SampleOp::kSampleLod)];
  EXPECT_EQ(t.fragments, 4u);
  EXPECT_EQ(t.taps, 4u * 16u);  // trilinear: eight taps on each of two levels
}

TEST(UnitVolume, ExplicitGradientsIncludeDwAndSkipTheFragmentsBias) {
  // Gradients of one slice in r (λ 0: A = 0 at slice 2) and of two (λ 1: ½); a 2-D λ from the
  // gradients (dw left out) would read 0 for both. The fragment's bias applies only to an
  // implicit sample.
  TextureSet set;
  set.add(ramp_volume(16, 16, 16));
  TextureUnit unit(set, {material(FilterMode::Trilinear)}, PipelineSetup{}, TechTable::defaults(),
                   true);
  Fragment f = frag(0.5, 0.5, 2.5 / 16, 0);
  f.op = static_cast<uint8_t>(SampleOp::kSampleGrad);
  f.dwdy = 1.0 / 16;
  EXPECT_NEAR(unit.process(f, 0).a, 0.0, 1e-6);
  f.dwdy = 2.0 / 16;
  EXPECT_NEAR(unit.process(f, 0).a, 0.5, 1e-6);
  f.dwdy = 1.0 / 16;
  f.lod_bias = 1;
  EXPECT_NEAR(unit.process(f, 0).a, 0.0, 1e-6);  // grad: bias ignored
  f.op = static_cast<uint8_t>(SampleOp::kSample);
  EXPECT_NEAR(unit.process(f, 0).a, 0.5, 1e-6);  // implicit: λ 0 + 1
  EXPECT_EQ(unit.material_op_tallies(0)[static_cast<size_t>(SampleOp::kSampleGrad)].fragments, 3u);
}

TEST(UnitVolume, LevelFractionIsTheAddressGeneratorsFixedPoint) {
  // λ = ½ + 2^-10 reads levels 0 (A = 0 at slice 2) and 1 (A = ½) at the fraction rounded to
  // mipmap_bits = 8 (½: A = ¼ exactly); a float fraction would read ¼ + 2^-11.
  TextureSet set;
  set.add(ramp_volume(16, 16, 16));
  TextureUnit unit(set, {material(FilterMode::Trilinear)}, PipelineSetup{}, TechTable::defaults(),
                   true);
  Fragment f = frag(0.5, 0.5, 2.5 / 16, 0);
  f.op = static_cast<uint8_t>(SampleOp::kSampleLod);
  f.lod = 0.5f + 0x1p-10f;
  EXPECT_EQ(unit.process(f, 0).a, 0.25f);
  // The same λ from derivatives: ρ = 2^(½ + 2^-10) slices in r.
  f.op = static_cast<uint8_t>(SampleOp::kSample);
  f.dwdx = std::exp2(0.5 + 0x1p-10) / 16;
  EXPECT_EQ(unit.process(f, 0).a, 0.25f);
}

TEST(UnitVolume, GatherIsRefused) {
  TextureSet set;
  set.add(ramp_volume(4, 4, 4));
  TextureUnit unit(set, {material(FilterMode::Bilinear)}, PipelineSetup{}, TechTable::defaults(),
                   true);
  Fragment f = frag(0.5, 0.5, 0.5);
  f.op = static_cast<uint8_t>(SampleOp::kGather);
  EXPECT_THROW((void)unit.process(f, 0), std::invalid_argument);
}

TEST(UnitVolume, CacheReadsTheLinesOfThreeDAddresses) {
  // A 2x2x2 footprint at texels 2..3 of each axis of a 16³ RGBA8 volume (4 B a texel, 64 B
  // lines): linear takes 4 lines (2 rows × 2 slices, a row a line), the 4×4×4 brick 2 (16
  // texels a line: one per z), Morton 1 (the 8 texels are 32 contiguous bytes). A layout
  // applied slice by slice (2-D Morton per z) would take 2.
  const uint64_t want[] = {4, 2, 1};
  int i = 0;
  for (TexelLayout l : {TexelLayout::Linear, TexelLayout::Tiled4x4, TexelLayout::Morton}) {
    TextureSet set;
    set.add(ramp_volume(16, 16, 16, TexelFormat::Rgba8));
    PipelineSetup setup;
    setup.layout = l;  // the unit places its textures so
    TextureUnit unit(set, {material(FilterMode::Bilinear)}, setup, TechTable::defaults(), true);
    (void)unit.process(frag(3.0 / 16, 3.0 / 16, 3.0 / 16), 0);
    EXPECT_EQ(unit.cache().stats().misses, want[i]) << to_string(l);
    EXPECT_EQ(unit.cache().stats().texel_reads, 8u);
    ++i;
  }
}

// A record's sampler picks the volume's address modes and border: outside in r, the
// material's clamp reads the edge slice, the record's border sampler its border colour.
TEST(UnitVolume, RecordsSamplerIsHonoured) {
  TextureSet set;
  set.add(ramp_volume(4, 4, 4));
  MaterialSetup m = material(FilterMode::Bilinear);
  auto table = std::make_shared<SamplerTable>(1);
  (*table)[0].name = "border";
  (*table)[0].filter = m.filter;
  (*table)[0].filter.address_w = AddressMode::Border;
  (*table)[0].filter.border = Rgba(0.0f, 0.0f, 0.0f, 1.0f);
  m.samplers = table;
  TextureUnit unit(set, {m}, PipelineSetup{}, TechTable::defaults(), false);
  Fragment f = frag(0.5, 0.5, 1.5);
  EXPECT_FLOAT_EQ(unit.process(f, 0).x, 3.5f / 4);  // clamp: the last slice
  f.sampler = 1;
  EXPECT_FLOAT_EQ(unit.process(f, 0).x, 0.0f);  // border
  EXPECT_FLOAT_EQ(unit.process(f, 0).w, 1.0f);
}

TEST(UnitVolume, HardCasesStayFinite) {
  TextureSet set;
  set.add(ramp_volume(4, 4, 1));  // depth 1
  TextureUnit unit(set, {material(FilterMode::Trilinear, AddressMode::Wrap)}, PipelineSetup{},
                   TechTable::defaults(), true);
  const double nan = std::nan("");
  for (const Fragment& f :
       {frag(0.5, 0.5, 0.9), frag(nan, 1e300, -1e300), frag(0.2, 0.2, nan, nan)}) {
    const Rgba c = unit.process(f, 0);
    for (int k = 0; k < 4; ++k) EXPECT_TRUE(std::isfinite(c[k]));
  }
  EXPECT_NEAR(unit.process(frag(0.375, 0.375, 0.9), 0).r, 0.5, 1e-6);  // one slice: R = ½
}

}  // namespace
}  // namespace texsim
