// The draw renderer and the colour stage on hand-made draws whose images are known exactly:
// the fill rule on a shared diagonal through pixel centres, culling, depth, near clipping, the
// mip level the exact derivatives select, texture orientation, alpha test, refused state, and
// the colour stage's equations.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "blocks/base/input_error.h"
#include "pipeline/render/colour_stage.h"
#include "pipeline/render/draw_fragment_trace.h"
#include "pipeline/render/draw_renderer.h"
#include "pipeline/render/frame_compare.h"
#include "testbench/lib/temp_dir.h"
#include "traces/trace_file.h"

namespace texsim {
namespace {

constexpr int kSize = 8;  // the viewport, kSize x kSize

// One colour per level (RGBA8) of a size x size texture with every level.
DrawTexture levels_texture(uint32_t id, uint32_t size,
                           const std::vector<std::array<uint8_t, 4>>& colours) {
  DrawTexture t;
  t.id = id;
  t.width = t.height = size;
  t.name = "test";
  for (uint32_t l = 0; (size >> l) >= 1; ++l) {
    const uint32_t n = (size >> l) * (size >> l);
    std::vector<uint8_t> px;
    for (uint32_t i = 0; i < n; ++i) px.insert(px.end(), colours[l].begin(), colours[l].end());
    t.levels.push_back(px);
  }
  return t;
}

// A quad over NDC [x0, x1] x [y0, y1] at depth z, every coordinate times w, s and t from 0 to
// s1, t1, counter-clockwise (front-facing) unless `cw`.
Draw quad(double x0, double y0, double x1, double y1, float z, std::array<uint8_t, 4> colour,
          float w = 1, float s1 = 1, float t1 = 1, bool cw = false) {
  Draw d;
  d.state.viewport_w = d.state.viewport_h = kSize;
  const double xs[4] = {x0, x1, x1, x0}, ys[4] = {y0, y0, y1, y1};
  const float ss[4] = {0, s1, s1, 0}, ts[4] = {0, 0, t1, t1};
  d.vertex_count = 4;
  for (int i = 0; i < 4; ++i) {
    d.position.insert(d.position.end(),
                      {static_cast<float>(xs[i]) * w, static_cast<float>(ys[i]) * w, z * w, w});
    d.st[0].insert(d.st[0].end(), {ss[i], ts[i]});
    d.color.insert(d.color.end(), colour.begin(), colour.end());
  }
  d.has_color = true;
  d.indices =
      cw ? std::vector<uint32_t>{0, 2, 1, 0, 3, 2} : std::vector<uint32_t>{0, 1, 2, 0, 2, 3};
  return d;
}

struct Rendered {
  RenderedFrame f;
  std::array<uint8_t, 4> at(int x, int y) const {  // image coordinates (top row 0)
    const size_t p = 4 * (static_cast<size_t>(y) * kSize + static_cast<size_t>(x));
    return {f.rgba[p], f.rgba[p + 1], f.rgba[p + 2], f.rgba[p + 3]};
  }
};

Rendered render(DrawTrace t) {
  if (t.textures.empty()) t.textures.push_back(levels_texture(0, 1, {{255, 255, 255, 255}}));
  static const toml::table kNone;
  DrawRenderer r(t, {0}, PipelineSetup::from_toml(kNone, "test"), TechTable::defaults(), false,
                 "test.draws");
  return {r.render(0)};
}

DrawTrace one_frame(std::vector<Draw> draws) {
  DrawTrace t;
  t.frames.push_back({7, std::move(draws), {}});
  return t;
}

TEST(DrawRenderer, SharedDiagonalThroughPixelCentresIsDrawnOnce) {
  // The quad's diagonal runs through the centres of (i, i); with ONE/ONE blending a pixel
  // covered by both triangles would come out twice as bright.
  Draw d = quad(-1, -1, 1, 1, 0, {60, 60, 60, 255});
  d.state.blend = true;
  d.state.blend_src = d.state.blend_dst = 1;
  const Rendered r = render(one_frame({d}));
  EXPECT_EQ(r.f.counts.fragments, 64u);
  EXPECT_EQ(r.f.counts.written, 64u);
  EXPECT_EQ(r.f.counts.blended, 64u);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) EXPECT_EQ(r.at(x, y)[0], 60) << x << "," << y;
}

TEST(DrawRenderer, BackFacesAreCulled) {
  Draw d = quad(-1, -1, 1, 1, 0, {200, 0, 0, 255}, 1, 1, 1, /*cw=*/true);
  d.state.cull = true;  // cull BACK, front CCW
  Rendered r = render(one_frame({d}));
  EXPECT_EQ(r.f.counts.culled, 2u);
  EXPECT_EQ(r.f.counts.written, 0u);
  d.state.front_face = gl::kCw;  // now it faces the viewer
  r = render(one_frame({d}));
  EXPECT_EQ(r.f.counts.culled, 0u);
  EXPECT_EQ(r.f.counts.written, 64u);
}

TEST(DrawRenderer, DepthTestKillsTheFartherQuad) {
  Draw nearq = quad(-1, -1, 1, 1, 0, {255, 0, 0, 255});
  nearq.state.depth_test = true;
  Draw farq = quad(-1, -1, 1, 1, 0.5f, {0, 255, 0, 255});
  farq.state.depth_test = true;
  Draw nearer = quad(-1, -1, 0, 1, -0.5f, {0, 0, 255, 255});  // the left half
  nearer.state.depth_test = true;
  const Rendered r = render(one_frame({nearq, farq, nearer}));
  EXPECT_EQ(r.f.counts.depth_killed, 64u);
  EXPECT_EQ(r.at(6, 3), (std::array<uint8_t, 4>{255, 0, 0, 255}));
  EXPECT_EQ(r.at(1, 3), (std::array<uint8_t, 4>{0, 0, 255, 255}));
}

TEST(DrawRenderer, ExactDerivativesSelectTheMipLevel) {
  // 32 texels over 8 pixels: ρ = 4, λ = 2 under any w; NEAREST_MIPMAP_NEAREST gives level 2.
  const std::vector<std::array<uint8_t, 4>> c = {{255, 0, 0, 255},   {0, 255, 0, 255},
                                                 {0, 0, 255, 255},   {255, 255, 0, 255},
                                                 {0, 255, 255, 255}, {255, 0, 255, 255}};
  for (float w : {1.0f, 3.0f}) {
    Draw d = quad(-1, -1, 1, 1, 0, {255, 255, 255, 255}, w);
    DrawUnit u;
    u.min_filter = 0x2700;  // NEAREST_MIPMAP_NEAREST
    u.mag_filter = 0x2600;
    d.units.push_back(u);
    DrawTrace t = one_frame({d});
    t.textures.push_back(levels_texture(0, 32, c));
    const Rendered r = render(t);
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) EXPECT_EQ(r.at(x, y), c[2]) << x << "," << y << " w " << w;
  }
}

