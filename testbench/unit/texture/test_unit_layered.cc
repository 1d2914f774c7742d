// The texture unit on layered textures: a cube map's fragments (direction in u, v, w) through
// the face selector and the seamless edge unit, an array's through the layer selector; the
// batched datapath leaves them to the one-by-one path with the same results; the report's rows
// count the face selector's and the layer selector's operations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "pipeline/texture/texture_unit.h"

namespace texsim {
namespace {

// Face f of cube c is the constant colour (f / 8, c, 0.25, 1); layer l of the array (l / 8).
TextureSet layered_set() {
  TextureSet set;
  std::vector<float> flat(size_t{16} * 16 * 4, 0.5f);
  set.add(Texture::from_rgba("flat", 16, 16, flat, TexelFormat::Rgba32f, true));
  std::vector<std::vector<float>> faces;
  for (int c = 0; c < 2; ++c) {
    for (int f = 0; f < 6; ++f) {
      std::vector<float> px(size_t{8} * 8 * 4);
      for (size_t i = 0; i < px.size(); i += 4) {
        px[i] = static_cast<float>(f) / 8;
        px[i + 1] = static_cast<float>(c);
        px[i + 2] = 0.25f;
        px[i + 3] = 1;
      }
      faces.push_back(px);
    }
  }
  set.add(Texture::from_slices("sky", TextureType::Cube, 8, 8, faces, TexelFormat::Rgba32f, true));
  std::vector<std::vector<float>> layers;
  layers.reserve(4);
  for (int l = 0; l < 4; ++l) layers.emplace_back(size_t{8} * 4 * 4, static_cast<float>(l) / 8);
  set.add(
      Texture::from_slices("arr", TextureType::Array, 8, 4, layers, TexelFormat::Rgba32f, true));
  return set;
}

MaterialSetup material(FilterMode f, bool seamless) {
  MaterialSetup m;
  m.name.push_back('m');  // (not `= "m"`: GCC 12's false -Wrestrict once inlined)
  m.filter.filter = f;
  m.filter.address_u = m.filter.address_v = AddressMode::Clamp;
  m.filter.seamless_cube = seamless;
  return m;
}

Fragment cube_frag(double x, double y, double z, float cube = 0) {
  Fragment f;
  f.tex = 1;
  f.u = x;
  f.v = y;
  f.w = z;
  f.dudx = f.dvdy = 0.01;
  f.layer = cube;
  return f;
}

TEST(UnitLayered, CubeFacesAndCubeArrayLayers) {
  TextureSet set = layered_set();
  TextureUnit unit(set, {material(FilterMode::Bilinear, true)}, PipelineSetup{},
                   TechTable::defaults(), true);
  // Face centres read their face's colour; the cube array's layer picks the cube.
  const double d[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int f = 0; f < 6; ++f) {
    const Rgba c = unit.process(cube_frag(d[f][0], d[f][1], d[f][2], 1.4f), 0);
    EXPECT_FLOAT_EQ(c.x, static_cast<float>(f) / 8) << f;
    EXPECT_FLOAT_EQ(c.y, 1.0f);
  }
  // Out-of-range cube index clamps; NaN reads cube 0.
  EXPECT_FLOAT_EQ(unit.process(cube_frag(0, 0, 1, 1e30f), 0).y, 1.0f);
  EXPECT_FLOAT_EQ(unit.process(cube_frag(0, 0, 1, std::nanf("")), 0).y, 0.0f);
  // The +X/+Y edge (a tie: +Y is selected) reads half +X, half +Y when seamless.
  const Rgba e = unit.process(cube_frag(1, 1, 0.2), 0);
  EXPECT_NEAR(e.x, (0.0f + 2.0f) / 16, 1e-5f);
  // A zero direction and a non-finite one filter without NaN.
  for (const Fragment& f : {cube_frag(0, 0, 0), cube_frag(std::nan(""), 1e300, -1e300)}) {
    const Rgba c = unit.process(f, 0);
    for (int k = 0; k < 4; ++k) EXPECT_TRUE(std::isfinite(c[k]));
  }
  bool row = false;
  for (const BlockUse& b : unit.blocks()) {
    if (b.name != "cube.face_select") continue;
    row = true;
    // 11 fragments selected a face; the edge one moved 2 taps to +X.
    EXPECT_EQ(b.ops.rcp, 11u);
    EXPECT_EQ(b.ops.cmp, 11 * CubeFaceSelect::ops_per_item().cmp +
                             2 * LayeredAddressGen::ops_per_edge_tap().cmp);
  }
  EXPECT_TRUE(row);
  EXPECT_GT(unit.cycles(), 0u);
}

TEST(UnitLayered, NonSeamlessStaysOnTheFace) {
  TextureSet set = layered_set();
  TextureUnit unit(set, {material(FilterMode::Bilinear, false)}, PipelineSetup{},
                   TechTable::defaults(), false);
  const Rgba e = unit.process(cube_frag(1, 1, 0.2), 0);
  EXPECT_FLOAT_EQ(e.x, 2.0f / 8);  // +Y only
}

TEST(UnitLayered, ArrayLayersRoundHalfToEven) {
  TextureSet set = layered_set();
  TextureUnit unit(set, {material(FilterMode::Trilinear, true)}, PipelineSetup{},
                   TechTable::defaults(), true);
  Fragment f;
  f.tex = 2;
  f.u = 0.3;
  f.v = 0.6;
  f.dudx = f.dvdy = 0.2;
  const float layer[] = {0.5f, 1.5f, 2.5f, -4.0f, 1e20f, 2.49f};
  const float want[] = {0, 2, 2, 0, 3, 2};
  for (size_t i = 0; i < std::size(layer); ++i) {
    f.layer = layer[i];
    EXPECT_FLOAT_EQ(unit.process(f, 0).x, want[i] / 8) << layer[i];
  }
  bool row = false;
  for (const BlockUse& b : unit.blocks()) row = row || b.name == "array.layer_select";
  EXPECT_TRUE(row);
}

// A record's sampler (Fragment::sampler, an id of the material's sampler table) is the one a
// layered fragment is read with: a non-seamless sampler keeps a cube's edge on one face, a
// border sampler reads the border colour off an array layer, an unnormalised one is refused.
TEST(UnitLayered, RecordsSamplerIsHonoured) {
  TextureSet set = layered_set();
  MaterialSetup m = material(FilterMode::Bilinear, true);
  auto table = std::make_shared<SamplerTable>(3);
  (*table)[0].name = "flat_faces";
  (*table)[0].filter = m.filter;
  (*table)[0].filter.seamless_cube = false;
  (*table)[1].name = "edge";
  (*table)[1].filter = m.filter;
  (*table)[1].filter.address_u = (*table)[1].filter.address_v = AddressMode::Border;
  (*table)[1].filter.border = Rgba(1.0f, 0.5f, 0.0f, 1.0f);
  (*table)[2].name = "texel";
  (*table)[2].filter = m.filter;
  (*table)[2].filter.unnormalized = true;
  (*table)[2].lod.max_lod = 0;
  m.samplers = table;
  TextureUnit unit(set, {m}, PipelineSetup{}, TechTable::defaults(), true);
  Fragment e = cube_frag(1, 1, 0.2);
  EXPECT_NEAR(unit.process(e, 0).x, (0.0f + 2.0f) / 16, 1e-5f);  // seamless: half +X, half +Y
  e.sampler = 1;
  EXPECT_FLOAT_EQ(unit.process(e, 0).x, 2.0f / 8);  // its own sampler: +Y only
  Fragment a;
  a.tex = 2;
  a.u = -0.5;
  a.v = 0.5;
  a.dudx = a.dvdy = 0.01;
  a.layer = 2;
  EXPECT_FLOAT_EQ(unit.process(a, 0).x, 2.0f / 8);  // clamp: the layer's edge texels
  a.sampler = 2;
  EXPECT_FLOAT_EQ(unit.process(a, 0).x, 1.0f);  // border: the sampler's colour
  EXPECT_FLOAT_EQ(unit.process(a, 0).y, 0.5f);
  a.sampler = 3;
  a.op = 1;  // explicit LOD 0, which a 2-D texture would serve
  EXPECT_THROW(unit.process(a, 0), std::invalid_argument);
  a.sampler = 4;
  EXPECT_THROW(unit.process(a, 0), std::invalid_argument);
}

TEST(UnitLayered, BatchedPathLeavesLayeredFragmentsToTheScalarPath) {
  std::vector<Fragment> frags;
  for (int i = 0; i < 300; ++i) {
    const double a = i * 0.05;
    Fragment f = i % 3 == 0 ? Fragment{} : cube_frag(std::cos(a), std::sin(a * 0.7), std::sin(a));
    f.x = static_cast<uint32_t>(i % 20);
    f.y = static_cast<uint32_t>(i / 20);
    if (i % 3 == 0) {
      f.u = a * 0.1;
      f.v = 0.3;
      f.dudx = f.dvdy = 1.0 / 16;
    }
    frags.push_back(f);
  }
  TextureSet s1 = layered_set(), s2 = layered_set();
  TextureUnit one(s1, {material(FilterMode::Trilinear, true)}, PipelineSetup{},
                  TechTable::defaults(), true);
  TextureUnit batch(s2, {material(FilterMode::Trilinear, true)}, PipelineSetup{},
                    TechTable::defaults(), true);
  std::vector<Rgba> a(frags.size()), b(frags.size());
  for (size_t i = 0; i < frags.size(); ++i) a[i] = one.process(frags[i], 0);
  batch.process_batch(frags.data(), frags.size(), 0, b.data());
  for (size_t i = 0; i < frags.size(); ++i) {
    for (int k = 0; k < 4; ++k) EXPECT_EQ(a[i][k], b[i][k]) << i;
  }
  EXPECT_EQ(one.cycles(), batch.cycles());
  EXPECT_EQ(one.cache().stats().hits, batch.cache().stats().hits);
}

}  // namespace
}  // namespace texsim
