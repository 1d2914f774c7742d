// The coordinate front end inside the texture unit (pipeline/raster/scene_front_end.*): a
// material's `coords` unit computes every fragment's coordinates and derivatives, checked against
// the exact projective map of the plane; coverage and depth agree with the reference generator;
// occluded pixels cost front-end work only; bad `coords` tables are refused with the key named.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "blocks/base/input_error.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/raster/fragment_generator.h"
#include "pipeline/raster/scene_front_end.h"
#include "pipeline/scene/procedural_texture.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {
namespace {

// A grazing floor (and optionally a wall in front of part of it), one material.
std::string scene_text(const std::string& coords, bool wall,
                       const std::string& uv_offset = "[0.0, 0.0]") {
  std::string s = R"(
[output]
width = 160
height = 100
[camera]
position = [0.0, 1.0, 0.0]
look_at = [0.0, 0.3, -10.0]
fov_y = 60.0
[textures.t]
source = "procedural:checker?size=256&cells=8"
[materials.m]
texture = "t"
filter = { mode = "trilinear", address = "wrap" }
)";
  if (!coords.empty()) s += "coords = " + coords + "\n";
  s += R"(
[[planes]]
material = "m"
origin = [-6.0, 0.0, -0.5]
edge_u = [12.0, 0.0, 0.0]
edge_v = [0.0, 0.0, -40.0]
uv_scale = [3.0, 10.0]
uv_offset = )" +
       uv_offset + "\n";
  if (wall) {
    s += R"(
[[planes]]
material = "m"
origin = [-0.5, 0.0, -3.0]
edge_u = [1.0, 0.0, 0.0]
edge_v = [0.0, 2.0, 0.0]
)";
  }
  return s;
}

struct Drawn {
  std::vector<Fragment> frags;
  std::vector<bool> textured;
  FrontEndStats stats;
  std::vector<BlockUse> blocks;
  uint64_t cycles = 0;
  int front = 0;
};

Drawn draw(const Scene& scene, bool timing = true) {
  TextureSet textures;
  for (const auto& t : scene.textures) textures.add(load_texture(t.source, scene.base_dir));
  std::vector<MaterialSetup> mats;
  for (const auto& m : scene.materials)
    mats.push_back(material_from_toml(m.name, m.texture, *m.effects, scene.path));
  TextureUnit unit(textures, mats, PipelineSetup{}, scene.tech, timing);
  std::vector<PlaneProjection> maps;
  for (const auto& p : scene.primitives) maps.emplace_back(scene, p);
  Drawn d;
  d.front = unit.front_stages();
  draw_scene_front_end(scene, maps, unit, [&](const Fragment& f, int, const Rgba* c) {
    d.frags.push_back(f);
    d.textured.push_back(c != nullptr);
  });
  d.stats = unit.front_end_stats();
  d.blocks = unit.blocks();
  d.cycles = unit.cycles();
  return d;
}

// Largest distance in texels between a fragment's coordinate and the exact one, modulo the
// texture's period (the front end rebases wrapped coordinates by whole periods).
double wrapped_err(double got, double exact, double size) {
  const double e = std::fmod(std::fabs(got - exact) * size, size);
  return std::min(e, size - e);
}

struct Case {
  const char* coords;
  double max_uv_texels;  // bound on |u − u_exact| in texels
  double max_deriv_rel;  // bound on derivative error relative to the footprint (max |J|)
};