TEST(DrawRenderer, TextureRowZeroIsAtTZero) {
  // A 2x2 texture, nearest: t = 0 is the bottom of the quad, so the first texel row (GL order)
  // lands on the image's bottom rows.
  DrawTexture tex;
  tex.id = 0;
  tex.width = tex.height = 2;
  tex.levels.push_back({255, 0, 0, 255, 0, 255, 0, 255,  // row t = 0: red, green
                        0, 0, 255, 255, 255, 255, 255, 255});
  Draw d = quad(-1, -1, 1, 1, 0, {255, 255, 255, 255});
  DrawUnit u;
  u.min_filter = u.mag_filter = 0x2600;
  u.wrap_s = u.wrap_t = 0x812F;
  d.units.push_back(u);
  DrawTrace t = one_frame({d});
  t.textures.push_back(tex);
  const Rendered r = render(t);
  EXPECT_EQ(r.at(0, kSize - 1), (std::array<uint8_t, 4>{255, 0, 0, 255}));
  EXPECT_EQ(r.at(kSize - 1, kSize - 1), (std::array<uint8_t, 4>{0, 255, 0, 255}));
  EXPECT_EQ(r.at(0, 0), (std::array<uint8_t, 4>{0, 0, 255, 255}));
}

TEST(DrawRenderer, NearPlaneClipsInClipSpace) {
  Draw d;
  d.state.viewport_w = d.state.viewport_h = kSize;
  d.vertex_count = 3;
  // One vertex behind the eye (w < 0): only the part with z >= -w is drawn.
  d.position = {-1, -1, 0, 1, 1, -1, 0, 1, 0, 3, -3, -1};
  d.indices = {0, 1, 2};
  Rendered r = render(one_frame({d}));
  EXPECT_EQ(r.f.counts.clipped_away, 0u);
  EXPECT_GT(r.f.counts.written, 0u);
  EXPECT_LT(r.f.counts.written, 64u);
  d.position = {-1, -1, -3, -1, 1, -1, -3, -1, 0, 1, -3, -1};  // wholly behind
  r = render(one_frame({d}));
  EXPECT_EQ(r.f.counts.clipped_away, 1u);
  EXPECT_EQ(r.f.counts.written, 0u);
}

