// `filter.arithmetic = "fixed"`: the texture unit's functional path takes FixedSampler's colour
// for the materials it covers; "float" (the default) leaves the unit as it was; materials and
// textures it does not cover are refused with the key's file:line:column.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "pipeline/texture/effect_registry.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {
namespace {

MaterialSetup parse(const std::string& text) {
  static std::vector<std::shared_ptr<toml::table>> keep;  // the reader points into the table
  keep.push_back(std::make_shared<toml::table>(toml::parse(text, std::string_view("m.toml"))));
  return material_from_toml("m", 0, *keep.back(), "m.toml");
}

Texture noise_texture(int w, int h, TexelFormat format) {
  std::mt19937 rng(29);
  std::vector<float> rgba(static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
  for (float& c : rgba) c = static_cast<float>(rng() % 256) / 255.0f;
  return Texture::from_rgba("noise", w, h, rgba, format, true);
}

uint32_t rgba8(const Rgba& c) {
  uint32_t v = 0;
  for (int k = 0; k < 4; ++k) {
    const auto b = static_cast<uint32_t>(std::lrint(c[k] * 255.0f));
    v |= b << (8 * k);
  }
  return v;
}

TEST(FixedArithmetic, KeyParsedDefaultFloat) {
  EXPECT_FALSE(parse("filter = { mode = \"trilinear\" }\n").filter.fixed_arithmetic);
  const MaterialSetup m = parse("filter = { mode = \"trilinear\", arithmetic = \"fixed\" }\n");
  EXPECT_TRUE(m.filter.fixed_arithmetic);
  EXPECT_EQ(m.arithmetic_where, "m.toml:1:45");
}

TEST(FixedArithmetic, UncoveredSettingsRefusedAtTheKey) {
  auto refused = [](const std::string& text, const std::string& why) {
    try {
      parse(text);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("m.toml:1:"), std::string::npos) << what;
      EXPECT_NE(what.find("filter.arithmetic"), std::string::npos) << what;
      EXPECT_NE(what.find(why), std::string::npos) << what;
    }
  };
  refused("filter = { mode = \"nearest\", arithmetic = \"fixed\" }\n", "nearest");
  refused("filter = { address = \"border\", arithmetic = \"fixed\" }\n", "border");
  refused("filter = { reduction = \"min\", arithmetic = \"fixed\" }\n", "reduction");
  refused("filter = { arithmetic = \"fixed\" }\nlod = { aniso = \"vulkan\" }\n", "anisotropic");
  refused("filter = { arithmetic = \"fixed\" }\newa = {}\n", "footprint");
  refused("filter = { arithmetic = \"double\" }\n", "arithmetic");
}

TEST(FixedArithmetic, UnitColoursAreFixedSamplers) {
  const MaterialSetup fl = parse("filter = { mode = \"trilinear\", address = \"mirror\" }\n");
  const MaterialSetup fx =
      parse("filter = { mode = \"trilinear\", address = \"mirror\", arithmetic = \"fixed\" }\n");
  TextureSet set;
  set.add(noise_texture(37, 64, TexelFormat::Rgba8));
  const TechTable tech = TechTable::defaults();
  TextureUnit unit(set, {fl, fx}, PipelineSetup{}, tech, false);
  EXPECT_FALSE(unit.material_fixed(0));
  EXPECT_TRUE(unit.material_fixed(1));
  const FixedSampler fs(FixedSampler::config_of(fx.filter, fx.lod));
  const FixedSampler::TextureDesc desc = FixedSampler::describe(set[0]);
  const std::vector<uint32_t> mem = FixedSampler::memory_image(set[0]);
  std::mt19937_64 rng(2929);
  std::uniform_real_distribution<double> coord(-2.0, 2.0), lg(-9.0, 0.0), d(-1.0, 1.0);
  int equal = 0, float_equal = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    Fragment f;
    f.u = coord(rng);
    f.v = coord(rng);
    const double s = std::exp2(lg(rng));
    f.dudx = s * d(rng);
    f.dvdx = s * d(rng);
    f.dudy = s * d(rng);
    f.dvdy = s * d(rng);
    const FixedSampler::Result r = fs.sample(FixedSampler::to_input(f), desc, mem);
    const uint32_t got = rgba8(unit.process(f, 1));
    equal += got == r.rgba && unit.last_fixed().addr == r.addr;
    float_equal += rgba8(unit.process(f, 0)) == r.rgba;
  }
  EXPECT_EQ(equal, n);
  // The float path differs by an LSB on some fragments: the key changes what the unit computes.
  EXPECT_LT(float_equal, n);
  EXPECT_EQ(unit.material_fragments(1), static_cast<uint64_t>(n));
}

TEST(FixedArithmetic, UncoveredTextureOrFragmentRefused) {
  const MaterialSetup fx = parse("filter = { mode = \"bilinear\", arithmetic = \"fixed\" }\n");
  const TechTable tech = TechTable::defaults();
  {
    TextureSet set;
    set.add(noise_texture(16, 16, TexelFormat::Rgba32f));
    try {
      TextureUnit unit(set, {fx}, PipelineSetup{}, tech, false);
      ADD_FAILURE() << "an RGBA32F texture was accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("m.toml:1:"), std::string::npos) << what;
      EXPECT_NE(what.find("rgba8"), std::string::npos) << what;
    }
  }
  TextureSet set;
  set.add(noise_texture(16, 16, TexelFormat::Rgba8));
  TextureUnit unit(set, {fx}, PipelineSetup{}, tech, false);
  Fragment f;
  f.u = f.v = 0.3;
  f.lod_bias = 0.5f;
  EXPECT_THROW(unit.process(f, 0), InputError);
  f.lod_bias = 0;
  EXPECT_NO_THROW(unit.process(f, 0));
}

}  // namespace
}  // namespace texsim