TEST(SceneFrontEnd, EveryMethodMatchesTheExactMapWithinItsBound) {
  // Bounds: the exact forms to their format's rounding; the whole-row quadratic to what
  // docs/studies/study-coords.md measures at this tilt (s16.16 is not usable at all with one map
  // per plane, see there; a separate test below shows the front end reports it).
  const Case cases[] = {
      {"{ method = 'heckbert', derivs = 'analytic', format = 'double' }", 1e-9, 1e-9},
      {"{ method = 'heckbert-rcp', derivs = 'analytic', format = 'float' }", 2e-3, 1e-3},
      {"{ method = 'incremental', derivs = 'iterative', format = 'double' }", 1e-8, 1e-2},
      {"{ method = 'incremental', derivs = 'iterative', format = 's20.28' }", 0.05, 3e-2},
      {"{ method = 'incremental-k4', derivs = 'quad', format = 'float' }", 5e-3, 3e-2},
      {"{ method = 'incremental-bidir', derivs = 'heckbert-fd', format = 's24.36' }", 1e-4, 1e-2},
      {"{ method = 'constant-depth', derivs = 'accelerated-fd', format = 'double' }", 1e-8, 1e-2},
      {"{ method = 'quadratic', derivs = 'analytic', format = 'double' }", 2.0, 1e-9},
  };
  const Scene ref_scene = parse_scene(scene_text("", false), "ref.toml", ".");
  const PlaneProjection exact(ref_scene, ref_scene.primitives[0]);
  std::set<std::pair<uint32_t, uint32_t>> ref_pixels;
  for (const Fragment& f : generate_fragments(ref_scene)) ref_pixels.insert({f.x, f.y});
  for (const Case& c : cases) {
    const Scene scene = parse_scene(scene_text(c.coords, false), "s.toml", ".");
    const Drawn d = draw(scene);
    ASSERT_EQ(d.front, 2) << c.coords;
    ASSERT_GT(d.frags.size(), 5000u);
    double worst_uv = 0, worst_d = 0;
    uint64_t mismatched = 0;
    for (size_t i = 0; i < d.frags.size(); ++i) {
      const Fragment& f = d.frags[i];
      ASSERT_TRUE(d.textured[i]) << c.coords << " pixel " << f.x << "," << f.y;
      mismatched += ref_pixels.count({f.x, f.y}) == 0;
      const UvSample s = exact.at(f.x + 0.5, f.y + 0.5);
      worst_uv = std::max({worst_uv, wrapped_err(f.u, s.u, 256), wrapped_err(f.v, s.v, 256)});
      const double scale =
          std::max({std::fabs(s.dudx), std::fabs(s.dvdx), std::fabs(s.dudy), std::fabs(s.dvdy)});
      // Forward differences (quad, fd, iterative) estimate the derivative over one pixel:
      // compare with the exact one-pixel difference where the method is a difference.
      const bool diff = std::string(c.coords).find("'analytic'") == std::string::npos;
      const UvSample sx = exact.at(f.x + 1.5, f.y + 0.5), sy = exact.at(f.x + 0.5, f.y + 1.5);
      const double ex[4] = {diff ? sx.u - s.u : s.dudx, diff ? sx.v - s.v : s.dvdx,
                            diff ? sy.u - s.u : s.dudy, diff ? sy.v - s.v : s.dvdy};
      const double got[4] = {f.dudx, f.dvdx, f.dudy, f.dvdy};
      if (std::string(c.coords).find("'quad'") != std::string::npos)
        continue;  // quad: the 2x2 block's differences
      for (int k = 0; k < 4; ++k) worst_d = std::max(worst_d, std::fabs(got[k] - ex[k]) / scale);
    }
    EXPECT_LT(worst_uv, c.max_uv_texels) << c.coords;
    EXPECT_LT(worst_d, c.max_deriv_rel) << c.coords;
    // Coverage: the triangles' pixels are the reference generator's, up to pixel centres on
    // the plane's boundary.
    EXPECT_LT(mismatched, d.frags.size() / 200) << c.coords;
    EXPECT_NEAR(static_cast<double>(d.frags.size()), static_cast<double>(ref_pixels.size()),
                0.01 * static_cast<double>(ref_pixels.size()));
  }
}