TEST(DrawRenderer, AlphaTestAndRefusedState) {
  Draw d = quad(-1, -1, 1, 1, 0, {255, 255, 255, 0});
  d.state.alpha_test = true;
  d.state.alpha_func = gl::kGreater;
  d.state.alpha_ref = 0;
  Rendered r = render(one_frame({d}));
  EXPECT_EQ(r.f.counts.alpha_killed, 64u);
  EXPECT_EQ(r.f.counts.written, 0u);
  Draw b = quad(-1, -1, 1, 1, 0, {255, 255, 255, 255});
  b.units.push_back(DrawUnit{});
  b.units[0].env_mode = gl::kBlend;
  r = render(one_frame({b}));
  EXPECT_EQ(r.f.counts.draws_refused, 1u);
  EXPECT_EQ(r.f.counts.refused.count("texture environment BLEND"), 1u);
  EXPECT_EQ(r.f.counts.written, 0u);
}

TEST(ColourStage, EnvironmentAndBlendEquations) {
  const Rgba in(0.5f, 0.25f, 1.0f, 0.5f), tex(0.5f, 1.0f, 0.0f, 0.25f);
  EXPECT_EQ(texture_env(gl::kModulate, in, tex), Rgba(0.25f, 0.25f, 0.0f, 0.125f));
  EXPECT_EQ(texture_env(gl::kReplace, in, tex), tex);
  EXPECT_EQ(texture_env(gl::kDecal, in, tex), Rgba(0.5f, 0.4375f, 0.75f, 0.5f));
  EXPECT_EQ(texture_env(gl::kAdd, in, tex), Rgba(1.0f, 1.0f, 1.0f, 0.125f));
  const Rgba dst(0.5f, 0.5f, 0.5f, 1.0f);
  EXPECT_EQ(blend(0x0306, 0, in, dst), Rgba(0.25f, 0.125f, 0.5f, 0.5f));  // DST_COLOR, ZERO
  EXPECT_EQ(blend(0x0302, 0x0303, in, dst), Rgba(0.5f, 0.375f, 0.75f, 0.75f));
  EXPECT_EQ(blend(1, 1, in, dst), Rgba(1.0f, 0.75f, 1.0f, 1.0f));  // clamped
  EXPECT_EQ(to_unorm8(0.5f), 128);                                 // 127.5 rounds up
  EXPECT_EQ(to_unorm8(1.5f / 255.0f), 2);
  EXPECT_EQ(to_unorm8(-1.0f), 0);
}

