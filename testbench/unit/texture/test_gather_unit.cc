// GatherUnit: the spec's texel order (i0,j1), (i1,j1), (i1,j0), (i0,j0), component select,
// constant offsets (the sampler's and the fragment's), wrap and border addressing; and gather
// fragments through the texture unit (the same values, four taps each, the operation tallied,
// the cache used when timed).
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "blocks/base/sample_op.h"
#include "blocks/texture/sampler/gather_unit.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {
namespace {

// 4×4 RGBA32F, no mips: texel (x, y) = (x + 10y, 100 + x + 10y, 200 + ..., 300 + ...).
Texture coded_texture() {
  std::vector<float> px(size_t{4} * 4 * 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x)
      for (int c = 0; c < 4; ++c)
        px[(static_cast<size_t>(y) * 4 + static_cast<size_t>(x)) * 4 + static_cast<size_t>(c)] =
            static_cast<float>(100 * c + x + 10 * y);
  return Texture::from_rgba("coded", 4, 4, px, TexelFormat::Rgba32f, false);
}

TexelAddressGen::Config config(AddressMode m) {
  TexelAddressGen::Config c;
  c.address_u = c.address_v = m;
  return c;
}

TEST(GatherUnit, SpecOrderComponentsAndOffsets) {
  const Texture tex = coded_texture();
  // (0.25, 0.25): u·w − ½ = 0.5, so i0 = j0 = 0.
  TexelQuad q = GatherUnit::quad(config(AddressMode::Wrap), tex, 0.25, 0.25, 0, 0);
  EXPECT_EQ(GatherUnit::gather(q, tex, 0, Rgba(0.0f), nullptr), Rgba(10, 11, 1, 0));
  EXPECT_EQ(GatherUnit::gather(q, tex, 1, Rgba(0.0f), nullptr), Rgba(110, 111, 101, 100));
  EXPECT_EQ(GatherUnit::gather(q, tex, 3, Rgba(0.0f), nullptr), Rgba(310, 311, 301, 300));
  // Fragment offsets (1, 2) on top of the sampler's (0, 0): i0 = 1, j0 = 2.
  q = GatherUnit::quad(config(AddressMode::Wrap), tex, 0.25, 0.25, 1, 2);
  EXPECT_EQ(GatherUnit::gather(q, tex, 0, Rgba(0.0f), nullptr), Rgba(31, 32, 22, 21));
  // The sampler's offset adds to the fragment's.
  TexelAddressGen::Config c = config(AddressMode::Wrap);
  c.offset_u = -1;
  q = GatherUnit::quad(c, tex, 0.25, 0.25, 1, 2);
  EXPECT_EQ(GatherUnit::gather(q, tex, 0, Rgba(0.0f), nullptr), Rgba(30, 31, 21, 20));
  EXPECT_THROW(GatherUnit::gather(q, tex, 4, Rgba(0.0f), nullptr), std::invalid_argument);
}

TEST(GatherUnit, WrapAndBorderAtTheEdge) {
  const Texture tex = coded_texture();
  // u = v = 0: i0 = j0 = −1.
  TexelQuad q = GatherUnit::quad(config(AddressMode::Wrap), tex, 0.0, 0.0, 0, 0);
  EXPECT_EQ(GatherUnit::gather(q, tex, 0, Rgba(0.0f), nullptr), Rgba(3, 0, 30, 33));
  q = GatherUnit::quad(config(AddressMode::Border), tex, 0.0, 0.0, 0, 0);
  int border = 0;
  EXPECT_EQ(GatherUnit::gather(q, tex, 2, Rgba(7, 8, 9, 1), &border), Rgba(9, 200, 9, 9));
  EXPECT_EQ(border, 3);
  // A non-finite coordinate is taken as 0.
  q = GatherUnit::quad(config(AddressMode::Wrap), tex, std::nan(""), 0.0, 0, 0);
  EXPECT_EQ(GatherUnit::gather(q, tex, 0, Rgba(0.0f), nullptr), Rgba(3, 0, 30, 33));
  // Its cost: four texel reads and the address arithmetic, no weights.
  const OpCounts o = GatherUnit::ops_per_item(config(AddressMode::Wrap));
  EXPECT_EQ(o.mem, 4u);
  EXPECT_GT(o.cmp, 4u);
}

TEST(GatherUnit, ThroughTheTextureUnit) {
  for (const bool timing : {false, true}) {
    TextureSet set;
    set.add(coded_texture());
    MaterialSetup m;
    m.name = "coded";
    m.filter.filter = FilterMode::Bilinear;
    PipelineSetup setup;
    TextureUnit unit(set, {m}, setup, TechTable::defaults(), timing);
    Fragment f;
    f.u = 0.25;
    f.v = 0.25;
    f.op = static_cast<uint8_t>(SampleOp::kGather);
    f.gather_component = 1;
    f.offset_u = 1;
    EXPECT_EQ(unit.process(f, 0), Rgba(111, 112, 102, 101));
    f.op = 0;  // sampled without the offset: the bilinear mean of the quad at i0 = j0 = 0
    f.offset_u = 0;
    EXPECT_EQ(unit.process(f, 0), Rgba(5.5f, 105.5f, 205.5f, 305.5f));
    const TextureUnit::OpTallies& t = unit.material_op_tallies(0);
    EXPECT_EQ(t[3].fragments, 1u);
    EXPECT_EQ(t[3].taps, 4u);
    EXPECT_EQ(t[3].issue_cycles, 1u);
    EXPECT_EQ(t[0].fragments, 0u);
    EXPECT_EQ(unit.material_fragments(0), 2u);
    if (timing) {
      EXPECT_GT(unit.cache().stats().accesses, 0u);
      EXPECT_GT(unit.cycles(), 0u);
    }
    f.op = 9;
    EXPECT_THROW(unit.process(f, 0), std::invalid_argument);
  }
}

}  // namespace
}  // namespace texsim