TEST(SceneFrontEnd, OccludedPixelsCostFrontEndWorkOnly) {
  const std::string c = "{ method = 'incremental', derivs = 'iterative', format = 'double' }";
  const Scene open = parse_scene(scene_text(c, false), "s.toml", ".");
  const Scene walled = parse_scene(scene_text(c, true), "s.toml", ".");
  const Drawn a = draw(open), b = draw(walled);
  // Every pixel once; fragments + occluded (+ rejected) = generated.
  std::set<std::pair<uint32_t, uint32_t>> seen;
  for (const Fragment& f : b.frags) EXPECT_TRUE(seen.insert({f.x, f.y}).second);
  EXPECT_EQ(b.frags.size() + b.stats.occluded + b.stats.rejected, b.stats.generated);
  EXPECT_GT(b.stats.occluded, 500u);  // the wall hides part of the floor
  // Same pixels as the reference generator's depth test (up to boundary pixel centres).
  const auto ref = generate_fragments(walled);
  EXPECT_NEAR(static_cast<double>(b.frags.size()), static_cast<double>(ref.size()),
              0.01 * static_cast<double>(ref.size()));
  // The coordinate block's ops count every generated pixel, hidden ones included.
  bool found = false;
  for (const BlockUse& u : b.blocks) {
    if (u.name != "coords.incremental[double]") continue;
    found = true;
    EXPECT_EQ(u.ops.div, 2 * b.stats.generated);  // one division pair per computed pixel
  }
  EXPECT_TRUE(found);
  EXPECT_GT(a.stats.generated, 0u);
  EXPECT_EQ(a.stats.occluded, 0u);
}

TEST(SceneFrontEnd, InstantiatedOnlyWhenAMaterialAsksAndChargedInCycles) {
  const Drawn none = draw(parse_scene(scene_text("", false), "s.toml", "."));
  EXPECT_EQ(none.front, 0);
  for (const BlockUse& u : none.blocks)
    EXPECT_EQ(u.name.rfind("coords.", 0), std::string::npos) << u.name;
  const Drawn fast = draw(parse_scene(
      scene_text("{ method = 'heckbert', derivs = 'analytic', format = 'float' }", false), "s.toml",
      "."));
  const Drawn slow = draw(parse_scene(
      scene_text(
          "{ method = 'heckbert', derivs = 'analytic', format = 'float', datapath = 'shared' }",
          false),
      "s.toml", "."));
  ASSERT_EQ(fast.frags.size(), slow.frags.size());
  bool found = false;
  for (const BlockUse& u : fast.blocks) {
    if (u.name != "coords.heckbert[float]") continue;
    found = true;
    // Heckbert direct: 6 mul, 6 add (numerators, denominator), 2 div per pixel
    // (docs/studies/study-coords.md).
    EXPECT_EQ(u.ops.div, 2 * fast.stats.generated);
    EXPECT_EQ(u.ops.mul, 6 * fast.stats.generated);
    EXPECT_NE(u.arithmetic.find("float"), std::string::npos);
  }
  EXPECT_TRUE(found);
  // One shared operator per kind issues a pixel every 6 cycles at best: the front end, not
  // the cache, then bounds the run.
  EXPECT_GE(slow.cycles, 6 * slow.stats.generated);
  EXPECT_GT(slow.cycles, fast.cycles + fast.cycles / 2);
}

TEST(SceneFrontEnd, DerivsNoneIsRefusedWhereTheFilterNeedsThem) {
  const std::string text = scene_text("{ method = 'heckbert', derivs = 'none' }", false);
  const Scene scene = parse_scene(text, "floor.toml", ".");
  try {
    material_from_toml("m", 0, *scene.materials[0].effects, scene.path);
    FAIL() << "derivs = none accepted for a trilinear material";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("floor.toml"), std::string::npos) << what;
    EXPECT_NE(what.find("derivs"), std::string::npos) << what;
  }
  // Bilinear needs no derivatives: the fragments carry none and read level 0.
  std::string bil = text;
  bil.replace(bil.find("trilinear"), 9, "bilinear");
  const Drawn d = draw(parse_scene(bil, "floor.toml", "."));
  ASSERT_FALSE(d.frags.empty());
  EXPECT_EQ(d.front, 1);
  for (const Fragment& f : d.frags) EXPECT_EQ(f.dudx, 0.0);
  EXPECT_THROW(draw(parse_scene(scene_text("{ method = 'heckbert', formt = 'float' }", false),
                                "s.toml", ".")),
               InputError);
}

