// Samplers as state: [samplers.NAME] tables checked with file:line:column, a material naming
// one, a fragment picking another by id (the same colours as a material whose own sampler it
// is), constant offsets of a fragment's own, and unnormalised coordinates (UnnormalizedTaps and
// Vulkan's restrictions).
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/base/sample_op.h"
#include "blocks/texture/sampler/unnormalized_taps.h"
#include "pipeline/scene/scene.h"
#include "pipeline/texture/effect_registry.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {
namespace {

// 8×8 RGBA32F with mips: texel (x, y) of level 0 = (x + 10y, 100 + x, 200 + y, 1).
Texture coded_texture() {
  std::vector<float> px(size_t{8} * 8 * 4);
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      float* p = &px[(static_cast<size_t>(y) * 8 + static_cast<size_t>(x)) * 4];
      p[0] = static_cast<float>(x + 10 * y);
      p[1] = static_cast<float>(100 + x);
      p[2] = static_cast<float>(200 + y);
      p[3] = 1;
    }
  }
  return Texture::from_rgba("coded", 8, 8, px, TexelFormat::Rgba32f, true);
}

std::string error_of(const std::string& text) {
  try {
    build_materials(parse_scene(text, "s.toml", ""));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const char* const kHead =
    "[textures.t]\nsource = \"procedural:checker?size=64&cells=4\"\n"            // lines 1-2
    "[samplers.a]\nmode = \"nearest\"\naddress = \"clamp\"\n"                    // lines 3-5
    "[samplers.b]\nmode = \"trilinear\"\nlod_bias = 1.5\ncompare = \"less\"\n";  // lines 6-9

TEST(SamplerState, MaterialsNameSamplersInNameOrder) {
  const Scene s =
      parse_scene(std::string(kHead) + "[materials.m]\ntexture = \"t\"\nsampler = \"b\"\n" +
                      "[materials.n]\ntexture = \"t\"\n",
                  "s.toml", "");
  const std::vector<MaterialSetup> mats = build_materials(s);
  ASSERT_EQ(mats.size(), 2u);
  EXPECT_EQ(mats[0].sampler, 2);  // a = 1, b = 2
  EXPECT_EQ(mats[0].filter.filter, FilterMode::Trilinear);
  EXPECT_EQ(mats[0].filter.compare, CompareOp::Less);
  EXPECT_EQ(mats[0].lod.lod_bias, 1.5f);
  ASSERT_NE(mats[0].samplers, nullptr);
  EXPECT_EQ((*mats[0].samplers)[0].name, "a");
  EXPECT_EQ(mats[1].sampler, 0);  // its own (default) filter and LOD
  EXPECT_EQ(mats[1].filter.filter, FilterMode::Bilinear);
}

TEST(SamplerState, BadSamplerKeysNameFileLineAndColumn) {
  const std::string head(kHead);
  const std::string m = "[materials.m]\ntexture = \"t\"\n";  // lines 10-11
  std::string e = error_of(head + "[samplers.c]\nmdoe = \"nearest\"\n" + m);
  EXPECT_NE(e.find("s.toml:11:"), std::string::npos) << e;
  EXPECT_NE(e.find("mdoe"), std::string::npos) << e;
  e = error_of(head + "[samplers.c]\noffset = [1, 0]\n" + m);
  EXPECT_NE(e.find("s.toml:11:"), std::string::npos) << e;
  EXPECT_NE(e.find("instruction"), std::string::npos) << e;
  e = error_of(head + m + "sampler = \"zz\"\n");
  EXPECT_NE(e.find("s.toml:12:"), std::string::npos) << e;
  EXPECT_NE(e.find("no sampler named 'zz' (samplers: 'a', 'b')"), std::string::npos) << e;
  e = error_of(head + m + "sampler = \"a\"\nfilter = { mode = \"bilinear\" }\n");
  EXPECT_NE(e.find("s.toml:13:"), std::string::npos) << e;
  e = error_of(head + m + "operation = { op = \"gather\", lod = 1.0 }\n");
  EXPECT_NE(e.find("only with op = \"lod\""), std::string::npos) << e;
  e = error_of(head + m + "operation = { op = \"lod\", lod = nan }\n");
  EXPECT_NE(e.find("finite"), std::string::npos) << e;
  e = error_of(head + m + "operation = { op = \"sample\", offset = [9, 0] }\n");
  EXPECT_NE(e.find("[-8, 7]"), std::string::npos) << e;
  e = error_of(head + "[samplers.c]\nunnormalized = true\nmax_lod = 0.0\n" + m +
               "sampler = \"c\"\n");
  EXPECT_NE(e.find("address \"clamp\" or \"border\""), std::string::npos) << e;
  e = error_of(head + "[samplers.c]\nunnormalized = true\naddress = \"clamp\"\n" + m);
  EXPECT_NE(e.find("max_lod = 0"), std::string::npos) << e;
  e = error_of(head +
               "[samplers.c]\nunnormalized = true\naddress = \"clamp\"\nmax_lod = 0.0\n"
               "mode = \"trilinear\"\n" +
               m);
  EXPECT_NE(e.find("s.toml:14:"), std::string::npos) << e;
  e = error_of(head + "[samplers.c]\nunnormalized = true\naddress = \"border\"\nmax_lod = 0.0\n" +
               m + "sampler = \"c\"\noperation = { op = \"gather\" }\n");
  EXPECT_NE(e.find("unnormalised"), std::string::npos) << e;
  // An unnormalised sampler with the implicit-LOD sample, asked by default or by name: refused
  // at the material's key (Vulkan allows no ImplicitLod instruction there).
  const std::string texel =
      "[samplers.c]\nunnormalized = true\naddress = \"clamp\"\nmax_lod = 0.0\n";
  e = error_of(head + texel + m + "sampler = \"c\"\n");
  EXPECT_NE(e.find("s.toml:16:11:"), std::string::npos) << e;
  EXPECT_NE(e.find("implicit-LOD"), std::string::npos) << e;
  e = error_of(head + texel + m + "sampler = \"c\"\noperation = { op = \"sample\" }\n");
  EXPECT_NE(e.find("s.toml:17:13:"), std::string::npos) << e;
  EXPECT_NE(e.find("operation 'sample' (implicit LOD)"), std::string::npos) << e;
  // ... and on a layered texture, whatever the operation.
  e = error_of(head + texel +
               "[textures.arr]\ntype = \"2d_array\"\nlayers = [\"procedural:checker?size=8\"]\n" +
               "[materials.m]\ntexture = \"arr\"\nsampler = \"c\"\n"
               "operation = { op = \"lod\", lod = 0.0 }\n");
  EXPECT_NE(e.find("s.toml:19:11:"), std::string::npos) << e;
  EXPECT_NE(e.find("2d_array"), std::string::npos) << e;
  // A sampler that compares or reduces cannot read a layered texture (its paths have no
  // reducer): refused at the material's key, not ignored.
  const std::string arr =
      "[textures.arr]\ntype = \"2d_array\"\nlayers = [\"procedural:checker?size=8\"]\n";
  e = error_of(head + "[samplers.c]\ncompare = \"less\"\n" + arr +
               "[materials.m]\ntexture = \"arr\"\nsampler = \"c\"\n");
  EXPECT_NE(e.find("s.toml:17:11:"), std::string::npos) << e;
  EXPECT_NE(e.find("compares or reduces"), std::string::npos) << e;
  e = error_of(head + arr + "[materials.m]\ntexture = \"arr\"\nfilter = { reduction = \"max\" }\n");
  EXPECT_NE(e.find("s.toml:15:"), std::string::npos) << e;
  EXPECT_NE(e.find("2d_array"), std::string::npos) << e;
  // A gather of a 3-D texture: refused at the material's operation, not at run time.
  e = error_of(head +
               "[textures.vol]\ntype = \"3d\"\nlayers = [\"procedural:checker?size=8\", "
               "\"procedural:checker?size=8\"]\n[materials.m]\ntexture = \"vol\"\n"
               "operation = { op = \"gather\" }\n");
  EXPECT_NE(e.find("s.toml:15:"), std::string::npos) << e;
  EXPECT_NE(e.find("a gather reads 2-D and cube images only"), std::string::npos) << e;
  // A footprint filter on a layered texture: refused at the material's texture key.
  e = error_of(head + arr + "[materials.m]\ntexture = \"arr\"\newa = { weight = \"lut\" }\n");
  EXPECT_NE(e.find("s.toml:14:"), std::string::npos) << e;
  EXPECT_NE(e.find("samples 2-D textures only"), std::string::npos) << e;
  // A good unnormalised sampler is accepted.
  EXPECT_EQ(error_of(head +
                     "[samplers.c]\nunnormalized = true\naddress = \"clamp\"\n"
                     "max_lod = 0.0\n" +
                     m + "sampler = \"c\"\noperation = { op = \"lod\", lod = 0.0 }\n"),
            "");
}

TEST(SamplerState, UnnormalizedTapsAreTheNormalisedOnesInTexels) {
  const Texture tex = coded_texture();
  TexelAddressGen::Config c;
  c.address_u = c.address_v = AddressMode::Clamp;
  for (const FilterMode mode : {FilterMode::Nearest, FilterMode::Bilinear}) {
    c.filter = mode;
    const TexelAddressGen gen(c);
    for (const double x : {-3.0, 0.0, 0.25, 1.5, 3.75, 7.5, 8.0, 11.0}) {
      const double y = 8.0 - x;
      FilterTaps a, b;
      UnnormalizedTaps::taps(c, tex, x, y, a);
      gen.taps(tex, x / 8, y / 8, LodResult{}, b);  // exact: a power-of-two size
      ASSERT_EQ(a.count, b.count);
      for (int k = 0; k < a.count; ++k) {
        EXPECT_EQ(a.tap[k].x, b.tap[k].x) << x;
        EXPECT_EQ(a.tap[k].y, b.tap[k].y) << x;
        EXPECT_EQ(a.tap[k].w, b.tap[k].w) << x;
        EXPECT_EQ(a.tap[k].level, 0);
      }
      // Scaled twice (texels read as normalised), the taps land elsewhere.
      FilterTaps twice;
      gen.taps(tex, x, y, LodResult{}, twice);
      if (x == 1.5) {
        EXPECT_NE(twice.tap[0].x, a.tap[0].x);
      }
    }
  }
  // Far outside: clamped, or the border colour with no texel read; NaN reads as 0.
  c.filter = FilterMode::Bilinear;
  c.address_u = c.address_v = AddressMode::Border;
  c.border = Rgba(0, 0, 1, 1);
  FilterTaps t;
  UnnormalizedTaps::taps(c, tex, 1e30, -1e30, t);
  EXPECT_EQ(t.border_taps, 4);
  EXPECT_EQ(t.border, Rgba(0, 0, 1, 1));
  UnnormalizedTaps::taps(c, tex, std::nan(""), 0.5, t);
  EXPECT_EQ(t.border_taps, 2);  // u = 0 → i0 = −1
  TexelAddressGen::Config nearest = c;
  nearest.filter = FilterMode::Nearest;
  EXPECT_EQ(UnnormalizedTaps::ops_per_item(c).mul, 4u);  // the bilinear weights
  EXPECT_EQ(UnnormalizedTaps::ops_per_item(nearest).mul, 0u);
}

MaterialSetup material(const char* name, FilterMode mode, AddressMode a) {
  MaterialSetup m;
  m.name = name;
  m.filter.filter = mode;
  m.filter.address_u = m.filter.address_v = a;
  return m;
}

TEST(SamplerState, AFragmentPicksASamplerAsIfItWereItsMaterials) {
  for (const bool timing : {false, true}) {
    TextureSet set;
    set.add(coded_texture());
    // Material 0 bilinear wrap (its own); the table: 1 = nearest clamp, 2 = trilinear mirror
    // with a bias; material 1 is sampler 2 itself, material 2 sampler 1 itself.
    auto table = std::make_shared<SamplerTable>();
    table->push_back({"a", material("", FilterMode::Nearest, AddressMode::Clamp).filter, {}});
    table->push_back({"b", material("", FilterMode::Trilinear, AddressMode::Mirror).filter, {}});
    (*table)[1].lod.lod_bias = 0.75f;
    std::vector<MaterialSetup> mats = {material("own", FilterMode::Bilinear, AddressMode::Wrap),
                                       material("b", FilterMode::Trilinear, AddressMode::Mirror),
                                       material("a", FilterMode::Nearest, AddressMode::Clamp)};
    mats[1].lod.lod_bias = 0.75f;
    mats[1].sampler = 2;
    mats[2].sampler = 1;
    for (auto& m : mats) m.samplers = table;
    TextureUnit unit(set, mats, PipelineSetup{}, TechTable::defaults(), timing);
    Fragment f;
    f.u = 1.13;
    f.v = -0.37;
    f.dudx = f.dvdy = 0.3;
    const Rgba own = unit.process(f, 0);
    for (const uint16_t s : {uint16_t{1}, uint16_t{2}}) {
      f.sampler = s;
      const Rgba picked = unit.process(f, 0);
      f.sampler = 0;
      const Rgba direct = unit.process(f, s == 1 ? 2 : 1);
      EXPECT_EQ(picked, direct) << s;
      EXPECT_NE(picked, own) << s;
      // Its material's own id is its own sampler.
      f.sampler = s;
      EXPECT_EQ(unit.process(f, s == 1 ? 2 : 1), direct) << s;
      f.sampler = 0;
    }
    EXPECT_EQ(unit.material_fragments(0), 3u);  // counted in the material that drew them
    f.sampler = 3;
    EXPECT_THROW(unit.process(f, 0), std::invalid_argument);
  }
}

TEST(SamplerState, AFragmentsOwnOffsetsAreAppliedBeforeWrapping) {
  TextureSet set;
  set.add(coded_texture());
  std::vector<MaterialSetup> mats = {material("plain", FilterMode::Bilinear, AddressMode::Wrap),
                                     material("offset", FilterMode::Bilinear, AddressMode::Wrap)};
  mats[1].filter.offset_u = 3;
  mats[1].filter.offset_v = -2;
  TextureUnit unit(set, mats, PipelineSetup{}, TechTable::defaults(), true);
  Fragment f;
  f.u = 0.9;
  f.v = 0.05;
  f.dudx = f.dvdy = 1.0 / 8;
  const Rgba offset = unit.process(f, 1);
  for (const uint8_t op : {uint8_t{0}, static_cast<uint8_t>(SampleOp::kSampleLod),
                           static_cast<uint8_t>(SampleOp::kSampleGrad)}) {
    Fragment g = f;
    g.op = op;
    g.offset_u = 3;
    g.offset_v = -2;
    const Rgba a = unit.process(g, 0);
    EXPECT_EQ(a, offset) << int{op};
    g.offset_u = 0;
    EXPECT_NE(unit.process(g, 0), a) << int{op};
  }
  // An explicit-LOD fragment's offsets add to the material's own.
  Fragment g = f;
  g.op = static_cast<uint8_t>(SampleOp::kSampleLod);
  g.offset_u = -3;
  g.offset_v = 2;
  EXPECT_EQ(unit.process(g, 1), unit.process(f, 0));
}

TEST(SamplerState, AnUnnormalisedSamplerReadsLevelZeroAtTexelCoordinates) {
  TextureSet set;
  set.add(coded_texture());
  std::vector<MaterialSetup> mats = {material("texel", FilterMode::Bilinear, AddressMode::Clamp),
                                     material("norm", FilterMode::Bilinear, AddressMode::Clamp)};
  mats[0].filter.unnormalized = true;
  mats[0].lod.max_lod = 0;
  mats[1].lod.max_lod = 0;
  TextureUnit unit(set, mats, PipelineSetup{}, TechTable::defaults(), true);
  Fragment f;
  f.u = 2.75;
  f.v = 5.5;
  f.dudx = f.dvdy = 4;  // would pick a coarse level if it were used
  Fragment n = f;
  n.u = f.u / 8;
  n.v = f.v / 8;
  // Vulkan refuses the implicit-LOD sample on an unnormalised sampler; explicit LOD 0 reads.
  EXPECT_THROW(unit.process(f, 0), std::invalid_argument);
  f.op = static_cast<uint8_t>(SampleOp::kSampleLod);
  EXPECT_EQ(unit.process(f, 0), unit.process(n, 1));
  f.lod = 1;
  EXPECT_THROW(unit.process(f, 0), std::invalid_argument);
  f.lod = 0;
  f.op = static_cast<uint8_t>(SampleOp::kGather);
  EXPECT_THROW(unit.process(f, 0), std::invalid_argument);
  f.op = 0;
  f.offset_u = 1;
  EXPECT_THROW(unit.process(f, 0), std::invalid_argument);
  EXPECT_EQ(unit.material_op_tallies(0)[1].taps, 4u);
}

}  // namespace
}  // namespace texsim