TEST(DrawRenderer, SamplerStateMapsToTexsimFilters) {
  std::string approx;
  DrawUnit u;
  u.min_filter = 0x2701;  // LINEAR_MIPMAP_NEAREST
  MaterialSetup m = material_for_sampler(u, 3, approx);
  EXPECT_EQ(m.filter.filter, FilterMode::Bilinear);
  EXPECT_EQ(m.texture, 3);
  EXPECT_EQ(approx, "");
  u.min_filter = 0x2601;  // LINEAR: level 0 only
  u.wrap_s = 0x2900;      // GL_CLAMP
  m = material_for_sampler(u, 0, approx);
  EXPECT_EQ(m.lod.max_lod, 0.0f);
  EXPECT_EQ(m.filter.address_u, AddressMode::Clamp);
  EXPECT_EQ(approx, "GL_CLAMP as CLAMP_TO_EDGE");
  u.max_anisotropy = 8;
  m = material_for_sampler(u, 0, approx);
  EXPECT_EQ(m.lod.aniso, AnisoMode::Vulkan);
  EXPECT_EQ(m.lod.max_aniso, 8);
}

}  // namespace
}  // namespace texsim

namespace texsim {
namespace {

// A 64x64 ramp, R = 4x and G = 4y at texel (x, y), every level by 2x2 averages (still ramps).
// Any symmetric filter reproduces a linear function, so the unit's texels and the truth agree
// wherever the map is near-affine over a pixel, and only if the truth follows the same map.
DrawTexture ramp_texture() {
  DrawTexture t;
  t.id = 0;
  t.width = t.height = 64;
  t.name = "ramp";
  for (uint32_t s = 64; s >= 1; s /= 2) {
    std::vector<uint8_t> px;
    const uint32_t k = 64 / s;
    for (uint32_t y = 0; y < s; ++y)
      for (uint32_t x = 0; x < s; ++x)
        px.insert(px.end(), {static_cast<uint8_t>(4 * (x * k) + 2 * (k - 1)),
                             static_cast<uint8_t>(4 * (y * k) + 2 * (k - 1)), 0, 255});
    t.levels.push_back(px);
  }
  return t;
}

// The quad tilted away from the viewer (w = 1 at the bottom, 3 at the top), 16 x 16 pixels
// over s, t in [0.25, 0.75]: a perspective map, texels about a pixel.
DrawTrace tilted_trace(uint32_t min_filter) {
  constexpr int kView = 16;
  Draw d;
  d.state.viewport_w = d.state.viewport_h = kView;
  const double xs[4] = {-1, 1, 1, -1}, ys[4] = {-1, -1, 1, 1};
  const float ws[4] = {1, 1, 3, 3}, ss[4] = {0.25f, 0.75f, 0.75f, 0.25f},
              ts[4] = {0.25f, 0.25f, 0.75f, 0.75f};
  d.vertex_count = 4;
  for (int i = 0; i < 4; ++i) {
    d.position.insert(d.position.end(), {static_cast<float>(xs[i]) * ws[i],
                                         static_cast<float>(ys[i]) * ws[i], 0, ws[i]});
    d.st[0].insert(d.st[0].end(), {ss[i], ts[i]});
  }
  d.indices = {0, 1, 2, 0, 2, 3};
  DrawUnit u;
  u.min_filter = min_filter;
  u.wrap_s = u.wrap_t = 0x812F;  // CLAMP_TO_EDGE
  u.env_mode = 0x1E01;           // REPLACE
  d.units.push_back(u);
  DrawTrace t;
  t.frames.push_back({3, {d}, {}});
  t.textures.push_back(ramp_texture());
  return t;
}

RenderedFrame tilted(bool truth, uint32_t min_filter) {
  const DrawTrace t = tilted_trace(min_filter);
  static const toml::table kNone;
  DrawRenderer r(t, {0}, PipelineSetup::from_toml(kNone, "test"), TechTable::defaults(), false,
                 "test.draws");
  if (truth) r.set_truth(PixelIntegrator(TruthPixel::Box, TruthSampling{}), 2);
  return r.render(0);
}

TEST(DrawRendererTruth, FollowsTheTrianglesPerspectiveMap) {
  const RenderedFrame f = tilted(true, 0x2703);
  ASSERT_TRUE(f.has_truth());
  EXPECT_EQ(f.accuracy.lookups, f.counts.lookups);
  EXPECT_GT(f.accuracy.lookups, 200u);
  // The unit's trilinear texel against the box integral of the ramp: a few 8-bit steps at
  // most (its 8-bit weights, the map's curvature over a pixel). A truth through a wrong map
  // (rows flipped, half a pixel off) is off by 4 or more steps per pixel of the ramp.
  EXPECT_LT(f.accuracy.max_abs, 3.0 / 255) << f.accuracy.max_abs * 255;
  EXPECT_GT(f.accuracy.psnr_db(), 50);
  EXPECT_GT(f.accuracy.samples, f.accuracy.lookups);  // the integral took several points
  EXPECT_EQ(f.truth_drawn, f.drawn);
  const FrameComparison c = compare_with_truth(f);
  EXPECT_EQ(c.drawn_both, f.counts.written);
  EXPECT_GT(c.psnr_db, 45);
}

TEST(DrawRendererTruth, MeasuresTheErrorOfACoarseFilter) {
  // Nearest texel, level 0 only: the truth (the same map) stays the ramp's integral, so the
  // error is that of nearest sampling, up to half a texel step (2 of 8-bit) and clearly above
  // the trilinear unit's.
  const RenderedFrame lin = tilted(true, 0x2703);
  const RenderedFrame nn = tilted(true, 0x2600);
  EXPECT_GT(nn.accuracy.mse(), 2 * lin.accuracy.mse());
  EXPECT_LT(nn.accuracy.psnr_db(), lin.accuracy.psnr_db());
}

TEST(DrawRendererTruth, OffLeavesTheFrameAsItWas) {
  const RenderedFrame with = tilted(true, 0x2703), without = tilted(false, 0x2703);
  EXPECT_FALSE(without.has_truth());
  EXPECT_EQ(without.accuracy.lookups, 0u);
  EXPECT_EQ(with.rgba, without.rgba);
  EXPECT_EQ(with.drawn, without.drawn);
}

TEST(DrawFragmentTrace, HoldsTheLookUpsTheUnitGetsAndItsTextures) {
  const TempDir dir("draw_fragment_trace");
  const std::string draws = dir.file("tilted.draws"), trc = dir.file("tilted.trc");
  DrawTrace t = tilted_trace(0x2703);
  write_draw_trace(draws, t);
  std::vector<Fragment> seen;
  {
    static const toml::table kNone;
    DrawRenderer r(t, {0}, PipelineSetup::from_toml(kNone, "test"), TechTable::defaults(), false,
                   "test.draws");
    r.set_lookup_observer([&](const Fragment& f) { seen.push_back(f); });
    r.render(0);
  }
  EXPECT_EQ(generate_draws_trace(draws, 0, 100, trc), seen.size());
  TraceHeader h;
  const std::vector<Fragment> got = read_trace(trc, &h);
  ASSERT_EQ(got.size(), seen.size());
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].frame, 3u);
    EXPECT_EQ(got[i].x, seen[i].x);
    EXPECT_EQ(got[i].y, seen[i].y);
    EXPECT_EQ(got[i].u, seen[i].u);
    EXPECT_EQ(got[i].dvdy, seen[i].dvdy);
  }
  ASSERT_EQ(h.textures.size(), 1u);
  ASSERT_TRUE(is_draws_source(h.textures[0].source));
  // The table's source loads the draw trace's own texture, levels included.
  DrawTextureCache cache;
  const Texture tex = cache.load(h.textures[0].source, "");
  EXPECT_EQ(tex.levels(), 7);
  EXPECT_EQ(tex.texel(1, 3, 0).r, texture_of_draw(t.textures[0]).texel(1, 3, 0).r);
  EXPECT_THROW(cache.load("draws:" + draws + "#9", ""), InputError);
  EXPECT_THROW(cache.load("draws:" + draws, ""), InputError);
  EXPECT_THROW(generate_draws_trace(draws, 4, 9, trc), InputError);  // no such frames
}

}  // namespace
}  // namespace texsim