TEST(SceneFrontEnd, MillionTexelOffsetsAreRebasedAndUnrepresentableOnesRejected) {
  // uv_offset 4000 textures = 1.02e6 texels: wrap rebases the map by whole textures, so a
  // 48-bit format keeps its precision.
  const std::string c = "{ method = 'incremental', derivs = 'iterative', format = 's20.28' }";
  const Scene far = parse_scene(scene_text(c, false, "[4000.0, -3000.0]"), "s.toml", ".");
  const PlaneProjection exact(far, far.primitives[0]);
  const Drawn d = draw(far);
  ASSERT_GT(d.frags.size(), 5000u);
  double worst = 0;
  for (const Fragment& f : d.frags) {
    const UvSample s = exact.at(f.x + 0.5, f.y + 0.5);
    worst = std::max({worst, wrapped_err(f.u, s.u, 256), wrapped_err(f.v, s.v, 256)});
  }
  EXPECT_LT(worst, 0.05);
  // Clamp has no period to rebase by: s16.16 (±32768 texels) cannot hold 1e6 texels, and every
  // pixel is rejected cleanly: not textured, counted, and never a NaN coordinate.
  std::string clamp = scene_text("{ method = 'heckbert', derivs = 'analytic', format = 's16.16' }",
                                 false, "[4000.0, 0.0]");
  clamp.replace(clamp.find("address = \"wrap\""), 16, "address = \"clamp\"");
  const Drawn r = draw(parse_scene(clamp, "s.toml", "."));
  ASSERT_FALSE(r.frags.empty());
  EXPECT_EQ(r.stats.rejected, r.frags.size());
  for (size_t i = 0; i < r.frags.size(); ++i) EXPECT_FALSE(r.textured[i]);
}

// A plane covering two pixels, drawn by a shared-datapath bicubic unit: the set-ups of its
// triangles and rows are charged as extra issue cycles to their first pixels, so the coordinate
// stage's issue slots outlast the run. The timing check used to call that a broken invariant
// (an internal error of `texsim run`; found by fuzz_scene).
TEST(SceneFrontEnd, SetUpCyclesOfTheLastPixelsDoNotBreakTheTimingInvariant) {
  const Scene scene = parse_scene(R"(
[output]
width = 24
height = 2
[textures.t]
source = "procedural:checker?size=32&cells=4"
[[planes]]
material = "m"
origin = [-2.0, -1.0, -4.0]
edge_u = [5.0, 0.0, 0.0]
edge_v = [0.0, 2.0, 0.0]
[materials.m]
texture = "t"
ewa = { weight = "map", weight_map = { kind = "full2d", element = "u8", size = 2 }, lanes = 1 }
coords = { method = "bicubic", derivs = "heckbert-fd", format = "s16.16", datapath = "shared" }
)",
                                  "s.toml", "");
  TextureSet textures;
  textures.add(load_texture(scene.textures[0].source, ""));
  TextureUnit unit(textures, build_materials(scene), PipelineSetup{}, scene.tech, true);
  std::vector<PlaneProjection> maps{PlaneProjection(scene, scene.primitives[0])};
  draw_scene_front_end(scene, maps, unit, [](const Fragment&, int, const Rgba*) {});
  EXPECT_EQ(unit.fragments(), 2u);
  const StageStats& coords = unit.pipeline()->stats(0);
  // The slots run past the last fragment's exit; the run's cycles include them, so the
  // stage's utilisation stays at most 1 (it read 1.23 when cycles stopped at the exit).
  EXPECT_GT(coords.busy, unit.pipeline()->cycles());
  EXPECT_GE(unit.cycles(), coords.busy);
  EXPECT_LE(unit.pipeline()->utilisation(0), 1.0);
  EXPECT_NO_THROW(unit.check_timing_invariants());
}

}  // namespace
}  // namespace texsim
